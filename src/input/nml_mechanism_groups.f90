!> The readers of the mechanism's single and structural groups (ffrf_input_nml_mechanism):
!> &mechanism, &model, &marker, &joint, &pressure and &integrator.
submodule (ffrf_input_nml_mechanism) ffrf_input_nml_mechanism_groups
   implicit none

contains

   module procedure read_model_group
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
   end procedure read_model_group

   module procedure read_mechanism_group
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
   end procedure read_mechanism_group

   module procedure read_marker_groups
      type(marker_input_t) :: defaults
      character(len=64) :: body, name
      character(len=64) :: group
      character(len=16) :: weighting
      real(dp) :: position(3), orientation(9)
      integer :: stat, k, node
      character(len=512) :: msg
      namelist /marker/ body, name, position, orientation, node, group, weighting
      allocate (markers(0))
      rewind (unit)
      do
         body = defaults%body
         name = defaults%name
         position = defaults%position
         node = defaults%node
         group = defaults%group
         weighting = defaults%weighting
         ! all zero: not given (a zero matrix is no rotation)
         orientation = 0.0_dp
         read (unit, nml=marker, iostat=stat, iomsg=msg)
         if (is_iostat_end(stat)) exit
         if (stat /= 0) then
            call namelist_read_error(error, 'marker', size(markers) + 1, msg, &
               'body, name, position, orientation, node, group, weighting')
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
         if (node > 0 .and. len_trim(group) > 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('marker', k, 'group') // &
               ': marker "' // trim(name) // '" of body "' // trim(body) // '" gives node ' // &
               'and group; give one (a mesh node, or the centre of a physical group)')
            return
         end if
         if ((node > 0 .or. len_trim(group) > 0) .and. any(position /= 0.0_dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('marker', k, 'position') // &
               ': marker "' // trim(name) // '" of body "' // trim(body) // '" gives a ' // &
               'position and a node or group, which places it; drop the position')
            return
         end if
         if (any(orientation /= 0.0_dp)) then
            call check_rotation(transpose(reshape(orientation, [3, 3])), &
               src%where('marker', k, 'orientation') // ': marker "' // trim(name) // &
               '" of body "' // trim(body) // '": the orientation', error)
            if (allocated(error)) return
            markers = [markers, marker_input_t(body, name, position, &
               transpose(reshape(orientation, [3, 3])), .true., node, group, to_lower(weighting))]
         else
            markers = [markers, marker_input_t(body, name, position, node=node, group=group, &
               weighting=to_lower(weighting))]
         end if
      end do
   end procedure read_marker_groups

   module procedure read_joint_groups
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
   end procedure read_joint_groups

   module procedure read_pressure_group
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
   end procedure read_pressure_group

   module procedure read_integrator_group
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
   end procedure read_integrator_group

end submodule ffrf_input_nml_mechanism_groups
