!> The resolved input as namelist text (ffrf_input_case): every group with every key, defaults
!> included, in the order the readers take them; results files and logs carry it.
submodule (ffrf_input_case) ffrf_input_case_echo
   use ffrf_input_nml_output, only: output_echo
   implicit none

contains

   module procedure case_echo
      character(len=*), parameter :: nl = new_line('a')
      integer :: k, v
      text = '&run title = ''' // nml_string(case%run%title) // ''', output = ''' // &
         nml_string(case%run%output) // ''', mode_shapes_msh = ''' // &
         msh_name(case%run%mode_shapes_msh) // &
         ''', log_level = ''' // nml_string(case%run%log_level) // ''''
      ! new key: echoed only when given, so that the echo of a case without it stays as it was
      if (len_trim(case%run%export) > 0) text = text // ', export = ''' // &
         nml_string(case%run%export) // ''''
      text = text // ' /' // nl
      do k = 1, size(case%bodies)
         associate (b => case%bodies(k))
            text = text // '&body name = ''' // nml_string(b%name) // ''', mesh_file = ''' // &
               nml_string(b%mesh_file) // ''', volumes ='
            do v = 1, size(b%volumes)
               if (len_trim(b%volumes(v)) > 0) text = text // ' ''' // &
                  nml_string(b%volumes(v)) // ''''
            end do
            text = text // ', young = ' // to_str(b%young, 12) // ', poisson = ' // &
               to_str(b%poisson, 12) // ', density = ' // to_str(b%density, 12)
            if (case%is_mechanism) text = text // motion_echo(case%motions(k))
            if (case%is_mechanism .and. case%motions(k)%type /= 'rigid') text = text // &
               ', geometric_stiffness = ' // &
               trim(merge('.true. ', '.false.', b%geometric_stiffness))
            if (len_trim(b%modes_file) > 0) text = text // ', modes_file = ''' // &
               nml_string(b%modes_file) // ''''
            text = text // ' /' // nl
         end associate
      end do
      do k = 1, size(case%interfaces)
         associate (f => case%interfaces(k))
            text = text // '&interface body = ''' // nml_string(f%body) // ''', name = ''' // &
               nml_string(f%name) // ''', mpc = ''' // nml_string(f%mpc) // &
               ''', weighting = ''' // nml_string(f%weighting) // ''', virtual_node = ''' // &
               nml_string(f%virtual_node) // ''''
            if (f%virtual_node == 'position') text = text // ', position = ' // &
               to_str(f%position(1), 12) // ' ' // to_str(f%position(2), 12) // ' ' // &
               to_str(f%position(3), 12)
            text = text // ', rc = ''' // nml_string(f%rc) // ''' /' // nl
         end associate
      end do
      text = text // '&modes num_modes = ' // to_str(case%modes%num_modes) // ', shift_hz = ' // &
         to_str(case%modes%shift_hz, 12) // ', formulation = ''' // &
         nml_string(case%modes%formulation) // ''', rc_label = ''' // &
         nml_string(case%modes%rc_label) // &
         ''', tolerance = ' // to_str(case%modes%tolerance, 6) // ', lanczos_vectors = ' // &
         to_str(case%modes%lanczos_vectors) // ', basis = ''' // nml_string(case%modes%basis) // &
         '''' // memory_echo(case%modes) // ' /' // nl
      if (case%is_mechanism) text = text // mechanism_echo(case%mechanism) // &
         output_echo(case%output)
      if (allocated(case%overrides)) text = text // case%overrides
   end procedure case_echo

   !> The memory, eigensolver and spectrum keys of &modes, only those not at their defaults (so
   !> the echo of a case without them is the one written before they existed).
   function memory_echo(m) result(text)
      type(modes_input_t), intent(in) :: m
      character(len=:), allocatable :: text
      text = ''
      if (m%out_of_core) text = text // ', out_of_core = .true.'
      if (len_trim(m%ooc_tmpdir) > 0) text = text // ', ooc_tmpdir = ''' // &
         nml_string(m%ooc_tmpdir) &
         // ''''
      if (m%memory_limit_mb /= -1) text = text // ', memory_limit_mb = ' // &
         to_str(m%memory_limit_mb)
      if (m%compression_tolerance /= 0.0_dp) text = text // ', compression_tolerance = ' // &
         to_str(m%compression_tolerance, 6)
      if (m%eigensolver /= 'auto') text = text // ', eigensolver = ''' // &
         nml_string(m%eigensolver) &
         // ''''
      if (m%max_frequency_hz > 0.0_dp) text = text // ', max_frequency_hz = ' // &
         to_str(m%max_frequency_hz, 12)
      if (.not. m%sturm_check) text = text // ', sturm_check = .false.'
   end function memory_echo

   !> The mechanism keys of a &body.
   function motion_echo(m) result(text)
      type(body_motion_input_t), intent(in) :: m
      character(len=:), allocatable :: text
      type(body_motion_input_t) :: default_motion
      text = ', type = ''' // nml_string(m%type) // ''''
      if (m%type == 'rigid') then
         text = text // ', mass = ' // to_str(m%mass, 12) // ', center_of_mass = ' // &
            vector_text(m%center_of_mass) // ', inertia = ' // vector_text(m%inertia)
      else
         ! num_modes = -1 (not given: &modes num_modes) is left out, so that the echo reads back
         if (m%num_modes >= 0) text = text // ', num_modes = ' // to_str(m%num_modes)
         text = text // ', modal_damping = ' // to_str(m%modal_damping, 6)
         if (len_trim(m%coarse_meshes(1)) > 0) text = text // ', coarse_meshes =' // &
            quoted_list(m%coarse_meshes)
      end if
      text = text // ', position = ' // vector_text(m%position)
      ! The pose keys only when they differ from their defaults, so that old echoes stay as
      ! they were; 17 digits so that the echo reads back to the same rotation
      if (any(m%orientation /= default_motion%orientation)) text = text // &
         ', orientation = ' // vector_text(reshape(transpose(m%orientation), [9]), 17)
      if (any(m%velocity /= 0.0_dp)) text = text // ', velocity = ' // &
         vector_text(m%velocity, 17)
      if (any(m%angular_velocity /= 0.0_dp)) text = text // ', angular_velocity = ' // &
         vector_text(m%angular_velocity, 17)
   end function motion_echo

   !> The mechanism groups, resolved.
   function mechanism_echo(mech) result(text)
      type(mechanism_case_input_t), intent(in) :: mech
      character(len=:), allocatable :: text
      character(len=*), parameter :: nl = new_line('a')
      type(galpha_settings_t) :: default_settings
      type(energy_watch_settings_t) :: default_watch
      integer :: k
      associate (m => mech%mechanism, p => mech%pressure, s => mech%integrator)
         ! A mechanism without a crank (and its defaults) has no crank keys in its echo
         if (len_trim(m%crank) == 0 .and. m%crank_angle_deg == 0.0_dp .and. &
            m%crank_speed == 0.0_dp) then
            text = '&mechanism gravity = '
         else
            text = '&mechanism crank = ''' // nml_string(m%crank) // ''', crank_angle_deg = ' &
               // to_str(m%crank_angle_deg, 12) // ', crank_speed = ' // &
               to_str(m%crank_speed, 12) // ', gravity = '
         end if
         text = text // vector_text(m%gravity) // ', label = ''' // nml_string(m%label) // &
            ''', progress_interval = ' // to_str(m%progress_interval, 6) // &
            ', animation_frames = ' // to_str(m%animation_frames) // ' /' // nl
         do k = 1, size(mech%markers)
            text = text // '&marker body = ''' // nml_string(mech%markers(k)%body) // &
               ''', name = ''' &
               // nml_string(mech%markers(k)%name) // ''', position = ' // &
               vector_text(mech%markers(k)%position)
            ! only when given (old echoes unchanged); 17 digits read back to the same rotation
            if (mech%markers(k)%oriented) text = text // ', orientation = ' // &
               vector_text(reshape(transpose(mech%markers(k)%orientation), [9]), 17)
            if (mech%markers(k)%node > 0) text = text // ', node = ' // &
               to_str(mech%markers(k)%node)
            if (len_trim(mech%markers(k)%group) > 0) text = text // ', group = ''' // &
               nml_string(mech%markers(k)%group) // ''', weighting = ''' // &
               nml_string(mech%markers(k)%weighting) // ''''
            text = text // ' /' // nl
         end do
         do k = 1, size(mech%joints)
            associate (j => mech%joints(k))
               text = text // '&joint name = ''' // nml_string(j%name) // ''', type = ''' // &
                  nml_string(j%type) // ''', body1 = ''' // nml_string(j%body1) // &
                  ''', marker1 = ''' // nml_string(j%marker1) // ''', body2 = ''' // &
                  nml_string(j%body2) // ''', marker2 = ''' &
                  // nml_string(j%marker2) // ''', axis = ' // vector_text(j%axis) // ' /' // nl
            end associate
         end do
         do k = 1, size(mech%loads)
            associate (l => mech%loads(k))
               text = text // '&load name = ''' // nml_string(l%name) // ''', type = ''' // &
                  nml_string(l%type) // ''', body = ''' // nml_string(l%body) // &
                  ''', marker = ''' // &
                  nml_string(l%marker) // ''', direction = ' // vector_text(l%direction)
               select case (trim(l%type))
               case ('force', 'torque')
                  text = text // ', value = ' // to_str(l%value, 12)
               case ('starter')
                  text = text // ', stall_torque = ' // to_str(l%stall_torque, 12) // &
                     ', free_speed = ' // to_str(l%free_speed, 12) // ', switch_off = ' // &
                     to_str(l%switch_off, 12)
               case ('drag')
                  text = text // ', coefficient = ' // to_str(l%coefficient, 12)
               end select
               if (len_trim(l%law%law) > 0) text = text // ', ' // law_echo(l%law)
               text = text // ' /' // nl
            end associate
         end do
         do k = 1, spring_count(mech)
            associate (x => mech%springs(k))
               text = text // '&spring name = ''' // nml_string(x%name) // ''', body1 = ''' // &
                  nml_string(x%body1) // ''', marker1 = ''' // nml_string(x%marker1) // &
                  ''', body2 = ''' // nml_string(x%body2) // ''', marker2 = ''' // &
                  nml_string(x%marker2) // ''', stiffness = ' // to_str(x%stiffness, 17) // &
                  ', damping = ' // to_str(x%damping, 17)
               if (x%free_length >= 0.0_dp) text = text // ', free_length = ' // &
                  to_str(x%free_length, 17)
               text = text // ' /' // nl
            end associate
         end do
         do k = 1, size(element_names(mech, 'torsion_spring'))
            associate (x => mech%torsion_springs(k))
               text = text // '&torsion_spring name = ''' // nml_string(x%name) // &
                  ''', joint = ''' // nml_string(x%joint) // ''', stiffness = ' // &
                  to_str(x%stiffness, 17) // ', damping = ' // to_str(x%damping, 17)
               if (x%free_angle_given) text = text // ', free_angle = ' // &
                  to_str(x%free_angle, 17)
               text = text // ' /' // nl
            end associate
         end do
         do k = 1, size(element_names(mech, 'bushing'))
            associate (x => mech%bushings(k))
               text = text // '&bushing name = ''' // nml_string(x%name) // ''', body1 = ''' // &
                  nml_string(x%body1) // ''', marker1 = ''' // nml_string(x%marker1) // &
                  ''', body2 = ''' // nml_string(x%body2) // ''', marker2 = ''' // &
                  nml_string(x%marker2) // ''', stiffness = ' // vector_text(x%stiffness, 17) // &
                  ', damping = ' // vector_text(x%damping, 17) // ' /' // nl
            end associate
         end do
         do k = 1, driver_count(mech)
            associate (x => mech%drivers(k))
               text = text // '&driver name = ''' // nml_string(x%name) // ''', joint = ''' // &
                  nml_string(x%joint) // ''', quantity = ''' // trim(x%quantity) // &
                  ''', offset = ' // to_str(x%offset, 17) // ', ' // law_echo(x%law) // ' /' // nl
            end associate
         end do
         do k = 1, sensor_count(mech)
            associate (x => mech%sensors(k))
               text = text // '&sensor name = ''' // nml_string(x%name) // ''', type = ''' // &
                  nml_string(x%type) // ''''
               if (len_trim(x%body) > 0) text = text // ', body = ''' // nml_string(x%body) // &
                  ''''
               if (len_trim(x%marker) > 0) text = text // ', marker = ''' // &
                  nml_string(x%marker) // ''''
               if (len_trim(x%joint) > 0) text = text // ', joint = ''' // &
                  nml_string(x%joint) // ''''
               if (x%node > 0) text = text // ', node = ' // to_str(x%node)
               if (len_trim(x%spring) > 0) text = text // ', spring = ''' // &
                  nml_string(x%spring) // ''''
               text = text // ' /' // nl
            end associate
         end do
         text = text // '&pressure bore = ' // to_str(p%bore, 12) // ', stroke = ' // &
            to_str(p%stroke, 12) // ', conrod_length = ' // to_str(p%conrod_length, 12) // &
            ', compression_ratio = ' // to_str(p%compression_ratio, 12) // &
            ', intake_pressure = ' // to_str(p%intake_pressure, 12) // ', exhaust_pressure = ' &
            // to_str(p%exhaust_pressure, 12) // ', polytropic_exponent = ' // &
            to_str(p%polytropic_exponent, 12) // ', wiebe_a = ' // to_str(p%wiebe_a, 12) // &
            ', wiebe_m = ' // to_str(p%wiebe_m, 12) // ', combustion_start_deg = ' // &
            to_str(p%combustion_start_deg, 12) // ', combustion_duration_deg = ' // &
            to_str(p%combustion_duration_deg, 12) // ', heat_per_cycle = ' // &
            to_str(p%heat_per_cycle, 12) // ', target_peak_pressure = ' // &
            to_str(p%target_peak_pressure, 12) // ', reference_pressure = ' // &
            to_str(p%reference_pressure, 12) // ', table_file = ''' // &
            nml_string(mech%pressure_table) // ''' /' // nl
         ! h left out when not given: the model selection or the default chooses it (log)
         text = text // '&integrator '
         if (mech%model%h_given) text = text // 'h = ' // to_str(s%h, 12) // ', '
         text = text // 't_end = ' // to_str(s%t_end, 12) // ', rho_inf = ' // &
            to_str(s%rho_inf, 12) // ', newton_atol = ' // to_str(s%newton_atol, 6) // &
            ', newton_rtol = ' // to_str(s%newton_rtol, 6) // ', max_iterations = ' // &
            to_str(s%max_iterations) // ', min_step = ' // to_str(s%min_step, 6) // &
            ', rank_rtol = ' // to_str(s%rank_rtol, 6) // ', jacobian = ''' // &
            choice_name(jacobian_choices, s%jacobian, 'adaptive') // ''', tangent_reuse = ' // &
            to_str(s%tangent_reuse)
         if (mech%max_steps /= mechanism_case_input_t_max_steps()) text = text // &
            ', max_steps = ' // to_str(mech%max_steps)
         ! Checkpoint keys only when set: they do not change the results
         if (s%checkpoint_seconds /= default_settings%checkpoint_seconds) text = text // &
            ', checkpoint_seconds = ' // to_str(s%checkpoint_seconds, 6)
         if (s%checkpoint_steps /= default_settings%checkpoint_steps) text = text // &
            ', checkpoint_steps = ' // to_str(s%checkpoint_steps)
         ! The linear solver's switch only when set (the default's results are every run's)
         if (s%sparse_threshold /= default_settings%sparse_threshold) text = text // &
            ', sparse_threshold = ' // to_str(s%sparse_threshold)
         ! The constraint formulation only when set (index3, the default, is every run's)
         if (s%constraints /= default_settings%constraints) text = text // &
            ', constraints = ''' // choice_name(constraints_choices, s%constraints, 'index3') &
            // ''''
         ! Energy watch keys only when set (the default watch is in every run)
         if (mech%energy_watch%mode /= default_watch%mode) text = text // &
            ', energy_watch = ''' // energy_watch_word(mech%energy_watch%mode) // ''''
         if (mech%energy_watch%tolerance /= default_watch%tolerance) text = text // &
            ', energy_watch_tolerance = ' // to_str(mech%energy_watch%tolerance, 6)
         if (mech%energy_watch%window /= default_watch%window) text = text // &
            ', energy_watch_window = ' // to_str(mech%energy_watch%window, 6)
         text = text // ' /' // nl
         text = text // '&model selection = ''' // nml_string(mech%model%selection) // &
            ''', speed_tolerance = ' // to_str(mech%model%speed_tolerance, 6) // &
            ', force_tolerance = ' // to_str(mech%model%force_tolerance, 6) // &
            ', candidate_modes = ' // to_str(mech%model%candidate_modes) // &
            ', resonance_floor = ' // to_str(mech%model%resonance_floor, 6)
         if (len_trim(mech%model%targets) > 0) text = text // ', targets = ''' // &
            nml_string(trim(mech%model%targets)) // ''''
         text = text // ' /' // nl
      end associate
   end function mechanism_echo

   !> " 'a', 'b'" of the non-blank entries.
   pure function quoted_list(items) result(text)
      character(len=*), intent(in) :: items(:)
      character(len=:), allocatable :: text
      integer :: k
      text = ''
      do k = 1, size(items)
         if (len_trim(items(k)) == 0) cycle
         if (len(text) > 0) text = text // ','
         text = text // ' ''' // nml_string(items(k)) // ''''
      end do
   end function quoted_list

   !> The law keys of a &driver or &load as namelist text (ffrf_input_mechanism
   !> time_law_input_t), full precision.
   function law_echo(law) result(text)
      type(time_law_input_t), intent(in) :: law
      character(len=:), allocatable :: text
      integer :: i
      text = 'law = ''' // trim(law%law) // ''''
      select case (trim(law%law))
      case ('constant')
         text = text // ', initial = ' // to_str(law%initial, 17)
      case ('constant_speed')
         text = text // ', initial = ' // to_str(law%initial, 17) // ', speed = ' // &
            to_str(law%speed, 17)
      case ('ramp', 'smooth_step')
         text = text // ', initial = ' // to_str(law%initial, 17) // ', final = ' // &
            to_str(law%final, 17) // ', t_start = ' // to_str(law%t_start, 17) // &
            ', duration = ' // to_str(law%duration, 17)
      case ('table')
         text = text // ', interpolation = ''' // trim(law%interpolation) // ''', beyond = ''' &
            // trim(law%beyond) // ''', table_time = '
         do i = 1, size(law%table_time)
            if (i > 1) text = text // ', '
            text = text // to_str(law%table_time(i), 17)
         end do
         text = text // ', table_value = '
         do i = 1, size(law%table_value)
            if (i > 1) text = text // ', '
            text = text // to_str(law%table_value(i), 17)
         end do
      end select
   end function law_echo

   module procedure nml_string
      integer :: k, n
      n = len_trim(text)
      quoted = repeat(' ', n + count_quotes())
      n = 0
      do k = 1, len_trim(text)
         n = n + 1
         quoted(n:n) = text(k:k)
         if (text(k:k) /= '''') cycle
         n = n + 1
         quoted(n:n) = ''''
      end do
   contains
      pure integer function count_quotes()
         integer :: j
         count_quotes = 0
         do j = 1, len_trim(text)
            if (text(j:j) == '''') count_quotes = count_quotes + 1
         end do
      end function count_quotes
   end procedure nml_string

   module procedure vector_text
      integer :: k, n
      n = 12
      if (present(digits)) n = digits
      text = ''
      do k = 1, size(v)
         if (k > 1) text = text // ', '
         text = text // to_str(v(k), n)
      end do
   end procedure vector_text

end submodule ffrf_input_case_echo
