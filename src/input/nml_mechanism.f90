!> Namelist groups of a mechanism run (a case with at least one &joint is a mechanism run):
!>   &mechanism   crank, crank_angle_deg, crank_speed [rad/s], gravity [m/s^2], label,
!>                progress_interval [s], animation_frames                     (optional, single)
!>   &marker      body, name, position [m, body frame; ground: global], orientation
!>                [rotation matrix by rows: the marker axes in the body frame]  (repeatable)
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
!>                energy_watch_tolerance, energy_watch_window [s], sparse_threshold
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
!>               marker frame, docs/mechanisms.md "Joint frames")
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
   use ffrf_input_nml_common, only: namelist_read_error
   use ffrf_input_nml_source, only: key_spec_t, real_key, integer_key, string_key, choice_key, &
      nml_source_t
   use ffrf_input_mechanism, only: mechanism_case_input_t, mechanism_input_t, &
      marker_input_t, joint_input_t, load_input_t, model_input_t, spring_input_t, &
      torsion_spring_input_t, bushing_input_t, &
      driver_input_t, time_law_input_t, law_function, load_choices, selection_choices
   use ffrf_mbs_time_function, only: time_function_t, time_function_words, max_table_points
   use ffrf_input_pressure, only: pressure_input_t
   use ffrf_mbs_generalized_alpha, only: galpha_settings_t, check_galpha_settings, &
      GALPHA_NEWTON_FULL, GALPHA_NEWTON_STEP, GALPHA_NEWTON_ADAPTIVE
   use ffrf_core_choices, only: choice_t, choice_words, choice_position, choice_name
   use ffrf_mbs_joints, only: joint_choices
   use ffrf_mbs_rotation, only: check_rotation
   use ffrf_mbs_energy_watch, only: energy_watch_settings_t, energy_watch_kind, &
      energy_watch_word, ENERGY_WATCH_WORDS
   implicit none
   private
   public :: read_mechanism_groups
   public :: mechanism_keys, marker_keys, joint_keys, load_keys, pressure_keys, integrator_keys, &
      model_keys, spring_keys, driver_keys, torsion_spring_keys, bushing_keys

   !> The law keys, for messages (module header)
   character(len=*), parameter :: law_key_names = 'law, initial, final, speed, t_start, ' // &
      'duration, table_time, table_value, interpolation, beyond'
   !> The &integrator jacobian table (GALPHA_NEWTON_* of ffrf_mbs_generalized_alpha)
   type(choice_t), parameter :: jacobian_choices(*) = [ &
      choice_t('adaptive', GALPHA_NEWTON_ADAPTIVE), choice_t('step', GALPHA_NEWTON_STEP), &
      choice_t('full', GALPHA_NEWTON_FULL)]

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
         real_key('orientation', -1.0e6_dp, 1.0e6_dp, '', count=9)]
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
      keys = [choice_key('law', 16, time_function_words), &
         real_key('initial', -1.0e12_dp, 1.0e12_dp, ''), &
         real_key('final', -1.0e12_dp, 1.0e12_dp, ''), &
         real_key('speed', -1.0e12_dp, 1.0e12_dp, '1/s'), &
         real_key('t_start', 0.0_dp, 1.0e6_dp, 's'), &
         real_key('duration', 0.0_dp, 1.0e6_dp, 's', lower_open=.true.), times, values, &
         choice_key('interpolation', 8, 'linear, cubic'), choice_key('beyond', 8, 'hold, periodic')]
   end function law_keys

   !> Keys of &driver (module header).
   function driver_keys() result(keys)
      type(key_spec_t), allocatable :: keys(:)
      keys = [string_key('name', 64), string_key('joint', 64), &
         choice_key('quantity', 16, 'coordinate, rate'), &
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
         real_key('resonance_floor', 0.0_dp, 1.0_dp, '', lower_open=.true.)]
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
      call read_mechanism_group(unit, input%mechanism, error)
      if (.not. allocated(error)) call read_marker_groups(unit, src, input%markers, error)
      if (.not. allocated(error)) call read_joint_groups(unit, src, input%joints, error)
      if (.not. allocated(error)) call read_load_groups(unit, src, input%loads, error)
      if (.not. allocated(error)) call read_spring_groups(unit, src, input%springs, error)
      if (.not. allocated(error)) call read_torsion_spring_groups(unit, src, &
         input%torsion_springs, error)
      if (.not. allocated(error)) call read_bushing_groups(unit, src, input%bushings, error)
      if (.not. allocated(error)) call read_driver_groups(unit, src, input%drivers, error)
      if (.not. allocated(error)) call read_pressure_group(unit, input%pressure, &
         input%pressure_table, error)
      if (.not. allocated(error)) call read_integrator_group(unit, src, input%integrator, &
         input%model%h_given, error, input%energy_watch)
      if (.not. allocated(error)) call read_model_group(unit, input%model, error)
      if (.not. allocated(error)) input%max_steps = src%integer_value('integrator', 1, &
         'max_steps', input%max_steps)
   end subroutine read_mechanism_groups

   !> &model: automatic model selection and its error targets.
   subroutine read_model_group(unit, input, error)
      integer, intent(in) :: unit
      type(model_input_t), intent(inout) :: input
      type(error_t), allocatable, intent(out) :: error
      character(len=16) :: selection
      real(dp) :: speed_tolerance, force_tolerance, resonance_floor
      integer :: candidate_modes, stat
      character(len=512) :: msg
      namelist /model/ selection, speed_tolerance, force_tolerance, candidate_modes, &
         resonance_floor
      selection = input%selection
      speed_tolerance = input%speed_tolerance
      force_tolerance = input%force_tolerance
      candidate_modes = input%candidate_modes
      resonance_floor = input%resonance_floor
      rewind (unit)
      read (unit, nml=model, iostat=stat, iomsg=msg)
      if (is_iostat_end(stat)) return
      if (stat /= 0) then
         call namelist_read_error(error, 'model', 0, msg, 'selection, speed_tolerance, ' // &
            'force_tolerance, candidate_modes, resonance_floor')
         return
      end if
      ! selection's word and the ranges were checked by the key spec (model_keys)
      selection = to_lower(selection)
      input%selection = selection
      input%speed_tolerance = speed_tolerance
      input%force_tolerance = force_tolerance
      input%candidate_modes = candidate_modes
      input%resonance_floor = resonance_floor
   end subroutine read_model_group

   subroutine read_mechanism_group(unit, input, error)
      integer, intent(in) :: unit
      type(mechanism_input_t), intent(inout) :: input
      type(error_t), allocatable, intent(out) :: error
      character(len=64) :: crank, label
      real(dp) :: crank_angle_deg, crank_speed, gravity(3), progress_interval
      integer :: animation_frames, stat
      character(len=512) :: msg
      namelist /mechanism/ crank, crank_angle_deg, crank_speed, gravity, label, &
         progress_interval, animation_frames
      crank = input%crank
      crank_angle_deg = input%crank_angle_deg
      crank_speed = input%crank_speed
      gravity = input%gravity
      label = input%label
      progress_interval = input%progress_interval
      animation_frames = input%animation_frames
      rewind (unit)
      read (unit, nml=mechanism, iostat=stat, iomsg=msg)
      if (is_iostat_end(stat)) return
      if (stat /= 0) then
         call namelist_read_error(error, 'mechanism', 0, msg, 'crank, crank_angle_deg, ' // &
            'crank_speed, gravity, label, progress_interval, animation_frames')
         return
      end if
      if (.not. (progress_interval > 0.0_dp)) then
         call fatal_error(error, FFRF_INPUT_ERROR, '&mechanism: progress_interval = ' // &
            to_str(progress_interval) // ' s, must be > 0')
      else if (animation_frames < 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, '&mechanism: animation_frames = ' // &
            to_str(animation_frames) // ', must be >= 0 (0: no animation file)')
      end if
      input = mechanism_input_t(crank, crank_angle_deg, crank_speed, gravity, label, &
         progress_interval, animation_frames)
   end subroutine read_mechanism_group

   subroutine read_marker_groups(unit, src, markers, error)
      integer, intent(in) :: unit
      type(nml_source_t), intent(in) :: src
      type(marker_input_t), allocatable, intent(out) :: markers(:)
      type(error_t), allocatable, intent(out) :: error
      type(marker_input_t) :: defaults
      character(len=64) :: body, name
      real(dp) :: position(3), orientation(9)
      integer :: stat, k
      character(len=512) :: msg
      namelist /marker/ body, name, position, orientation
      allocate (markers(0))
      rewind (unit)
      do
         body = defaults%body
         name = defaults%name
         position = defaults%position
         ! all zero: not given (a zero matrix is no rotation)
         orientation = 0.0_dp
         read (unit, nml=marker, iostat=stat, iomsg=msg)
         if (is_iostat_end(stat)) exit
         if (stat /= 0) then
            call namelist_read_error(error, 'marker', size(markers) + 1, msg, &
               'body, name, position, orientation')
            return
         end if
         k = size(markers) + 1
         if (len_trim(body) == 0 .or. len_trim(name) == 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('marker', k, '') // &
               ': body and name are required')
            return
         end if
         if (any(markers%body == body .and. markers%name == name)) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('marker', k, 'name') // &
               ': marker "' // trim(name) // '" of body "' // trim(body) // '" is given twice')
            return
         end if
         if (any(orientation /= 0.0_dp)) then
            call check_rotation(transpose(reshape(orientation, [3, 3])), &
               src%where('marker', k, 'orientation') // ': marker "' // trim(name) // &
               '" of body "' // trim(body) // '": the orientation', error)
            if (allocated(error)) return
            markers = [markers, marker_input_t(body, name, position, &
               transpose(reshape(orientation, [3, 3])), .true.)]
         else
            markers = [markers, marker_input_t(body, name, position)]
         end if
      end do
   end subroutine read_marker_groups

   subroutine read_joint_groups(unit, src, joints, error)
      integer, intent(in) :: unit
      type(nml_source_t), intent(in) :: src
      type(joint_input_t), allocatable, intent(out) :: joints(:)
      type(error_t), allocatable, intent(out) :: error
      type(joint_input_t) :: defaults
      character(len=64) :: name, body1, marker1, body2, marker2
      character(len=16) :: type
      real(dp) :: axis(3)
      integer :: stat, k
      character(len=512) :: msg
      character(len=:), allocatable :: where
      namelist /joint/ name, type, body1, marker1, body2, marker2, axis
      allocate (joints(0))
      rewind (unit)
      do
         name = defaults%name
         type = defaults%type
         body1 = defaults%body1
         marker1 = defaults%marker1
         body2 = defaults%body2
         marker2 = defaults%marker2
         axis = defaults%axis
         read (unit, nml=joint, iostat=stat, iomsg=msg)
         if (is_iostat_end(stat)) exit
         k = size(joints) + 1
         if (stat /= 0) then
            call namelist_read_error(error, 'joint', k, msg, &
               'name, type, body1, marker1, body2, marker2, axis')
            return
         end if
         where = src%where('joint', k, '') // ' "' // trim(name) // '"'
         type = to_lower(type)
         if (len_trim(name) == 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('joint', k, '') // &
               ': name is missing')
         else if (any(joints%name == name)) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('joint', k, 'name') // &
               ': the name is used twice; joint names must be unique')
         else if (len_trim(type) == 0) then
            ! a word given was checked by the key spec (joint_keys); here only its absence
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': type is missing; give one of ' &
               // choice_words(joint_choices))
         else if (len_trim(body1) == 0 .or. len_trim(marker1) == 0 .or. &
            len_trim(body2) == 0 .or. len_trim(marker2) == 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': body1, marker1, body2 and ' // &
               'marker2 are required')
         else if (body1 == body2) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': body1 and body2 are both "' // &
               trim(body1) // '"; a joint connects two different bodies')
         else if (.not. (norm2(axis) > 0.0_dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('joint', k, 'axis') // &
               ': the axis is zero; give a direction')
         end if
         if (allocated(error)) return
         joints = [joints, joint_input_t(name, type, body1, marker1, body2, marker2, &
            axis / norm2(axis))]
      end do
   end subroutine read_joint_groups

   subroutine read_load_groups(unit, src, loads, error)
      integer, intent(in) :: unit
      type(nml_source_t), intent(in) :: src
      type(load_input_t), allocatable, intent(out) :: loads(:)
      type(error_t), allocatable, intent(out) :: error
      type(load_input_t) :: defaults
      character(len=64) :: name, body, marker
      character(len=16) :: type
      real(dp) :: direction(3), value, stall_torque, free_speed, switch_off, coefficient
      integer :: stat, k
      character(len=512) :: msg
      character(len=:), allocatable :: where
      type(time_law_input_t) :: given_law
      type(time_function_t) :: fun
      character(len=16) :: law
      real(dp) :: initial, final, speed, t_start, duration
      real(dp) :: table_time(max_table_points), table_value(max_table_points)
      character(len=8) :: interpolation, beyond
      namelist /load/ name, type, body, marker, direction, value, stall_torque, free_speed, &
         switch_off, coefficient, law, initial, final, speed, t_start, duration, table_time, &
         table_value, interpolation, beyond
      allocate (loads(0))
      rewind (unit)
      do
         call reset_law_keys(law, initial, final, speed, t_start, duration, table_time, &
            table_value, interpolation, beyond)
         name = defaults%name
         type = defaults%type
         body = defaults%body
         marker = defaults%marker
         direction = defaults%direction
         ! unset: 1 with a law (the law gives the magnitude), else the default
         value = huge(1.0_dp)
         stall_torque = defaults%stall_torque
         free_speed = defaults%free_speed
         switch_off = defaults%switch_off
         coefficient = defaults%coefficient
         read (unit, nml=load, iostat=stat, iomsg=msg)
         if (is_iostat_end(stat)) exit
         k = size(loads) + 1
         if (stat /= 0) then
            call namelist_read_error(error, 'load', k, msg, 'name, type, body, marker, ' // &
               'direction, value, stall_torque, free_speed, switch_off, coefficient, ' // &
               law_key_names)
            return
         end if
         given_law = law_as_given(law, initial, final, speed, t_start, duration, &
            table_time, table_value, interpolation, beyond)
         if (value == huge(1.0_dp)) value = merge(1.0_dp, defaults%value, len_trim(law) > 0)
         type = to_lower(type)
         if (len_trim(name) == 0) name = type
         where = src%where('load', k, '') // ' "' // trim(name) // '"'
         if (len_trim(type) == 0) then
            ! a word given was checked by the key spec (load_keys); here only its absence
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': type is missing; give one of ' &
               // choice_words(load_choices))
         else if (len_trim(body) == 0 .or. len_trim(marker) == 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': body and marker are required')
         else if (.not. (norm2(direction) > 0.0_dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('load', k, 'direction') // &
               ': the direction is zero; give a direction')
         else if (type == 'starter' .and. .not. (free_speed > 0.0_dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': free_speed = ' // &
               to_str(free_speed) // ' rad/s, must be > 0')
         else if (type == 'drag' .and. .not. (coefficient >= 0.0_dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': coefficient = ' // &
               to_str(coefficient) // ' N m s^2, must be >= 0')
         else if (len_trim(law) > 0 .and. type /= 'force' .and. type /= 'torque') then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('load', k, 'law') // ': ' // &
               '&load "' // trim(name) // '" of type ' // trim(type) // ' takes no law; a ' // &
               'law scales a force or torque load')
         else if (len_trim(law) > 0) then
            call law_function(given_law, src%where('load', k, 'law') // ': &load "' // &
               trim(name) // '"', fun, error)
         end if
         if (allocated(error)) return
         ! grown by hand: gfortran 12 leaks the allocatable components of a structure
         ! constructor inside an array constructor (the law's table; seen by ctest
         ! capi_bad_calls_asan)
         block
            type(load_input_t), allocatable :: grown(:)
            allocate (grown(size(loads) + 1))
            grown(:size(loads)) = loads
            grown(size(grown)) = load_input_t(name, type, body, marker, &
               direction / norm2(direction), value, stall_torque, free_speed, switch_off, &
               coefficient, given_law)
            call move_alloc(grown, loads)
         end block
      end do
   end subroutine read_load_groups

   !> The &driver groups (module header), in input order.
   subroutine read_driver_groups(unit, src, drivers, error)
      integer, intent(in) :: unit
      type(nml_source_t), intent(in) :: src
      type(driver_input_t), allocatable, intent(out) :: drivers(:)
      type(error_t), allocatable, intent(out) :: error
      type(driver_input_t) :: defaults
      character(len=64) :: name, joint
      character(len=16) :: quantity
      real(dp) :: offset
      integer :: stat, k
      character(len=512) :: msg
      type(time_law_input_t) :: given_law
      type(time_function_t) :: fun
      character(len=16) :: law
      real(dp) :: initial, final, speed, t_start, duration
      real(dp) :: table_time(max_table_points), table_value(max_table_points)
      character(len=8) :: interpolation, beyond
      namelist /driver/ name, joint, quantity, offset, law, initial, final, speed, t_start, &
         duration, table_time, table_value, interpolation, beyond
      allocate (drivers(0))
      rewind (unit)
      do
         name = defaults%name
         joint = defaults%joint
         quantity = defaults%quantity
         offset = defaults%offset
         call reset_law_keys(law, initial, final, speed, t_start, duration, table_time, &
            table_value, interpolation, beyond)
         law = 'constant_speed'
         read (unit, nml=driver, iostat=stat, iomsg=msg)
         if (is_iostat_end(stat)) exit
         k = size(drivers) + 1
         if (stat /= 0) then
            call namelist_read_error(error, 'driver', k, msg, 'name, joint, quantity, ' // &
               'offset, ' // law_key_names)
            return
         end if
         given_law = law_as_given(law, initial, final, speed, t_start, duration, &
            table_time, table_value, interpolation, beyond)
         quantity = to_lower(quantity)
         if (len_trim(name) == 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('driver', k, '') // &
               ': name is missing')
         else if (any(drivers%name == name)) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('driver', k, 'name') // &
               ': the name is used twice; driver names must be unique')
         else if (len_trim(joint) == 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('driver', k, '') // &
               ': &driver "' // trim(name) // '": joint is required (a revolute or ' // &
               'prismatic &joint)')
         else
            call law_function(given_law, src%where('driver', k, 'law') // ': &driver "' // &
               trim(name) // '"', fun, error)
         end if
         if (allocated(error)) return
         block   ! grown by hand, as the loads (read_load_groups)
            type(driver_input_t), allocatable :: grown(:)
            allocate (grown(size(drivers) + 1))
            grown(:size(drivers)) = drivers
            grown(size(grown)) = driver_input_t(name, joint, quantity, offset, given_law)
            call move_alloc(grown, drivers)
         end block
      end do
   end subroutine read_driver_groups

   !> The law keys' defaults before a read (time_law_input_t; table entries unset: huge).
   pure subroutine reset_law_keys(law, initial, final, speed, t_start, duration, table_time, &
         table_value, interpolation, beyond)
      character(len=*), intent(out) :: law, interpolation, beyond
      real(dp), intent(out) :: initial, final, speed, t_start, duration
      real(dp), intent(out) :: table_time(:), table_value(:)
      type(time_law_input_t) :: defaults
      law = defaults%law
      initial = defaults%initial
      final = defaults%final
      speed = defaults%speed
      t_start = defaults%t_start
      duration = defaults%duration
      table_time = huge(1.0_dp)
      table_value = huge(1.0_dp)
      interpolation = defaults%interpolation
      beyond = defaults%beyond
   end subroutine reset_law_keys

   !> The law keys as read (the table entries given: those before the first unset one).
   pure function law_as_given(law, initial, final, speed, t_start, duration, table_time, &
         table_value, interpolation, beyond) result(given)
      character(len=*), intent(in) :: law, interpolation, beyond
      real(dp), intent(in) :: initial, final, speed, t_start, duration
      real(dp), intent(in) :: table_time(:), table_value(:)
      type(time_law_input_t) :: given
      given%law = to_lower(law)
      given%initial = initial
      given%final = final
      given%speed = speed
      given%t_start = t_start
      given%duration = duration
      given%table_time = table_time(:count_set(table_time))
      given%table_value = table_value(:count_set(table_value))
      given%interpolation = to_lower(interpolation)
      given%beyond = to_lower(beyond)
   end function law_as_given

   !> Number of leading entries not unset (huge).
   pure integer function count_set(values) result(n)
      real(dp), intent(in) :: values(:)
      do n = 0, size(values) - 1
         if (values(n + 1) == huge(1.0_dp)) return
      end do
      n = size(values)
   end function count_set

   !> The &spring groups (module header), in input order.
   subroutine read_spring_groups(unit, src, springs, error)
      integer, intent(in) :: unit
      type(nml_source_t), intent(in) :: src
      type(spring_input_t), allocatable, intent(out) :: springs(:)
      type(error_t), allocatable, intent(out) :: error
      type(spring_input_t) :: defaults
      character(len=64) :: name, body1, marker1, body2, marker2
      real(dp) :: stiffness, damping, free_length
      integer :: stat, k
      character(len=512) :: msg
      namelist /spring/ name, body1, marker1, body2, marker2, stiffness, damping, free_length
      allocate (springs(0))
      rewind (unit)
      do
         name = defaults%name
         body1 = defaults%body1
         marker1 = defaults%marker1
         body2 = defaults%body2
         marker2 = defaults%marker2
         stiffness = defaults%stiffness
         damping = defaults%damping
         free_length = defaults%free_length
         read (unit, nml=spring, iostat=stat, iomsg=msg)
         if (is_iostat_end(stat)) exit
         k = size(springs) + 1
         if (stat /= 0) then
            call namelist_read_error(error, 'spring', k, msg, 'name, body1, marker1, body2, ' &
               // 'marker2, stiffness, damping, free_length')
            return
         end if
         call check_marker_pair_group(src, 'spring', k, name, springs%name, body1, marker1, &
            body2, marker2, error)
         if (allocated(error)) return
         springs = [springs, spring_input_t(name, body1, marker1, body2, marker2, stiffness, &
            damping, free_length)]
      end do
   end subroutine read_spring_groups

   !> The &torsion_spring groups (module header), in input order.
   subroutine read_torsion_spring_groups(unit, src, springs, error)
      integer, intent(in) :: unit
      type(nml_source_t), intent(in) :: src
      type(torsion_spring_input_t), allocatable, intent(out) :: springs(:)
      type(error_t), allocatable, intent(out) :: error
      type(torsion_spring_input_t) :: defaults
      character(len=64) :: name, joint
      real(dp) :: stiffness, damping, free_angle
      real(dp), parameter :: unset = huge(1.0_dp)
      integer :: stat, k
      character(len=512) :: msg
      namelist /torsion_spring/ name, joint, stiffness, damping, free_angle
      allocate (springs(0))
      rewind (unit)
      do
         name = defaults%name
         joint = defaults%joint
         stiffness = defaults%stiffness
         damping = defaults%damping
         free_angle = unset
         read (unit, nml=torsion_spring, iostat=stat, iomsg=msg)
         if (is_iostat_end(stat)) exit
         k = size(springs) + 1
         if (stat /= 0) then
            call namelist_read_error(error, 'torsion_spring', k, msg, 'name, joint, ' // &
               'stiffness, damping, free_angle')
            return
         end if
         if (len_trim(name) == 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('torsion_spring', k, '') // &
               ': name is missing')
         else if (any(springs%name == name)) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('torsion_spring', k, 'name') &
               // ': the name is used twice; torsion spring names must be unique')
         else if (len_trim(joint) == 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('torsion_spring', k, '') // &
               ' "' // trim(name) // '": joint is required (a revolute or cylindrical &joint)')
         end if
         if (allocated(error)) return
         springs = [springs, torsion_spring_input_t(name, joint, stiffness, damping, &
            merge(0.0_dp, free_angle, free_angle == unset), free_angle /= unset)]
      end do
   end subroutine read_torsion_spring_groups

   !> The rules a group between two markers of two bodies shares (&spring, &bushing; group k,
   !> `names` those of the groups before it): a unique name, all four ends, two bodies.
   subroutine check_marker_pair_group(src, group, k, name, names, body1, marker1, body2, &
      marker2, error)
      type(nml_source_t), intent(in) :: src
      character(len=*), intent(in) :: group, name, body1, marker1, body2, marker2
      integer, intent(in) :: k
      character(len=*), intent(in) :: names(:)
      type(error_t), allocatable, intent(out) :: error
      if (len_trim(name) == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, src%where(group, k, '') // &
            ': name is missing')
      else if (any(names == name)) then
         call fatal_error(error, FFRF_INPUT_ERROR, src%where(group, k, 'name') // &
            ': the name is used twice; ' // group // ' names must be unique')
      else if (len_trim(body1) == 0 .or. len_trim(marker1) == 0 .or. &
         len_trim(body2) == 0 .or. len_trim(marker2) == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, src%where(group, k, '') // ' "' // &
            trim(name) // '": body1, marker1, body2 and marker2 are required')
      else if (body1 == body2) then
         call fatal_error(error, FFRF_INPUT_ERROR, src%where(group, k, 'body2') // ': &' // &
            group // ' "' // trim(name) // '": body1 and body2 are both "' // trim(body1) // &
            '"; a ' // group // ' connects two different bodies')
      end if
   end subroutine check_marker_pair_group

   !> The &bushing groups (module header), in input order.
   subroutine read_bushing_groups(unit, src, bushings, error)
      integer, intent(in) :: unit
      type(nml_source_t), intent(in) :: src
      type(bushing_input_t), allocatable, intent(out) :: bushings(:)
      type(error_t), allocatable, intent(out) :: error
      type(bushing_input_t) :: defaults
      character(len=64) :: name, body1, marker1, body2, marker2
      real(dp) :: stiffness(6), damping(6)
      integer :: stat, k
      character(len=512) :: msg
      namelist /bushing/ name, body1, marker1, body2, marker2, stiffness, damping
      allocate (bushings(0))
      rewind (unit)
      do
         name = defaults%name
         body1 = defaults%body1
         marker1 = defaults%marker1
         body2 = defaults%body2
         marker2 = defaults%marker2
         stiffness = defaults%stiffness
         damping = defaults%damping
         read (unit, nml=bushing, iostat=stat, iomsg=msg)
         if (is_iostat_end(stat)) exit
         k = size(bushings) + 1
         if (stat /= 0) then
            call namelist_read_error(error, 'bushing', k, msg, 'name, body1, marker1, body2, ' &
               // 'marker2, stiffness, damping')
            return
         end if
         call check_marker_pair_group(src, 'bushing', k, name, bushings%name, body1, marker1, &
            body2, marker2, error)
         if (allocated(error)) return
         bushings = [bushings, bushing_input_t(name, body1, marker1, body2, marker2, &
            stiffness, damping)]
      end do
   end subroutine read_bushing_groups

   subroutine read_pressure_group(unit, input, table_file, error)
      integer, intent(in) :: unit
      type(pressure_input_t), intent(inout) :: input
      character(len=*), intent(inout) :: table_file
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: bore, stroke, conrod_length, compression_ratio, intake_pressure, &
         exhaust_pressure, polytropic_exponent, wiebe_a, wiebe_m, combustion_start_deg, &
         combustion_duration_deg, heat_per_cycle, target_peak_pressure, reference_pressure
      integer :: stat
      character(len=512) :: msg
      namelist /pressure/ bore, stroke, conrod_length, compression_ratio, intake_pressure, &
         exhaust_pressure, polytropic_exponent, wiebe_a, wiebe_m, combustion_start_deg, &
         combustion_duration_deg, heat_per_cycle, target_peak_pressure, reference_pressure, &
         table_file
      bore = input%bore
      stroke = input%stroke
      conrod_length = input%conrod_length
      compression_ratio = input%compression_ratio
      intake_pressure = input%intake_pressure
      exhaust_pressure = input%exhaust_pressure
      polytropic_exponent = input%polytropic_exponent
      wiebe_a = input%wiebe_a
      wiebe_m = input%wiebe_m
      combustion_start_deg = input%combustion_start_deg
      combustion_duration_deg = input%combustion_duration_deg
      heat_per_cycle = input%heat_per_cycle
      target_peak_pressure = input%target_peak_pressure
      reference_pressure = input%reference_pressure
      rewind (unit)
      read (unit, nml=pressure, iostat=stat, iomsg=msg)
      if (is_iostat_end(stat)) return
      if (stat /= 0) then
         call namelist_read_error(error, 'pressure', 0, msg, 'bore, stroke, conrod_length, ' // &
            'compression_ratio, intake_pressure, exhaust_pressure, polytropic_exponent, ' // &
            'wiebe_a, wiebe_m, combustion_start_deg, combustion_duration_deg, ' // &
            'heat_per_cycle, target_peak_pressure, reference_pressure, table_file')
         return
      end if
      ! Ranges are checked by pressure_model_t%init with the key names.
      input = pressure_input_t(bore, stroke, conrod_length, compression_ratio, &
         intake_pressure, exhaust_pressure, polytropic_exponent, wiebe_a, wiebe_m, &
         combustion_start_deg, combustion_duration_deg, heat_per_cycle, target_peak_pressure, &
         reference_pressure, input%step_deg)
   end subroutine read_pressure_group

   subroutine read_integrator_group(unit, src, settings, h_given, error, watch)
      integer, intent(in) :: unit
      type(nml_source_t), intent(in) :: src
      type(galpha_settings_t), intent(inout) :: settings
      !> .true. when the group gives h
      logical, intent(out) :: h_given
      type(error_t), allocatable, intent(out) :: error
      !> The energy watch of the run (energy_watch, energy_watch_tolerance, energy_watch_window)
      type(energy_watch_settings_t), intent(inout) :: watch
      real(dp) :: h, t_end, rho_inf, newton_atol, newton_rtol, min_step, rank_rtol
      real(dp) :: checkpoint_seconds, energy_watch_tolerance, energy_watch_window
      integer :: max_iterations, tangent_reuse, checkpoint_steps, stat, sparse_threshold
      character(len=16) :: jacobian, energy_watch
      character(len=512) :: msg
      namelist /integrator/ h, t_end, rho_inf, newton_atol, newton_rtol, max_iterations, &
         min_step, rank_rtol, jacobian, tangent_reuse, checkpoint_seconds, checkpoint_steps, &
         energy_watch, energy_watch_tolerance, energy_watch_window, sparse_threshold
      energy_watch = energy_watch_word(watch%mode)
      energy_watch_tolerance = watch%tolerance
      energy_watch_window = watch%window
      h = -1.0_dp
      checkpoint_seconds = settings%checkpoint_seconds
      checkpoint_steps = settings%checkpoint_steps
      t_end = settings%t_end
      rho_inf = settings%rho_inf
      newton_atol = settings%newton_atol
      newton_rtol = settings%newton_rtol
      max_iterations = settings%max_iterations
      min_step = settings%min_step
      rank_rtol = settings%rank_rtol
      tangent_reuse = settings%tangent_reuse
      sparse_threshold = settings%sparse_threshold
      jacobian = choice_name(jacobian_choices, settings%jacobian, 'step')
      rewind (unit)
      read (unit, nml=integrator, iostat=stat, iomsg=msg)
      if (.not. is_iostat_end(stat)) then
         if (stat /= 0) then
            call namelist_read_error(error, 'integrator', 0, msg, 'h, t_end, rho_inf, ' // &
               'newton_atol, newton_rtol, max_iterations, min_step, rank_rtol, jacobian, ' // &
               'tangent_reuse, checkpoint_seconds, checkpoint_steps, energy_watch, ' // &
               'energy_watch_tolerance, energy_watch_window, sparse_threshold')
            return
         end if
      end if
      h_given = src%has_key('integrator', 1, 'h')
      if (h_given) settings%h = h
      settings%t_end = t_end
      settings%rho_inf = rho_inf
      settings%newton_atol = newton_atol
      settings%newton_rtol = newton_rtol
      settings%max_iterations = max_iterations
      settings%min_step = min_step
      settings%rank_rtol = rank_rtol
      settings%tangent_reuse = tangent_reuse
      settings%sparse_threshold = sparse_threshold
      settings%checkpoint_seconds = checkpoint_seconds
      settings%checkpoint_steps = checkpoint_steps
      ! the words of energy_watch and jacobian were checked by the key spec (integrator_keys)
      watch%mode = energy_watch_kind(to_lower(energy_watch))
      watch%tolerance = energy_watch_tolerance
      watch%window = energy_watch_window
      settings%jacobian = jacobian_choices(choice_position(jacobian_choices, jacobian))%kind
      if (.not. (settings%min_step <= settings%h)) then
         call fatal_error(error, FFRF_INPUT_ERROR, src%where('integrator', 1, 'min_step') // &
            ': must not exceed h = ' // to_str(settings%h) // ' s')
         return
      end if
      call check_galpha_settings(settings, error)
      if (allocated(error)) error%message = src%where('integrator', 1, '') // ': ' // &
         error%message
   end subroutine read_integrator_group

end module ffrf_input_nml_mechanism
