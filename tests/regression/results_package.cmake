# The pip-installable results reader (issue 26 item 3; docs/results.md "Python package"):
# `pip install ./postprocess` into a fresh virtual environment (offline: Debian's setuptools,
# numpy, h5py, matplotlib through --system-site-packages), then its console scripts and
# ffrf_results.load on a modal crank run, a mechanism run with sensors and an engine run,
# against the same datasets read with h5py; schema_version 99.0 refused, a file without the
# attribute read (tests/postprocess/check_package.py). Skips (77) without python3-venv.
add_test(NAME results_package
  COMMAND ${Python3_EXECUTABLE} ${PROJECT_SOURCE_DIR}/tests/postprocess/check_package.py
    --source ${PROJECT_SOURCE_DIR}/postprocess --work ${PROJECT_BINARY_DIR}/tests/results_package
    --modal ${PROJECT_BINARY_DIR}/tests/regression/crank_lc8_rc2.h5
    --mechanism ${PROJECT_BINARY_DIR}/tests/sensors/slider_wheel.h5
    --engine ${PROJECT_BINARY_DIR}/tests/engine/engine_lc8_rc1.h5)
set_tests_properties(results_package PROPERTIES LABELS "regression;postprocess"
  FIXTURES_REQUIRED "crank_lc8_results;sensors_slider_results;engine_lc8_rc1_results"
  SKIP_RETURN_CODE 77 TIMEOUT 120)
