# Marker frames (issue 24: joints act between marker frames, so joints at flexible interfaces
# take any axis). The flexible double pendulum of gravity.cmake turned into the x-z plane with
# its meshes left as they were (frames_pendulum_xz.nml: revolute joints about the links' -y
# axis, framed markers at the interfaces); check_frames_pendulum.py compares its angles with
# the x-y scene whose links are turned so that the whole scene is this one turned by -90 deg
# about x (exact invariance), with the unturned x-y run (mesh anisotropy only), with the rigid
# double pendulum, and checks its energy balance and the balance's order in h with a run at
# h/2. About 3 x 3 + 5 s of CPU.
# frames_run(NAME CASE DIR [ARGS...]): the driver on CASE into ${_out}/DIR, one thread,
# setting up frames_pendulum_results
function(frames_run name case dir)
  file(MAKE_DIRECTORY "${_out}/${dir}")
  add_test(NAME ${name}
    COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 $<TARGET_FILE:ffrf>
      ${CMAKE_CURRENT_SOURCE_DIR}/regression/${case} --mesh-dir ${PROJECT_BINARY_DIR}/meshes
      --output-dir ${_out}/${dir} ${ARGN})
  set_tests_properties(${name} PROPERTIES LABELS "regression;mbs"
    FIXTURES_REQUIRED beam_lc6_mesh FIXTURES_SETUP frames_pendulum_results)
endfunction()
add_test(NAME regression_frames_pendulum_check
  COMMAND $<TARGET_FILE:ffrf> ${CMAKE_CURRENT_SOURCE_DIR}/regression/frames_pendulum_xz.nml
    --mesh-dir ${PROJECT_BINARY_DIR}/meshes --output-dir ${_out} --check)
set_tests_properties(regression_frames_pendulum_check PROPERTIES LABELS "regression;mbs"
  FIXTURES_REQUIRED beam_lc6_mesh)
frames_run(regression_frames_pendulum frames_pendulum_xz.nml frames)
frames_run(regression_frames_pendulum_half frames_pendulum_xz.nml frames_half
  --set integrator.h=1.25e-4)
# the x-y scene with both links turned by R_x(-90 deg): frames_pendulum_xz.nml turned as a whole
frames_run(regression_frames_pendulum_posed gravity_double_pendulum.nml frames_posed
  --set "body[link1].orientation=1, 0, 0, 0, 0, 1, 0, -1, 0"
  --set "body[link2].orientation=1, 0, 0, 0, 0, 1, 0, -1, 0")
add_test(NAME regression_frames_pendulum_values
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_frames_pendulum.py
    ${_out}/frames/frames_pendulum_xz.h5 ${_out}/gravity_double_pendulum.h5
    --half ${_out}/frames_half/frames_pendulum_xz.h5
    --posed ${_out}/frames_posed/gravity_double_pendulum.h5)
set_tests_properties(regression_frames_pendulum_values PROPERTIES LABELS "regression;mbs"
  FIXTURES_REQUIRED "frames_pendulum_results;gravity_pendulum_results")
# A &marker orientation that is not a rotation, and a joint axis that is not an oriented
# marker's z axis: one-line input errors naming the place, exit 2, also under --check.
# frames_error(NAME CASE MESSAGE [ARGS...]): the driver's --check on tests/data/frames/CASE
# exits 2 with MESSAGE on one line
function(frames_error name case message)
  set(_command $<TARGET_FILE:ffrf> ${PROJECT_SOURCE_DIR}/tests/data/frames/${case}
    --output-dir ${_out} --check ${ARGN})
  add_test(NAME ${name}
    COMMAND ${CMAKE_COMMAND} "-DCOMMAND=${_command}"
      -DEXIT_CODE=2 "-DMESSAGE=${message}"
      -P ${CMAKE_CURRENT_SOURCE_DIR}/regression/expect_error.cmake)
  set_tests_properties(${name} PROPERTIES LABELS "regression;errors")
endfunction()
frames_error(error_marker_orientation_not_orthonormal bad_marker_orientation.nml
  "bad_marker_orientation.nml:11: &marker orientation = .*: marker \"pivot\" of body \"ground\": the orientation is not orthonormal: largest \\|A A\\^T - I\\| = ")
frames_error(error_marker_orientation_reflection rigid_pendulum_oriented.nml
  "marker \"pivot\" of body \"ground\": the orientation has det = -"
  --set "marker[pivot].orientation=1,0,0,0,0,1,0,1,0")
frames_error(error_joint_axis_not_marker_z rigid_pendulum_oriented.nml
  "&joint \"hinge\": axis = \\(.*\\) is not the z axis \\(.*\\) of &marker \"pivot\" of body \"ground\""
  --set "joint[hinge].axis=0,0,1")
# Joint frames given at both ends that agree (issue 24, docs/mechanisms.md "Joint frames"): the
# rigid pendulum turned as a whole by R_z(30 deg) R_x(40 deg), its rod further by 25 deg about
# its own axis and its end marker oriented back onto the pivot's frame, the inputs rounded to
# 10 decimals (the two frames agree to 9e-11); it runs, and check_joint_frames.py compares its
# motion turned back with the unturned pendulum's. About 1 s.
function(joint_frames_run name dir)
  file(MAKE_DIRECTORY "${_out}/${dir}")
  add_test(NAME ${name}
    COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 $<TARGET_FILE:ffrf>
      ${PROJECT_SOURCE_DIR}/tests/data/frames/rigid_pendulum_oriented.nml
      --output-dir ${_out}/${dir} ${ARGN})
  set_tests_properties(${name} PROPERTIES LABELS "regression;mbs"
    FIXTURES_SETUP joint_frames_results)
endfunction()
joint_frames_run(regression_joint_frames_reference joint_frames_reference)
joint_frames_run(regression_joint_frames_turned joint_frames_turned
  "--set" "mechanism.gravity=-3.1528732255, 5.4609366164, -7.5148959870"
  "--set" "marker[pivot].orientation=0.8660254038, -0.3213938048, -0.3830222216, 0.5, 0.5566703992, 0.6634139482, 0, -0.7660444431, 0.6427876097"
  "--set" "joint[hinge].axis=-0.3830222216, 0.6634139482, 0.6427876097"
  "--set" "body[rod].position=0.4330127019, 0.25, 0"
  "--set" "body[rod].orientation=0.8660254038, -0.2113091309, 0.4531538935, 0.5, 0.3659981508, -0.7848855672, 0, 0.9063077870, 0.4226182617"
  "--set" "marker[end].orientation=1, 0, 0, 0, -0.4226182617, 0.9063077870, 0, -0.9063077870, -0.4226182617")
add_test(NAME regression_joint_frames_agree
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_joint_frames.py
    ${_out}/joint_frames_reference/rigid_pendulum_oriented.h5
    ${_out}/joint_frames_turned/rigid_pendulum_oriented.h5)
set_tests_properties(regression_joint_frames_agree PROPERTIES LABELS "regression;mbs"
  FIXTURES_REQUIRED joint_frames_results)

# A flexible interface's own &marker orientation (issue 24, docs/mechanisms.md "Joint frames"),
# compared by check_iface_orient.py: (1) frames_pendulum_xz.nml with its joint frames given at
# the links' interfaces (the axis frame turned by 90 deg about the joint axis) against the axis
# run; (2) a universal joint between two interfaces, its cross arms turned by 45 deg about the
# shafts (only the interfaces' orientation can say so), against the scene turned as a whole by
# R_x(-45 deg) with the elbow's frame from its axis, and against the same scene with the axis
# frame at the interfaces (it must move otherwise). About 5 x 1.3 s.
# iface_orient_run(NAME CASE DIR [ARGS...]): the driver on tests/data/frames/CASE into
# ${_out}/DIR, one thread, setting up iface_orient_results
function(iface_orient_run name case dir)
  file(MAKE_DIRECTORY "${_out}/${dir}")
  add_test(NAME ${name}
    COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 $<TARGET_FILE:ffrf>
      ${PROJECT_SOURCE_DIR}/tests/data/frames/${case} --mesh-dir ${PROJECT_BINARY_DIR}/meshes
      --output-dir ${_out}/${dir} ${ARGN})
  set_tests_properties(${name} PROPERTIES LABELS "regression;mbs"
    FIXTURES_REQUIRED beam_lc6_mesh FIXTURES_SETUP iface_orient_results)
endfunction()
iface_orient_run(regression_iface_orient_pendulum flexible_pendulum_iface_oriented.nml iface_orient)
iface_orient_run(regression_iface_orient_universal universal_pendulum_iface.nml iface_orient)
iface_orient_run(regression_iface_orient_universal_turned universal_pendulum_turned.nml iface_orient)
iface_orient_run(regression_iface_orient_universal_plain universal_pendulum_iface.nml
  iface_orient_plain --set "marker[end1].orientation=0, 0, 1, 1, 0, 0, 0, 1, 0"
  --set "marker[end0].orientation=0, 0, 1, 1, 0, 0, 0, 1, 0")
add_test(NAME regression_iface_orient_check
  COMMAND $<TARGET_FILE:ffrf> ${PROJECT_SOURCE_DIR}/tests/data/frames/universal_pendulum_iface.nml
    --mesh-dir ${PROJECT_BINARY_DIR}/meshes --output-dir ${_out}/iface_orient --check)
set_tests_properties(regression_iface_orient_check PROPERTIES LABELS "regression;mbs"
  FIXTURES_REQUIRED beam_lc6_mesh)
add_test(NAME regression_iface_orient_pendulum_agree
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_iface_orient.py
    ${_out}/frames/frames_pendulum_xz.h5
    ${_out}/iface_orient/flexible_pendulum_iface_oriented.h5)
set_tests_properties(regression_iface_orient_pendulum_agree PROPERTIES LABELS "regression;mbs"
  FIXTURES_REQUIRED "frames_pendulum_results;iface_orient_results")
add_test(NAME regression_iface_orient_universal_agree
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_iface_orient.py
    --turned ${_out}/iface_orient/universal_pendulum_turned.h5
    ${_out}/iface_orient/universal_pendulum_iface.h5
    --plain ${_out}/iface_orient_plain/universal_pendulum_iface.h5)
set_tests_properties(regression_iface_orient_universal_agree PROPERTIES LABELS "regression;mbs"
  FIXTURES_REQUIRED iface_orient_results)
