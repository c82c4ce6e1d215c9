# Plain-Makefile programs (pkgconfig/Makefile) built in a fresh WORK_DIR against an installed
# prefix with nothing but pkg-config, then checked (`make check`).
# cmake -DSRC_DIR= -DWORK_DIR= -DPKG_CONFIG_DIR= -DFORTRAN_SOURCE= -DWITH_C=yes|no -DFC= -DCC=
#       -DCASE= -DMESH_DIR= -DPYTHON= -DCHECK_SCRIPT= -P run_pkgconfig_test.cmake
find_program(MAKE_PROGRAM NAMES gmake make REQUIRED)
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
execute_process(COMMAND "${MAKE_PROGRAM}" -C "${WORK_DIR}" -f "${SRC_DIR}/Makefile" check
    "SRC_DIR=${SRC_DIR}" "PKG_CONFIG_PATH=${PKG_CONFIG_DIR}" "FORTRAN_SOURCE=${FORTRAN_SOURCE}"
    "WITH_C=${WITH_C}" "FC=${FC}" "CC=${CC}" "CASE=${CASE}" "MESH_DIR=${MESH_DIR}"
    "PYTHON=${PYTHON}" "CHECK_SCRIPT=${CHECK_SCRIPT}"
  RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
message(STATUS "${out}${err}")
if(NOT code EQUAL 0)
  message(FATAL_ERROR "make check failed (${code})")
endif()
