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
   use ffrf_input_nml_run, only: run_input_t, read_run_group, run_keys, check_export
   use ffrf_input_nml_output, only: output_input_t, read_output_group, output_keys, &
      check_history_names
   use ffrf_input_nml_body, only: read_body_groups, body_keys
   use ffrf_input_nml_interface, only: read_interface_groups, interface_keys
   use ffrf_input_nml_modes, only: read_modes_group, modes_keys
   use ffrf_input_nml_mechanism, only: read_mechanism_groups, mechanism_keys, marker_keys, &
      joint_keys, load_keys, pressure_keys, integrator_keys, model_keys, spring_keys, driver_keys, &
      torsion_spring_keys, bushing_keys, jacobian_choices, constraints_choices
   use ffrf_core_choices, only: choice_name
   use ffrf_input_nml_sensor, only: read_sensor_groups, sensor_keys
   use ffrf_input_overrides, only: override_t, apply_overrides, overrides_echo, overrides_set
   use ffrf_input_mechanism, only: body_motion_input_t, mechanism_case_input_t, GROUND_NAME, &
      marker_input_t, &
      time_law_input_t, joint_input_t
   use ffrf_mbs_generalized_alpha, only: galpha_settings_t
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
      !> Histories, their rate, compression, size check (&output; mechanism runs)
      type(output_input_t) :: output
      !> The overrides the case was read with (command line, sweep table) as namelist comment
      !> lines, appended to the echo; unallocated or '' for none
      character(len=:), allocatable :: overrides
   end type case_input_t

   interface
      !> An output named in a case stays inside the output directory: a relative path without a
      !> '..' component ('' is the default name). `where` starts the message (FILE:LINE: &run key).
      module subroutine check_output_path(where, path, error)
         character(len=*), intent(in) :: where, path
         type(error_t), allocatable, intent(out) :: error
      end subroutine check_output_path

      !> The run's steps (t_end - t_start)/h stay within &integrator max_steps, and a given h fits
      !> in the run: checked before anything is computed (h = 1e-9 with t_end = 2 would otherwise
      !> run for days). Without a given h, the default h (or the automatic model's) is checked
      !> when the integration starts.
      module subroutine check_step_count(src, case, error)
         type(nml_source_t), intent(in) :: src
         type(case_input_t), intent(in) :: case
         type(error_t), allocatable, intent(out) :: error
      end subroutine check_step_count

      !> The resolved input as namelist text (defaults filled in), for the log and /input.
      module function case_echo(case) result(text)
         type(case_input_t), intent(in) :: case
         character(len=:), allocatable :: text
      end function case_echo

      !> The default of &integrator max_steps (echoed only when another is given).
      pure integer(i8) module function mechanism_case_input_t_max_steps() result(n)
      end function mechanism_case_input_t_max_steps

      !> "x, y, z" of a vector, `digits` (12) significant digits each.
      module function vector_text(v, digits) result(text)
         real(dp), intent(in) :: v(:)
         integer, intent(in), optional :: digits
         character(len=:), allocatable :: text
      end function vector_text

      !> Every body, marker and interface a &joint, &load, &marker or &mechanism names exists: the
      !> markers of a body with a mesh are its interfaces, those of a rigid body or the ground
      !> are its &marker groups.
      module subroutine check_mechanism_names(src, case, error)
         !> The case text: FILE:LINE of the names
         type(nml_source_t), intent(in) :: src
         type(case_input_t), intent(in) :: case
         type(error_t), allocatable, intent(out) :: error
      end subroutine check_mechanism_names

      !> Number of &driver groups (0 for a case built in memory without them).
      pure integer module function driver_count(mech)
         type(mechanism_case_input_t), intent(in) :: mech
      end function driver_count

      !> Number of &spring groups (0 for a case built in memory without them).
      pure integer module function spring_count(mech)
         type(mechanism_case_input_t), intent(in) :: mech
      end function spring_count

      !> Number of &sensor groups (0 for a case built in memory without them).
      pure integer module function sensor_count(mech)
         type(mechanism_case_input_t), intent(in) :: mech
      end function sensor_count

      !> Names of the groups `group` (spring, torsion_spring, bushing) of the case; none for a
      !> case built in memory without them.
      pure module function element_names(mech, group) result(names)
         type(mechanism_case_input_t), intent(in) :: mech
         character(len=*), intent(in) :: group
         character(len=64), allocatable :: names(:)
      end function element_names

      !> Index of the &body called name, 0 if none (e.g. the ground).
      pure integer module function body_index(case, name) result(k)
         type(case_input_t), intent(in) :: case
         character(len=*), intent(in) :: name
      end function body_index

      !> The mode-shape file name, 'none' when no file is written (quotes doubled as nml_string).
      pure module function msh_name(file_name) result(name)
         character(len=*), intent(in) :: file_name
         character(len=:), allocatable :: name
      end function msh_name

      !> A string value for the echo between single quotes: trailing blanks dropped, each ' doubled
      !> (title = 'it''s'), so that the echo reads back as the same input.
      pure module function nml_string(text) result(quoted)
         character(len=*), intent(in) :: text
         character(len=:), allocatable :: quoted
      end function nml_string

      !> "input/crank_rc1.nml" -> "crank_rc1"; "-" (standard input) -> "stdin".
      pure module function case_name_of(file_name) result(name)
         character(len=*), intent(in) :: file_name
         character(len=:), allocatable :: name
      end function case_name_of
   end interface

contains

   !> The namelist groups of a case and their keys (the reader modules' *_keys).
   function case_groups() result(groups)
      type(group_spec_t), allocatable :: groups(:)
      ! element by element: gfortran 12 leaks the keys of group_spec_t(...) constructors in an
      ! array constructor (valgrind, tests/capi)
      allocate (groups(17))
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
      call set(17, 'output', .false., output_keys())
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
      if (.not. allocated(error)) call read_output_group(unit, case%output, error)
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
         if (.not. allocated(error)) call check_history_names(case%output, [character(len=64) &
            :: case%bodies%name, case%mechanism%joints%name, history_sensors(case)], error)
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
      if (.not. allocated(error)) call check_export(src%where('run', 1, 'export'), &
         case%run%export, error)
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

   !> The names of the case's sensors (none for a case built without &sensor groups).
   function history_sensors(case) result(names)
      type(case_input_t), intent(in) :: case
      character(len=64), allocatable :: names(:)
      allocate (names(0))
      if (allocated(case%mechanism%sensors)) names = case%mechanism%sensors%name
   end function history_sensors

end module ffrf_input_case
