# Installation test: `cmake --install` into a prefix, then a tiny outside CMake project finds the
# package with find_package(ffrf), links ffrf::ffrf and computes modes through the public API.
add_test(NAME install_find_package
  COMMAND ${CMAKE_COMMAND} -DBUILD_DIR=${PROJECT_BINARY_DIR}
    -DPREFIX=${PROJECT_BINARY_DIR}/tests/install/prefix
    -DPROJECT_DIR=${CMAKE_CURRENT_SOURCE_DIR}/install/project
    -DWORK_DIR=${PROJECT_BINARY_DIR}/tests/install/project
    -DGENERATOR=${CMAKE_GENERATOR}
    -DCASE=${CMAKE_CURRENT_SOURCE_DIR}/regression/crank_lc8_rc2.nml
    -DMESH_DIR=${PROJECT_BINARY_DIR}/meshes
    -P ${CMAKE_CURRENT_SOURCE_DIR}/install/run_install_test.cmake)
set_tests_properties(install_find_package PROPERTIES LABELS install
  FIXTURES_REQUIRED crank_lc8_mesh ENVIRONMENT OPENBLAS_NUM_THREADS=1)
