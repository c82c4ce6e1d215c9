# Tests against an installed SHARED ffrf, as a user builds and installs it:
#   install_shared            fixture ffrf_shared_install: a -DBUILD_SHARED_LIBS=ON build of this
#                             source tree (library and driver only) in tests/install/shared/build,
#                             installed into tests/install/shared/prefix (build_shared.cmake)
#   install_find_package_shared   tests/install/project with find_package(ffrf) on that prefix
#   install_pkgconfig_{shared,static}  plain Makefile (pkgconfig/Makefile): a C program linked with
#                             `pkg-config --libs ffrf` alone prints the version pkg-config reports;
#                             a Fortran program (fflags + --libs) computes modes equal to the driver's
#                             (static: the prefix of install_static, where --libs carries every library)
#   example_<name>            every examples/<name>/ (a Makefile with `all` and `check`): a fresh copy,
#                             `make all`, `make check` with PKG_CONFIG_PATH on the shared prefix,
#                             CASE_DIR = input/, MESH_DIR = this build's meshes
# The C parts need include/ffrf.h (the C API); without it only the Fortran parts are tested.
set(FFRF_SHARED_DIR ${PROJECT_BINARY_DIR}/tests/install/shared)
set(FFRF_SHARED_PREFIX ${FFRF_SHARED_DIR}/prefix)
set(FFRF_CHECK_FREQUENCIES ${PROJECT_SOURCE_DIR}/examples/c_modal/check_frequencies.py)
set(FFRF_INSTALL_CASE ${CMAKE_CURRENT_SOURCE_DIR}/regression/crank_lc8_rc2.nml)
if(EXISTS ${PROJECT_SOURCE_DIR}/include/ffrf.h)
  set(FFRF_HAVE_C_API yes)
else()
  set(FFRF_HAVE_C_API no)
endif()

add_test(NAME install_shared
  COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${PROJECT_SOURCE_DIR} -DBUILD_DIR=${FFRF_SHARED_DIR}/build
    -DPREFIX=${FFRF_SHARED_PREFIX} -DGENERATOR=${CMAKE_GENERATOR}
    -DFortran_COMPILER=${CMAKE_Fortran_COMPILER} -DC_COMPILER=${CMAKE_C_COMPILER}
    -DPYTHON=${Python3_EXECUTABLE} -P ${CMAKE_CURRENT_SOURCE_DIR}/install/build_shared.cmake)
set_tests_properties(install_shared PROPERTIES LABELS install TIMEOUT 1800
  FIXTURES_SETUP ffrf_shared_install)

add_test(NAME install_find_package_shared
  COMMAND ${CMAKE_COMMAND} -DPREFIX=${FFRF_SHARED_PREFIX} -DBINDIR=${CMAKE_INSTALL_BINDIR}
    -DPROJECT_DIR=${CMAKE_CURRENT_SOURCE_DIR}/install/project
    -DWORK_DIR=${FFRF_SHARED_DIR}/project -DGENERATOR=${CMAKE_GENERATOR}
    -DCASE=${FFRF_INSTALL_CASE} -DMESH_DIR=${PROJECT_BINARY_DIR}/meshes
    -DPYTHON=${Python3_EXECUTABLE} -DCHECK_SCRIPT=${FFRF_CHECK_FREQUENCIES}
    -P ${CMAKE_CURRENT_SOURCE_DIR}/install/run_install_test.cmake)
set_tests_properties(install_find_package_shared PROPERTIES LABELS install
  FIXTURES_REQUIRED "crank_lc8_mesh;ffrf_shared_install" ENVIRONMENT OPENBLAS_NUM_THREADS=1)

foreach(kind shared static)
  if(kind STREQUAL "shared")
    set(prefix ${FFRF_SHARED_PREFIX})
    set(fixture ffrf_shared_install)
  else()
    set(prefix ${PROJECT_BINARY_DIR}/tests/install/prefix)     # install_static (install.cmake)
    set(fixture ffrf_static_install)
  endif()
  add_test(NAME install_pkgconfig_${kind}
    COMMAND ${CMAKE_COMMAND} -DSRC_DIR=${CMAKE_CURRENT_SOURCE_DIR}/install/pkgconfig
      -DWORK_DIR=${PROJECT_BINARY_DIR}/tests/install/pkgconfig_${kind}
      -DPKG_CONFIG_DIR=${prefix}/${CMAKE_INSTALL_LIBDIR}/pkgconfig
      -DFORTRAN_SOURCE=${CMAKE_CURRENT_SOURCE_DIR}/install/project/main.f90
      -DWITH_C=${FFRF_HAVE_C_API} -DFC=${CMAKE_Fortran_COMPILER} -DCC=${CMAKE_C_COMPILER}
      -DCASE=${FFRF_INSTALL_CASE} -DMESH_DIR=${PROJECT_BINARY_DIR}/meshes
      -DPYTHON=${Python3_EXECUTABLE} -DCHECK_SCRIPT=${FFRF_CHECK_FREQUENCIES}
      -P ${CMAKE_CURRENT_SOURCE_DIR}/install/run_pkgconfig_test.cmake)
  set_tests_properties(install_pkgconfig_${kind} PROPERTIES LABELS install
    FIXTURES_REQUIRED "crank_lc8_mesh;${fixture}" ENVIRONMENT OPENBLAS_NUM_THREADS=1)
endforeach()

# Every example folder; the meshes of input/ the examples' cases read.
file(GLOB _examples LIST_DIRECTORIES true "${PROJECT_SOURCE_DIR}/examples/*")
foreach(dir IN LISTS _examples)
  if(NOT EXISTS ${dir}/Makefile)
    continue()
  endif()
  get_filename_component(name ${dir} NAME)
  if(NOT FFRF_HAVE_C_API)
    message(STATUS "example_${name}: no include/ffrf.h (C API) in this tree, test not added")
    continue()
  endif()
  add_test(NAME example_${name}
    COMMAND ${CMAKE_COMMAND} -DEXAMPLE_DIR=${dir} -DWORK_DIR=${FFRF_SHARED_DIR}/examples/${name}
      -DPKG_CONFIG_DIR=${FFRF_SHARED_PREFIX}/${CMAKE_INSTALL_LIBDIR}/pkgconfig
      -DCASE_DIR=${PROJECT_SOURCE_DIR}/input -DMESH_DIR=${PROJECT_BINARY_DIR}/meshes
      -DPYTHON=${Python3_EXECUTABLE} -P ${CMAKE_CURRENT_SOURCE_DIR}/install/run_example.cmake)
  set_tests_properties(example_${name} PROPERTIES LABELS "install;example"
    FIXTURES_REQUIRED "ffrf_shared_install;crank_mesh;conrod_mesh;crank_lc10_mesh;crank_lc8_mesh;conrod_lc8_mesh"
    ENVIRONMENT OPENBLAS_NUM_THREADS=1)
endforeach()
