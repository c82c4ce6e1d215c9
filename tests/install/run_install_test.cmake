# An outside CMake project (PROJECT_DIR) finds the installed package with find_package(ffrf),
# computes the case's modes through `use ffrf`, and must print the frequencies the installed
# driver writes for the same case (CHECK_SCRIPT, 1e-12 relative: same library, same machine).
# cmake -DPREFIX= -DBINDIR= -DPROJECT_DIR= -DWORK_DIR= -DGENERATOR= -DCASE= -DMESH_DIR= -DPYTHON=
#       -DCHECK_SCRIPT= -P run_install_test.cmake
function(run)
  execute_process(COMMAND ${ARGV} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "failed (${code}): ${ARGV}\n${out}\n${err}")
  endif()
  message(STATUS "${out}${err}")
endfunction()
file(REMOVE_RECURSE "${WORK_DIR}")
run(${CMAKE_COMMAND} -S "${PROJECT_DIR}" -B "${WORK_DIR}" -G "${GENERATOR}"
  "-DCMAKE_PREFIX_PATH=${PREFIX}")
run(${CMAKE_COMMAND} --build "${WORK_DIR}")
execute_process(COMMAND "${WORK_DIR}/modes_app" "${CASE}" "${MESH_DIR}"
  OUTPUT_FILE "${WORK_DIR}/modes_app.txt" RESULT_VARIABLE code ERROR_VARIABLE err)
if(NOT code EQUAL 0)
  file(READ "${WORK_DIR}/modes_app.txt" out)
  message(FATAL_ERROR "modes_app failed (${code}):\n${out}\n${err}")
endif()
file(MAKE_DIRECTORY "${WORK_DIR}/driver")
run("${PREFIX}/${BINDIR}/ffrf" "${CASE}" --mesh-dir "${MESH_DIR}" --output-dir "${WORK_DIR}/driver"
  --quiet)
get_filename_component(name "${CASE}" NAME_WE)
run("${PYTHON}" "${CHECK_SCRIPT}" "${WORK_DIR}/modes_app.txt" "${WORK_DIR}/driver/${name}.h5")
