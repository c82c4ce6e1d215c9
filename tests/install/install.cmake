# Installation test of this build (static by default): `cmake --install` into a prefix (fixture
# ffrf_static_install), then a tiny outside CMake project finds the package with
# find_package(ffrf), links ffrf::ffrf, computes modes through `use ffrf` and must print the
# frequencies the installed driver writes for the same case.
set(FFRF_STATIC_PREFIX ${PROJECT_BINARY_DIR}/tests/install/prefix)
add_test(NAME install_static
  COMMAND ${CMAKE_COMMAND} -DBUILD_DIR=${PROJECT_BINARY_DIR} -DPREFIX=${FFRF_STATIC_PREFIX}
    -P ${CMAKE_CURRENT_SOURCE_DIR}/install/install_prefix.cmake)
set_tests_properties(install_static PROPERTIES LABELS install
  FIXTURES_SETUP ffrf_static_install)
add_test(NAME install_find_package
  COMMAND ${CMAKE_COMMAND} -DPREFIX=${FFRF_STATIC_PREFIX}
    -DBINDIR=${CMAKE_INSTALL_BINDIR}
    -DPROJECT_DIR=${CMAKE_CURRENT_SOURCE_DIR}/install/project
    -DWORK_DIR=${PROJECT_BINARY_DIR}/tests/install/project
    -DGENERATOR=${CMAKE_GENERATOR}
    -DCASE=${CMAKE_CURRENT_SOURCE_DIR}/regression/crank_lc8_rc2.nml
    -DMESH_DIR=${PROJECT_BINARY_DIR}/meshes
    -DPYTHON=${Python3_EXECUTABLE}
    -DCHECK_SCRIPT=${PROJECT_SOURCE_DIR}/examples/c_modal/check_frequencies.py
    -P ${CMAKE_CURRENT_SOURCE_DIR}/install/run_install_test.cmake)
set_tests_properties(install_find_package PROPERTIES LABELS install
  FIXTURES_REQUIRED "crank_lc8_mesh;ffrf_static_install" ENVIRONMENT OPENBLAS_NUM_THREADS=1)
