# Output rate, peaks, compression, chosen histories and the predicted size (&output, issue 29;
# docs/results.md "Output rate, peaks, compression, size"; tests/regression/check_output_rate.py):
#  - regression_output_rate_crankless: the flexible spatial double pendulum (two links, 8 modes
#    each, 0.06 s at h = 5e-4): no engine histories without a crank; samples every 5 ms equal
#    the full-rate rows exactly, their /peaks the extremes per interval exactly; every_steps =
#    every_seconds; compressed = uncompressed values; --restart between two samples = the
#    straight run; histories = 'energies'; the predicted size within 10 %. Seven short runs.
#  - regression_output_rate_engine: the lc 8 mm engine, 0.02 s: the conrod's peak reaction
#    components from 1 ms output equal the full-rate ones exactly; prediction within 10 %.
#  - regression_output_rate_free_space: refused on a 2 MB tmpfs (exit 3, no file).
set(_rate_out "${PROJECT_BINARY_DIR}/tests/output_rate")
add_test(NAME regression_output_rate_crankless
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 ${Python3_EXECUTABLE}
    ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_output_rate.py crankless $<TARGET_FILE:ffrf>
    ${PROJECT_SOURCE_DIR}/input/spatial_pendulum.nml ${PROJECT_BINARY_DIR}/meshes
    ${_rate_out}/crankless)
set_tests_properties(regression_output_rate_crankless PROPERTIES
  LABELS "regression;results" FIXTURES_REQUIRED link_mesh)
add_test(NAME regression_output_rate_engine
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 ${Python3_EXECUTABLE}
    ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_output_rate.py engine $<TARGET_FILE:ffrf>
    ${PROJECT_BINARY_DIR}/tests/engine/engine_lc8_rc1.nml ${PROJECT_BINARY_DIR}/meshes
    ${_rate_out}/engine --sample 0.001)
set_tests_properties(regression_output_rate_engine PROPERTIES
  LABELS "regression;results;engine" FIXTURES_REQUIRED "crank_lc8_mesh;conrod_lc8_mesh")
add_test(NAME regression_output_rate_free_space
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 ${Python3_EXECUTABLE}
    ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_output_rate.py free_space $<TARGET_FILE:ffrf>
    ${PROJECT_SOURCE_DIR}/input/spatial_pendulum.nml ${PROJECT_BINARY_DIR}/meshes
    ${_rate_out}/free_space)
set_tests_properties(regression_output_rate_free_space PROPERTIES
  LABELS "regression;results" FIXTURES_REQUIRED link_mesh)
