!> A case file: the namelist groups of one run, read, checked against each other, and echoed.
module ffrf_io_case
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, add_context, FFRF_INPUT_ERROR, FFRF_IO_ERROR
   use ffrf_core_strings, only: to_str, to_lower
   use ffrf_modes_input, only: body_input_t, modes_input_t
   use ffrf_mpc_interface, only: interface_input_t
   use ffrf_io_nml_common, only: check_group_names
   use ffrf_io_nml_run, only: run_input_t, read_run_group
   use ffrf_io_nml_body, only: read_body_groups
   use ffrf_io_nml_interface, only: read_interface_groups
   use ffrf_io_nml_modes, only: read_modes_group
   implicit none
   private
   public :: case_input_t, read_case, case_echo

   !> Everything a modal run needs.
   type :: case_input_t
      !> Case file as given
      character(len=:), allocatable :: file_name
      !> Case name: the file name without folder and extension
      character(len=:), allocatable :: name
      type(run_input_t) :: run
      type(body_input_t), allocatable :: bodies(:)
      type(interface_input_t), allocatable :: interfaces(:)
      type(modes_input_t) :: modes
   end type case_input_t

contains

   !> Read and check the case file `file_name`.
   subroutine read_case(file_name, case, error)
      character(len=*), intent(in) :: file_name
      type(case_input_t), intent(out) :: case
      type(error_t), allocatable, intent(out) :: error
      integer :: unit, stat, k
      character(len=512) :: msg
      case%file_name = file_name
      case%name = case_name_of(file_name)
      open (newunit=unit, file=file_name, status='old', action='read', iostat=stat, iomsg=msg)
      if (stat /= 0) then
         call fatal_error(error, FFRF_IO_ERROR, 'cannot open case file "' // file_name // &
            '": ' // trim(msg))
         return
      end if
      call check_group_names(unit, [character(len=16) :: 'run', 'body', 'interface', 'modes'], &
         error)
      if (.not. allocated(error)) call read_run_group(unit, case%run, error)
      if (.not. allocated(error)) call read_body_groups(unit, case%bodies, error)
      if (.not. allocated(error)) call read_interface_groups(unit, case%interfaces, error)
      if (.not. allocated(error)) call read_modes_group(unit, case%modes, error)
      close (unit)
      if (allocated(error)) then
         call add_context(error, file_name)
         return
      end if
      do k = 1, size(case%interfaces)
         if (.not. any(case%bodies%name == case%interfaces(k)%body)) then
            call fatal_error(error, FFRF_INPUT_ERROR, file_name // ': &interface #' // &
               to_str(k) // ' "' // trim(case%interfaces(k)%name) // '": body "' // &
               trim(case%interfaces(k)%body) // '" is not a &body of this case')
            return
         end if
         if (any(case%interfaces(:k - 1)%body == case%interfaces(k)%body .and. &
               case%interfaces(:k - 1)%name == case%interfaces(k)%name)) then
            call fatal_error(error, FFRF_INPUT_ERROR, file_name // ': &interface #' // &
               to_str(k) // ' "' // trim(case%interfaces(k)%name) // '" of body "' // &
               trim(case%interfaces(k)%body) // '" is given twice')
            return
         end if
      end do
      if (len_trim(case%run%output) == 0) case%run%output = case%name // '.h5'
      if (len_trim(case%run%mode_shapes_msh) == 0) then
         case%run%mode_shapes_msh = case%name // '_modes.msh'
      else if (to_lower(trim(case%run%mode_shapes_msh)) == 'none') then
         case%run%mode_shapes_msh = ''
      end if
   end subroutine read_case

   !> The resolved input as namelist text (defaults filled in), for the log and /input.
   function case_echo(case) result(text)
      type(case_input_t), intent(in) :: case
      character(len=:), allocatable :: text
      character(len=*), parameter :: nl = new_line('a')
      integer :: k, v
      text = '&run title = ''' // trim(case%run%title) // ''', output = ''' // &
         trim(case%run%output) // ''', mode_shapes_msh = ''' // &
         msh_name(case%run%mode_shapes_msh) // &
         ''', log_level = ''' // trim(case%run%log_level) // ''' /' // nl
      do k = 1, size(case%bodies)
         associate (b => case%bodies(k))
            text = text // '&body name = ''' // trim(b%name) // ''', mesh_file = ''' // &
               trim(b%mesh_file) // ''', volumes ='
            do v = 1, size(b%volumes)
               if (len_trim(b%volumes(v)) > 0) text = text // ' ''' // trim(b%volumes(v)) // ''''
            end do
            text = text // ', young = ' // to_str(b%young, 12) // ', poisson = ' // &
               to_str(b%poisson, 12) // ', density = ' // to_str(b%density, 12) // ' /' // nl
         end associate
      end do
      do k = 1, size(case%interfaces)
         associate (f => case%interfaces(k))
            text = text // '&interface body = ''' // trim(f%body) // ''', name = ''' // &
               trim(f%name) // ''', mpc = ''' // trim(f%mpc) // ''', weighting = ''' // &
               trim(f%weighting) // ''', virtual_node = ''' // trim(f%virtual_node) // ''''
            if (f%virtual_node == 'position') text = text // ', position = ' // &
               to_str(f%position(1), 12) // ' ' // to_str(f%position(2), 12) // ' ' // &
               to_str(f%position(3), 12)
            text = text // ', rc = ''' // trim(f%rc) // ''' /' // nl
         end associate
      end do
      text = text // '&modes num_modes = ' // to_str(case%modes%num_modes) // ', shift_hz = ' // &
         to_str(case%modes%shift_hz, 12) // ', formulation = ''' // &
         trim(case%modes%formulation) // ''', rc_label = ''' // trim(case%modes%rc_label) // &
         ''', tolerance = ' // to_str(case%modes%tolerance, 6) // ', lanczos_vectors = ' // &
         to_str(case%modes%lanczos_vectors) // ' /' // nl
   end function case_echo

   !> The mode-shape file name, 'none' when no file is written.
   pure function msh_name(file_name) result(name)
      character(len=*), intent(in) :: file_name
      character(len=:), allocatable :: name
      name = trim(file_name)
      if (len(name) == 0) name = 'none'
   end function msh_name

   !> "input/crank_rc1.nml" -> "crank_rc1".
   pure function case_name_of(file_name) result(name)
      character(len=*), intent(in) :: file_name
      character(len=:), allocatable :: name
      integer :: slash, dot
      slash = index(file_name, '/', back=.true.)
      name = file_name(slash + 1:)
      dot = index(name, '.', back=.true.)
      if (dot > 1) name = name(:dot - 1)
   end function case_name_of

end module ffrf_io_case
