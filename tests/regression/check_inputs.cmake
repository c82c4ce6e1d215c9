# Every ffrf case in INPUT_DIR (*.nml but study.nml, the sweep's own file) passes `ffrf --check`
# with exit 0 and an empty stderr, each in under a second (the fuzzer's budget per input).
#   cmake -DFFRF=ffrf -DINPUT_DIR=dir -DMESH_DIR=dir -P check_inputs.cmake
file(GLOB cases "${INPUT_DIR}/*.nml")
list(FILTER cases EXCLUDE REGEX "/study\\.nml$")
list(LENGTH cases count)
if(count EQUAL 0)
  message(FATAL_ERROR "no case in ${INPUT_DIR}")
endif()
foreach(case IN LISTS cases)
  string(TIMESTAMP start "%s%f")
  execute_process(COMMAND ${FFRF} ${case} --check --quiet --mesh-dir ${MESH_DIR}
    RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 20)
  string(TIMESTAMP finish "%s%f")
  math(EXPR ms "(${finish} - ${start}) / 1000")
  if(NOT code STREQUAL "0" OR NOT err STREQUAL "")
    message(FATAL_ERROR "${case}: exit ${code}\n${out}${err}")
  endif()
  if(ms GREATER 1000)
    message(FATAL_ERROR "${case}: --check took ${ms} ms, more than 1 s")
  endif()
  message(STATUS "${case}: checked in ${ms} ms")
endforeach()
