# The automatic model of a scene without a crank (issue 24 item 2; docs/mechanisms.md "Targets on
# sensors"): the flexible double pendulum of tests/data/scene/auto_double_pendulum.nml chooses
# its modes and step for two &model targets; a converged run of the same scene (all 10
# candidate modes per link, h = 2.5e-6 s) is the reference of check_scene_auto_model.py.
# About 8 + 10 s alone (19 + 19 s measured on the busy 2-core machine).
set(_scene_out "${PROJECT_BINARY_DIR}/tests/scene")
# Three tests of one scene: ${test} (the automatic model, with the overrides auto_args, a list),
# ${test}_reference (the converged run: the arguments after auto_args override the model),
# ${test}_check (the comparison)
function(scene_auto_model_tests test case auto_dir reference_dir auto_args)
  set(_nml ${CMAKE_CURRENT_SOURCE_DIR}/data/scene/${case}.nml)
  file(MAKE_DIRECTORY ${_scene_out}/${auto_dir} ${_scene_out}/${reference_dir})
  add_test(NAME ${test} COMMAND $<TARGET_FILE:ffrf> ${_nml} --mesh-dir ${PROJECT_BINARY_DIR}/meshes
    --output-dir ${_scene_out}/${auto_dir} --threads 1 ${auto_args})
  add_test(NAME ${test}_reference COMMAND $<TARGET_FILE:ffrf> ${_nml}
    --mesh-dir ${PROJECT_BINARY_DIR}/meshes --output-dir ${_scene_out}/${reference_dir}
    --threads 1 ${ARGN})
  set_tests_properties(${test} ${test}_reference PROPERTIES LABELS "regression;mbs"
    FIXTURES_REQUIRED beam_lc6_mesh FIXTURES_SETUP ${test}_results)
  add_test(NAME ${test}_check
    COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_scene_auto_model.py
      ${_scene_out}/${auto_dir}/${case}.h5 ${_scene_out}/${reference_dir}/${case}.h5)
  set_tests_properties(${test}_check PROPERTIES LABELS "regression;mbs"
    FIXTURES_REQUIRED ${test}_results)
endfunction()
scene_auto_model_tests(regression_scene_auto_model auto_double_pendulum auto reference ""
  --set body[link1].num_modes=10 --set body[link2].num_modes=10 --set integrator.h=2.5e-6)
# Bad targets: a tolerance out of (0, 1) at reading, a name that is no &sensor at --check
add_test(NAME error_scene_targets_tolerance
  COMMAND ${CMAKE_COMMAND}
    "-DCOMMAND=$<TARGET_FILE:ffrf>;${CMAKE_CURRENT_SOURCE_DIR}/data/scene/auto_double_pendulum.nml;--mesh-dir;${PROJECT_BINARY_DIR}/meshes;--output-dir;${_scene_out};--check;--set;model.targets=tip_deflection 2"
    -DEXIT_CODE=2 "-DMESSAGE=&model targets: the tolerance of \"tip_deflection\" is \"2\", must be a number in \\(0, 1\\)"
    -P ${CMAKE_CURRENT_SOURCE_DIR}/regression/expect_error.cmake)
add_test(NAME error_scene_targets_sensor
  COMMAND ${CMAKE_COMMAND}
    "-DCOMMAND=$<TARGET_FILE:ffrf>;${CMAKE_CURRENT_SOURCE_DIR}/data/scene/auto_double_pendulum.nml;--mesh-dir;${PROJECT_BINARY_DIR}/meshes;--output-dir;${_scene_out};--check;--set;model.targets=tip 1e-2"
    -DEXIT_CODE=2 "-DMESSAGE=&model targets: no &sensor \"tip\"; name a &sensor of type reaction, node_displacement, joint_coordinate, position, velocity, angular_velocity"
    -P ${CMAKE_CURRENT_SOURCE_DIR}/regression/expect_error.cmake)
set_tests_properties(error_scene_targets_tolerance error_scene_targets_sensor PROPERTIES
  LABELS "regression;errors" FIXTURES_REQUIRED beam_lc6_mesh)
# A second scene (issue 24 item 2, part 2): the driven boom with a tip mass of
# tests/data/scene/auto_driven_boom.nml, peak and mean targets on a node, a joint force, a
# marker's velocity and angular velocity; its reference has all 10 candidate modes and
# h = 2.5e-6 s. About 8 + 6 s alone.
scene_auto_model_tests(regression_scene_auto_model_boom auto_driven_boom boom boom_reference ""
  --set body[boom].num_modes=10 --set integrator.h=2.5e-6)
# The mesh chosen (item 2, part 4): the same boom on mesh_file beam_lc4.msh with coarse_meshes
# beam_lc40.msh and beam_lc6.msh; the estimate takes the coarsest whose kept modes' frequency
# errors (Richardson against the next finer mesh) fit a third of each tolerance (beam_lc6.msh:
# beam_lc40.msh's tip deflection error is estimated at 0.12); the reference is beam_lc4.msh
# with all 10 candidate modes and h = 2.5e-6 s. About 16 + 12 s alone.
scene_auto_model_tests(regression_scene_auto_model_boom_mesh auto_driven_boom boom_mesh
  boom_mesh_reference "--set;body[boom].mesh_file=beam_lc4.msh;--set;body[boom].coarse_meshes='beam_lc40.msh', 'beam_lc6.msh'"
  --set body[boom].mesh_file=beam_lc4.msh --set body[boom].num_modes=10
  --set integrator.h=2.5e-6)
set_property(TEST regression_scene_auto_model_boom_mesh
  regression_scene_auto_model_boom_mesh_reference APPEND PROPERTY FIXTURES_REQUIRED
  beam_lc4_mesh beam_lc40_mesh)
# --check refuses what the automatic model would refuse, without the pre-run or any modes: a
# target without a tolerance, a sensor the estimate cannot serve (its kind; a marker on a body
# whose modes it does not choose)
set(_boom_check "$<TARGET_FILE:ffrf>;${CMAKE_CURRENT_SOURCE_DIR}/data/scene/auto_driven_boom.nml;--mesh-dir;${PROJECT_BINARY_DIR}/meshes;--output-dir;${_scene_out};--check")
add_test(NAME error_scene_targets_no_tolerance
  COMMAND ${CMAKE_COMMAND} "-DCOMMAND=${_boom_check};--set;model.targets=tip_spin mean"
    -DEXIT_CODE=2 "-DMESSAGE=&model targets = 'tip_spin mean': \"tip_spin\" has no tolerance"
    -P ${CMAKE_CURRENT_SOURCE_DIR}/regression/expect_error.cmake)
add_test(NAME error_scene_targets_kind
  COMMAND ${CMAKE_COMMAND} "-DCOMMAND=${_boom_check};--set;model.targets=luff_torque 1e-2"
    -DEXIT_CODE=2 "-DMESSAGE=&model targets: &sensor \"luff_torque\" is of type driver; the automatic model estimates targets on reaction, node_displacement, joint_coordinate, position, velocity, angular_velocity"
    -P ${CMAKE_CURRENT_SOURCE_DIR}/regression/expect_error.cmake)
add_test(NAME error_scene_targets_marker
  COMMAND ${CMAKE_COMMAND} "-DCOMMAND=${_boom_check};--set;model.targets=hook_position mean 1e-2"
    -DEXIT_CODE=2 "-DMESSAGE=&model targets: &sensor \"hook_position\" \\(position\\) measures no interface of a body whose modes the automatic model chooses"
    -P ${CMAKE_CURRENT_SOURCE_DIR}/regression/expect_error.cmake)
set_tests_properties(error_scene_targets_no_tolerance error_scene_targets_kind
  error_scene_targets_marker PROPERTIES LABELS "regression;errors" FIXTURES_REQUIRED beam_lc6_mesh)
