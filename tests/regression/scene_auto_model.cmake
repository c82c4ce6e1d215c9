# The automatic model of a scene without a crank (issue 24 item 2; docs/mechanisms.md "Targets on
# sensors"): the flexible double pendulum of tests/data/scene/auto_double_pendulum.nml chooses
# its modes and step for two &model targets; a converged run of the same scene (all 10
# candidate modes per link, h = 2.5e-6 s) is the reference of check_scene_auto_model.py.
# About 8 + 10 s alone (19 + 19 s measured on the busy 2-core machine).
set(_scene_out "${PROJECT_BINARY_DIR}/tests/scene")
file(MAKE_DIRECTORY ${_scene_out}/auto ${_scene_out}/reference)
add_test(NAME regression_scene_auto_model
  COMMAND $<TARGET_FILE:ffrf> ${CMAKE_CURRENT_SOURCE_DIR}/data/scene/auto_double_pendulum.nml
    --mesh-dir ${PROJECT_BINARY_DIR}/meshes --output-dir ${_scene_out}/auto --threads 1)
set_tests_properties(regression_scene_auto_model PROPERTIES LABELS "regression;mbs"
  FIXTURES_REQUIRED beam_lc6_mesh FIXTURES_SETUP scene_auto_model_results)
add_test(NAME regression_scene_auto_model_reference
  COMMAND $<TARGET_FILE:ffrf> ${CMAKE_CURRENT_SOURCE_DIR}/data/scene/auto_double_pendulum.nml
    --mesh-dir ${PROJECT_BINARY_DIR}/meshes --output-dir ${_scene_out}/reference --threads 1
    --set body[link1].num_modes=10
    --set body[link2].num_modes=10 --set integrator.h=2.5e-6)
set_tests_properties(regression_scene_auto_model_reference PROPERTIES LABELS "regression;mbs"
  FIXTURES_REQUIRED beam_lc6_mesh FIXTURES_SETUP scene_auto_model_results)
add_test(NAME regression_scene_auto_model_check
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_scene_auto_model.py
    ${_scene_out}/auto/auto_double_pendulum.h5
    ${_scene_out}/reference/auto_double_pendulum.h5)
set_tests_properties(regression_scene_auto_model_check PROPERTIES LABELS "regression;mbs"
  FIXTURES_REQUIRED scene_auto_model_results)
# Bad targets: a tolerance out of (0, 1) at reading, a name that is no &sensor before the modes
add_test(NAME error_scene_targets_tolerance
  COMMAND ${CMAKE_COMMAND}
    "-DCOMMAND=$<TARGET_FILE:ffrf>;${CMAKE_CURRENT_SOURCE_DIR}/data/scene/auto_double_pendulum.nml;--mesh-dir;${PROJECT_BINARY_DIR}/meshes;--output-dir;${_scene_out};--check;--set;model.targets=tip_deflection 2"
    -DEXIT_CODE=2 "-DMESSAGE=&model targets: the tolerance of \"tip_deflection\" is \"2\", must be a number in \\(0, 1\\)"
    -P ${CMAKE_CURRENT_SOURCE_DIR}/regression/expect_error.cmake)
add_test(NAME error_scene_targets_sensor
  COMMAND ${CMAKE_COMMAND}
    "-DCOMMAND=$<TARGET_FILE:ffrf>;${CMAKE_CURRENT_SOURCE_DIR}/data/scene/auto_double_pendulum.nml;--mesh-dir;${PROJECT_BINARY_DIR}/meshes;--output-dir;${_scene_out};--set;model.targets=tip 1e-2"
    -DEXIT_CODE=2 "-DMESSAGE=&model targets: no &sensor \"tip\"; name a &sensor of type reaction or node_displacement"
    -P ${CMAKE_CURRENT_SOURCE_DIR}/regression/expect_error.cmake)
set_tests_properties(error_scene_targets_tolerance error_scene_targets_sensor PROPERTIES
  LABELS "regression;errors" FIXTURES_REQUIRED beam_lc6_mesh)
