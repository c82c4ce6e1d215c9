!> The application side of compute_body_modes: a body's Gmsh file is read here (its path taken
!> from the mesh folder when relative), then ffrf_modes_modal_analysis computes the modes of the
!> mesh object; modes/ sees no file names.
module ffrf_app_body_modes
   use ffrf_core_error, only: error_t
   use ffrf_core_log, only: logger_t, stage_timer_t, stage_times_t
   use ffrf_core_paths, only: join_path
   use ffrf_la_sparse, only: csr_t
   use ffrf_mesh_mesh, only: mesh_t
   use ffrf_mesh_gmsh, only: read_gmsh
   use ffrf_mpc_interface, only: interface_spec_t
   use ffrf_modes_input, only: modes_spec_t
   use ffrf_input_body, only: body_input_t
   use ffrf_model_model, only: body_spec_of
   use ffrf_modes_modal_analysis, only: body_modes_t, compute_body_modes
   use ffrf_input_interface, only: interface_input_t
   use ffrf_input_modes, only: modes_input_t
   use ffrf_model_specs, only: body_interface_specs, modes_spec_of
   implicit none
   private
   public :: read_body_mesh, compute_body_modes_from_file, compute_input_body_modes

contains

   !> Read the Gmsh file of a body (body_input%mesh_file, relative to mesh_dir unless absolute);
   !> the reading time goes to `times` as "<body>: mesh file".
   subroutine read_body_mesh(body_input, mesh_dir, times, mesh, error)
      !> Body: name and mesh file
      type(body_input_t), intent(in) :: body_input
      !> Folder relative mesh files are taken from ('' = as given)
      character(len=*), intent(in) :: mesh_dir
      !> Stage times, appended to
      type(stage_times_t), intent(inout) :: times
      !> The mesh as read
      type(mesh_t), intent(out) :: mesh
      type(error_t), allocatable, intent(out) :: error
      type(stage_timer_t) :: timer
      call timer%begin()
      call read_gmsh(join_path(mesh_dir, trim(body_input%mesh_file)), mesh, error)
      if (allocated(error)) return
      call times%add(trim(body_input%name) // ': mesh file', timer%seconds())
   end subroutine read_body_mesh

   !> read_body_mesh, then compute_body_modes on the mesh (same arguments otherwise).
   subroutine compute_body_modes_from_file(body_input, interfaces, modes, mesh_dir, &
         log, times, body, error, mass_matrix, stiffness_matrix)
      !> Body: mesh file, volumes, material
      type(body_input_t), intent(in) :: body_input
      !> The body's interfaces, resolved (ffrf_model_specs)
      type(interface_spec_t), intent(in) :: interfaces(:)
      !> Number of modes, shift, formulation, basis, resolved
      type(modes_spec_t), intent(in) :: modes
      !> Folder relative mesh files are taken from
      character(len=*), intent(in) :: mesh_dir
      !> Progress log
      type(logger_t), intent(in) :: log
      !> Stage times, appended to
      type(stage_times_t), intent(inout) :: times
      !> Result
      type(body_modes_t), intent(out) :: body
      type(error_t), allocatable, intent(out) :: error
      !> The consistent FE mass matrix of the body
      type(csr_t), intent(out), optional :: mass_matrix
      !> The FE stiffness matrix of the body
      type(csr_t), intent(out), optional :: stiffness_matrix
      type(mesh_t) :: mesh
      call read_body_mesh(body_input, mesh_dir, times, mesh, error)
      if (allocated(error)) return
      call compute_body_modes(mesh, body_spec_of(body_input), interfaces, modes, log, times, &
         body, error, mass_matrix, stiffness_matrix)
   end subroutine compute_body_modes_from_file

   !> The modes of a body from the input as read: its &interface groups (those naming the body,
   !> in input order) and &modes resolved by the model (ffrf_model_specs), then
   !> compute_body_modes_from_file. num_modes is &modes num_modes as given.
   subroutine compute_input_body_modes(body_input, interface_inputs, modes_input, mesh_dir, &
         log, times, body, error, mass_matrix, stiffness_matrix)
      !> Body: mesh file, volumes, material
      type(body_input_t), intent(in) :: body_input
      !> &interface groups (those of this body are used)
      type(interface_input_t), intent(in) :: interface_inputs(:)
      !> &modes as read
      type(modes_input_t), intent(in) :: modes_input
      !> Folder relative mesh files are taken from
      character(len=*), intent(in) :: mesh_dir
      !> Progress log
      type(logger_t), intent(in) :: log
      !> Stage times, appended to
      type(stage_times_t), intent(inout) :: times
      !> Result
      type(body_modes_t), intent(out) :: body
      type(error_t), allocatable, intent(out) :: error
      !> The consistent FE mass matrix of the body
      type(csr_t), intent(out), optional :: mass_matrix
      !> The FE stiffness matrix of the body
      type(csr_t), intent(out), optional :: stiffness_matrix
      type(interface_spec_t), allocatable :: interfaces(:)
      type(modes_spec_t) :: modes
      call body_interface_specs(interface_inputs, body_input%name, interfaces, error)
      if (.not. allocated(error)) call modes_spec_of(modes_input, modes, error)
      if (allocated(error)) return
      call compute_body_modes_from_file(body_input, interfaces, modes, mesh_dir, log, times, &
         body, error, mass_matrix, stiffness_matrix)
   end subroutine compute_input_body_modes

end module ffrf_app_body_modes
