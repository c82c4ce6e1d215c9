# The spring-damper (&spring, src/mbs/spring_damper.f90; issue 24, item 1):
#  - regression_springs: a mass on a spring-damper against the closed-form damped oscillator
#    (all steps, order 2, period and decay) and an undamped spring on the IFToMM A01 pendulum
#    (conservation of T + m g y + k (l - L0)^2 / 2, order 2 of the drift)
#    (tests/regression/check_springs.py). About 10 s.
add_test(NAME regression_springs
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 ${Python3_EXECUTABLE}
    ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_springs.py $<TARGET_FILE:ffrf>
    ${PROJECT_SOURCE_DIR}/input/spring_oscillator.nml
    ${PROJECT_SOURCE_DIR}/input/spring_pendulum.nml ${PROJECT_BINARY_DIR}/meshes
    ${PROJECT_BINARY_DIR}/tests/springs)
set_tests_properties(regression_springs PROPERTIES LABELS "regression;springs")

# Bad &spring, &torsion_spring and &bushing input: one line naming the file, line and group, exit
# 2, from a run and --check.
set(_spring_scene "&body name = 'mass', type = 'rigid', mass = 1.0, inertia = 1.0e-3, 1.0e-3, 1.0e-3, 0, 0, 0, position = 0.6, 0.0, 0.0 /\n&marker body = 'mass', name = 'P', position = 0.0, 0.0, 0.0 /\n&marker body = 'ground', name = 'anchor', position = 0.0, 0.0, 0.0 /\n&marker body = 'ground', name = 'guide', position = 0.6, 0.0, 0.0 /\n&joint name = 'guide', type = 'prismatic', body1 = 'ground', marker1 = 'guide', body2 = 'mass', marker2 = 'P', axis = 1.0, 0.0, 0.0 /\n&integrator h = 1.0e-3, t_end = 0.01 /\n&model selection = 'manual' /")
set(_torsion_scene "&body name = 'disc', type = 'rigid', mass = 2.0, inertia = 0.01, 0.01, 0.02, 0, 0, 0 /\n&marker body = 'disc', name = 'centre', position = 0.0, 0.0, 0.0 /\n&marker body = 'ground', name = 'hinge', position = 0.0, 0.0, 0.0 /\n&joint name = 'hinge', type = 'revolute', body1 = 'ground', marker1 = 'hinge', body2 = 'disc', marker2 = 'centre', axis = 0.0, 0.0, 1.0 /\n&joint name = 'slide', type = 'prismatic', body1 = 'ground', marker1 = 'hinge', body2 = 'disc', marker2 = 'centre', axis = 0.0, 0.0, 1.0 /\n&integrator h = 1.0e-3, t_end = 0.01 /\n&model selection = 'manual' /")
set(_bushing_scene "&body name = 'block', type = 'rigid', mass = 2.0, inertia = 0.01, 0.02, 0.03, 0, 0, 0 /\n&marker body = 'block', name = 'centre', position = 0.0, 0.0, 0.0 /\n&marker body = 'block', name = 'corner', position = 0.1, 0.0, 0.0 /\n&marker body = 'ground', name = 'base', position = 0.0, 0.0, 0.0 /\n&joint name = 'hinge', type = 'revolute', body1 = 'ground', marker1 = 'base', body2 = 'block', marker2 = 'centre', axis = 0.0, 0.0, 1.0 /\n&integrator h = 1.0e-3, t_end = 0.01 /\n&model selection = 'manual' /")
foreach(_mode run check)
  if(_mode STREQUAL "check")
    set(_extra "--check")
  else()
    set(_extra "")
  endif()
  ffrf_error_case(spring_same_body_${_mode} 2 "spring_same_body_${_mode}\\.nml:8: &spring body2 = .mass.: &spring \"s\": body1 and body2 are both \"mass\"; a spring connects two different bodies"
    "${_spring_scene}\n&spring name = 's', body1 = 'mass', marker1 = 'P', body2 = 'mass', marker2 = 'P', stiffness = 1.0 /" ${_extra})
  ffrf_error_case(spring_unknown_marker_${_mode} 2 "spring_unknown_marker_${_mode}\\.nml:8: .*&spring \"s\": marker \"nowhere\" of body \"ground\" is not defined"
    "${_spring_scene}\n&spring name = 's', body1 = 'ground', marker1 = 'nowhere', body2 = 'mass', marker2 = 'P', stiffness = 1.0 /" ${_extra})
  ffrf_error_case(spring_unknown_body_${_mode} 2 "spring_unknown_body_${_mode}\\.nml:8: .*&spring \"s\": body \"block\" is not a &body of this case"
    "${_spring_scene}\n&spring name = 's', body1 = 'ground', marker1 = 'anchor', body2 = 'block', marker2 = 'P', stiffness = 1.0 /" ${_extra})
  ffrf_error_case(spring_negative_stiffness_${_mode} 2 "spring_negative_stiffness_${_mode}\\.nml:8: &spring stiffness = -1\\.0: out of range"
    "${_spring_scene}\n&spring name = 's', body1 = 'ground', marker1 = 'anchor', body2 = 'mass', marker2 = 'P', stiffness = -1.0 /" ${_extra})
  ffrf_error_case(spring_negative_damping_${_mode} 2 "spring_negative_damping_${_mode}\\.nml:8: &spring damping = -0.5: out of range"
    "${_spring_scene}\n&spring name = 's', body1 = 'ground', marker1 = 'anchor', body2 = 'mass', marker2 = 'P', stiffness = 1.0, damping = -0.5 /" ${_extra})
  ffrf_error_case(spring_zero_length_${_mode} 2 "spring_zero_length_${_mode}\\.nml:8: .*&spring \"s\": its markers coincide at the start \\(length 0\\) and free_length is not given"
    "${_spring_scene}\n&spring name = 's', body1 = 'ground', marker1 = 'guide', body2 = 'mass', marker2 = 'P', stiffness = 1.0 /" ${_extra})
  ffrf_error_case(torsion_not_revolute_${_mode} 2 "torsion_not_revolute_${_mode}\\.nml:8: &torsion_spring \"t\": joint \"slide\" is prismatic; a torsion spring needs a revolute or cylindrical joint"
    "${_torsion_scene}\n&torsion_spring name = 't', joint = 'slide', stiffness = 1.0 /" ${_extra})
  ffrf_error_case(torsion_unknown_joint_${_mode} 2 "torsion_unknown_joint_${_mode}\\.nml:8: &torsion_spring \"t\": joint \"axle\" is not a &joint of this case \\(joints: hinge, slide\\)"
    "${_torsion_scene}\n&torsion_spring name = 't', joint = 'axle', stiffness = 1.0 /" ${_extra})
  ffrf_error_case(torsion_negative_stiffness_${_mode} 2 "torsion_negative_stiffness_${_mode}\\.nml:8: &torsion_spring stiffness = -1\\.0: out of range"
    "${_torsion_scene}\n&torsion_spring name = 't', joint = 'hinge', stiffness = -1.0 /" ${_extra})
  ffrf_error_case(torsion_negative_damping_${_mode} 2 "torsion_negative_damping_${_mode}\\.nml:8: &torsion_spring damping = -0.5: out of range"
    "${_torsion_scene}\n&torsion_spring name = 't', joint = 'hinge', stiffness = 1.0, damping = -0.5 /" ${_extra})
  ffrf_error_case(torsion_sensor_unknown_${_mode} 2 "torsion_sensor_unknown_${_mode}\\.nml:9: &sensor \"s\": spring \"spring\" is not a &torsion_spring of this case \\(torsion_springs: t\\)"
    "${_torsion_scene}\n&torsion_spring name = 't', joint = 'hinge', stiffness = 1.0 /\n&sensor name = 's', type = 'torsion_spring', spring = 'spring' /" ${_extra})
  ffrf_error_case(bushing_same_body_${_mode} 2 "bushing_same_body_${_mode}\\.nml:8: &bushing body2 = .block.: &bushing \"b\": body1 and body2 are both \"block\"; a bushing connects two different bodies"
    "${_bushing_scene}\n&bushing name = 'b', body1 = 'block', marker1 = 'centre', body2 = 'block', marker2 = 'corner', stiffness = 1, 1, 1, 1, 1, 1 /" ${_extra})
  ffrf_error_case(bushing_negative_entry_${_mode} 2 "bushing_negative_entry_${_mode}\\.nml:8: &bushing stiffness.*-1\\.0.*out of range"
    "${_bushing_scene}\n&bushing name = 'b', body1 = 'ground', marker1 = 'base', body2 = 'block', marker2 = 'centre', stiffness = 1, 1, 1, 1, -1.0, 1 /" ${_extra})
  ffrf_error_case(bushing_negative_damping_${_mode} 2 "bushing_negative_damping_${_mode}\\.nml:8: &bushing damping.*-0\\.5.*out of range"
    "${_bushing_scene}\n&bushing name = 'b', body1 = 'ground', marker1 = 'base', body2 = 'block', marker2 = 'centre', damping = -0.5, 0, 0, 0, 0, 0 /" ${_extra})
  ffrf_error_case(bushing_unknown_marker_${_mode} 2 "bushing_unknown_marker_${_mode}\\.nml:8: .*&bushing \"b\": marker \"nowhere\" of body \"ground\" is not defined"
    "${_bushing_scene}\n&bushing name = 'b', body1 = 'ground', marker1 = 'nowhere', body2 = 'block', marker2 = 'centre' /" ${_extra})
  ffrf_error_case(bushing_unknown_body_${_mode} 2 "bushing_unknown_body_${_mode}\\.nml:8: .*&bushing \"b\": body \"crate\" is not a &body of this case"
    "${_bushing_scene}\n&bushing name = 'b', body1 = 'ground', marker1 = 'base', body2 = 'crate', marker2 = 'centre' /" ${_extra})
endforeach()

# regression_springs_flexible: springs at flexible bodies' virtual nodes in the lc 8 mm engine of
# engine.cmake (flexible crank and conrod) to 10 ms: one from a ground point to the conrod's
# small end (free length: the starting distance, with a damper), one from the crank's pin B2 to
# the ground point; the spring sensors against the position sensor of the small end.
set(_springs_out "${PROJECT_BINARY_DIR}/tests/springs")
file(MAKE_DIRECTORY "${_springs_out}")
file(READ "${PROJECT_BINARY_DIR}/tests/engine/engine_lc8_rc1.nml" _flexible_springs)
ffrf_replace(_flexible_springs "t_end = 0.1," "t_end = 0.01,")
string(APPEND _flexible_springs "&marker body = 'ground', name = 'anchor', position = 0.05, 0.25, 0.0 /\n"
  "&spring name = 'small_end_spring', body1 = 'ground', marker1 = 'anchor', body2 = 'conrod', "
  "marker2 = 'small_end', stiffness = 2.0e4, damping = 5.0 /\n"
  "&spring name = 'pin_spring', body1 = 'crank', marker1 = 'B2', body2 = 'ground', "
  "marker2 = 'anchor', stiffness = 1.0e4, free_length = 0.1 /\n"
  "&sensor name = 'small_end_spring', type = 'spring', spring = 'small_end_spring' /\n"
  "&sensor name = 'pin_spring', type = 'spring', spring = 'pin_spring' /\n"
  "&sensor name = 'small_end_position', type = 'position', body = 'conrod', marker = 'small_end' /\n"
  "&sensor name = 'small_end_velocity', type = 'velocity', body = 'conrod', marker = 'small_end' /\n")
file(WRITE "${_springs_out}/engine_flexible_springs.nml" "${_flexible_springs}")
add_test(NAME regression_springs_flexible
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 ${Python3_EXECUTABLE}
    ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_springs.py flexible $<TARGET_FILE:ffrf>
    ${_springs_out}/engine_flexible_springs.nml ${PROJECT_BINARY_DIR}/meshes ${_springs_out})
set_tests_properties(regression_springs_flexible PROPERTIES LABELS "regression;springs"
  FIXTURES_REQUIRED "crank_lc8_mesh;conrod_lc8_mesh")

# The torsion spring-damper (&torsion_spring, src/mbs/torsion_spring.f90; issue 24, item 1):
# regression_torsion_springs: input/torsion_pendulum.nml against the closed-form damped
# torsional oscillator (period, decay, order 2), the energy balance with the damper's
# dissipation and the results file's external work, and a multi-turn undamped run against
# (w/w0) sin(w0 t) (tests/regression/check_torsion_springs.py). About 10 s.
add_test(NAME regression_torsion_springs
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 ${Python3_EXECUTABLE}
    ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_torsion_springs.py $<TARGET_FILE:ffrf>
    ${PROJECT_SOURCE_DIR}/input/torsion_pendulum.nml ${PROJECT_BINARY_DIR}/meshes
    ${PROJECT_BINARY_DIR}/tests/torsion_springs)
set_tests_properties(regression_torsion_springs PROPERTIES LABELS "regression;springs")

# regression_torsion_restart: the multi-turn torsion pendulum wound 2 turns at a restart state,
# continued by --restart, equals the run straight to t_end in every entry, bitwise (the torsion
# springs' unwrapping references are in the restart state, docs/restart.md "Unwrapped angles");
# a restart state without them is refused (tests/regression/check_torsion_restart.py). About 2 s.
add_test(NAME regression_torsion_restart
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 ${Python3_EXECUTABLE}
    ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_torsion_restart.py $<TARGET_FILE:ffrf>
    ${PROJECT_SOURCE_DIR}/input/torsion_pendulum.nml ${PROJECT_BINARY_DIR}/meshes
    ${PROJECT_BINARY_DIR}/tests/torsion_restart)
set_tests_properties(regression_torsion_restart PROPERTIES LABELS "regression;springs")

# The 6-dof bushing (&bushing, src/mbs/bushing.f90; issue 24, item 1): regression_bushings runs
# input/bushing_mass.nml (a block held by a bushing, six directions at once) against the
# closed-form frequencies sqrt(k/m), sqrt(k_r/J_i), amplitudes v0/w, energy conservation and
# the results file's external work (tests/regression/check_bushings.py). About 1 s.
add_test(NAME regression_bushings
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 ${Python3_EXECUTABLE}
    ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_bushings.py $<TARGET_FILE:ffrf>
    ${PROJECT_SOURCE_DIR}/input/bushing_mass.nml ${PROJECT_BINARY_DIR}/meshes
    ${PROJECT_BINARY_DIR}/tests/bushings)
set_tests_properties(regression_bushings PROPERTIES LABELS "regression;springs")

