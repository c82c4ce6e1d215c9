# Engine charts (owner: charts): plot_engine.py and engine_summary.py on synthetic engine
# results files. Python3_EXECUTABLE is picked in tests/CMakeLists.txt and unit/output.cmake
# (Debian's /usr/bin/python3, which sees python3-h5py/numpy/matplotlib).
if(Python3_Interpreter_FOUND)
  set(_ffrf_engine_out "${PROJECT_BINARY_DIR}/postprocess_tests/engine")
  file(MAKE_DIRECTORY "${_ffrf_engine_out}")
  # 3 complete runs with an analytic regime speed, a killed run, a file without /time
  add_test(NAME postprocess_make_engine_sample
    COMMAND ${Python3_EXECUTABLE} ${PROJECT_SOURCE_DIR}/tests/postprocess/make_engine_sample.py
      -o ${_ffrf_engine_out})
  set_tests_properties(postprocess_make_engine_sample PROPERTIES LABELS "postprocess"
    FIXTURES_SETUP postprocess_engine_sample)
  # summary numbers against the analytic mean and amplitude, PNGs, incomplete and bad files
  add_test(NAME postprocess_engine_charts
    COMMAND ${Python3_EXECUTABLE} ${PROJECT_SOURCE_DIR}/tests/postprocess/check_engine_charts.py
      --summary-script ${PROJECT_SOURCE_DIR}/postprocess/engine_summary.py
      --plot-script ${PROJECT_SOURCE_DIR}/postprocess/plot_engine.py ${_ffrf_engine_out})
  set_tests_properties(postprocess_engine_charts PROPERTIES LABELS "postprocess"
    FIXTURES_REQUIRED postprocess_engine_sample ENVIRONMENT "MPLBACKEND=Agg")
else()
  message(WARNING "no Python 3 interpreter: engine chart tests are not registered")
endif()
