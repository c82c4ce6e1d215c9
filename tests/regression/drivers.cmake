# Drivers of joints and loads over time (&driver, &load law; src/mbs/joint_driver.f90,
# src/mbs/time_function.f90; issue 24, item 1):
#  - regression_drivers: input/driven_crank.nml, a crank whose speed is a smooth step under
#    gravity (angle, rate and driving torque against closed forms) and a slider pushed by a force
#    table (travel against the closed form), the energy balance with the driver's work
#    and --restart from 0.6 s equal to the uninterrupted run, bitwise
#    (tests/regression/check_drivers.py). About 2 s.
add_test(NAME regression_drivers
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 ${Python3_EXECUTABLE}
    ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_drivers.py $<TARGET_FILE:ffrf>
    ${PROJECT_SOURCE_DIR}/input/driven_crank.nml ${PROJECT_BINARY_DIR}/meshes
    ${PROJECT_BINARY_DIR}/tests/drivers)
set_tests_properties(regression_drivers PROPERTIES LABELS "regression;drivers")

# Bad &driver and law input: one line naming the file, line and group, exit 2, from a run and
# --check.
set(_driver_scene "&body name = 'link', type = 'rigid', mass = 1.0, center_of_mass = 0.1, 0.0, 0.0, inertia = 1.0e-3, 1.0e-3, 1.0e-3, 0, 0, 0 /\n&marker body = 'link', name = 'O', position = 0.0, 0.0, 0.0 /\n&marker body = 'ground', name = 'O', position = 0.0, 0.0, 0.0 /\n&joint name = 'bearing', type = 'revolute', body1 = 'ground', marker1 = 'O', body2 = 'link', marker2 = 'O' /\n&joint name = 'ball', type = 'spherical', body1 = 'ground', marker1 = 'O', body2 = 'link', marker2 = 'O' /\n&integrator h = 1.0e-3, t_end = 0.01 /\n&model selection = 'manual' /")
foreach(_mode run check)
  if(_mode STREQUAL "check")
    set(_extra "--check")
  else()
    set(_extra "")
  endif()
  ffrf_error_case(driver_spherical_joint_${_mode} 2 "driver_spherical_joint_${_mode}\\.nml:8: &driver \"m\": joint \"ball\" is spherical; a driver needs a revolute or prismatic joint"
    "${_driver_scene}\n&driver name = 'm', joint = 'ball', law = 'constant_speed', speed = 1.0 /" ${_extra})
  ffrf_error_case(driver_unknown_joint_${_mode} 2 "driver_unknown_joint_${_mode}\\.nml:8: &driver \"m\": joint \"hinge\" is not a &joint of this case"
    "${_driver_scene}\n&driver name = 'm', joint = 'hinge', law = 'constant_speed', speed = 1.0 /" ${_extra})
  ffrf_error_case(driver_decreasing_times_${_mode} 2 "driver_decreasing_times_${_mode}\\.nml:8: .*&driver \"m\": table_time\\(3\\) = 0\\.1 s is not after table_time\\(2\\) = 0\\.2 s; the times must increase strictly"
    "${_driver_scene}\n&driver name = 'm', joint = 'bearing', law = 'table', table_time = 0.0, 0.2, 0.1, table_value = 0.0, 1.0, 2.0 /" ${_extra})
  ffrf_error_case(driver_one_point_${_mode} 2 "driver_one_point_${_mode}\\.nml:8: .*&driver \"m\": a table of 1 points; give 2 to 1000"
    "${_driver_scene}\n&driver name = 'm', joint = 'bearing', law = 'table', table_time = 0.0, table_value = 1.0 /" ${_extra})
  ffrf_error_case(load_law_decreasing_times_${_mode} 2 "load_law_decreasing_times_${_mode}\\.nml:8: .*&load \"push\": table_time\\(2\\) = 0 s is not after table_time\\(1\\) = 0\\.5 s"
    "${_driver_scene}\n&load name = 'push', type = 'force', body = 'link', marker = 'O', direction = 1.0, 0.0, 0.0, value = 1.0, law = 'table', table_time = 0.5, 0.0, table_value = 0.0, 1.0 /" ${_extra})
  ffrf_error_case(driver_sensor_without_driver_${_mode} 2 "driver_sensor_without_driver_${_mode}\\.nml:8: &sensor \"d\": joint \"bearing\" has no &driver"
    "${_driver_scene}\n&sensor name = 'd', type = 'driver', joint = 'bearing' /" ${_extra})
  ffrf_error_case(driver_zero_duration_${_mode} 2 "driver_zero_duration_${_mode}\\.nml:8: &driver duration = 0\\.0: out of range"
    "${_driver_scene}\n&driver name = 'm', joint = 'bearing', law = 'ramp', final = 1.0, duration = 0.0 /" ${_extra})
  ffrf_error_case(driver_periodic_end_${_mode} 2 "driver_periodic_end_${_mode}\\.nml:8: .*&driver \"m\": a periodic table must end at its first value"
    "${_driver_scene}\n&driver name = 'm', joint = 'bearing', law = 'table', beyond = 'periodic', table_time = 0.0, 1.0, table_value = 0.0, 1.0 /" ${_extra})
  ffrf_error_case(driver_unknown_law_${_mode} 2 "driver_unknown_law_${_mode}\\.nml:8: &driver law = 'sine'"
    "${_driver_scene}\n&driver name = 'm', joint = 'bearing', law = 'sine' /" ${_extra})
  ffrf_error_case(load_law_on_drag_${_mode} 2 "load_law_on_drag_${_mode}\\.nml:8: &load law = .ramp.: &load \"d\" of type drag takes no law"
    "${_driver_scene}\n&load name = 'd', type = 'drag', body = 'link', marker = 'O', law = 'ramp', final = 1.0 /" ${_extra})
endforeach()
