# Strict input (issue 10, part 3): every bad input ends with exit 2 (input) or 3 (file) and ONE
# line "ffrf: error: FILE:LINE: &group key = value: what is wrong, what is allowed" in our words.
# The cases run the real driver (no --check) so that each fails on a solver that lets the input
# slip through (0 steps reported complete, a run that never ends, a compiler runtime message).
set(_in "${PROJECT_BINARY_DIR}/tests/input_errors")
file(MAKE_DIRECTORY "${_in}")
set(_crank "&body name = 'crank', mesh_file = 'crank_lc8.msh', volumes = 'crank' /")
set(_b2 "&interface body = 'crank', name = 'B2', rc = 'Tx Ty Tz Rx Ry Rz' /")
# a rigid arm on a revolute to the ground: 4 lines, so a 5th line is line 5
set(_arm "&body name = 'arm', type = 'rigid', mass = 1.0, inertia = 0.01, 0.01, 0.01, 0, 0, 0 /
&marker body = 'arm', name = 'hinge', position = 0, 0, 0 /
&marker body = 'ground', name = 'hinge', position = 0, 0, 0 /
&joint name = 'pivot', type = 'revolute', body1 = 'ground', marker1 = 'hinge', body2 = 'arm', marker2 = 'hinge' /")
set(_expect "${CMAKE_CURRENT_SOURCE_DIR}/regression/expect_input.cmake")

# ffrf_input_case(<name> <exit code> <message regex> <case text> [extra driver args])
function(ffrf_input_case name code regex text)
  file(WRITE "${_in}/${name}.nml" "${text}\n")
  add_test(NAME input_${name}
    COMMAND ${CMAKE_COMMAND}
      "-DCOMMAND=$<TARGET_FILE:ffrf>;${_in}/${name}.nml;--mesh-dir;${PROJECT_BINARY_DIR}/meshes;--output-dir;${_in};${ARGN}"
      -DEXIT_CODE=${code} "-DMESSAGE=${regex}" -P ${_expect})
  set_tests_properties(input_${name} PROPERTIES LABELS "regression;errors;input"
    FIXTURES_REQUIRED crank_lc8_mesh TIMEOUT 30 ENVIRONMENT OPENBLAS_NUM_THREADS=1)
endfunction()

# Namelist structure
ffrf_input_case(group_not_closed 2 "group_not_closed\\.nml:3: &modes: not closed by '/'"
  "${_crank}\n${_b2}\n&modes num_modes = 4\n&run title = 'x' /")
ffrf_input_case(group_not_closed_at_end 2 "group_not_closed_at_end\\.nml:3: &modes: not closed by '/' \\(end of the file"
  "${_crank}\n${_b2}\n&modes num_modes = 4")
ffrf_input_case(second_single_group 2 "second_single_group\\.nml:4: &modes: a second &modes group \\(the first is on line 3\\)"
  "${_crank}\n${_b2}\n&modes num_modes = 4 /\n&modes num_modes = 5 /")
ffrf_input_case(text_after_slash 2 "text_after_slash\\.nml:3: &modes: text after the closing '/': \"num_modes = 5\""
  "${_crank}\n${_b2}\n&modes num_modes = 4 / num_modes = 5")
ffrf_input_case(repeated_key 2 "repeated_key\\.nml:3: &modes num_modes = 5: given twice in this group"
  "${_crank}\n${_b2}\n&modes num_modes = 4, num_modes = 5 /")
ffrf_input_case(text_outside_group 2 "text_outside_group\\.nml:2: text outside a namelist group: \"num_modes = 4\""
  "${_crank}\nnum_modes = 4\n${_b2}")
string(REPEAT " " 600 _blanks)
ffrf_input_case(long_line 2 "long_line\\.nml:3: &modes num_modez = 4: unknown key. the keys of &modes are num_modes"
  "${_crank}\n${_b2}\n&modes ${_blanks}num_modez = 4 /")
ffrf_input_case(empty_value 2 "empty_value\\.nml:2: &interface position = 1,: an empty value"
  "${_crank}\n&interface body = 'crank', name = 'B2', virtual_node = 'position', position = 1,, 0 /")
ffrf_input_case(array_element 2 "array_element\\.nml:2: &interface position\\(\\.\\.\\.\\): array elements are not accepted"
  "${_crank}\n&interface body = 'crank', name = 'B2', position(2) = 1.0 /")

# Types, in our words
ffrf_input_case(real_is_word 2 "real_is_word\\.nml:1: &body young = steel: not a number. give a finite real in \\(0, 1E\\+13\\] Pa"
  "&body name = 'crank', mesh_file = 'crank_lc8.msh', young = steel /\n${_b2}")
ffrf_input_case(integer_is_string 2 "integer_is_string\\.nml:3: &modes num_modes = 'four': not an integer. give an integer in 1\\.\\.10000"
  "${_crank}\n${_b2}\n&modes num_modes = 'four' /")
ffrf_input_case(string_unquoted 2 "string_unquoted\\.nml:2: &interface rc = Tx: not a quoted string"
  "${_crank}\n&interface body = 'crank', name = 'B2', rc = Tx /")
ffrf_input_case(vector_too_short 2 "vector_too_short\\.nml:2: &interface position = 1, 0: 2 value\\(s\\) given, position takes exactly 3"
  "${_crank}\n&interface body = 'crank', name = 'B2', virtual_node = 'position', position = 1, 0 /")
string(REPEAT "a" 300 _long)
ffrf_input_case(mesh_path_too_long 2 "mesh_path_too_long\\.nml:1: &body mesh_file = 'aaaa.*: has 304 characters, more than the 256 mesh_file can hold"
  "&body name = 'crank', mesh_file = '${_long}.msh' /\n${_b2}")

# Reals finite and in their documented ranges, named by key
ffrf_input_case(h_inf 2 "h_inf\\.nml:5: &integrator h = Inf: not a finite number. give a finite real in \\(0, 10\\] s"
  "${_arm}\n&integrator h = Inf /")
ffrf_input_case(h_huge 2 "h_huge\\.nml:5: &integrator h = 1e300: out of range. give a finite real in \\(0, 10\\] s"
  "${_arm}\n&integrator h = 1e300 /")
ffrf_input_case(h_negative 2 "h_negative\\.nml:5: &integrator h = -1: out of range"
  "${_arm}\n&integrator h = -1 /")
ffrf_input_case(h_longer_than_run 2 "h_longer_than_run\\.nml:5: &integrator h = 5: longer than the run"
  "${_arm}\n&integrator h = 5, t_end = 2 /")
ffrf_input_case(t_end_inf 2 "t_end_inf\\.nml:5: &integrator t_end = Inf: not a finite number"
  "${_arm}\n&integrator t_end = Inf /")
ffrf_input_case(gravity_nan 2 "gravity_nan\\.nml:5: &mechanism gravity = NaN, 0, 0: value 1 \\(NaN\\): not a finite number"
  "${_arm}\n&mechanism gravity = NaN, 0, 0 /")
ffrf_input_case(stall_torque_nan 2 "stall_torque_nan\\.nml:6: &load stall_torque = NaN: not a finite number"
  "${_arm}\n&mechanism crank = 'arm' /\n&load name = 'starter', type = 'starter', body = 'arm', marker = 'hinge', stall_torque = NaN /")
ffrf_input_case(crank_angle_huge 2 "crank_angle_huge\\.nml:5: &mechanism crank_angle_deg = 1e300: out of range. give a finite real in \\[-720, 720\\] deg"
  "${_arm}\n&mechanism crank = 'arm', crank_angle_deg = 1e300 /")
ffrf_input_case(young_inf 2 "young_inf\\.nml:1: &body young = Inf: not a finite number"
  "&body name = 'crank', mesh_file = 'crank_lc8.msh', young = Inf /\n${_b2}")
ffrf_input_case(density_inf 2 "density_inf\\.nml:1: &body density = Inf: not a finite number"
  "&body name = 'crank', mesh_file = 'crank_lc8.msh', density = Inf /\n${_b2}")
ffrf_input_case(density_overflow 2 "density_overflow\\.nml:1: &body density = 1e400: not a finite number"
  "&body name = 'crank', mesh_file = 'crank_lc8.msh', density = 1e400 /\n${_b2}")
ffrf_input_case(position_nan 2 "position_nan\\.nml:2: &interface position = 0, NaN, 0: value 2 \\(NaN\\): not a finite number"
  "${_crank}\n&interface body = 'crank', name = 'B2', rc = '123456', virtual_node = 'position', position = 0, NaN, 0 /")
ffrf_input_case(body_position_nan 2 "body_position_nan\\.nml:1: &body position = NaN, 0, 0: value 1 \\(NaN\\): not a finite number"
  "&body name = 'arm', type = 'rigid', mass = 1.0, inertia = 0.01, 0.01, 0.01, 0, 0, 0, position = NaN, 0, 0 /\n&marker body = 'arm', name = 'hinge', position = 0, 0, 0 /\n&marker body = 'ground', name = 'hinge', position = 0, 0, 0 /\n&joint name = 'pivot', type = 'revolute', body1 = 'ground', marker1 = 'hinge', body2 = 'arm', marker2 = 'hinge' /")
ffrf_input_case(rc_repeated_dof 2 "rc_repeated_dof\\.nml:2: &interface rc = 'Tx Tx': dof Tx is given twice"
  "${_crank}\n&interface body = 'crank', name = 'B2', rc = 'Tx Tx' /")

# Sizes that follow from values, checked before the run
ffrf_input_case(too_many_steps 2 "too_many_steps\\.nml:5: &integrator t_end = 1000: \\(t_end - t_start\\)/h = 1E\\+09 steps .*more than max_steps = 10000000"
  "${_arm}\n&integrator h = 1e-6, t_end = 1000 /")
ffrf_input_case(animation_frames_huge 2 "animation_frames_huge\\.nml:5: &mechanism animation_frames = 1000000000: out of range. give an integer in 0\\.\\.1000"
  "${_arm}\n&mechanism animation_frames = 1000000000 /")
ffrf_input_case(table_device 3 "&pressure table_file \"/dev/zero\" is a device. give a regular file"
  "${_arm}\n&mechanism crank = 'arm' /\n&load name = 'gas', type = 'pressure', body = 'arm', marker = 'hinge' /\n&pressure table_file = '/dev/zero' /")

# Outputs stay inside --output-dir (inputs may be absolute)
ffrf_input_case(output_absolute 2 "output_absolute\\.nml:1: &run output = '/.*: an absolute path"
  "&run output = '${_in}/abs.h5' /\n${_crank}\n${_b2}")
# &run export: words of export_choices only (src/core/choices.f90)
ffrf_input_case(export_unknown 2 "export_unknown\\.nml:1: &run export = 'exudyn vtk': export = .vtk. is not an export format; use one of xdmf, exudyn \\(a blank-separated list"
  "&run export = 'exudyn vtk' /\n${_crank}\n${_b2}")
ffrf_input_case(output_parent 2 "output_parent\\.nml:1: &run mode_shapes_msh = '\\.\\./escape\\.msh': a '\\.\\.' component leaves the output folder"
  "&run mode_shapes_msh = '../escape.msh' /\n${_crank}\n${_b2}")

# Case files: regular and bounded, or '-' for standard input
if(NOT EXISTS "${_in}/fifo_case.nml")
  execute_process(COMMAND mkfifo "${_in}/fifo_case.nml")
endif()
add_test(NAME input_case_fifo COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:ffrf>;${_in}/fifo_case.nml;--output-dir;${_in}" -DEXIT_CODE=3
  "-DMESSAGE=case file \".*fifo_case\\.nml\" is a FIFO" -P ${_expect})
add_test(NAME input_case_folder COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:ffrf>;${_in};--output-dir;${_in}" -DEXIT_CODE=3
  "-DMESSAGE=case file \".*input_errors\" is a folder" -P ${_expect})
file(WRITE "${_in}/stdin_bad.txt" "${_arm}\n&integrator h = Inf /\n")
add_test(NAME input_stdin_error COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:ffrf>;-;--output-dir;${_in}" -DEXIT_CODE=2
  "-DMESSAGE=stdin:5: &integrator h = Inf: not a finite number"
  "-DINPUT_FILE=${_in}/stdin_bad.txt" -P ${_expect})
file(WRITE "${_in}/stdin_good.txt" "${_arm}\n&integrator h = 1e-3, t_end = 0.01 /\n")
add_test(NAME input_stdin_check COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:ffrf>;-;--check;--quiet;--output-dir;${_in}" -DEXIT_CODE=0
  "-DINPUT_FILE=${_in}/stdin_good.txt" -P ${_expect})
set_tests_properties(input_case_fifo input_case_folder input_stdin_error input_stdin_check
  PROPERTIES LABELS "regression;errors;input" TIMEOUT 30)

# Positive: a line over 512 characters is read whole; --check passes
file(WRITE "${_in}/long_line_ok.nml" "&body name = 'crank',${_blanks} mesh_file = 'crank_lc8.msh', volumes = 'crank' /\n${_b2}\n")
add_test(NAME input_long_line_ok COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:ffrf>;${_in}/long_line_ok.nml;--check;--quiet;--mesh-dir;${PROJECT_BINARY_DIR}/meshes"
  -DEXIT_CODE=0 -P ${_expect})
set_tests_properties(input_long_line_ok PROPERTIES LABELS "regression;input" TIMEOUT 30
  FIXTURES_REQUIRED crank_lc8_mesh)

# Positive: every case in input/ passes --check (case text, meshes, interfaces), each in < 1 s
add_test(NAME input_check_all COMMAND ${CMAKE_COMMAND} -DFFRF=$<TARGET_FILE:ffrf>
  -DINPUT_DIR=${PROJECT_SOURCE_DIR}/input -DMESH_DIR=${PROJECT_BINARY_DIR}/meshes
  -P ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_inputs.cmake)
set_tests_properties(input_check_all PROPERTIES LABELS "regression;input" TIMEOUT 120
  ENVIRONMENT OPENBLAS_NUM_THREADS=1
  FIXTURES_REQUIRED "crank_mesh;conrod_mesh;crank_lc10_mesh;crank_lc8_mesh;conrod_lc8_mesh;link_mesh;cantilever_mesh;
    slider_rod_mesh")

# &body orientation (issue 24, item 1): a rotation matrix by rows; one not orthonormal and a
# reflection (det = -1) are refused by --check with exit 2, the message naming FILE:LINE, the
# key, the body and the defect (largest |A A^T - I| = 0.002001 for a 1.001 on the diagonal)
set(_arm_rotated "&body name = 'arm', type = 'rigid', mass = 1.0, inertia = 0.01, 0.01, 0.01, 0, 0, 0,
  orientation = ORIENTATION /
&marker body = 'arm', name = 'hinge', position = 0, 0, 0 /
&marker body = 'ground', name = 'hinge', position = 0, 0, 0 /
&joint name = 'pivot', type = 'revolute', body1 = 'ground', marker1 = 'hinge', body2 = 'arm', marker2 = 'hinge' /")
string(REPLACE "ORIENTATION" "1, 0, 0, 0, 1, 0, 0, 0, 1.001" _text "${_arm_rotated}")
ffrf_input_case(body_orientation_not_orthonormal 2
  "body_orientation_not_orthonormal\\.nml:2: &body orientation = 1, 0, 0, 0, 1, 0, 0, 0, 1\\.001: \"arm\": the orientation is not orthonormal: largest \\|A A\\^T - I\\| = 0\\.002001 > 1e-9"
  "${_text}" --check)
string(REPLACE "ORIENTATION" "1, 0, 0, 0, 1, 0, 0, 0, -1" _text "${_arm_rotated}")
ffrf_input_case(body_orientation_reflection 2
  "body_orientation_reflection\\.nml:2: &body orientation = 1, 0, 0, 0, 1, 0, 0, 0, -1: \"arm\": the orientation has det = -1, a reflection, not a rotation"
  "${_text}" --check)
string(REPLACE "ORIENTATION" "0, 0, 1, 0, 1, 0, 1, 0, 0" _text "${_arm_rotated}")
ffrf_input_case(body_orientation_reflection_run 2
  "body_orientation_reflection_run\\.nml:2: &body orientation = 0, 0, 1, 0, 1, 0, 1, 0, 0: \"arm\": the orientation has det = -1"
  "${_text}")
