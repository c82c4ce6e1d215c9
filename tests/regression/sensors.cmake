# Sensors (&sensor; docs/sensors.md) against independent references, by check_sensors.py:
#  - sensors_slider_wheel: a crank-less rigid slider-crank under gravity
#    (tests/data/sensors/slider_wheel.nml) with every sensor type: closed-form slider position,
#    revolute angle against the body orientation, velocity and acceleration against central
#    differences to O(h^2), reaction against /joints, energy against J omega^2 / 2; its log and
#    results file say nothing of a crank;
#  - sensors_flexible_marker: a flexible conrod's small-end virtual node (elastic motion included)
#    against R + A (x_V + Psi_V zeta) of its series, its velocity against the central difference,
#    its strain energy against 1/2 sum omega_i^2 zeta_i^2; a mesh node's displacement and position
#    against its /modes/shape rows and the mesh file;
#  - sensors_engine_crank: the engine's crank sensors equal /time/crank_angle and
#    /time/crank_speed bitwise (the all-rigid lc8 engine of engine.cmake);
#  - sensors_plot: postprocess/plot_sensors.py plots (and writes as CSV) the slider's 11 sensors;
#  - sensors_error_*: a bad &sensor gets one line naming the place, and --check refuses it.
set(_out "${PROJECT_BINARY_DIR}/tests/sensors")
file(MAKE_DIRECTORY "${_out}")
set(_case "${PROJECT_SOURCE_DIR}/tests/data/sensors/slider_wheel.nml")
add_test(NAME sensors_slider_wheel
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 ${Python3_EXECUTABLE}
    ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_sensors.py slider $<TARGET_FILE:ffrf> ${_case}
    ${PROJECT_BINARY_DIR}/meshes ${_out})
set_tests_properties(sensors_slider_wheel PROPERTIES LABELS "regression;sensors"
  FIXTURES_SETUP sensors_slider_results)
# One postprocess command plots any case's sensors (and writes them as CSV)
add_test(NAME sensors_plot
  COMMAND ${Python3_EXECUTABLE} ${PROJECT_SOURCE_DIR}/postprocess/plot_sensors.py
    ${_out}/slider_wheel.h5 --output ${_out}/slider_wheel_sensors.png
    --csv ${_out}/slider_wheel_sensors.csv)
set_tests_properties(sensors_plot PROPERTIES LABELS "regression;sensors;postprocess"
  FIXTURES_REQUIRED sensors_slider_results PASS_REGULAR_EXPRESSION "11 sensors -> ")
add_test(NAME sensors_engine_crank
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_sensors.py engine
    ${PROJECT_BINARY_DIR}/tests/engine/engine_lc8_all_rigid.h5)
set_tests_properties(sensors_engine_crank PROPERTIES LABELS "regression;sensors;engine"
  FIXTURES_REQUIRED engine_lc8_all_rigid_results)

# A flexible body's marker: the lc 8 mm engine of engine.cmake (flexible crank and conrod, 10
# modes each) to 10 ms with sensors on the conrod's small-end virtual node and energy
file(READ "${PROJECT_BINARY_DIR}/tests/engine/engine_lc8_rc1.nml" _flexible)
ffrf_replace(_flexible "t_end = 0.1," "t_end = 0.01,")
string(APPEND _flexible "&sensor name = 'small_end_position', type = 'position', body = 'conrod', "
  "marker = 'small_end' /\n&sensor name = 'small_end_velocity', type = 'velocity', "
  "body = 'conrod', marker = 'small_end' /\n&sensor name = 'conrod_energy', type = 'energy', "
  "body = 'conrod' /\n&sensor name = 'conrod_node_u', type = 'node_displacement', "
  "body = 'conrod', node = 100 /\n&sensor name = 'conrod_node_x', type = 'node_position', "
  "body = 'conrod', node = 100 /\n")
file(WRITE "${_out}/engine_flexible_sensors.nml" "${_flexible}")
add_test(NAME sensors_flexible_marker
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 ${Python3_EXECUTABLE}
    ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_sensors.py flexible $<TARGET_FILE:ffrf>
    ${_out}/engine_flexible_sensors.nml ${PROJECT_BINARY_DIR}/meshes ${_out})
set_tests_properties(sensors_flexible_marker PROPERTIES LABELS "regression;sensors"
  FIXTURES_REQUIRED "crank_lc8_mesh;conrod_lc8_mesh")

# ffrf_sensor_error(<name> <old> <new> <regex>): the slider-crank with <old> replaced by <new>
# must fail --check with exit code 2 and one line matching <regex> (the driver's exit code is
# printed after its output: "exit=2")
function(ffrf_sensor_error name old new regex)
  file(READ "${_case}" text)
  ffrf_replace(text "${old}" "${new}")
  file(WRITE "${_out}/${name}.nml" "${text}")
  add_test(NAME sensors_error_${name}
    COMMAND sh -c "\"$0\" \"$1\" --mesh-dir \"$2\" --output-dir \"$3\" --check; echo exit=$?"
      $<TARGET_FILE:ffrf> ${_out}/${name}.nml ${PROJECT_BINARY_DIR}/meshes ${_out})
  set_tests_properties(sensors_error_${name} PROPERTIES LABELS "regression;sensors"
    PASS_REGULAR_EXPRESSION "ffrf: error: [^\n]*${regex}[^\n]*\nexit=2")
endfunction()
ffrf_sensor_error(unknown_marker "body = 'slider', marker = 'S' /\n&sensor name = 'pin_position'"
  "body = 'slider', marker = 'Q' /\n&sensor name = 'pin_position'"
  "unknown_marker.nml:[0-9]+: &sensor \"slider_position\": marker \"Q\" of body \"slider\" is not defined")
ffrf_sensor_error(unknown_joint "joint = 'bearing' /\n&sensor name = 'guide_travel'"
  "joint = 'axle' /\n&sensor name = 'guide_travel'"
  "unknown_joint.nml:[0-9]+: &sensor \"bearing_angle\": joint \"axle\" is not a &joint of this case")
ffrf_sensor_error(unknown_body "type = 'energy', body = 'wheel'"
  "type = 'energy', body = 'rotor'"
  "unknown_body.nml:[0-9]+: &sensor \"wheel_energy\": body \"rotor\" is not a &body of this case")
ffrf_sensor_error(unknown_type "type = 'energy', body = 'wheel'"
  "type = 'power', body = 'wheel'"
  "unknown_type.nml:[0-9]+: &sensor type = 'power': not allowed; type is one of position, velocity")
ffrf_sensor_error(missing_marker "body = 'slider', marker = 'S' /\n&sensor name = 'pin_position'"
  "body = 'slider' /\n&sensor name = 'pin_position'"
  "missing_marker.nml:[0-9]+: &sensor #3 \"slider_position\": type 'position' needs body and marker")
ffrf_sensor_error(node_without_mesh "type = 'energy', body = 'wheel'"
  "type = 'node_position', body = 'wheel', node = 5"
  "node_without_mesh.nml:[0-9]+: &sensor \"wheel_energy\": body \"wheel\" has no mesh, so no node 5")
