# Engine time-series writer (owner: series). test_io_engine_results leaves its files in
# tests/series/ of the build tree (complete run, killed-run copy); the Python check below reads
# them with postprocess/ffrf_results.read_engine and runs engine_summary.py on the complete one.
file(MAKE_DIRECTORY "${PROJECT_BINARY_DIR}/tests/series")
ffrf_add_unit_suite(test_io_engine_results CHECKED LABELS io)
set_tests_properties(test_io_engine_results PROPERTIES FIXTURES_SETUP engine_series_files)
if(Python3_Interpreter_FOUND)
  add_test(NAME postprocess_engine_series
    COMMAND ${Python3_EXECUTABLE} ${PROJECT_SOURCE_DIR}/tests/postprocess/check_engine_series.py
      --summary-script ${PROJECT_SOURCE_DIR}/postprocess/engine_summary.py
      ${PROJECT_BINARY_DIR}/tests/series)
  set_tests_properties(postprocess_engine_series PROPERTIES LABELS "postprocess"
    FIXTURES_REQUIRED engine_series_files ENVIRONMENT "MPLBACKEND=Agg")
endif()
