!> Reads a modal case through the installed ffrf library, computes the first body's modes and
!> prints them as "<body> <mode> <frequency in Hz>" lines (17 digits after the point: exact
!> round trip), for comparison with the installed driver's results file of the same case.
program modes_app
   use ffrf, only: dp, error_t, logger_t, stage_times_t, case_input_t, read_case, body_modes_t, &
      compute_body_modes, mesh_t, read_gmsh, interface_spec_t, modes_spec_t, &
      body_interface_specs, modes_spec_of, body_spec_of, LOG_QUIET
   implicit none
   type(case_input_t) :: case
   type(mesh_t) :: mesh
   type(interface_spec_t), allocatable :: interfaces(:)
   type(modes_spec_t) :: modes
   type(body_modes_t) :: body
   type(logger_t) :: log
   type(stage_times_t) :: times
   type(error_t), allocatable :: error
   character(len=512) :: case_file, mesh_dir
   integer :: i
   call get_command_argument(1, case_file)
   call get_command_argument(2, mesh_dir)
   log%level = LOG_QUIET
   call read_case(trim(case_file), case, error)
   if (.not. allocated(error)) call read_gmsh(trim(mesh_dir) // '/' // &
      trim(case%bodies(1)%mesh_file), mesh, error)
   if (.not. allocated(error)) call body_interface_specs(case%interfaces, case%bodies(1)%name, &
      interfaces, error)
   if (.not. allocated(error)) call modes_spec_of(case%modes, modes, error)
   if (.not. allocated(error)) call compute_body_modes(mesh, body_spec_of(case%bodies(1)), &
      interfaces, modes, log, times, body, error)
   if (allocated(error)) then
      print '(a)', 'modes_app: ' // error%message
      error stop 1
   end if
   print '(a, i0, a)', '# modes_app: ', size(body%frequency_hz), ' modes'
   do i = 1, size(body%frequency_hz)
      print '(a, 1x, i0, 1x, es25.17e3)', trim(case%bodies(1)%name), i, body%frequency_hz(i)
   end do
end program modes_app
