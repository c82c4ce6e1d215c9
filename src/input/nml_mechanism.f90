!> Namelist groups of a mechanism run (a case with at least one &joint is a mechanism run):
!>   &mechanism   crank, crank_angle_deg, crank_speed [rad/s], gravity [m/s^2], label,
!>                progress_interval [s], animation_frames                     (optional, single)
!>   &marker      body, name, position [m, body frame; ground: global], orientation
!>                [rotation matrix by rows: the marker axes in the body frame], node, group
!>                [flexible body: a mesh node, a physical surface's RBE3 point, or the centre
!>                of a physical curve's or point's nodes], weighting
!>                (repeatable)
!>   &joint       name, type, body1, marker1, body2, marker2, axis            (repeatable)
!>   &load        name, type (a word of load_choices), body, marker, direction,
!>                value, stall_torque, free_speed, switch_off, coefficient    (repeatable)
!>   &spring      name, body1, marker1, body2, marker2, stiffness [N/m], damping [N s/m],
!>                free_length [m]                                             (repeatable)
!>   &torsion_spring  name, joint, stiffness [N m/rad], damping [N m s/rad], free_angle [rad]
!>                                                                            (repeatable)
!>   &bushing     name, body1, marker1, body2, marker2, stiffness (6: kx, ky, kz [N/m], krx,
!>                kry, krz [N m/rad]), damping (6: [N s/m], [N m s/rad])     (repeatable)
!>   &driver      name, joint, quantity (coordinate|rate), offset [rad or m], and the law keys
!>                                                                            (repeatable)
!>   law keys of &driver and of a force or torque &load (docs/mechanisms.md "Laws over time"):
!>                law (constant|constant_speed|ramp|smooth_step|table), initial, final, speed,
!>                t_start [s], duration [s], table_time [s], table_value, interpolation
!>                (linear|cubic), beyond (hold|periodic)
!>   &pressure    bore, stroke, conrod_length, compression_ratio, intake_pressure,
!>                exhaust_pressure, polytropic_exponent, wiebe_a, wiebe_m,
!>                combustion_start_deg, combustion_duration_deg, heat_per_cycle,
!>                target_peak_pressure, reference_pressure, table_file    (optional, single)
!>   &integrator  h, t_end, rho_inf, newton_atol, newton_rtol, max_iterations, min_step,
!>                rank_rtol, jacobian ('adaptive', 'step', 'full'), tangent_reuse,
!>                checkpoint_seconds, checkpoint_steps, energy_watch ('off', 'warn', 'stop'),
!>                energy_watch_tolerance, energy_watch_window [s], sparse_threshold,
!>                constraints ('index3', 'index2')
!>                                                                            (optional, single)
!>   &model       selection ('auto', 'manual'), speed_tolerance, force_tolerance,
!>                candidate_modes, resonance_floor                            (optional, single)
!>   &sensor      name, type, body, marker, joint: read by ffrf_input_nml_sensor (repeatable;
!>                docs/sensors.md)
!>   &body        its mechanism keys (type, num_modes, ..., position and the starting pose:
!>                orientation [rotation matrix by rows], velocity [m/s], angular_velocity
!>                [rad/s]) are read by ffrf_input_nml_body, whose header gives their ranges
!> Defaults: ffrf_input_mechanism, ffrf_input_pressure's pressure_input_t (the scene's engine)
!> and galpha_settings_t. Names are checked against each other by ffrf_input_case.
!> Types, counts and ranges (checked by ffrf_input_nml_source from the *_keys functions below; every
!> real must be finite; names and labels <= 64 characters, file names <= 256):
!>   &mechanism  crank_angle_deg in [-720, 720] deg; crank_speed in [-1e4, 1e4] rad/s; gravity:
!>               3 reals in [-1e4, 1e4] m/s^2, global axes, uniform field acting on every rigid
!>               and flexible body (flexible: on the frame and the modes through the shape
!>               integral int rho Psi dV; docs/theory.md 3.6, docs/gravity.md; its work enters
!>               /energy like any applied load); progress_interval in (0, 1e6] s;
!>               animation_frames integer in 0..1000 (each frame holds a displacement field)
!>   &marker     position: 3 reals in [-1e4, 1e4] m; orientation: 9 reals in [-1e6, 1e6], a
!>               rotation (|A A^T - I| <= 1e-9, det A > 0; absent: the joint's axis sets the
!>               marker frame, docs/mechanisms.md "Joint frames"); node: a Gmsh node tag >= 1
!>               and group: a physical surface, curve or point name (flexible body only, one of
!>               the two, no position: docs/mechanisms.md "Markers at mesh points"); weighting: a
!>               surface's RBE3 weights, a word of weighting_choices (as &interface)
!>   &joint      type: a word of joint_choices (ffrf_mbs_joints); axis: 3 reals in [-1e6, 1e6],
!>               not all zero
!>   &load       direction: 3 reals in [-1e6, 1e6], not all zero; value in [-1e12, 1e12] N or
!>               N m; stall_torque in [0, 1e9] N m; free_speed in (0, 1e5] rad/s; switch_off in
!>               [0, 1e6] s; coefficient in [0, 1e9] N m s^2
!>   &driver     name unique, required; joint: a revolute or prismatic &joint (checked by
!>               ffrf_input_case); offset in [-1e6, 1e6]
!>   law keys    initial, final in [-1e12, 1e12] (the unit of what the law gives); speed in
!>               [-1e12, 1e12] per s; t_start in [0, 1e6] s; duration in (0, 1e6] s; table_time
!>               in [-1e9, 1e9] s and table_value in [-1e12, 1e12], 1 to 1000 values each, as
!>               many values as times, times strictly increasing, at least 2 points; beyond =
!>               'periodic' needs the last value equal to the first (ffrf_mbs_time_function);
!>               a &load with a law: type force or torque, its magnitude value * g(t) (value
!>               not given: 1, so that the law gives the magnitude in N or N m)
!>   &spring     stiffness in [0, 1e12] N/m; damping in [0, 1e12] N s/m; free_length in
!>               [0, 1e6] m (absent: the distance of the markers at the start, which must not be
!>               0); body1 /= body2; name unique
!>   &torsion_spring  joint: a revolute or cylindrical &joint (checked by ffrf_input_case);
!>               stiffness in [0, 1e12] N m/rad; damping in [0, 1e12] N m s/rad; free_angle in
!>               [-1e6, 1e6] rad (absent: the joint angle at the start); name unique
!>   &bushing    stiffness, damping: 6 reals each in [0, 1e12] (default 0); body1 /= body2;
!>               name unique
!>   &pressure   bore, stroke in (0, 10] m; conrod_length in (0, 100] m (> stroke/2);
!>               compression_ratio in (1, 1000]; intake_pressure, exhaust_pressure in (0, 1e9] Pa;
!>               polytropic_exponent in (1, 3]; wiebe_a in (0, 100]; wiebe_m in [0, 100];
!>               combustion_start_deg in [180, 540) deg; combustion_duration_deg in (0, 360] deg
!>               (start + duration <= 540); heat_per_cycle in [-1e9, 1e9] J (negative: tuned to
!>               target_peak_pressure); target_peak_pressure in (0, 1e10] Pa; reference_pressure
!>               in [0, 1e9] Pa; table_file: a regular file of at most 16 MiB
!>   &integrator h in (0, 10] s; t_end in (0, 1e6] s; rho_inf in [0, 1]; newton_atol in (0, 1];
!>               newton_rtol in (0, 1); max_iterations in 1..1000; min_step in (0, 10] s (<= h);
!>               rank_rtol in (0, 1); tangent_reuse in 0..1000000; max_steps (integer, default
!>               10 000 000): the largest number of steps (t_end - t_start)/h a run may take,
!>               raise it on purpose for a longer run; checkpoint_steps integer >= 0,
!>               checkpoint_seconds in [0, 1e9] s (the checkpoint work); energy_watch
!>               (default 'warn'; ffrf_mbs_energy_watch), energy_watch_tolerance in (0, 1]
!>               (default 1e-4), energy_watch_window in (0, 1e6] s (default 0.1 s);
!>               sparse_threshold integer >= 1 (default 800): order of the iteration matrix
!>               from which MUMPS's sparse LU replaces LAPACK's dense one (1: always sparse,
!>               a large value: always dense; docs/performance_threads.md)
!>   &model      speed_tolerance, force_tolerance in (0, 1); candidate_modes in 1..200;
!>               resonance_floor in (0, 1]
module ffrf_input_nml_mechanism
   use ffrf_core_kinds, only: dp, i8
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str, to_lower, join_words
   use ffrf_input_interface, only: weighting_choices
   use ffrf_input_nml_common, only: read_status, check_unique_name
   use ffrf_input_nml_source, only: key_spec_t, real_key, integer_key, string_key, choice_key, &
      nml_source_t
   use ffrf_input_mechanism, only: mechanism_case_input_t, mechanism_input_t, &
      marker_input_t, joint_input_t, load_input_t, model_input_t, spring_input_t, parse_targets, &
      torsion_spring_input_t, bushing_input_t, &
      driver_input_t, time_law_input_t, law_function, load_choices, selection_choices, &
      quantity_choices
   use ffrf_mbs_time_function, only: time_function_t, time_law_choices, max_table_points
   use ffrf_input_pressure, only: pressure_input_t
   use ffrf_mbs_generalized_alpha, only: galpha_settings_t, check_galpha_settings, &
      GALPHA_NEWTON_FULL, GALPHA_NEWTON_STEP, GALPHA_NEWTON_ADAPTIVE, GALPHA_INDEX3, &
      GALPHA_INDEX2
   use ffrf_core_choices, only: choice_t, choice_words, choice_position, choice_name, &
      interpolation_choices, beyond_choices
   use ffrf_mbs_joints, only: joint_choices
   use ffrf_mbs_rotation, only: check_rotation
   use ffrf_mbs_energy_watch, only: energy_watch_settings_t, energy_watch_kind, &
      energy_watch_word, ENERGY_WATCH_WORDS
   implicit none
   private
   public :: read_mechanism_groups
   public :: mechanism_keys, marker_keys, joint_keys, load_keys, pressure_keys, integrator_keys, &
      model_keys, spring_keys, driver_keys, torsion_spring_keys, bushing_keys
   public :: jacobian_choices, constraints_choices

   !> The &integrator jacobian table (GALPHA_NEWTON_* of ffrf_mbs_generalized_alpha)
   type(choice_t), parameter :: jacobian_choices(*) = [ &
      choice_t('adaptive', GALPHA_NEWTON_ADAPTIVE), choice_t('step', GALPHA_NEWTON_STEP), &
      choice_t('full', GALPHA_NEWTON_FULL)]
   !> The &integrator constraints table (GALPHA_INDEX* of ffrf_mbs_generalized_alpha):
   !> index-3 constraints, or the stabilized index-2 formulation (theory.md 4.6)
   type(choice_t), parameter :: constraints_choices(*) = [ &
      choice_t('index3', GALPHA_INDEX3), choice_t('index2', GALPHA_INDEX2)]

   interface
      !> &model: automatic model selection and its error targets.
      module subroutine read_model_group(unit, src, input, error)
         integer, intent(in) :: unit
         type(nml_source_t), intent(in) :: src
         type(model_input_t), intent(inout) :: input
         type(error_t), allocatable, intent(out) :: error
      end subroutine read_model_group

      module subroutine read_mechanism_group(unit, src, input, error)
         integer, intent(in) :: unit
         type(nml_source_t), intent(in) :: src
         type(mechanism_input_t), intent(inout) :: input
         type(error_t), allocatable, intent(out) :: error
      end subroutine read_mechanism_group

      module subroutine read_marker_groups(unit, src, markers, error)
         integer, intent(in) :: unit
         type(nml_source_t), intent(in) :: src
         type(marker_input_t), allocatable, intent(out) :: markers(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine read_marker_groups

      module subroutine read_joint_groups(unit, src, joints, error)
         integer, intent(in) :: unit
         type(nml_source_t), intent(in) :: src
         type(joint_input_t), allocatable, intent(out) :: joints(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine read_joint_groups

      module subroutine read_pressure_group(unit, src, input, table_file, error)
         integer, intent(in) :: unit
         type(nml_source_t), intent(in) :: src
         type(pressure_input_t), intent(inout) :: input
         character(len=*), intent(inout) :: table_file
         type(error_t), allocatable, intent(out) :: error
      end subroutine read_pressure_group

      module subroutine read_integrator_group(unit, src, settings, h_given, error, watch)
         integer, intent(in) :: unit
         type(nml_source_t), intent(in) :: src
         type(galpha_settings_t), intent(inout) :: settings
         !> .true. when the group gives h
         logical, intent(out) :: h_given
         type(error_t), allocatable, intent(out) :: error
         !> The energy watch of the run (energy_watch, energy_watch_tolerance, energy_watch_window)
         type(energy_watch_settings_t), intent(inout) :: watch
      end subroutine read_integrator_group

      module subroutine read_load_groups(unit, src, loads, error)
         integer, intent(in) :: unit
         type(nml_source_t), intent(in) :: src
         type(load_input_t), allocatable, intent(out) :: loads(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine read_load_groups

      !> The &driver groups (module header), in input order.
      module subroutine read_driver_groups(unit, src, drivers, error)
         integer, intent(in) :: unit
         type(nml_source_t), intent(in) :: src
         type(driver_input_t), allocatable, intent(out) :: drivers(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine read_driver_groups

      !> The groups between two markers of two bodies (module header), each in input order:
      !> &spring, then &bushing; each group read straight into its record, then the rules they
      !> share (check_marker_pair_group).
      module subroutine read_marker_pair_groups(unit, src, springs, bushings, error)
         integer, intent(in) :: unit
         type(nml_source_t), intent(in) :: src
         type(spring_input_t), allocatable, intent(out) :: springs(:)
         type(bushing_input_t), allocatable, intent(out) :: bushings(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine read_marker_pair_groups

      !> The &torsion_spring groups (module header), in input order.
      module subroutine read_torsion_spring_groups(unit, src, springs, error)
         integer, intent(in) :: unit
         type(nml_source_t), intent(in) :: src
         type(torsion_spring_input_t), allocatable, intent(out) :: springs(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine read_torsion_spring_groups
   end interface

contains

   !> Keys of &mechanism (module header).
   function mechanism_keys() result(keys)
      type(key_spec_t), allocatable :: keys(:)
      keys = [string_key('crank', 64), real_key('crank_angle_deg', -720.0_dp, 720.0_dp, 'deg'), &
         real_key('crank_speed', -1.0e4_dp, 1.0e4_dp, 'rad/s'), &
         real_key('gravity', -1.0e4_dp, 1.0e4_dp, 'm/s^2', count=3), string_key('label', 64), &
         real_key('progress_interval', 0.0_dp, 1.0e6_dp, 's', lower_open=.true.), &
         integer_key('animation_frames', 0_i8, 1000_i8)]
   end function mechanism_keys

   !> Keys of &marker (module header).
   function marker_keys() result(keys)
      type(key_spec_t), allocatable :: keys(:)
      keys = [string_key('body', 64), string_key('name', 64), &
         real_key('position', -1.0e4_dp, 1.0e4_dp, 'm', count=3), &
         real_key('orientation', -1.0e6_dp, 1.0e6_dp, '', count=9), &
         integer_key('node', 1_i8, int(huge(1), i8)), string_key('group', 64), &
         choice_key('weighting', 16, choice_words(weighting_choices))]
   end function marker_keys

   !> Keys of &joint (module header).
   function joint_keys() result(keys)
      type(key_spec_t), allocatable :: keys(:)
      keys = [string_key('name', 64), choice_key('type', 16, choice_words(joint_choices)), &
         string_key('body1', 64), string_key('marker1', 64), string_key('body2', 64), &
         string_key('marker2', 64), real_key('axis', -1.0e6_dp, 1.0e6_dp, '', count=3)]
   end function joint_keys

   !> Keys of &load (module header).
   function load_keys() result(keys)
      type(key_spec_t), allocatable :: keys(:)
      keys = [string_key('name', 64), choice_key('type', 16, choice_words(load_choices)), &
         string_key('body', 64), string_key('marker', 64), &
         real_key('direction', -1.0e6_dp, 1.0e6_dp, '', count=3), &
         real_key('value', -1.0e12_dp, 1.0e12_dp, 'N or N m'), &
         real_key('stall_torque', 0.0_dp, 1.0e9_dp, 'N m'), &
         real_key('free_speed', 0.0_dp, 1.0e5_dp, 'rad/s', lower_open=.true.), &
         real_key('switch_off', 0.0_dp, 1.0e6_dp, 's'), &
         real_key('coefficient', 0.0_dp, 1.0e9_dp, 'N m s^2'), law_keys()]
   end function load_keys

   !> Keys of a law over time, in &driver and &load (module header).
   function law_keys() result(keys)
      type(key_spec_t), allocatable :: keys(:)
      type(key_spec_t) :: times, values
      times = real_key('table_time', -1.0e9_dp, 1.0e9_dp, 's')
      times%max_count = max_table_points
      values = real_key('table_value', -1.0e12_dp, 1.0e12_dp, '')
      values%max_count = max_table_points
      keys = [choice_key('law', 16, choice_words(time_law_choices)), &
         real_key('initial', -1.0e12_dp, 1.0e12_dp, ''), &
         real_key('final', -1.0e12_dp, 1.0e12_dp, ''), &
         real_key('speed', -1.0e12_dp, 1.0e12_dp, '1/s'), &
         real_key('t_start', 0.0_dp, 1.0e6_dp, 's'), &
         real_key('duration', 0.0_dp, 1.0e6_dp, 's', lower_open=.true.), times, values, &
         choice_key('interpolation', 8, choice_words(interpolation_choices)), &
         choice_key('beyond', 8, choice_words(beyond_choices))]
   end function law_keys

   !> Keys of &driver (module header).
   function driver_keys() result(keys)
      type(key_spec_t), allocatable :: keys(:)
      keys = [string_key('name', 64), string_key('joint', 64), &
         choice_key('quantity', 16, choice_words(quantity_choices)), &
         real_key('offset', -1.0e6_dp, 1.0e6_dp, 'rad or m'), law_keys()]
   end function driver_keys

   !> Keys of &pressure (module header).
   function pressure_keys() result(keys)
      type(key_spec_t), allocatable :: keys(:)
      keys = [real_key('bore', 0.0_dp, 10.0_dp, 'm', lower_open=.true.), &
         real_key('stroke', 0.0_dp, 10.0_dp, 'm', lower_open=.true.), &
         real_key('conrod_length', 0.0_dp, 100.0_dp, 'm', lower_open=.true.), &
         real_key('compression_ratio', 1.0_dp, 1000.0_dp, '', lower_open=.true.), &
         real_key('intake_pressure', 0.0_dp, 1.0e9_dp, 'Pa', lower_open=.true.), &
         real_key('exhaust_pressure', 0.0_dp, 1.0e9_dp, 'Pa', lower_open=.true.), &
         real_key('polytropic_exponent', 1.0_dp, 3.0_dp, '', lower_open=.true.), &
         real_key('wiebe_a', 0.0_dp, 100.0_dp, '', lower_open=.true.), &
         real_key('wiebe_m', 0.0_dp, 100.0_dp, ''), &
         real_key('combustion_start_deg', 180.0_dp, 540.0_dp, 'deg', upper_open=.true.), &
         real_key('combustion_duration_deg', 0.0_dp, 360.0_dp, 'deg', lower_open=.true.), &
         real_key('heat_per_cycle', -1.0e9_dp, 1.0e9_dp, 'J'), &
         real_key('target_peak_pressure', 0.0_dp, 1.0e10_dp, 'Pa', lower_open=.true.), &
         real_key('reference_pressure', 0.0_dp, 1.0e9_dp, 'Pa'), string_key('table_file', 256)]
   end function pressure_keys

   !> Keys of &integrator (module header). max_steps is read from the source by ffrf_input_case
   !> (not a namelist key); checkpoint_steps and checkpoint_seconds belong to the checkpoint work.
   function integrator_keys() result(keys)
      type(key_spec_t), allocatable :: keys(:)
      keys = [real_key('h', 0.0_dp, 10.0_dp, 's', lower_open=.true.), &
         real_key('t_end', 0.0_dp, 1.0e6_dp, 's', lower_open=.true.), &
         real_key('rho_inf', 0.0_dp, 1.0_dp, ''), &
         real_key('newton_atol', 0.0_dp, 1.0_dp, '', lower_open=.true.), &
         real_key('newton_rtol', 0.0_dp, 1.0_dp, '', lower_open=.true., upper_open=.true.), &
         integer_key('max_iterations', 1_i8, 1000_i8), &
         real_key('min_step', 0.0_dp, 10.0_dp, 's', lower_open=.true.), &
         real_key('rank_rtol', 0.0_dp, 1.0_dp, '', lower_open=.true., upper_open=.true.), &
         choice_key('jacobian', 16, choice_words(jacobian_choices)), &
         choice_key('constraints', 16, choice_words(constraints_choices)), &
         integer_key('tangent_reuse', 0_i8, 1000000_i8), &
         integer_key('sparse_threshold', 1_i8, int(huge(1), i8)), &
         integer_key('max_steps', 1_i8, 1000000000000_i8, in_namelist=.false.), &
         integer_key('checkpoint_steps', 0_i8, int(huge(1), i8)), &
         real_key('checkpoint_seconds', 0.0_dp, 1.0e9_dp, 's'), &
         choice_key('energy_watch', 16, join_words(ENERGY_WATCH_WORDS, ', ')), &
         real_key('energy_watch_tolerance', 0.0_dp, 1.0_dp, '', lower_open=.true.), &
         real_key('energy_watch_window', 0.0_dp, 1.0e6_dp, 's', lower_open=.true.)]
   end function integrator_keys

   !> Keys of &model (module header).
   function model_keys() result(keys)
      type(key_spec_t), allocatable :: keys(:)
      keys = [choice_key('selection', 16, choice_words(selection_choices)), &
         real_key('speed_tolerance', 0.0_dp, 1.0_dp, '', lower_open=.true., upper_open=.true.), &
         real_key('force_tolerance', 0.0_dp, 1.0_dp, '', lower_open=.true., upper_open=.true.), &
         integer_key('candidate_modes', 1_i8, 200_i8), &
         real_key('resonance_floor', 0.0_dp, 1.0_dp, '', lower_open=.true.), &
         string_key('targets', 512)]
   end function model_keys

   !> Read every mechanism group of the open case file.
   !> Keys of &spring (module header).
   function spring_keys() result(keys)
      type(key_spec_t), allocatable :: keys(:)
      keys = [string_key('name', 64), string_key('body1', 64), string_key('marker1', 64), &
         string_key('body2', 64), string_key('marker2', 64), &
         real_key('stiffness', 0.0_dp, 1.0e12_dp, 'N/m'), &
         real_key('damping', 0.0_dp, 1.0e12_dp, 'N s/m'), &
         real_key('free_length', 0.0_dp, 1.0e6_dp, 'm')]
   end function spring_keys

   !> Keys of &torsion_spring (module header).
   function torsion_spring_keys() result(keys)
      type(key_spec_t), allocatable :: keys(:)
      keys = [string_key('name', 64), string_key('joint', 64), &
         real_key('stiffness', 0.0_dp, 1.0e12_dp, 'N m/rad'), &
         real_key('damping', 0.0_dp, 1.0e12_dp, 'N m s/rad'), &
         real_key('free_angle', -1.0e6_dp, 1.0e6_dp, 'rad')]
   end function torsion_spring_keys

   !> Keys of &bushing (module header).
   function bushing_keys() result(keys)
      type(key_spec_t), allocatable :: keys(:)
      keys = [string_key('name', 64), string_key('body1', 64), string_key('marker1', 64), &
         string_key('body2', 64), string_key('marker2', 64), &
         real_key('stiffness', 0.0_dp, 1.0e12_dp, 'N/m, N m/rad', count=6), &
         real_key('damping', 0.0_dp, 1.0e12_dp, 'N s/m, N m s/rad', count=6)]
   end function bushing_keys

   subroutine read_mechanism_groups(unit, src, input, error)
      integer, intent(in) :: unit
      !> The checked case text (FILE:LINE of the keys)
      type(nml_source_t), intent(in) :: src
      type(mechanism_case_input_t), intent(out) :: input
      type(error_t), allocatable, intent(out) :: error
      call read_mechanism_group(unit, src, input%mechanism, error)
      if (.not. allocated(error)) call read_marker_groups(unit, src, input%markers, error)
      if (.not. allocated(error)) call read_joint_groups(unit, src, input%joints, error)
      if (.not. allocated(error)) call read_load_groups(unit, src, input%loads, error)
      if (.not. allocated(error)) call read_marker_pair_groups(unit, src, input%springs, &
         input%bushings, error)
      if (.not. allocated(error)) call read_torsion_spring_groups(unit, src, &
         input%torsion_springs, error)
      if (.not. allocated(error)) call read_driver_groups(unit, src, input%drivers, error)
      if (.not. allocated(error)) call read_pressure_group(unit, src, input%pressure, &
         input%pressure_table, error)
      if (.not. allocated(error)) call read_integrator_group(unit, src, input%integrator, &
         input%model%h_given, error, input%energy_watch)
      if (.not. allocated(error)) call read_model_group(unit, src, input%model, error)
      if (.not. allocated(error)) input%max_steps = src%integer_value('integrator', 1, &
         'max_steps', input%max_steps)
   end subroutine read_mechanism_groups

end module ffrf_input_nml_mechanism
