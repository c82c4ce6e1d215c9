# Error paths of the driver: each bad input gives a one-line "ffrf: error: ..." naming the file,
# group, key or entity, and the documented exit code (2 input, 3 file, 1 command line).
# The cases are small namelist files written here; they use the crank_lc8 mesh fixture.
set(_dir "${PROJECT_BINARY_DIR}/tests/error_cases")
file(MAKE_DIRECTORY "${_dir}")
set(_body "&body name = 'crank', mesh_file = 'crank_lc8.msh', volumes = 'crank' /")
set(_iface "&interface body = 'crank', name = 'B2', rc = 'Tx Ty Tz Rx Ry Rz' /")

# ffrf_error_case(<name> <exit code> <message regex> <case text> [extra driver args])
function(ffrf_error_case name code regex text)
  file(WRITE "${_dir}/${name}.nml" "${text}\n")
  add_test(NAME error_${name}
    COMMAND ${CMAKE_COMMAND}
      "-DCOMMAND=$<TARGET_FILE:ffrf>;${_dir}/${name}.nml;--mesh-dir;${PROJECT_BINARY_DIR}/meshes;--output-dir;${_dir};${ARGN}"
      -DEXIT_CODE=${code} "-DMESSAGE=${regex}" -P ${CMAKE_CURRENT_SOURCE_DIR}/regression/expect_error.cmake)
  set_tests_properties(error_${name} PROPERTIES LABELS "regression;errors"
    FIXTURES_REQUIRED crank_lc8_mesh)
endfunction()

ffrf_error_case(unknown_key 2 "unknown_key\\.nml:3: &modes num_modez = 4: unknown key" "${_body}\n${_iface}\n&modes num_modez = 4 /")
ffrf_error_case(unknown_group 2 "unknown namelist group &mode;" "${_body}\n${_iface}\n&mode num_modes = 4 /")
ffrf_error_case(missing_body 2 "no &body group" "${_iface}")
ffrf_error_case(poisson_range 2 "poisson_range\\.nml:1: &body poisson = 0.5: out of range. give a finite real in \\(-1, 0.5\\)"
  "&body name = 'crank', mesh_file = 'crank_lc8.msh', poisson = 0.5 /\n${_iface}")
ffrf_error_case(num_modes_range 2 "num_modes = 0" "${_body}\n${_iface}\n&modes num_modes = 0 /")
ffrf_error_case(bad_rc_dof 2 "unknown dof \"tw\"" "${_body}\n&interface body = 'crank', name = 'B2', rc = 'Tx Tw' /")
ffrf_error_case(bad_mpc 2 "bad_mpc\\.nml:2: &interface mpc = 'RBE4': not allowed. mpc is one of RBE2, RBE3" "${_body}\n&interface body = 'crank', name = 'B2', mpc = 'RBE4' /")
ffrf_error_case(unknown_interface_body 2 "body \"crnk\" is not a &body" "${_body}\n&interface body = 'crnk', name = 'B2' /")
ffrf_error_case(missing_mesh 3 "no_such_mesh.msh"
  "&body name = 'crank', mesh_file = 'no_such_mesh.msh' /\n${_iface}")
ffrf_error_case(missing_volume 2 "no physical volume .crnk."
  "&body name = 'crank', mesh_file = 'crank_lc8.msh', volumes = 'crnk' /\n${_iface}")
ffrf_error_case(missing_surface 2 "B4" "${_body}\n&interface body = 'crank', name = 'B4', rc = '123456' /")
ffrf_error_case(free_rotation 2 "rigid-body motion.*rotation about an axis along \\(0, 0, 1\\)"
  "${_body}\n&interface body = 'crank', name = 'B1', rc = 'Tx Ty Tz' /\n&interface body = 'crank', name = 'B3', rc = 'Tx Ty' /")
# &modes max_frequency_hz and sturm_check (issue 22)
ffrf_error_case(max_frequency_range 2 "max_frequency_range\\.nml:3: &modes max_frequency_hz = -5: out of range. give a finite real in \\[0, 1E\\+09\\] Hz"
  "${_body}\n${_iface}\n&modes max_frequency_hz = -5 /")
ffrf_error_case(max_frequency_positive_shift 2 "max_frequency_positive_shift\\.nml:3: &modes shift_hz = 100 Hz cannot go with max_frequency_hz = 20000 Hz.*give shift_hz <= 0"
  "${_body}\n${_iface}\n&modes max_frequency_hz = 20000, shift_hz = 100 /")
ffrf_error_case(max_frequency_without_sturm 2 "max_frequency_without_sturm\\.nml:3: &modes sturm_check = .false. cannot go with max_frequency_hz = 20000 Hz"
  "${_body}\n${_iface}\n&modes max_frequency_hz = 20000, sturm_check = .false. /")
ffrf_error_case(max_frequency_below_first_mode 2 "no mode below the upper bound 100 Hz.*counts 0 eigenvalues below it; raise max_frequency_hz above the first mode"
  "${_body}\n${_iface}\n&modes max_frequency_hz = 100 /")
ffrf_error_case(missing_case 3 "case file \".*missing_case\\.nml\" does not exist" "" )
file(REMOVE "${_dir}/missing_case.nml")
ffrf_error_case(bad_option 1 "unknown option --frobnicate" "${_body}\n${_iface}" --frobnicate)
ffrf_error_case(inverted_element 2 "mesh .*inverted_tet.msh.*tetrahedron 3 is inverted"
  "&body name = 'block', mesh_file = '${PROJECT_SOURCE_DIR}/tests/data/regression/inverted_tet.msh' /\n&interface body = 'block', name = 'face', rc = '123456' /")

# Mechanism input (a case with &joint groups): a rigid arm on a revolute to the ground
set(_arm "&body name = 'arm', type = 'rigid', mass = 1.0, inertia = 0.01, 0.01, 0.01, 0, 0, 0 /
&marker body = 'arm', name = 'hinge', position = 0, 0, 0 /
&marker body = 'ground', name = 'hinge', position = 0, 0, 0 /")
set(_pivot "&joint name = 'pivot', type = 'revolute', body1 = 'ground', marker1 = 'hinge', body2 = 'arm', marker2 = 'hinge' /")
ffrf_error_case(joint_unknown_body 2 "&joint \"pivot\": body \"arn\" is not a &body"
  "${_arm}\n&joint name = 'pivot', type = 'revolute', body1 = 'ground', marker1 = 'hinge', body2 = 'arn', marker2 = 'hinge' /")
ffrf_error_case(joint_missing_interface 2 "&joint \"bearing\": body \"crank\" has no interface \"B4\""
  "${_body}\n${_iface}\n&marker body = 'ground', name = 'axis', position = 0, 0, 0 /\n&joint name = 'bearing', type = 'revolute', body1 = 'ground', marker1 = 'axis', body2 = 'crank', marker2 = 'B4' /")
ffrf_error_case(rigid_inertia_not_positive 2 "\"arm\": the inertia .* is not positive definite"
  "${_pivot}\n&body name = 'arm', type = 'rigid', mass = 1.0, inertia = 0.01, 0.01, 0.01, 0.02, 0, 0 /\n&marker body = 'arm', name = 'hinge', position = 0, 0, 0 /\n&marker body = 'ground', name = 'hinge', position = 0, 0, 0 /")
ffrf_error_case(rigid_mass_zero 2 "\"arm\": rigid body mass = 0 kg"
  "${_pivot}\n&body name = 'arm', type = 'rigid', inertia = 0.01, 0.01, 0.01, 0, 0, 0 /\n&marker body = 'arm', name = 'hinge', position = 0, 0, 0 /")
ffrf_error_case(joint_undefined_marker 2 "marker \"tip\" of body \"arm\" is not defined"
  "${_arm}\n&joint name = 'pivot', type = 'revolute', body1 = 'ground', marker1 = 'hinge', body2 = 'arm', marker2 = 'tip' /")
ffrf_error_case(joint_bad_type 2 "joint_bad_type\\.nml:4: &joint type = 'hinge': not allowed. type is one of revolute"
  "${_arm}\n&joint name = 'pivot', type = 'hinge', body1 = 'ground', marker1 = 'hinge', body2 = 'arm', marker2 = 'hinge' /")
# a partial word (the readers' old substring check let 'cyl' through to the model) and a misuse
# of the cylindrical joint: a &driver on it (drivers take revolute and prismatic joints)
ffrf_error_case(joint_partial_type 2 "joint_partial_type\\.nml:4: &joint type = 'cyl': not allowed. type is one of revolute, prismatic, spherical, universal, fixed, cylindrical"
  "${_arm}\n&joint name = 'pivot', type = 'cyl', body1 = 'ground', marker1 = 'hinge', body2 = 'arm', marker2 = 'hinge' /")
ffrf_error_case(driver_on_cylindrical 2 "driver_on_cylindrical\\.nml:5: &driver \"m\": joint \"sleeve\" is cylindrical; a driver needs a revolute or prismatic joint"
  "${_arm}\n&joint name = 'sleeve', type = 'cylindrical', body1 = 'ground', marker1 = 'hinge', body2 = 'arm', marker2 = 'hinge' /\n&driver name = 'm', joint = 'sleeve', law = 'constant_speed', speed = 1.0 /")
ffrf_error_case(load_needs_crank 2 "&load \"starter\" \\(starter\\) depends on the crank"
  "${_arm}\n${_pivot}\n&load name = 'starter', type = 'starter', body = 'arm', marker = 'hinge' /")
ffrf_error_case(integrator_rho 2 "integrator_rho\\.nml:5: &integrator rho_inf = 1.5: out of range. give a finite real in \\[0, 1\\]"
  "${_arm}\n${_pivot}\n&integrator rho_inf = 1.5 /")
file(WRITE "${_dir}/bad_table.txt" "# angle_deg pressure_pa\n0 1.0e5\n90 1.0e5\nninety 2.0e5\n")
ffrf_error_case(pressure_table_line 2 "table_file .*bad_table.txt\", line 4: expected two numbers"
  "${_arm}\n${_pivot}\n&mechanism crank = 'arm' /\n&load name = 'gas', type = 'pressure', body = 'arm', marker = 'hinge' /\n&pressure table_file = '${_dir}/bad_table.txt' /")
ffrf_error_case(pressure_table_missing 3 "&pressure table_file .*no_such_table.txt"
  "${_arm}\n${_pivot}\n&mechanism crank = 'arm' /\n&load name = 'gas', type = 'pressure', body = 'arm', marker = 'hinge' /\n&pressure table_file = 'no_such_table.txt' /")
# Geometric stiffness (docs/validation.md "FFRF limits"): only for flexible bodies, and only for a
# body held by reference conditions (the centrifugal load of a free-free body is not in equilibrium)
ffrf_error_case(rigid_geometric_stiffness 2 "geometric_stiffness = .true. needs a flexible body"
  "&body name = 'crank', mesh_file = 'crank_lc8.msh', volumes = 'crank', type = 'rigid', geometric_stiffness = .true. /\n${_iface}")
ffrf_error_case(free_free_geometric_stiffness 2 "geometric stiffness needs reference conditions"
  "&body name = 'crank', mesh_file = 'crank_lc8.msh', volumes = 'crank', num_modes = 2, geometric_stiffness = .true. /\n&interface body = 'crank', name = 'B2' /\n&marker body = 'ground', name = 'pin', position = 0, 0.045, 0 /\n&joint name = 'pin', type = 'spherical', body1 = 'ground', marker1 = 'pin', body2 = 'crank', marker2 = 'B2' /")
ffrf_error_case(bad_basis 2 "bad_basis\\.nml:3: &modes basis = 'guyan': not allowed. basis is one of rc_normal, craig_bampton" "${_body}\n${_iface}\n&modes basis = 'guyan' /")

# &model (the automatic model): a bad selection and a target out of range
ffrf_error_case(model_selection 2 "model_selection\\.nml:5: &model selection = 'automatic': not allowed. selection is one of auto, manual"
  "${_arm}\n${_pivot}\n&model selection = 'automatic' /")
ffrf_error_case(model_tolerance 2 "model_tolerance\\.nml:5: &model force_tolerance = 0.0: out of range. give a finite real in \\(0, 1\\)"
  "${_arm}\n${_pivot}\n&model force_tolerance = 0.0 /")

# Markers at mesh points (&marker node, group; docs/mechanisms.md "Markers at mesh points"): a
# crank held at B2 by a fixed joint, a marker at a node or at a physical group (surface, curve,
# point)
set(_held "&body name = 'crank', mesh_file = 'crank_lc8.msh', volumes = 'crank', num_modes = 2 /
${_iface}
&marker body = 'ground', name = 'pin', position = 0, 0.045, 0 /
&joint name = 'pin', type = 'fixed', body1 = 'ground', marker1 = 'pin', body2 = 'crank', marker2 = 'B2' /")
set(_push "&load name = 'push', type = 'force', body = 'crank', marker = 'P', direction = 0, 1, 0, value = 1 /")
ffrf_error_case(marker_node_unknown 2 "&body \"crank\": &marker \"P\": node = 99999999 is not a node of the body's mesh"
  "${_held}\n&marker body = 'crank', name = 'P', node = 99999999 /\n${_push}")
ffrf_error_case(marker_node_unknown_check 2 "&body \"crank\": &marker \"P\": node = 99999999 is not a node of the body's mesh"
  "${_held}\n&marker body = 'crank', name = 'P', node = 99999999 /\n${_push}" --check)
ffrf_error_case(marker_group_unknown_check 2 "&marker \"P\": group = 'B9' is not a physical surface, curve or point of the body's mesh"
  "${_held}\n&marker body = 'crank', name = 'P', group = 'B9' /\n${_push}" --check)
ffrf_error_case(marker_node_rigid 2 "marker_node_rigid\\.nml:4: &marker \"tip\": body \"arm\" is rigid; node and group place a marker on a flexible body's mesh"
  "${_arm}\n&marker body = 'arm', name = 'tip', node = 5 /\n${_pivot}")
ffrf_error_case(marker_group_ground 2 "&marker \"floor\": the ground has no mesh"
  "${_arm}\n&marker body = 'ground', name = 'floor', group = 'B1' /\n${_pivot}")
ffrf_error_case(marker_node_and_group 2 "marker_node_and_group\\.nml.*marker \"P\" of body \"crank\" gives node and group; give one"
  "${_held}\n&marker body = 'crank', name = 'P', node = 5, group = 'B1' /")
ffrf_error_case(marker_flexible_unplaced 2 "&marker \"P\": body \"crank\" has a mesh; place the marker by node = <a node tag> or group"
  "${_held}\n&marker body = 'crank', name = 'P', position = 0, 0, 0 /")
ffrf_error_case(marker_joint_at_point 2 "&joint \"hold\": marker \"P\" of the flexible body \"crank\" is a node or group marker .*declare the group as an &interface and join there"
  "${_held}\n&marker body = 'crank', name = 'P', group = 'B1' /\n&marker body = 'ground', name = 'q', position = 0, 0, 0 /\n&joint name = 'hold', type = 'spherical', body1 = 'ground', marker1 = 'q', body2 = 'crank', marker2 = 'P' /" --check)
ffrf_error_case(marker_weighting_word 2 "marker_weighting_word\\.nml:5: &marker weighting = 'areas': not allowed. weighting is one of uniform, area, area_consistent"
  "${_held}\n&marker body = 'crank', name = 'P', group = 'B1', weighting = 'areas' /\n${_push}" --check)
ffrf_error_case(marker_weighting_at_node 2 "marker_weighting_at_node\\.nml:5: &marker weighting = 'area': marker \"P\" of body \"crank\" is at node 5, where weighting .* means nothing; drop weighting"
  "${_held}\n&marker body = 'crank', name = 'P', node = 5, weighting = 'area' /\n${_push}" --check)
ffrf_error_case(marker_node_coarse_meshes 2 "marker_node_coarse_meshes\\.nml:5: &marker \"P\": body \"crank\" has coarse_meshes, whose node tags are other points"
  "&body name = 'crank', mesh_file = 'crank_lc8.msh', volumes = 'crank', coarse_meshes = 'crank_lc10.msh' /\n${_iface}\n&marker body = 'ground', name = 'pin', position = 0, 0.045, 0 /\n&joint name = 'pin', type = 'fixed', body1 = 'ground', marker1 = 'pin', body2 = 'crank', marker2 = 'B2' /\n&marker body = 'crank', name = 'P', node = 5 /\n${_push}" --check)
# Joint frames that disagree in the starting pose (issue 24): both markers of a joint carry a
# &marker orientation, the frames (turned by their &body orientations) checked in the given
# poses to 1e-6 rad in what the joint locks; the run and --check refuse alike. The arm's frame
# is the ground's turned by 90 deg about x (z axes apart by pi/2 = 1.571 rad), or by 1e-3 rad
# about z (z axes equal: a revolute takes it, a prismatic, fixed or universal joint does not).
set(_framed "&body name = 'arm', type = 'rigid', mass = 1.0, inertia = 0.01, 0.01, 0.01, 0, 0, 0 /
&marker body = 'ground', name = 'hinge', position = 0, 0, 0, orientation = 1, 0, 0, 0, 1, 0, 0, 0, 1 /")
set(_tilted "&marker body = 'arm', name = 'hinge', position = 0, 0, 0, orientation = 1, 0, 0, 0, 0, -1, 0, 1, 0 /")
set(_twisted "&marker body = 'arm', name = 'hinge', position = 0, 0, 0, orientation = 0.9999995, -0.001, 0, 0.001, 0.9999995, 0, 0, 0, 1 /")
set(_framed_joint "body1 = 'ground', marker1 = 'hinge', body2 = 'arm', marker2 = 'hinge' /")
foreach(_mode run check)
  if(_mode STREQUAL "check")
    set(_args --check)
  else()
    set(_args)
  endif()
  ffrf_error_case(joint_frames_revolute_${_mode} 2 "&joint \"pivot\" \\(revolute\\): the frames of its markers \"hinge\" \\(body \"ground\"\\) and \"hinge\" \\(body \"arm\"\\) disagree in the starting pose: their z axes are 1\\.57 rad apart \\(more than 1E-06 rad\\); give the two &marker orientations"
    "${_framed}\n${_tilted}\n&joint name = 'pivot', type = 'revolute', ${_framed_joint}" ${_args})
  ffrf_error_case(joint_frames_prismatic_${_mode} 2 "&joint \"slide\" \\(prismatic\\): .* their frames are 0\\.001 rad apart"
    "${_framed}\n${_twisted}\n&joint name = 'slide', type = 'prismatic', ${_framed_joint}" ${_args})
endforeach()
ffrf_error_case(joint_frames_fixed_check 2 "&joint \"weld\" \\(fixed\\): .* their frames are 0\\.001 rad apart"
  "${_framed}\n${_twisted}\n&joint name = 'weld', type = 'fixed', ${_framed_joint}" --check)
ffrf_error_case(joint_frames_cylindrical_check 2 "&joint \"sleeve\" \\(cylindrical\\): .* their z axes are 1\\.57 rad apart"
  "${_framed}\n${_tilted}\n&joint name = 'sleeve', type = 'cylindrical', ${_framed_joint}" --check)
ffrf_error_case(joint_frames_universal_check 2 "&joint \"cardan\" \\(universal\\): .* their cross arms x1, y2 \\(off perpendicular\\) are 0\\.001 rad apart"
  "${_framed}\n${_twisted}\n&joint name = 'cardan', type = 'universal', ${_framed_joint}" --check)
# A flexible interface's own &marker orientation (docs/mechanisms.md "Joint frames"): a &marker
# named as the crank's interface B2 orients it; its virtual node places it (a position is
# refused), it must be a rotation, and it must agree with the other end's frame at a joint
# (B2 tilted by 90 deg about x against the framed ground pin: run and --check alike).
set(_b2_tilted "&marker body = 'crank', name = 'B2', orientation = 1, 0, 0, 0, 0, -1, 0, 1, 0 /")
set(_pin_framed "&marker body = 'ground', name = 'pin', position = 0, 0.045, 0, orientation = 1, 0, 0, 0, 1, 0, 0, 0, 1 /
&joint name = 'pin', type = 'revolute', body1 = 'ground', marker1 = 'pin', body2 = 'crank', marker2 = 'B2' /")
set(_iface_frames_msg "&joint \"pin\" \\(revolute\\): the frames of its markers \"pin\" \\(body \"ground\"\\) and \"B2\" \\(body \"crank\"\\) disagree in the starting pose: their z axes are 1\\.57 rad apart")
ffrf_error_case(iface_orient_frames_run 2 "${_iface_frames_msg}" "${_body}\n${_iface}\n${_b2_tilted}\n${_pin_framed}")
ffrf_error_case(iface_orient_frames_check 2 "${_iface_frames_msg}" "${_body}\n${_iface}\n${_b2_tilted}\n${_pin_framed}" --check)
ffrf_error_case(iface_orient_position_check 2 "iface_orient_position_check\\.nml:4: &marker \"B2\": the &interface of that name on body \"crank\" is placed by its virtual node; drop the position"
  "${_body}\n${_iface}\n&marker body = 'ground', name = 'pin', position = 0, 0.045, 0 /\n&marker body = 'crank', name = 'B2', position = 0, 0, 0.01, orientation = 1, 0, 0, 0, 1, 0, 0, 0, 1 /\n&joint name = 'pin', type = 'fixed', body1 = 'ground', marker1 = 'pin', body2 = 'crank', marker2 = 'B2' /" --check)
ffrf_error_case(iface_orient_unoriented_check 2 "&marker \"B2\": body \"crank\" has an &interface of that name, which the marker can only orient; give its orientation"
  "${_held}\n&marker body = 'crank', name = 'B2' /" --check)
ffrf_error_case(iface_orient_not_orthonormal_check 2 "iface_orient_not_orthonormal_check\\.nml:[0-9]+: &marker orientation = .*: marker \"B2\" of body \"crank\": the orientation is not orthonormal"
  "${_held}\n&marker body = 'crank', name = 'B2', orientation = 1, 0, 0, 0, 1, 0, 0, 0, 1.1 /" --check)
