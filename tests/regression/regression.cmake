# Regression runs of the ffrf driver on the reference crank (lc = 8 mm fixture), read back by the
# Python postprocess in ctest.
if(NOT Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
  set(Python3_EXECUTABLE /usr/bin/python3)
endif()
set(_out "${PROJECT_BINARY_DIR}/tests/regression")
file(MAKE_DIRECTORY "${_out}")
add_test(NAME regression_crank_lc8_rc2
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 $<TARGET_FILE:ffrf>
    ${CMAKE_CURRENT_SOURCE_DIR}/regression/crank_lc8_rc2.nml
    --mesh-dir ${PROJECT_BINARY_DIR}/meshes --output-dir ${_out})
set_tests_properties(regression_crank_lc8_rc2 PROPERTIES LABELS regression
  FIXTURES_REQUIRED crank_lc8_mesh FIXTURES_SETUP crank_lc8_results)

add_test(NAME regression_crank_lc8_rc2_check
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_results.py
    ${_out}/crank_lc8_rc2.h5)
add_test(NAME regression_crank_lc8_rc2_plots
  COMMAND ${CMAKE_COMMAND} -E chdir ${_out} ${Python3_EXECUTABLE}
    ${PROJECT_SOURCE_DIR}/postprocess/plot_modes.py crank_lc8_rc2.h5 -o crank_lc8_rc2_modes.png
    --modes 2)
add_test(NAME regression_crank_lc8_rc2_table
  COMMAND ${CMAKE_COMMAND} -E chdir ${_out} ${Python3_EXECUTABLE}
    ${PROJECT_SOURCE_DIR}/postprocess/frequency_table.py crank_lc8_rc2.h5
    --markdown crank_lc8_rc2.md --csv crank_lc8_rc2.csv)
set_tests_properties(regression_crank_lc8_rc2_check regression_crank_lc8_rc2_plots
  regression_crank_lc8_rc2_table PROPERTIES LABELS "regression;postprocess"
  FIXTURES_REQUIRED crank_lc8_results)
set_tests_properties(regression_crank_lc8_rc2_plots regression_crank_lc8_rc2_table PROPERTIES
  FIXTURES_SETUP crank_lc8_postprocess)
# what the plot and table scripts wrote, read back: the CSV's frequencies equal the results
# file's exactly (h5py), the plot is a real, non-blank PNG
add_test(NAME regression_crank_lc8_rc2_table_content
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_outputs.py table
    ${_out}/crank_lc8_rc2.csv ${_out}/crank_lc8_rc2.h5)
add_test(NAME regression_crank_lc8_rc2_plots_content
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_outputs.py png
    ${_out}/crank_lc8_rc2_modes.png)
set_tests_properties(regression_crank_lc8_rc2_table_content regression_crank_lc8_rc2_plots_content
  PROPERTIES LABELS "regression;postprocess" FIXTURES_REQUIRED "crank_lc8_results;crank_lc8_postprocess")
