# Builds and checks one example against the installed package: a fresh copy of the folder, then
# `make all` and `make check` (the check exits non-zero on a wrong result).
# cmake -DEXAMPLE_DIR= -DWORK_DIR= -DPKG_CONFIG_DIR= -DCASE_DIR= -DMESH_DIR= -DPYTHON= -P run_example.cmake
find_program(MAKE_PROGRAM NAMES gmake make REQUIRED)
file(REMOVE_RECURSE "${WORK_DIR}")
get_filename_component(parent "${WORK_DIR}" DIRECTORY)
file(COPY "${EXAMPLE_DIR}" DESTINATION "${parent}")
get_filename_component(name "${EXAMPLE_DIR}" NAME)
if(NOT "${parent}/${name}" STREQUAL "${WORK_DIR}")
  file(RENAME "${parent}/${name}" "${WORK_DIR}")
endif()
foreach(target all check)
  execute_process(COMMAND "${MAKE_PROGRAM}" -C "${WORK_DIR}" ${target}
      "PKG_CONFIG_PATH=${PKG_CONFIG_DIR}" "CASE_DIR=${CASE_DIR}" "MESH_DIR=${MESH_DIR}"
      "OUT_DIR=${WORK_DIR}/out" "PYTHON=${PYTHON}"
    RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message(STATUS "make ${target}:\n${out}${err}")
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "make ${target} failed (${code})")
  endif()
endforeach()
