# Marker frames (issue 24: joints act between marker frames, so joints at flexible interfaces
# take any axis). The flexible double pendulum of gravity.cmake turned into the x-z plane with
# its meshes left as they were (frames_pendulum_xz.nml: revolute joints about the links' -y
# axis, framed markers at the interfaces); check_frames_pendulum.py compares its angles with
# the x-y scene whose links are turned so that the whole scene is this one turned by -90 deg
# about x (exact invariance), with the unturned x-y run (mesh anisotropy only), with the rigid
# double pendulum, and checks its energy balance and the balance's order in h with a run at
# h/2. About 3 x 3 + 5 s of CPU.
add_test(NAME regression_frames_pendulum_check
  COMMAND $<TARGET_FILE:ffrf> ${CMAKE_CURRENT_SOURCE_DIR}/regression/frames_pendulum_xz.nml
    --mesh-dir ${PROJECT_BINARY_DIR}/meshes --output-dir ${_out} --check)
set_tests_properties(regression_frames_pendulum_check PROPERTIES LABELS "regression;mbs"
  FIXTURES_REQUIRED beam_lc6_mesh)
add_test(NAME regression_frames_pendulum
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 $<TARGET_FILE:ffrf>
    ${CMAKE_CURRENT_SOURCE_DIR}/regression/frames_pendulum_xz.nml
    --mesh-dir ${PROJECT_BINARY_DIR}/meshes --output-dir ${_out})
set_tests_properties(regression_frames_pendulum PROPERTIES LABELS "regression;mbs"
  FIXTURES_REQUIRED beam_lc6_mesh FIXTURES_SETUP frames_pendulum_results)
file(MAKE_DIRECTORY "${_out}/frames_half")
add_test(NAME regression_frames_pendulum_half
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 $<TARGET_FILE:ffrf>
    ${CMAKE_CURRENT_SOURCE_DIR}/regression/frames_pendulum_xz.nml
    --mesh-dir ${PROJECT_BINARY_DIR}/meshes --output-dir ${_out}/frames_half
    --set integrator.h=1.25e-4)
set_tests_properties(regression_frames_pendulum_half PROPERTIES LABELS "regression;mbs"
  FIXTURES_REQUIRED beam_lc6_mesh FIXTURES_SETUP frames_pendulum_results)
# the x-y scene with both links turned by R_x(-90 deg): frames_pendulum_xz.nml turned as a whole
file(MAKE_DIRECTORY "${_out}/frames_posed")
add_test(NAME regression_frames_pendulum_posed
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 $<TARGET_FILE:ffrf>
    ${CMAKE_CURRENT_SOURCE_DIR}/regression/gravity_double_pendulum.nml
    --mesh-dir ${PROJECT_BINARY_DIR}/meshes --output-dir ${_out}/frames_posed
    --set "body[link1].orientation=1, 0, 0, 0, 0, 1, 0, -1, 0"
    --set "body[link2].orientation=1, 0, 0, 0, 0, 1, 0, -1, 0")
set_tests_properties(regression_frames_pendulum_posed PROPERTIES LABELS "regression;mbs"
  FIXTURES_REQUIRED beam_lc6_mesh FIXTURES_SETUP frames_pendulum_results)
add_test(NAME regression_frames_pendulum_values
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_frames_pendulum.py
    ${_out}/frames_pendulum_xz.h5 ${_out}/gravity_double_pendulum.h5
    --half ${_out}/frames_half/frames_pendulum_xz.h5
    --posed ${_out}/frames_posed/gravity_double_pendulum.h5)
set_tests_properties(regression_frames_pendulum_values PROPERTIES LABELS "regression;mbs"
  FIXTURES_REQUIRED "frames_pendulum_results;gravity_pendulum_results")
# A &marker orientation that is not a rotation, and a joint axis that is not an oriented
# marker's z axis: one-line input errors naming the place, exit 2, also under --check
add_test(NAME error_marker_orientation_not_orthonormal
  COMMAND ${CMAKE_COMMAND}
    "-DCOMMAND=$<TARGET_FILE:ffrf>;${PROJECT_SOURCE_DIR}/tests/data/frames/bad_marker_orientation.nml;--output-dir;${_out};--check"
    -DEXIT_CODE=2 "-DMESSAGE=bad_marker_orientation.nml:11: &marker orientation = .*: marker \"pivot\" of body \"ground\": the orientation is not orthonormal: largest \\|A A\\^T - I\\| = "
    -P ${CMAKE_CURRENT_SOURCE_DIR}/regression/expect_error.cmake)
set_tests_properties(error_marker_orientation_not_orthonormal PROPERTIES LABELS "regression;errors")
add_test(NAME error_marker_orientation_reflection
  COMMAND ${CMAKE_COMMAND}
    "-DCOMMAND=$<TARGET_FILE:ffrf>;${PROJECT_SOURCE_DIR}/tests/data/frames/rigid_pendulum_oriented.nml;--output-dir;${_out};--check;--set;marker[pivot].orientation=1,0,0,0,0,1,0,1,0"
    -DEXIT_CODE=2 "-DMESSAGE=marker \"pivot\" of body \"ground\": the orientation has det = -"
    -P ${CMAKE_CURRENT_SOURCE_DIR}/regression/expect_error.cmake)
set_tests_properties(error_marker_orientation_reflection PROPERTIES LABELS "regression;errors")
add_test(NAME error_joint_axis_not_marker_z
  COMMAND ${CMAKE_COMMAND}
    "-DCOMMAND=$<TARGET_FILE:ffrf>;${PROJECT_SOURCE_DIR}/tests/data/frames/rigid_pendulum_oriented.nml;--output-dir;${_out};--check;--set;joint[hinge].axis=0,0,1"
    -DEXIT_CODE=2 "-DMESSAGE=&joint \"hinge\": axis = \\(.*\\) is not the z axis \\(.*\\) of &marker \"pivot\" of body \"ground\""
    -P ${CMAKE_CURRENT_SOURCE_DIR}/regression/expect_error.cmake)
set_tests_properties(error_joint_axis_not_marker_z PROPERTIES LABELS "regression;errors")
