!> The readers of the mechanism's single and structural groups (ffrf_input_nml_mechanism):
!> &mechanism, &model, &marker, &joint, &pressure and &integrator.
submodule (ffrf_input_nml_mechanism) ffrf_input_nml_mechanism_groups
   implicit none

contains

   module procedure read_model_group
      integer :: stat
      character(len=512) :: msg
      character(len=64), allocatable :: names(:)
      real(dp), allocatable :: tolerances(:)
      rewind (unit)
      call read_model(input%selection, input%speed_tolerance, input%force_tolerance, &
         input%candidate_modes, input%resonance_floor, input%targets)
      if (is_iostat_end(stat)) return
      call read_status(src, 'model', 0, stat, msg, error)
      if (.not. allocated(error)) call parse_targets(input%targets, names, tolerances, error)
      ! selection's word and the ranges were checked by the key spec (model_keys)
      input%selection = to_lower(input%selection)
   contains
      !> The namelist read of &model into its fields (absent keys keep their values).
      subroutine read_model(selection, speed_tolerance, force_tolerance, candidate_modes, &
            resonance_floor, targets)
         character(len=*), intent(inout) :: selection, targets
         real(dp), intent(inout) :: speed_tolerance, force_tolerance, resonance_floor
         integer, intent(inout) :: candidate_modes
         namelist /model/ selection, speed_tolerance, force_tolerance, candidate_modes, &
            resonance_floor, targets
         read (unit, nml=model, iostat=stat, iomsg=msg)
      end subroutine read_model
   end procedure read_model_group

   module procedure read_mechanism_group
      integer :: stat
      character(len=512) :: msg
      rewind (unit)
      call read_mechanism(input%crank, input%crank_angle_deg, input%crank_speed, input%gravity, &
         input%label, input%progress_interval, input%animation_frames)
      if (is_iostat_end(stat)) return
      call read_status(src, 'mechanism', 0, stat, msg, error)
      if (allocated(error)) return
      if (.not. (input%progress_interval > 0.0_dp)) then
         call fatal_error(error, FFRF_INPUT_ERROR, '&mechanism: progress_interval = ' // &
            to_str(input%progress_interval) // ' s, must be > 0')
      else if (input%animation_frames < 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, '&mechanism: animation_frames = ' // &
            to_str(input%animation_frames) // ', must be >= 0 (0: no animation file)')
      end if
   contains
      !> The namelist read of &mechanism into its fields (absent keys keep their values).
      subroutine read_mechanism(crank, crank_angle_deg, crank_speed, gravity, label, &
            progress_interval, animation_frames)
         character(len=*), intent(inout) :: crank, label
         real(dp), intent(inout) :: crank_angle_deg, crank_speed, gravity(3), progress_interval
         integer, intent(inout) :: animation_frames
         namelist /mechanism/ crank, crank_angle_deg, crank_speed, gravity, label, &
            progress_interval, animation_frames
         read (unit, nml=mechanism, iostat=stat, iomsg=msg)
      end subroutine read_mechanism
   end procedure read_mechanism_group

   module procedure read_marker_groups
      real(dp) :: orientation(9)
      integer :: k, stat
      character(len=512) :: msg
      allocate (markers(src%count('marker')))
      rewind (unit)
      do k = 1, size(markers)
         ! all zero: not given (a zero matrix is no rotation)
         orientation = 0.0_dp
         call read_marker(markers(k)%body, markers(k)%name, markers(k)%position, orientation, &
            markers(k)%node, markers(k)%group, markers(k)%weighting)
         if (allocated(error)) return
      end do
   contains
      !> &marker k: the namelist read into its fields (absent keys keep their defaults), then
      !> its rules: body and name, given once, an orientation that is a rotation, a mesh point
      !> (node or group) that is not also given a position, no weighting at a node.
      subroutine read_marker(body, name, position, orientation, node, group, weighting)
         character(len=*), intent(inout) :: body, name, group, weighting
         real(dp), intent(inout) :: position(3), orientation(9)
         integer, intent(inout) :: node
         namelist /marker/ body, name, position, orientation, node, group, weighting
         read (unit, nml=marker, iostat=stat, iomsg=msg)
         call read_status(src, 'marker', k, stat, msg, error)
         if (allocated(error)) return
         weighting = to_lower(weighting)
         if (len_trim(body) == 0 .or. len_trim(name) == 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('marker', k, '') // &
               ': body and name are required')
         else if (any(markers(:k - 1)%body == body .and. markers(:k - 1)%name == name)) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('marker', k, 'name') // &
               ': marker "' // trim(name) // '" of body "' // trim(body) // '" is given twice')
         else if (node > 0 .and. len_trim(group) > 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('marker', k, 'group') // &
               ': marker "' // trim(name) // '" of body "' // trim(body) // '" gives node ' // &
               'and group; give one (a mesh node, or the centre of a physical group)')
         else if (node > 0 .and. src%has_key('marker', k, 'weighting')) then
            ! (issue 24) the RBE3 weights of a group's point mean nothing at a single node
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('marker', k, 'weighting') // &
               ': marker "' // trim(name) // '" of body "' // trim(body) // '" is at node ' // &
               to_str(node) // ', where weighting (the RBE3 weights of a group marker) means ' &
               // 'nothing; drop weighting')
         else if ((node > 0 .or. len_trim(group) > 0) .and. any(position /= 0.0_dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('marker', k, 'position') // &
               ': marker "' // trim(name) // '" of body "' // trim(body) // '" gives a ' // &
               'position and a node or group, which places it; drop the position')
         else if (any(orientation /= 0.0_dp)) then
            markers(k)%orientation = transpose(reshape(orientation, [3, 3]))
            markers(k)%oriented = .true.
            call check_rotation(markers(k)%orientation, src%where('marker', k, &
               'orientation') // ': marker "' // trim(name) // '" of body "' // trim(body) // &
               '": the orientation', error)
         end if
      end subroutine read_marker
   end procedure read_marker_groups

   module procedure read_joint_groups
      integer :: k, stat
      character(len=512) :: msg
      allocate (joints(src%count('joint')))
      rewind (unit)
      do k = 1, size(joints)
         associate (joint => joints(k))
            call read_joint(joint%name, joint%type, joint%body1, joint%marker1, joint%body2, &
               joint%marker2, joint%axis)
            if (.not. allocated(error)) call check_joint(joint, joints(:k - 1)%name, k, error)
         end associate
         if (allocated(error)) return
      end do
   contains
      !> The rules of &joint k (`names` those before it); its axis made a unit vector.
      subroutine check_joint(joint, names, k, error)
         type(joint_input_t), intent(inout) :: joint
         character(len=*), intent(in) :: names(:)
         integer, intent(in) :: k
         type(error_t), allocatable, intent(out) :: error
         character(len=:), allocatable :: where
         where = src%where('joint', k, '') // ' "' // trim(joint%name) // '"'
         joint%type = to_lower(joint%type)
         call check_unique_name(src, 'joint', k, joint%name, names, error)
         if (allocated(error)) return
         if (len_trim(joint%type) == 0) then
            ! a word given was checked by the key spec (joint_keys); here only its absence
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': type is missing; give one of ' &
               // choice_words(joint_choices))
         else if (len_trim(joint%body1) == 0 .or. len_trim(joint%marker1) == 0 .or. &
            len_trim(joint%body2) == 0 .or. len_trim(joint%marker2) == 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': body1, marker1, body2 and ' // &
               'marker2 are required')
         else if (joint%body1 == joint%body2) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': body1 and body2 are both "' // &
               trim(joint%body1) // '"; a joint connects two different bodies')
         else if (.not. (norm2(joint%axis) > 0.0_dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('joint', k, 'axis') // &
               ': the axis is zero; give a direction')
         else
            joint%axis = joint%axis / norm2(joint%axis)
         end if
      end subroutine check_joint

      !> The namelist read of &joint k into its fields (absent keys keep their defaults).
      subroutine read_joint(name, type, body1, marker1, body2, marker2, axis)
         character(len=*), intent(inout) :: name, type, body1, marker1, body2, marker2
         real(dp), intent(inout) :: axis(3)
         namelist /joint/ name, type, body1, marker1, body2, marker2, axis
         read (unit, nml=joint, iostat=stat, iomsg=msg)
         call read_status(src, 'joint', k, stat, msg, error)
      end subroutine read_joint
   end procedure read_joint_groups

   module procedure read_pressure_group
      integer :: stat
      character(len=512) :: msg
      rewind (unit)
      call read_pressure(input%bore, input%stroke, input%conrod_length, input%compression_ratio, &
         input%intake_pressure, input%exhaust_pressure, input%polytropic_exponent, &
         input%wiebe_a, input%wiebe_m, input%combustion_start_deg, &
         input%combustion_duration_deg, input%heat_per_cycle, input%target_peak_pressure, &
         input%reference_pressure)
      ! Ranges are checked by pressure_model_t%init with the key names.
      if (.not. is_iostat_end(stat)) call read_status(src, 'pressure', 0, stat, msg, error)
   contains
      !> The namelist read of &pressure into its fields (absent keys keep their values).
      subroutine read_pressure(bore, stroke, conrod_length, compression_ratio, intake_pressure, &
            exhaust_pressure, polytropic_exponent, wiebe_a, wiebe_m, combustion_start_deg, &
            combustion_duration_deg, heat_per_cycle, target_peak_pressure, reference_pressure)
         real(dp), intent(inout) :: bore, stroke, conrod_length, compression_ratio, &
            intake_pressure, exhaust_pressure, polytropic_exponent, wiebe_a, wiebe_m, &
            combustion_start_deg, combustion_duration_deg, heat_per_cycle, &
            target_peak_pressure, reference_pressure
         ! the keys by topic: engine geometry; gas exchange and compression; the Wiebe
         ! combustion; the scale of the pressure; a measured table instead of the model
         namelist /pressure/ bore, stroke, conrod_length, compression_ratio, &
            intake_pressure, exhaust_pressure, polytropic_exponent, &
            wiebe_a, wiebe_m, combustion_start_deg, combustion_duration_deg, heat_per_cycle, &
            target_peak_pressure, reference_pressure, table_file
         read (unit, nml=pressure, iostat=stat, iomsg=msg)
      end subroutine read_pressure
   end procedure read_pressure_group

   module procedure read_integrator_group
      character(len=16) :: jacobian, energy_watch, constraints
      integer :: stat
      character(len=512) :: msg
      energy_watch = energy_watch_word(watch%mode)
      jacobian = choice_name(jacobian_choices, settings%jacobian, 'step')
      constraints = choice_name(constraints_choices, settings%constraints, 'index3')
      rewind (unit)
      call read_integrator(settings%h, settings%t_end, settings%rho_inf, settings%newton_atol, &
         settings%newton_rtol, settings%max_iterations, settings%min_step, settings%rank_rtol, &
         settings%tangent_reuse, settings%checkpoint_seconds, settings%checkpoint_steps, &
         watch%tolerance, watch%window, settings%sparse_threshold)
      if (.not. is_iostat_end(stat)) call read_status(src, 'integrator', 0, stat, msg, error)
      if (allocated(error)) return
      h_given = src%has_key('integrator', 1, 'h')
      ! the words of energy_watch and jacobian were checked by the key spec (integrator_keys)
      watch%mode = energy_watch_kind(to_lower(energy_watch))
      settings%jacobian = jacobian_choices(choice_position(jacobian_choices, jacobian))%kind
      settings%constraints = constraints_choices(choice_position(constraints_choices, &
         constraints))%kind
      if (.not. (settings%min_step <= settings%h)) then
         call fatal_error(error, FFRF_INPUT_ERROR, src%where('integrator', 1, 'min_step') // &
            ': must not exceed h = ' // to_str(settings%h) // ' s')
         return
      end if
      call check_galpha_settings(settings, error)
      if (allocated(error)) error%message = src%where('integrator', 1, '') // ': ' // &
         error%message
   contains
      !> The namelist read of &integrator into its fields (absent keys keep their values; the
      !> words jacobian and energy_watch into those of the host).
      subroutine read_integrator(h, t_end, rho_inf, newton_atol, newton_rtol, max_iterations, &
            min_step, rank_rtol, tangent_reuse, checkpoint_seconds, checkpoint_steps, &
            energy_watch_tolerance, energy_watch_window, sparse_threshold)
         real(dp), intent(inout) :: h, t_end, rho_inf, newton_atol, newton_rtol, min_step, &
            rank_rtol, checkpoint_seconds, energy_watch_tolerance, energy_watch_window
         integer, intent(inout) :: max_iterations, tangent_reuse, checkpoint_steps, &
            sparse_threshold
         namelist /integrator/ h, t_end, rho_inf, newton_atol, newton_rtol, max_iterations, &
            min_step, rank_rtol, jacobian, tangent_reuse, checkpoint_seconds, &
            checkpoint_steps, energy_watch, energy_watch_tolerance, energy_watch_window, &
            sparse_threshold, constraints
         read (unit, nml=integrator, iostat=stat, iomsg=msg)
      end subroutine read_integrator
   end procedure read_integrator_group

end submodule ffrf_input_nml_mechanism_groups
