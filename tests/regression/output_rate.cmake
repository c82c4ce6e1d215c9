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
set(_rate_spatial "${PROJECT_SOURCE_DIR}/input/spatial_pendulum.nml")
foreach(_rate crankless engine free_space)
  set(_rate_case "${_rate_spatial}")
  set(_rate_extra "")
  set(_rate_fixtures link_mesh)
  if(_rate STREQUAL "engine")
    set(_rate_case "${PROJECT_BINARY_DIR}/tests/engine/engine_lc8_rc1.nml")
    set(_rate_extra --sample 0.001)
    set(_rate_fixtures "crank_lc8_mesh;conrod_lc8_mesh")
  endif()
  add_test(NAME regression_output_rate_${_rate}
    COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 ${Python3_EXECUTABLE}
      ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_output_rate.py ${_rate} $<TARGET_FILE:ffrf>
      ${_rate_case} ${PROJECT_BINARY_DIR}/meshes ${_rate_out}/${_rate} ${_rate_extra})
  set_tests_properties(regression_output_rate_${_rate} PROPERTIES
    LABELS "regression;results" FIXTURES_REQUIRED "${_rate_fixtures}")
endforeach()

# regression_output_live_read (issue 29 item 3): the spatial pendulum, compressed and decimated,
# read while it runs: its checkpoint copy by ffrf_results (status 'running'), its .part file by
# h5py without HDF5's file lock; stopped by SIGTERM (exit 5), the rows read mid-run equal the
# finished file's exactly (tests/regression/check_live_read.py). About 1 s.
add_test(NAME regression_output_live_read
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 ${Python3_EXECUTABLE}
    ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_live_read.py $<TARGET_FILE:ffrf>
    ${_rate_spatial} ${PROJECT_BINARY_DIR}/meshes ${_rate_out}/live_read)
set_tests_properties(regression_output_live_read PROPERTIES
  LABELS "regression;results" FIXTURES_REQUIRED link_mesh)
