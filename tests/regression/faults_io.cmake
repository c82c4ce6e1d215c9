# Signals that stay caught, outputs that never write through a link or over an input, and
# allocation failure that ends (issue 23, items 1, 2 and 6), by faults_io.py on small modal and
# engine cases (tests/engine of the build). TIMEOUT bounds each test: memory_limit asserts that
# a run under ulimit -v ends by itself (OpenBLAS's buffer retry used to spin forever).
foreach(test signal_stages output_paths memory_limit)
  add_test(NAME regression_faults_io_${test}
    COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/faults_io.py ${test}
      $<TARGET_FILE:ffrf> ${PROJECT_BINARY_DIR}/meshes ${PROJECT_BINARY_DIR}/tests/engine
      ${PROJECT_BINARY_DIR}/tests/faults_io/${test})
  set_tests_properties(regression_faults_io_${test} PROPERTIES
    LABELS "regression;engine;output" TIMEOUT 120
    FIXTURES_REQUIRED "crank_lc8_mesh;crank_lc10_mesh;conrod_lc8_mesh")
endforeach()
