# &body orientation, velocity and angular_velocity (issue 24, item 1), on the IFToMM A01
# pendulum (input/iftomm_a01_pendulum.nml) against independent references
# (tests/regression/check_pose.py):
#  - the scene rotated by a rotation Q (position, orientation, gravity, hinge axis) swings as Q
#    times the planar run, 1e-12 m at every step of 10 s (measured 1.3e-14 m);
#  - started at the phase 0.4 s of the exact solution with the angular velocity from its energy,
#    it follows the exact elliptic solution to 2.5e-4 m (measured 1.6e-4 m at h = 1e-3 s);
#  - a radial velocity of 0.05 m/s added is projected out, the [assembly] log line saying so,
#    and the run equals the consistent one;
#  - the phase start rotated by Q equals Q times the phase start.
#  - a start 1 mm off the link length is moved back 1 mm, the [assembly] line saying so.
# The input errors of orientation are input_body_orientation_* (input_errors.cmake). About 2 s.
add_test(NAME regression_pose_pendulum
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 ${Python3_EXECUTABLE}
    ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_pose.py $<TARGET_FILE:ffrf>
    ${PROJECT_SOURCE_DIR}/input/iftomm_a01_pendulum.nml ${PROJECT_BINARY_DIR}/meshes
    ${PROJECT_BINARY_DIR}/tests/pose)
set_tests_properties(regression_pose_pendulum PROPERTIES LABELS "regression;pose;iftomm")
#  - regression_pose_flexible: a flexible conrod (4 modes) hinged at its big end and started
#    turning at 2 rad/s (tests/data/pose/flexible_pendulum.nml): the tip's starting velocity is
#    omega x r (1e-12 m/s), and the scene rotated about z by orientation and gravity swings as
#    Q times the unrotated one (1e-12 m; measured 1.3e-16 m). About 3 s.
add_test(NAME regression_pose_flexible
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 ${Python3_EXECUTABLE}
    ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_pose.py flexible $<TARGET_FILE:ffrf>
    ${CMAKE_CURRENT_SOURCE_DIR}/data/pose/flexible_pendulum.nml ${PROJECT_BINARY_DIR}/meshes
    ${PROJECT_BINARY_DIR}/tests/pose_flexible)
set_tests_properties(regression_pose_flexible PROPERTIES LABELS "regression;pose"
  FIXTURES_REQUIRED conrod_lc8_mesh)
#  - regression_pose_engine: the rigid engine (input/engine_rigid.nml, 10 ms) started at 100 rad/s
#    with and without the flywheel's angular_velocity given (the projection with a rotor speed):
#    the conrod's origin starts at omega r = 4.5 m/s, the flywheel's consistent value is kept
#    (< 1e-12 rad/s changed), the crank speeds agree to 1e-12 relative (measured 3.1e-13).
add_test(NAME regression_pose_engine
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 ${Python3_EXECUTABLE}
    ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_pose.py engine $<TARGET_FILE:ffrf>
    ${PROJECT_SOURCE_DIR}/input/engine_rigid.nml ${PROJECT_BINARY_DIR}/meshes
    ${PROJECT_BINARY_DIR}/tests/pose_engine)
set_tests_properties(regression_pose_engine PROPERTIES LABELS "regression;pose" TIMEOUT 300
  FIXTURES_REQUIRED "crank_mesh;conrod_mesh;crank_lc10_mesh;crank_lc8_mesh;conrod_lc8_mesh")
