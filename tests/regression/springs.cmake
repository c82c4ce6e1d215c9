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

# Bad &spring input: one line naming the file, line and group, exit 2, from a run and --check.
set(_spring_scene "&body name = 'mass', type = 'rigid', mass = 1.0, inertia = 1.0e-3, 1.0e-3, 1.0e-3, 0, 0, 0, position = 0.6, 0.0, 0.0 /\n&marker body = 'mass', name = 'P', position = 0.0, 0.0, 0.0 /\n&marker body = 'ground', name = 'anchor', position = 0.0, 0.0, 0.0 /\n&marker body = 'ground', name = 'guide', position = 0.6, 0.0, 0.0 /\n&joint name = 'guide', type = 'prismatic', body1 = 'ground', marker1 = 'guide', body2 = 'mass', marker2 = 'P', axis = 1.0, 0.0, 0.0 /\n&integrator h = 1.0e-3, t_end = 0.01 /\n&model selection = 'manual' /")
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
endforeach()
