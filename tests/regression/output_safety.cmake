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
