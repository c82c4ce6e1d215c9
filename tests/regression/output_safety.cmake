# Results files that survive faults (issue 10, parts 1 and 2), by output_safety.py on the engine
# cases of engine.cmake (tests/engine of the build): two runs on one output, a full disk for a
# modal and an engine run, SIGTERM/SIGINT/SIGHUP/SIGUSR1/SIGXCPU at several moments, restart
# of a finished and of a killed (kill -9) run.
foreach(test concurrent disk_full signals restart)
  add_test(NAME regression_output_safety_${test}
    COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/output_safety.py ${test}
      $<TARGET_FILE:ffrf> ${PROJECT_BINARY_DIR}/meshes ${PROJECT_BINARY_DIR}/tests/engine
      ${PROJECT_BINARY_DIR}/tests/output_safety/${test})
  set_tests_properties(regression_output_safety_${test} PROPERTIES
    LABELS "regression;engine;output" TIMEOUT 600
    FIXTURES_REQUIRED "crank_lc8_mesh;conrod_lc8_mesh;crank_mesh")
endforeach()

# A mechanism run that fails after its modes and before its integration (issue 24): the results
# file with the input echo, the modes (equal to a modal run's) and status "error: ..."
# (check_failed_start.py on tests/data/faults/failed_start.nml, a start that cannot assemble).
add_test(NAME regression_failed_start
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 ${Python3_EXECUTABLE}
    ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_failed_start.py $<TARGET_FILE:ffrf>
    ${CMAKE_CURRENT_SOURCE_DIR}/data/faults/failed_start.nml ${PROJECT_BINARY_DIR}/meshes
    ${PROJECT_BINARY_DIR}/tests/failed_start)
set_tests_properties(regression_failed_start PROPERTIES LABELS "regression;output"
  FIXTURES_REQUIRED link_mesh)
