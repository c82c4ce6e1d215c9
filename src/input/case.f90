!> A case file: the namelist groups of one run, read, checked against each other, and echoed.
!> The case text is read once into memory (ffrf_input_nml_source: a regular file of at most 16 MiB,
!> or standard input for the case name '-', then named "stdin" with relative meshes taken from
!> the current folder), checked strictly (groups, keys, types, ranges), then read by the group
!> readers of src/input/nml_*.f90. Checked here across groups: interface and mechanism names, the
!> output paths of &run (relative, no '..': outputs stay inside --output-dir) and the number of
!> integration steps (t_end - t_start)/h against &integrator max_steps.
module ffrf_input_case
   use ffrf_core_serial_section, only: enter_serial_section, leave_serial_section, SECTION_FILES
   use ffrf_core_kinds, only: dp, i8
   use ffrf_core_error, only: error_t, fatal_error, add_context, FFRF_INPUT_ERROR, FFRF_IO_ERROR
   use ffrf_core_strings, only: to_str, to_lower, join_words
   use ffrf_input_body, only: body_input_t
   use ffrf_input_modes, only: modes_input_t
   use ffrf_input_interface, only: interface_input_t
   use ffrf_input_nml_source, only: nml_source_t, group_spec_t, key_spec_t, read_case_text
   use ffrf_input_nml_run, only: run_input_t, read_run_group, run_keys
   use ffrf_input_nml_body, only: read_body_groups, body_keys
   use ffrf_input_nml_interface, only: read_interface_groups, interface_keys
   use ffrf_input_nml_modes, only: read_modes_group, modes_keys
   use ffrf_input_nml_mechanism, only: read_mechanism_groups, mechanism_keys, marker_keys, &
      joint_keys, load_keys, pressure_keys, integrator_keys, model_keys, spring_keys, driver_keys, &
      torsion_spring_keys, bushing_keys
   use ffrf_input_nml_sensor, only: read_sensor_groups, sensor_keys
   use ffrf_input_overrides, only: override_t, apply_overrides, overrides_echo, overrides_set
   use ffrf_input_mechanism, only: body_motion_input_t, mechanism_case_input_t, GROUND_NAME, &
      time_law_input_t, joint_input_t
   use ffrf_mbs_generalized_alpha, only: GALPHA_NEWTON_FULL, GALPHA_NEWTON_STEP, galpha_settings_t
   use ffrf_mbs_energy_watch, only: energy_watch_settings_t, energy_watch_word
   implicit none
   private
   public :: case_input_t, read_case, case_echo, body_index, vector_text, case_groups
   public :: check_output_path, read_case_with_overrides, case_name_of

   !> Everything a modal or mechanism run needs.
   type :: case_input_t
      !> Case file as given
      character(len=:), allocatable :: file_name
      !> Case name: the file name without folder and extension
      character(len=:), allocatable :: name
      type(run_input_t) :: run
      type(body_input_t), allocatable :: bodies(:)
      type(interface_input_t), allocatable :: interfaces(:)
      type(modes_input_t) :: modes
      !> How each body moves (mechanism runs), same order as bodies
      type(body_motion_input_t), allocatable :: motions(:)
      !> .true. for a mechanism run (the case has a &joint group)
      logical :: is_mechanism = .false.
      !> Markers, joints, loads, pressure, integrator (mechanism runs)
      type(mechanism_case_input_t) :: mechanism
      !> The overrides the case was read with (command line, sweep table) as namelist comment
      !> lines, appended to the echo; unallocated or '' for none
      character(len=:), allocatable :: overrides
   end type case_input_t

contains

   !> The namelist groups of a case and their keys (the reader modules' *_keys).
   function case_groups() result(groups)
      type(group_spec_t), allocatable :: groups(:)
      ! element by element: gfortran 12 leaks the keys of group_spec_t(...) constructors in an
      ! array constructor (valgrind, tests/capi)
      allocate (groups(16))
      call set(1, 'run', .false., run_keys())
      call set(2, 'body', .true., body_keys())
      call set(3, 'interface', .true., interface_keys())
      call set(4, 'modes', .false., modes_keys())
      call set(5, 'mechanism', .false., mechanism_keys())
      call set(6, 'marker', .true., marker_keys())
      call set(7, 'joint', .true., joint_keys())
      call set(8, 'load', .true., load_keys())
      call set(9, 'pressure', .false., pressure_keys())
      call set(10, 'integrator', .false., integrator_keys())
      call set(11, 'model', .false., model_keys())
      call set(12, 'sensor', .true., sensor_keys())
      call set(13, 'spring', .true., spring_keys())
      call set(14, 'driver', .true., driver_keys())
      call set(15, 'torsion_spring', .true., torsion_spring_keys())
      call set(16, 'bushing', .true., bushing_keys())
   contains
      subroutine set(k, name, repeatable, keys)
         integer, intent(in) :: k
         character(len=*), intent(in) :: name
         logical, intent(in) :: repeatable
         type(key_spec_t), intent(in) :: keys(:)
         groups(k)%name = name
         groups(k)%repeatable = repeatable
         groups(k)%keys = keys
      end subroutine set
   end function case_groups

   !> Read and check the case file `file_name` ('-': standard input, the case is then named
   !> "stdin"). The file is read once; nothing else opens it.
   subroutine read_case(file_name, case, error)
      character(len=*), intent(in) :: file_name
      type(case_input_t), intent(out) :: case
      type(error_t), allocatable, intent(out) :: error
      type(override_t), allocatable :: none(:)
      allocate (none(0))
      call read_case_with_overrides(file_name, none, case, error)
   end subroutine read_case

   !> read_case with `overrides` (ffrf_input_overrides: --set, a sweep row, --output) set into
   !> the checked text before the groups are read: a bad value gets the namelist's message with
   !> the override's origin. When run.output is overridden and &run gives no mode_shapes_msh,
   !> the mode shapes go to <output stem>_modes.msh (each task of a job array its own file).
   !> One case read at a time in the process: two handles reading their cases at once in two
   !> threads made gfortran 12's namelist read fail ("Invalid string input"; ctest capi_threads),
   !> so the parse and the namelist reads run in the input-file serial section.
   subroutine read_case_with_overrides(file_name, overrides, case, error)
      character(len=*), intent(in) :: file_name
      type(override_t), intent(in) :: overrides(:)
      type(case_input_t), intent(out) :: case
      type(error_t), allocatable, intent(out) :: error
      call enter_serial_section(SECTION_FILES)
      call read_case_in_section(file_name, overrides, case, error)
      call leave_serial_section(SECTION_FILES)
   end subroutine read_case_with_overrides

   !> read_case_with_overrides inside the input-file serial section.
   subroutine read_case_in_section(file_name, overrides, case, error)
      character(len=*), intent(in) :: file_name
      type(override_t), intent(in) :: overrides(:)
      type(case_input_t), intent(out) :: case
      type(error_t), allocatable, intent(out) :: error
      type(nml_source_t) :: src
      character(len=:), allocatable :: text
      integer :: unit, stat, k
      character(len=512) :: msg
      if (file_name == '-') then
         case%file_name = 'stdin'
         case%name = 'stdin'
      else
         case%file_name = file_name
         case%name = case_name_of(file_name)
      end if
      call read_case_text(file_name, text, error)
      if (allocated(error)) return
      call src%parse(case%file_name, text, case_groups(), error)
      if (allocated(error)) return
      deallocate (text)
      call apply_overrides(src, overrides, error)
      if (allocated(error)) return
      case%overrides = overrides_echo(overrides)
      ! The checked groups go to the namelist reads through a scratch file, in canonical form
      open (newunit=unit, status='scratch', action='readwrite', form='formatted', iostat=stat, &
         iomsg=msg)
      if (stat /= 0) then
         call fatal_error(error, FFRF_IO_ERROR, case%file_name // ': cannot open a scratch ' // &
            'file to read the case (TMPDIR): ' // trim(msg))
         return
      end if
      call src%write_namelist(unit, error)
      if (.not. allocated(error)) call read_run_group(unit, case%run, error)
      if (.not. allocated(error)) call read_body_groups(unit, src, case%bodies, case%motions, &
         error)
      if (.not. allocated(error)) call read_interface_groups(unit, src, case%interfaces, error)
      if (.not. allocated(error)) call read_modes_group(unit, src, case%modes, error)
      if (.not. allocated(error)) then
         case%is_mechanism = src%count('joint') > 0
         if (case%is_mechanism) call read_mechanism_groups(unit, src, case%mechanism, error)
         if (case%is_mechanism .and. .not. allocated(error)) call read_sensor_groups(unit, src, &
            case%mechanism%sensors, error)
         if (.not. case%is_mechanism .and. src%count('sensor') > 0) call fatal_error(error, &
            FFRF_INPUT_ERROR, src%where('sensor', 1, '') // ': a modal run has no sensors ' // &
            '(they measure a mechanism run, a case with &joint groups); remove it')
      end if
      close (unit)
      if (allocated(error)) then
         if (.not. located(error%message)) call add_context(error, &
            case%file_name)
         return
      end if
      do k = 1, size(case%interfaces)
         if (.not. any(case%bodies%name == case%interfaces(k)%body)) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('interface', k, 'body') // &
               ': body "' // trim(case%interfaces(k)%body) // '" is not a &body of this ' // &
               'case (bodies: ' // join_words(case%bodies%name, ', ') // ')')
            return
         end if
         if (any(case%interfaces(:k - 1)%body == case%interfaces(k)%body .and. &
               case%interfaces(:k - 1)%name == case%interfaces(k)%name)) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('interface', k, 'name') // &
               ': interface "' // trim(case%interfaces(k)%name) // '" of body "' // &
               trim(case%interfaces(k)%body) // '" is given twice')
            return
         end if
      end do
      do k = 1, size(case%bodies)
         if (case%is_mechanism .or. len_trim(case%bodies(k)%modes_file) == 0) cycle
         call fatal_error(error, FFRF_INPUT_ERROR, src%where('body', k, 'modes_file') // &
            ': "' // trim(case%bodies(k)%name) // '": a modal run computes the modes; ' // &
            'modes_file takes them from an earlier run in a mechanism run (a case with ' // &
            '&joint groups); remove it here')
         return
      end do
      if (case%is_mechanism) then
         call check_mechanism_names(src, case, error)
         if (.not. allocated(error)) call check_step_count(src, case, error)
         if (allocated(error)) then
            if (.not. located(error%message)) call add_context(error, &
               case%file_name)
            return
         end if
      end if
      call check_output_path(src%where('run', 1, 'output'), case%run%output, error)
      if (.not. allocated(error)) call check_output_path(src%where('run', 1, &
         'mode_shapes_msh'), case%run%mode_shapes_msh, error)
      if (allocated(error)) return
      if (len_trim(case%run%output) == 0) case%run%output = case%name // '.h5'
      if (len_trim(case%run%mode_shapes_msh) == 0 .and. overrides_set(overrides, 'run', &
         'output')) then
         case%run%mode_shapes_msh = case_name_of(trim(case%run%output)) // '_modes.msh'
         k = index(trim(case%run%output), '/', back=.true.)
         if (k > 0) case%run%mode_shapes_msh = case%run%output(:k) // case%run%mode_shapes_msh
      else if (len_trim(case%run%mode_shapes_msh) == 0) then
         case%run%mode_shapes_msh = case%name // '_modes.msh'
      else if (to_lower(trim(case%run%mode_shapes_msh)) == 'none') then
         case%run%mode_shapes_msh = ''
      end if
   contains
      !> The message starts with its place: FILE: or an override's origin.
      logical function located(message)
         character(len=*), intent(in) :: message
         integer :: o
         located = index(message, case%file_name // ':') == 1
         do o = 1, size(overrides)
            if (index(message, overrides(o)%origin) == 1) located = .true.
         end do
      end function located
   end subroutine read_case_in_section

   !> An output named in a case stays inside the output directory: a relative path without a
   !> '..' component ('' is the default name). `where` starts the message (FILE:LINE: &run key).
   subroutine check_output_path(where, path, error)
      character(len=*), intent(in) :: where, path
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: rest, part
      integer :: slash
      if (len_trim(path) == 0) return
      if (path(1:1) == '/') then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': an absolute path; outputs stay ' &
            // 'inside the output folder (--output-dir): give a path relative to it')
         return
      end if
      rest = trim(path)
      do while (len(rest) > 0)
         slash = index(rest, '/')
         if (slash == 0) then
            part = rest
            rest = ''
         else
            part = rest(:slash - 1)
            rest = rest(slash + 1:)
         end if
         if (part == '..') then
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': a ''..'' component leaves ' &
               // 'the output folder (--output-dir); give a path inside it')
            return
         end if
      end do
   end subroutine check_output_path

   !> The run's steps (t_end - t_start)/h stay within &integrator max_steps, and a given h fits
   !> in the run: checked before anything is computed (h = 1e-9 with t_end = 2 would otherwise
   !> run for days). Without a given h, the default h (or the automatic model's) is checked
   !> when the integration starts.
   subroutine check_step_count(src, case, error)
      type(nml_source_t), intent(in) :: src
      type(case_input_t), intent(in) :: case
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: steps
      associate (s => case%mechanism%integrator, max_steps => case%mechanism%max_steps)
         if (case%mechanism%model%h_given .and. s%h > s%t_end - s%t_start) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('integrator', 1, 'h') // &
               ': longer than the run, t_end - t_start = ' // to_str(s%t_end - s%t_start) // &
               ' s; give h < t_end')
            return
         end if
         steps = (s%t_end - s%t_start) / s%h
         if (steps > real(max_steps, dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('integrator', 1, 't_end') // &
               ': (t_end - t_start)/h = ' // to_str(steps, 4) // ' steps of h = ' // &
               to_str(s%h) // ' s, more than max_steps = ' // to_str(max_steps) // &
               '; shorten the run, enlarge h, or raise &integrator max_steps on purpose')
         end if
      end associate
   end subroutine check_step_count

   !> The resolved input as namelist text (defaults filled in), for the log and /input.
   function case_echo(case) result(text)
      type(case_input_t), intent(in) :: case
      character(len=:), allocatable :: text
      character(len=*), parameter :: nl = new_line('a')
      integer :: k, v
      text = '&run title = ''' // nml_string(case%run%title) // ''', output = ''' // &
         nml_string(case%run%output) // ''', mode_shapes_msh = ''' // &
         msh_name(case%run%mode_shapes_msh) // &
         ''', log_level = ''' // nml_string(case%run%log_level) // ''' /' // nl
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
      if (case%is_mechanism) text = text // mechanism_echo(case%mechanism)
      if (allocated(case%overrides)) text = text // case%overrides
   end function case_echo

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
            jacobian_name(s%jacobian) // ''', tangent_reuse = ' // to_str(s%tangent_reuse)
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
            ', resonance_floor = ' // to_str(mech%model%resonance_floor, 6) // ' /' // nl
      end associate
   end function mechanism_echo

   !> The default of &integrator max_steps (echoed only when another is given).
   pure integer(i8) function mechanism_case_input_t_max_steps() result(n)
      type(mechanism_case_input_t) :: defaults
      n = defaults%max_steps
   end function mechanism_case_input_t_max_steps

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

   pure function jacobian_name(policy) result(name)
      integer, intent(in) :: policy
      character(len=:), allocatable :: name
      select case (policy)
      case (GALPHA_NEWTON_FULL)
         name = 'full'
      case (GALPHA_NEWTON_STEP)
         name = 'step'
      case default
         name = 'adaptive'
      end select
   end function jacobian_name

   !> "x, y, z" of a vector, `digits` (12) significant digits each.
   function vector_text(v, digits) result(text)
      real(dp), intent(in) :: v(:)
      integer, intent(in), optional :: digits
      character(len=:), allocatable :: text
      integer :: k, n
      n = 12
      if (present(digits)) n = digits
      text = ''
      do k = 1, size(v)
         if (k > 1) text = text // ', '
         text = text // to_str(v(k), n)
      end do
   end function vector_text

   !> A joint at a &marker with an orientation acts in that frame, marker1's when both have one
   !> (docs/mechanisms.md "Joint frames"): the axis of every kind but spherical and fixed must
   !> be the frame's z axis in the starting pose (global: the body's orientation times the
   !> marker's).
   subroutine check_joint_axis(where, case, joint, error)
      character(len=*), intent(in) :: where
      type(case_input_t), intent(in) :: case
      type(joint_input_t), intent(in) :: joint
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: z(3)
      integer :: m
      character(len=64) :: body, marker
      if (joint%type == 'spherical' .or. joint%type == 'fixed') return
      body = joint%body1
      marker = joint%marker1
      m = oriented_marker(body, marker)
      if (m == 0) then
         body = joint%body2
         marker = joint%marker2
         m = oriented_marker(body, marker)
      end if
      if (m == 0) return
      z = case%mechanism%markers(m)%orientation(:, 3)
      if (body /= GROUND_NAME) z = matmul(case%motions(body_index(case, body))%orientation, z)
      if (abs(dot_product(joint%axis / norm2(joint%axis), z)) < 1.0_dp - 1.0e-9_dp) &
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': axis = (' // &
         vector_text(joint%axis) // ') is not the z axis (' // vector_text(z) // ') of ' // &
         '&marker "' // trim(marker) // '" of body "' // trim(body) // '" (its orientation, ' // &
         'in the starting pose); give axis along it, or leave the marker''s orientation out')
   contains
      !> Index of the &marker (body, name) when it has an orientation, else 0.
      integer function oriented_marker(b, name)
         character(len=*), intent(in) :: b, name
         oriented_marker = findloc(case%mechanism%markers%body == b .and. &
            case%mechanism%markers%name == name, .true., dim=1)
         if (oriented_marker > 0) then
            if (.not. case%mechanism%markers(oriented_marker)%oriented) oriented_marker = 0
         end if
      end function oriented_marker
   end subroutine check_joint_axis

   !> Every body, marker and interface a &joint, &load, &marker or &mechanism names exists: the
   !> markers of a body with a mesh are its interfaces, those of a rigid body or the ground
   !> are its &marker groups.
   subroutine check_mechanism_names(src, case, error)
      !> The case text: FILE:LINE of the names
      type(nml_source_t), intent(in) :: src
      type(case_input_t), intent(in) :: case
      type(error_t), allocatable, intent(out) :: error
      integer :: k, j
      associate (mech => case%mechanism)
         do k = 1, size(case%interfaces)
            if (case%motions(body_index(case, case%interfaces(k)%body))%type == 'rigid') then
               call fatal_error(error, FFRF_INPUT_ERROR, src%at('interface', k, 'body') // &
                  ': &interface "' // &
                  trim(case%interfaces(k)%name) // '": body "' // &
                  trim(case%interfaces(k)%body) // '" is rigid (no mesh); give its joint ' // &
                  'points as &marker groups')
               return
            end if
         end do
         do k = 1, size(mech%markers)
            associate (m => mech%markers(k))
               if (m%body == GROUND_NAME) cycle
               if (body_index(case, m%body) == 0) then
                  call fatal_error(error, FFRF_INPUT_ERROR, src%at('marker', k, 'body') // &
                     ': &marker "' // trim(m%name) // &
                     '": body "' // trim(m%body) // '" is not a &body of this case (nor ' // &
                     '"ground")')
               else if (case%motions(body_index(case, m%body))%type /= 'rigid') then
                  call fatal_error(error, FFRF_INPUT_ERROR, src%at('marker', k, 'body') // &
                     ': &marker "' // trim(m%name) // '": body "' // trim(m%body) // &
                     '" has a mesh; its markers are its &interface groups (virtual nodes)')
               end if
               if (allocated(error)) return
            end associate
         end do
         do k = 1, size(mech%joints)
            associate (j => mech%joints(k))
               call check_marker(case, src%at('joint', k, 'body1') // ': &joint "' // &
                  trim(j%name) // '"', j%body1, j%marker1, error)
               if (.not. allocated(error)) call check_marker(case, src%at('joint', k, 'body2') &
                  // ': &joint "' // trim(j%name) // '"', j%body2, j%marker2, error)
               if (.not. allocated(error)) call check_joint_axis(src%at('joint', k, 'axis') // &
                  ': &joint "' // trim(j%name) // '"', case, j, error)
               if (allocated(error)) return
            end associate
         end do
         do k = 1, size(mech%loads)
            associate (l => mech%loads(k))
               call check_marker(case, src%at('load', k, 'body') // ': &load "' // &
                  trim(l%name) // '"', l%body, l%marker, error)
               if (allocated(error)) return
               if (l%body == GROUND_NAME) then
                  call fatal_error(error, FFRF_INPUT_ERROR, src%at('load', k, 'body') // &
                     ': &load "' // trim(l%name) // '": a load on the ground does nothing; ' // &
                     'name a moving body')
                  return
               end if
               if (any(l%type == [character(len=16) :: 'pressure', 'starter', 'drag']) .and. &
                  len_trim(mech%mechanism%crank) == 0) then
                  call fatal_error(error, FFRF_INPUT_ERROR, src%at('load', k, 'type') // &
                     ': &load "' // trim(l%name) // '" (' // trim(l%type) // ') depends on ' // &
                     'the crank angle or speed: name the crank body in &mechanism crank = ...')
                  return
               end if
            end associate
         end do
         do k = 1, spring_count(mech)
            associate (x => mech%springs(k))
               call check_marker(case, src%at('spring', k, 'body1') // ': &spring "' // &
                  trim(x%name) // '"', x%body1, x%marker1, error)
               if (.not. allocated(error)) call check_marker(case, src%at('spring', k, 'body2') &
                  // ': &spring "' // trim(x%name) // '"', x%body2, x%marker2, error)
               if (.not. allocated(error) .and. x%free_length < 0.0_dp) then
                  if (rigid_start_distance(case, x%body1, x%marker1, x%body2, x%marker2) == &
                     0.0_dp) call fatal_error(error, FFRF_INPUT_ERROR, src%at('spring', k, &
                     'body2') // ': &spring "' // trim(x%name) // '": its markers coincide ' &
                     // 'at the start (length 0) and free_length is not given; give ' // &
                     'free_length (m)')
               end if
               if (allocated(error)) return
            end associate
         end do
         do k = 1, driver_count(mech)
            associate (x => mech%drivers(k))
               j = findloc(mech%joints%name, x%joint, dim=1)
               if (j == 0) then
                  call fatal_error(error, FFRF_INPUT_ERROR, src%at('driver', k, 'joint') // &
                     ': &driver "' // trim(x%name) // '": joint "' // trim(x%joint) // &
                     '" is not a &joint of this case (joints: ' // &
                     join_words(mech%joints%name, ', ') // ')')
               else if (mech%joints(j)%type /= 'revolute' .and. &
                  mech%joints(j)%type /= 'prismatic') then
                  call fatal_error(error, FFRF_INPUT_ERROR, src%at('driver', k, 'joint') // &
                     ': &driver "' // trim(x%name) // '": joint "' // trim(x%joint) // &
                     '" is ' // trim(mech%joints(j)%type) // '; a driver needs a revolute ' // &
                     'or prismatic joint')
               else if (count(mech%drivers(:k)%joint == x%joint) > 1) then
                  call fatal_error(error, FFRF_INPUT_ERROR, src%at('driver', k, 'joint') // &
                     ': &driver "' // trim(x%name) // '": joint "' // trim(x%joint) // &
                     '" has a driver already; one driver per joint')
               end if
               if (allocated(error)) return
            end associate
         end do
         do k = 1, size(element_names(mech, 'torsion_spring'))
            associate (x => mech%torsion_springs(k))
               j = findloc(mech%joints%name, x%joint, dim=1)
               if (j == 0) then
                  call fatal_error(error, FFRF_INPUT_ERROR, src%at('torsion_spring', k, &
                     'joint') // ': &torsion_spring "' // trim(x%name) // '": joint "' // &
                     trim(x%joint) // '" is not a &joint of this case (joints: ' // &
                     join_words(mech%joints%name, ', ') // ')')
               else if (mech%joints(j)%type /= 'revolute' .and. &
                  mech%joints(j)%type /= 'cylindrical') then
                  call fatal_error(error, FFRF_INPUT_ERROR, src%at('torsion_spring', k, &
                     'joint') // ': &torsion_spring "' // trim(x%name) // '": joint "' // &
                     trim(x%joint) // '" is ' // trim(mech%joints(j)%type) // &
                     '; a torsion spring needs a revolute or cylindrical joint')
               end if
               if (allocated(error)) return
            end associate
         end do
         do k = 1, size(element_names(mech, 'bushing'))
            associate (x => mech%bushings(k))
               call check_marker(case, src%at('bushing', k, 'body1') // ': &bushing "' // &
                  trim(x%name) // '"', x%body1, x%marker1, error)
               if (.not. allocated(error)) call check_marker(case, src%at('bushing', k, &
                  'body2') // ': &bushing "' // trim(x%name) // '"', x%body2, x%marker2, error)
               if (allocated(error)) return
            end associate
         end do
         call check_sensor_names(src, case, error)
         if (allocated(error)) return
         if (len_trim(mech%mechanism%crank) > 0) then
            if (body_index(case, mech%mechanism%crank) == 0) then
               call fatal_error(error, FFRF_INPUT_ERROR, src%at('mechanism', 1, 'crank') // &
                  ': &mechanism: crank = "' // &
                  trim(mech%mechanism%crank) // '" is not a &body of this case')
               return
            end if
         end if
      end associate
   end subroutine check_mechanism_names

   !> Distance at the start between two markers of rigid bodies or the ground (&body position +
   !> A &marker position, A the &body orientation); -1 when an end is a
   !> flexible body's interface (known only from its mesh: the run checks it).
   pure real(dp) function rigid_start_distance(case, body1, marker1, body2, marker2) &
      result(distance)
      type(case_input_t), intent(in) :: case
      character(len=*), intent(in) :: body1, marker1, body2, marker2
      real(dp) :: point1(3), point2(3)
      logical :: known1, known2
      call start_point(body1, marker1, point1, known1)
      call start_point(body2, marker2, point2, known2)
      distance = -1.0_dp
      if (known1 .and. known2) distance = norm2(point2 - point1)
   contains
      pure subroutine start_point(body, marker, point, known)
         character(len=*), intent(in) :: body, marker
         real(dp), intent(out) :: point(3)
         logical, intent(out) :: known
         integer :: b, m
         point = 0.0_dp
         b = body_index(case, body)
         known = body == GROUND_NAME
         if (b > 0) then
            known = case%motions(b)%type == 'rigid'
            point = case%motions(b)%position
         end if
         if (.not. known) return
         m = findloc(case%mechanism%markers%body == body .and. &
            case%mechanism%markers%name == marker, .true., dim=1)
         known = m > 0
         if (.not. known) return
         if (b > 0) then
            point = point + matmul(case%motions(b)%orientation, case%mechanism%markers(m)%position)
         else
            point = point + case%mechanism%markers(m)%position
         end if
      end subroutine start_point
   end function rigid_start_distance

   !> Number of &driver groups (0 for a case built in memory without them).
   pure integer function driver_count(mech)
      type(mechanism_case_input_t), intent(in) :: mech
      driver_count = 0
      if (allocated(mech%drivers)) driver_count = size(mech%drivers)
   end function driver_count

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

   !> Number of &spring groups (0 for a case built in memory without them).
   pure integer function spring_count(mech)
      type(mechanism_case_input_t), intent(in) :: mech
      spring_count = 0
      if (allocated(mech%springs)) spring_count = size(mech%springs)
   end function spring_count

   !> Number of &sensor groups (0 for a case built in memory without them).
   pure integer function sensor_count(mech)
      type(mechanism_case_input_t), intent(in) :: mech
      sensor_count = 0
      if (allocated(mech%sensors)) sensor_count = size(mech%sensors)
   end function sensor_count

   !> The body, marker and joint a &sensor names exist (the marker as check_marker asks).
   subroutine check_sensor_names(src, case, error)
      type(nml_source_t), intent(in) :: src
      type(case_input_t), intent(in) :: case
      type(error_t), allocatable, intent(out) :: error
      logical :: missing
      character(len=:), allocatable :: group
      integer :: k
      associate (mech => case%mechanism)
         if (.not. allocated(mech%sensors)) return
         do k = 1, size(mech%sensors)
            associate (x => mech%sensors(k))
               if (len_trim(x%marker) > 0) then
                  call check_marker(case, src%at('sensor', k, 'marker') // ': &sensor "' // &
                     trim(x%name) // '"', x%body, x%marker, error)
               else if (len_trim(x%body) > 0) then
                  if (body_index(case, x%body) == 0) then
                     call fatal_error(error, FFRF_INPUT_ERROR, src%at('sensor', k, 'body') // &
                        ': &sensor "' // trim(x%name) // '": body "' // trim(x%body) // &
                        '" is not a &body of this case (bodies: ' // &
                        join_words(case%bodies%name, ', ') // ')')
                  else if (x%node > 0 .and. &
                     len_trim(case%bodies(body_index(case, x%body))%mesh_file) == 0) then
                     call fatal_error(error, FFRF_INPUT_ERROR, src%at('sensor', k, 'node') // &
                        ': &sensor "' // trim(x%name) // '": body "' // trim(x%body) // &
                        '" has no mesh, so no node ' // to_str(x%node) // '; measure a ' // &
                        'body with a mesh_file')
                  end if
               end if
               if (.not. allocated(error) .and. len_trim(mech%mechanism%crank) > 0 .and. &
                  (x%name == 'crank_angle' .or. x%name == 'crank_speed')) call fatal_error( &
                  error, FFRF_INPUT_ERROR, src%at('sensor', k, 'name') // ': &sensor "' // &
                  trim(x%name) // '": the name belongs to the engine''s own sensor (a case ' // &
                  'with &mechanism crank has crank_angle and crank_speed); name it otherwise')
               if (.not. allocated(error) .and. len_trim(x%joint) > 0) then
                  if (.not. any(mech%joints%name == x%joint)) call fatal_error(error, &
                     FFRF_INPUT_ERROR, src%at('sensor', k, 'joint') // ': &sensor "' // &
                     trim(x%name) // '": joint "' // trim(x%joint) // '" is not a &joint ' // &
                     'of this case (joints: ' // join_words(mech%joints%name, ', ') // ')')
               end if
               if (.not. allocated(error) .and. trim(x%type) == 'driver') then
                  missing = driver_count(mech) == 0
                  if (.not. missing) missing = .not. any(mech%drivers%joint == x%joint)
                  if (missing) call fatal_error(error, FFRF_INPUT_ERROR, src%at('sensor', k, &
                     'joint') // ': &sensor "' // trim(x%name) // '": joint "' // &
                     trim(x%joint) // '" has no &driver; add &driver name = ..., joint = ''' // &
                     trim(x%joint) // ''' /')
               end if
               if (.not. allocated(error) .and. len_trim(x%spring) > 0) then
                  ! spring names a &spring, or the &torsion_spring or &bushing of those types
                  group = 'spring'
                  if (trim(x%type) == 'torsion_spring' .or. trim(x%type) == 'bushing') &
                     group = trim(x%type)
                  call check_spring_name(src%at('sensor', k, 'spring') // ': &sensor "' // &
                     trim(x%name) // '"', group, x%spring, element_names(mech, group), error)
               end if
               if (allocated(error)) return
            end associate
         end do
      end associate
   end subroutine check_sensor_names

   !> `name` (of a &sensor at `where`) is one of `names`, the &`group` names of the case.
   subroutine check_spring_name(where, group, name, names, error)
      character(len=*), intent(in) :: where, group, name
      character(len=64), intent(in) :: names(:)
      type(error_t), allocatable, intent(out) :: error
      if (size(names) == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': spring "' // trim(name) // &
            '" is not a &' // group // ' of this case (it has none)')
      else if (.not. any(names == name)) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': spring "' // trim(name) // &
            '" is not a &' // group // ' of this case (' // group // 's: ' // &
            join_words(names, ', ') // ')')
      end if
   end subroutine check_spring_name

   !> Names of the groups `group` (spring, torsion_spring, bushing) of the case; none for a
   !> case built in memory without them.
   pure function element_names(mech, group) result(names)
      type(mechanism_case_input_t), intent(in) :: mech
      character(len=*), intent(in) :: group
      character(len=64), allocatable :: names(:)
      allocate (names(0))
      select case (group)
      case ('spring')
         if (allocated(mech%springs)) names = mech%springs%name
      case ('torsion_spring')
         if (allocated(mech%torsion_springs)) names = mech%torsion_springs%name
      case ('bushing')
         if (allocated(mech%bushings)) names = mech%bushings%name
      end select
   end function element_names

   !> body is 'ground' or a &body, and marker one of its markers (module header).
   subroutine check_marker(case, where, body, marker, error)
      type(case_input_t), intent(in) :: case
      character(len=*), intent(in) :: where, body, marker
      type(error_t), allocatable, intent(out) :: error
      integer :: b
      b = body_index(case, body)
      if (body /= GROUND_NAME .and. b == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': body "' // trim(body) // &
            '" is not a &body of this case (bodies: ' // join_words(case%bodies%name, ', ') // &
            ', ground)')
      else if (body == GROUND_NAME .or. case%motions(max(b, 1))%type == 'rigid') then
         if (.not. any(case%mechanism%markers%body == body .and. &
            case%mechanism%markers%name == marker)) call fatal_error(error, FFRF_INPUT_ERROR, &
            where // ': marker "' // trim(marker) // '" of body "' // trim(body) // &
            '" is not defined; add &marker body = ''' // trim(body) // ''', name = ''' // &
            trim(marker) // ''', position = x, y, z /')
      else if (.not. any(case%interfaces%body == body .and. case%interfaces%name == marker)) &
         then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': body "' // trim(body) // &
            '" has no interface "' // trim(marker) // '" (the markers of a meshed body are ' // &
            'its &interface groups: ' // interface_list(case, body) // ')')
      end if
   end subroutine check_marker

   !> Index of the &body called name, 0 if none (e.g. the ground).
   pure integer function body_index(case, name) result(k)
      type(case_input_t), intent(in) :: case
      character(len=*), intent(in) :: name
      do k = 1, size(case%bodies)
         if (case%bodies(k)%name == name) return
      end do
      k = 0
   end function body_index


   function interface_list(case, body) result(text)
      type(case_input_t), intent(in) :: case
      character(len=*), intent(in) :: body
      character(len=:), allocatable :: text
      integer :: k
      text = ''
      do k = 1, size(case%interfaces)
         if (case%interfaces(k)%body /= body) cycle
         if (len(text) > 0) text = text // ', '
         text = text // trim(case%interfaces(k)%name)
      end do
      if (len(text) == 0) text = 'none'
   end function interface_list

   !> The mode-shape file name, 'none' when no file is written (quotes doubled as nml_string).
   pure function msh_name(file_name) result(name)
      character(len=*), intent(in) :: file_name
      character(len=:), allocatable :: name
      name = nml_string(file_name)
      if (len(name) == 0) name = 'none'
   end function msh_name

   !> A string value for the echo between single quotes: trailing blanks dropped, each ' doubled
   !> (title = 'it''s'), so that the echo reads back as the same input.
   pure function nml_string(text) result(quoted)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: quoted
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
   end function nml_string

   !> "input/crank_rc1.nml" -> "crank_rc1"; "-" (standard input) -> "stdin".
   pure function case_name_of(file_name) result(name)
      character(len=*), intent(in) :: file_name
      character(len=:), allocatable :: name
      integer :: slash, dot
      if (file_name == '-') then
         name = 'stdin'
         return
      end if
      slash = index(file_name, '/', back=.true.)
      name = file_name(slash + 1:)
      dot = index(name, '.', back=.true.)
      if (dot > 1) name = name(:dot - 1)
   end function case_name_of

end module ffrf_input_case
