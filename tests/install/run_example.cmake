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
# PKG_CONFIG_PATH both in the environment (make 4.3 runs $(shell ...) without the command line's
# variables) and on the command line; the prefix's libdir on LD_LIBRARY_PATH, as a user of a
# private prefix sets it (c_modal also records it as rpath)
get_filename_component(libdir "${PKG_CONFIG_DIR}" DIRECTORY)
set(ld_path "${libdir}")
if(DEFINED ENV{LD_LIBRARY_PATH} AND NOT "$ENV{LD_LIBRARY_PATH}" STREQUAL "")
  set(ld_path "${libdir}:$ENV{LD_LIBRARY_PATH}")
endif()
foreach(target all check)
  execute_process(COMMAND ${CMAKE_COMMAND} -E env "PKG_CONFIG_PATH=${PKG_CONFIG_DIR}"
      "LD_LIBRARY_PATH=${ld_path}" "${MAKE_PROGRAM}" -C "${WORK_DIR}" ${target}
      "PKG_CONFIG_PATH=${PKG_CONFIG_DIR}" "CASE_DIR=${CASE_DIR}" "MESH_DIR=${MESH_DIR}"
      "OUT_DIR=${WORK_DIR}/out" "PYTHON=${PYTHON}"
    RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message(STATUS "make ${target}:\n${out}${err}")
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "make ${target} failed (${code})")
  endif()
endforeach()
