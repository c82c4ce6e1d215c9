!> Namelist groups of a mechanism run (a case with at least one &joint is a mechanism run):
!>   &mechanism   crank, crank_angle_deg, crank_speed [rad/s], gravity [m/s^2], label,
!>                progress_interval [s], animation_frames                     (optional, single)
!>   &marker      body, name, position [m, body frame; ground: global]       (repeatable)
!>   &joint       name, type, body1, marker1, body2, marker2, axis            (repeatable)
!>   &load        name, type (pressure|starter|drag|force|torque), body, marker, direction,
!>                value, stall_torque, free_speed, switch_off, coefficient    (repeatable)
!>   &pressure    bore, stroke, conrod_length, compression_ratio, intake_pressure,
!>                exhaust_pressure, polytropic_exponent, wiebe_a, wiebe_m,
!>                combustion_start_deg, combustion_duration_deg, heat_per_cycle,
!>                target_peak_pressure, reference_pressure, table_file    (optional, single)
!>   &integrator  h, t_end, rho_inf, newton_atol, newton_rtol, max_iterations, min_step,
!>                rank_rtol, jacobian ('adaptive', 'step', 'full'), tangent_reuse,
!>                checkpoint_seconds, checkpoint_steps                       (optional, single)
!>   &model       selection ('auto', 'manual'), speed_tolerance, force_tolerance,
!>                candidate_modes, resonance_floor                            (optional, single)
!> Defaults: ffrf_mbs_mechanism_input, ffrf_mbs_pressure's pressure_input_t (the scene's engine)
!> and galpha_settings_t. Names are checked against each other by ffrf_io_case.
module ffrf_io_nml_mechanism
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str, to_lower
   use ffrf_io_nml_common, only: namelist_read_error
   use ffrf_mbs_mechanism_input, only: mechanism_case_input_t, mechanism_input_t, &
      marker_input_t, joint_input_t, load_input_t, model_input_t
   use ffrf_mbs_pressure, only: pressure_input_t
   use ffrf_mbs_generalized_alpha, only: galpha_settings_t, check_galpha_settings, &
      GALPHA_NEWTON_FULL, GALPHA_NEWTON_STEP, GALPHA_NEWTON_ADAPTIVE
   use ffrf_mbs_joints, only: joint_kinds
   implicit none
   private
   public :: read_mechanism_groups, has_group

   !> Load types &load accepts
   character(len=*), parameter :: load_types = 'pressure, starter, drag, force, torque'

contains

   !> .true. when the open case file has a line starting with &<group> (any case).
   function has_group(unit, group) result(found)
      integer, intent(in) :: unit
      character(len=*), intent(in) :: group
      logical :: found
      character(len=512) :: line
      integer :: stat, n
      found = .false.
      n = len(group) + 1
      rewind (unit)
      do
         read (unit, '(a)', iostat=stat) line
         if (stat /= 0) exit
         line = adjustl(line)
         if (to_lower(line(1:n)) == '&' // group .and. scan(line(n + 1:n + 1), ' /,') == 1) then
            found = .true.
            exit
         end if
      end do
      rewind (unit)
   end function has_group

   !> Read every mechanism group of the open case file.
   subroutine read_mechanism_groups(unit, input, error)
      integer, intent(in) :: unit
      type(mechanism_case_input_t), intent(out) :: input
      type(error_t), allocatable, intent(out) :: error
      call read_mechanism_group(unit, input%mechanism, error)
      if (.not. allocated(error)) call read_marker_groups(unit, input%markers, error)
      if (.not. allocated(error)) call read_joint_groups(unit, input%joints, error)
      if (.not. allocated(error)) call read_load_groups(unit, input%loads, error)
      if (.not. allocated(error)) call read_pressure_group(unit, input%pressure, &
         input%pressure_table, error)
      if (.not. allocated(error)) call read_integrator_group(unit, input%integrator, &
         input%model%h_given, error)
      if (.not. allocated(error)) call read_model_group(unit, input%model, error)
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
      selection = to_lower(selection)
      if (all(selection /= [character(len=16) :: 'auto', 'manual'])) then
         call fatal_error(error, FFRF_INPUT_ERROR, '&model: selection = ''' // trim(selection) &
            // ''', must be ''auto'' or ''manual''')
      else if (.not. (speed_tolerance > 0.0_dp .and. speed_tolerance < 1.0_dp)) then
         call fatal_error(error, FFRF_INPUT_ERROR, '&model: speed_tolerance = ' // &
            to_str(speed_tolerance) // ', must lie in (0, 1) (relative error, e.g. 1e-3)')
      else if (.not. (force_tolerance > 0.0_dp .and. force_tolerance < 1.0_dp)) then
         call fatal_error(error, FFRF_INPUT_ERROR, '&model: force_tolerance = ' // &
            to_str(force_tolerance) // ', must lie in (0, 1) (relative error, e.g. 1e-2)')
      else if (.not. (resonance_floor > 0.0_dp .and. resonance_floor <= 1.0_dp)) then
         call fatal_error(error, FFRF_INPUT_ERROR, '&model: resonance_floor = ' // &
            to_str(resonance_floor) // ', must lie in (0, 1]')
      else if (candidate_modes < 1 .or. candidate_modes > 200) then
         call fatal_error(error, FFRF_INPUT_ERROR, '&model: candidate_modes = ' // &
            to_str(candidate_modes) // ', must lie in 1..200')
      end if
      if (allocated(error)) return
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

   subroutine read_marker_groups(unit, markers, error)
      integer, intent(in) :: unit
      type(marker_input_t), allocatable, intent(out) :: markers(:)
      type(error_t), allocatable, intent(out) :: error
      type(marker_input_t) :: defaults
      character(len=64) :: body, name
      real(dp) :: position(3)
      integer :: stat, k
      character(len=512) :: msg
      namelist /marker/ body, name, position
      allocate (markers(0))
      rewind (unit)
      do
         body = defaults%body
         name = defaults%name
         position = defaults%position
         read (unit, nml=marker, iostat=stat, iomsg=msg)
         if (is_iostat_end(stat)) exit
         if (stat /= 0) then
            call namelist_read_error(error, 'marker', size(markers) + 1, msg, &
               'body, name, position')
            return
         end if
         k = size(markers) + 1
         if (len_trim(body) == 0 .or. len_trim(name) == 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, '&marker #' // to_str(k) // &
               ': body and name are required')
            return
         end if
         if (any(markers%body == body .and. markers%name == name)) then
            call fatal_error(error, FFRF_INPUT_ERROR, '&marker #' // to_str(k) // ' "' // &
               trim(name) // '" of body "' // trim(body) // '" is given twice')
            return
         end if
         markers = [markers, marker_input_t(body, name, position)]
      end do
   end subroutine read_marker_groups

   subroutine read_joint_groups(unit, joints, error)
      integer, intent(in) :: unit
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
         where = '&joint #' // to_str(k) // ' "' // trim(name) // '"'
         type = to_lower(type)
         if (len_trim(name) == 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, '&joint #' // to_str(k) // &
               ': name is missing')
         else if (any(joints%name == name)) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': the name is used twice')
         else if (index(joint_kinds, trim(type)) == 0 .or. len_trim(type) == 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': type = ''' // trim(type) // &
               ''', must be one of ' // joint_kinds)
         else if (len_trim(body1) == 0 .or. len_trim(marker1) == 0 .or. &
            len_trim(body2) == 0 .or. len_trim(marker2) == 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': body1, marker1, body2 and ' // &
               'marker2 are required')
         else if (body1 == body2) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': body1 and body2 are both "' // &
               trim(body1) // '"; a joint connects two different bodies')
         else if (.not. (norm2(axis) > 0.0_dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': axis is zero')
         end if
         if (allocated(error)) return
         joints = [joints, joint_input_t(name, type, body1, marker1, body2, marker2, &
            axis / norm2(axis))]
      end do
   end subroutine read_joint_groups

   subroutine read_load_groups(unit, loads, error)
      integer, intent(in) :: unit
      type(load_input_t), allocatable, intent(out) :: loads(:)
      type(error_t), allocatable, intent(out) :: error
      type(load_input_t) :: defaults
      character(len=64) :: name, body, marker
      character(len=16) :: type
      real(dp) :: direction(3), value, stall_torque, free_speed, switch_off, coefficient
      integer :: stat, k
      character(len=512) :: msg
      character(len=:), allocatable :: where
      namelist /load/ name, type, body, marker, direction, value, stall_torque, free_speed, &
         switch_off, coefficient
      allocate (loads(0))
      rewind (unit)
      do
         name = defaults%name
         type = defaults%type
         body = defaults%body
         marker = defaults%marker
         direction = defaults%direction
         value = defaults%value
         stall_torque = defaults%stall_torque
         free_speed = defaults%free_speed
         switch_off = defaults%switch_off
         coefficient = defaults%coefficient
         read (unit, nml=load, iostat=stat, iomsg=msg)
         if (is_iostat_end(stat)) exit
         k = size(loads) + 1
         if (stat /= 0) then
            call namelist_read_error(error, 'load', k, msg, 'name, type, body, marker, ' // &
               'direction, value, stall_torque, free_speed, switch_off, coefficient')
            return
         end if
         type = to_lower(type)
         if (len_trim(name) == 0) name = type
         where = '&load #' // to_str(k) // ' "' // trim(name) // '"'
         if (all(type /= [character(len=16) :: 'pressure', 'starter', 'drag', 'force', &
            'torque'])) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': type = ''' // trim(type) // &
               ''', must be one of ' // load_types)
         else if (len_trim(body) == 0 .or. len_trim(marker) == 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': body and marker are required')
         else if (.not. (norm2(direction) > 0.0_dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': direction is zero')
         else if (type == 'starter' .and. .not. (free_speed > 0.0_dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': free_speed = ' // &
               to_str(free_speed) // ' rad/s, must be > 0')
         else if (type == 'drag' .and. .not. (coefficient >= 0.0_dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': coefficient = ' // &
               to_str(coefficient) // ' N m s^2, must be >= 0')
         end if
         if (allocated(error)) return
         loads = [loads, load_input_t(name, type, body, marker, direction / norm2(direction), &
            value, stall_torque, free_speed, switch_off, coefficient)]
      end do
   end subroutine read_load_groups

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

   subroutine read_integrator_group(unit, settings, h_given, error)
      integer, intent(in) :: unit
      type(galpha_settings_t), intent(inout) :: settings
      !> .true. when the group gives h
      logical, intent(out) :: h_given
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: h, t_end, rho_inf, newton_atol, newton_rtol, min_step, rank_rtol
      real(dp) :: checkpoint_seconds
      integer :: max_iterations, tangent_reuse, checkpoint_steps, stat
      character(len=16) :: jacobian
      character(len=512) :: msg
      namelist /integrator/ h, t_end, rho_inf, newton_atol, newton_rtol, max_iterations, &
         min_step, rank_rtol, jacobian, tangent_reuse, checkpoint_seconds, checkpoint_steps
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
      select case (settings%jacobian)
      case (GALPHA_NEWTON_FULL)
         jacobian = 'full'
      case (GALPHA_NEWTON_ADAPTIVE)
         jacobian = 'adaptive'
      case default
         jacobian = 'step'
      end select
      rewind (unit)
      read (unit, nml=integrator, iostat=stat, iomsg=msg)
      if (.not. is_iostat_end(stat)) then
         if (stat /= 0) then
            call namelist_read_error(error, 'integrator', 0, msg, 'h, t_end, rho_inf, ' // &
               'newton_atol, newton_rtol, max_iterations, min_step, rank_rtol, jacobian, ' // &
               'tangent_reuse, checkpoint_seconds, checkpoint_steps')
            return
         end if
      end if
      h_given = h /= -1.0_dp
      if (h_given) settings%h = h
      settings%t_end = t_end
      settings%rho_inf = rho_inf
      settings%newton_atol = newton_atol
      settings%newton_rtol = newton_rtol
      settings%max_iterations = max_iterations
      settings%min_step = min_step
      settings%rank_rtol = rank_rtol
      settings%tangent_reuse = tangent_reuse
      settings%checkpoint_seconds = checkpoint_seconds
      settings%checkpoint_steps = checkpoint_steps
      select case (to_lower(jacobian))
      case ('adaptive')
         settings%jacobian = GALPHA_NEWTON_ADAPTIVE
      case ('step')
         settings%jacobian = GALPHA_NEWTON_STEP
      case ('full')
         settings%jacobian = GALPHA_NEWTON_FULL
      case default
         call fatal_error(error, FFRF_INPUT_ERROR, '&integrator: jacobian = ''' // &
            trim(jacobian) // ''', must be ''adaptive'', ''step'' or ''full''')
         return
      end select
      call check_galpha_settings(settings, error)
      if (allocated(error)) error%message = '&integrator: ' // error%message
   end subroutine read_integrator_group

end module ffrf_io_nml_mechanism
