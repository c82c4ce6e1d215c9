!> Reads a modal case through the installed ffrf library and computes the first body's modes.
program modes_app
   use ffrf, only: dp, error_t, logger_t, stage_times_t, case_input_t, read_case, body_modes_t, &
      compute_body_modes, mesh_t, read_gmsh, interface_spec_t, modes_spec_t, &
      body_interface_specs, modes_spec_of, LOG_QUIET
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
   call get_command_argument(1, case_file)
   call get_command_argument(2, mesh_dir)
   log%level = LOG_QUIET
   call read_case(trim(case_file), case, error)
   if (.not. allocated(error)) call read_gmsh(trim(mesh_dir) // '/' // &
      trim(case%bodies(1)%mesh_file), mesh, error)
   if (.not. allocated(error)) call body_interface_specs(case%interfaces, case%bodies(1)%name, &
      interfaces, error)
   if (.not. allocated(error)) call modes_spec_of(case%modes, modes, error)
   if (.not. allocated(error)) call compute_body_modes(mesh, case%bodies(1), interfaces, modes, &
      log, times, body, error)
   if (allocated(error)) then
      print '(a)', 'modes_app: ' // error%message
      error stop 1
   end if
   print '(a, i0, a, f10.2, a)', 'modes_app: ', size(body%frequency_hz), ' modes, first at ', &
      body%frequency_hz(1), ' Hz'
   if (.not. (body%frequency_hz(1) > 100.0_dp)) error stop 1
end program modes_app
