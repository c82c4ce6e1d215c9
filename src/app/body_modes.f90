!> The application side of compute_body_modes: a body's Gmsh file is read here (its path taken
!> from the mesh folder when relative), then ffrf_modes_modal_analysis computes the modes of the
!> mesh object; modes/ sees no file names. reuse_body_modes takes them from an earlier results
!> file instead (&body modes_file), checked against their fingerprint.
module ffrf_app_body_modes
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: logger_t, stage_timer_t, stage_times_t, LOG_QUIET
   use ffrf_core_paths, only: join_path
   use ffrf_la_sparse, only: csr_t
   use ffrf_mesh_mesh, only: mesh_t
   use ffrf_mesh_bulk_data, only: read_mesh_file
   use ffrf_modes_input, only: body_spec_t
   use ffrf_mpc_interface, only: interface_spec_t, interface_t
   use ffrf_modes_input, only: modes_spec_t
   use ffrf_input_body, only: body_input_t
   use ffrf_model_model, only: body_spec_of
   use ffrf_modes_modal_analysis, only: body_modes_t, compute_body_modes
   use ffrf_input_interface, only: interface_input_t
   use ffrf_input_modes, only: modes_input_t
   use ffrf_model_specs, only: body_interface_specs, modes_spec_of
   use ffrf_modes_fingerprint, only: modes_fingerprint_t, make_fingerprint, compare_fingerprints
   use ffrf_io_modes_file, only: stored_modes_t, read_stored_modes
   use ffrf_modes_reused_modes, only: body_without_modes
   implicit none
   private
   public :: read_body_mesh, compute_body_modes_from_file, compute_input_body_modes, &
      reuse_body_modes, check_stored_modes, mesh_body_spec

contains

   !> Read the mesh file of a body (body_input%mesh_file, relative to mesh_dir unless absolute;
   !> Gmsh, or Nastran bulk data by its suffix); the reading time goes to `times` as
   !> "<body>: mesh file".
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
      call read_mesh_file(join_path(mesh_dir, trim(body_input%mesh_file)), mesh, error)
      if (allocated(error)) return
      call times%add(trim(body_input%name) // ': mesh file', timer%seconds())
   end subroutine read_body_mesh

   !> The body to cut from `mesh` (body_spec_of), its material taken from a Nastran deck (the
   !> MAT1 of the body's PSOLIDs) for each of young, poisson, density that &body does not give
   !> (docs/input.md "Nastran bulk data"); a body whose PSOLIDs have different MAT1 is refused.
   subroutine mesh_body_spec(body_input, mesh, spec, error, log)
      type(body_input_t), intent(in) :: body_input
      !> The mesh as read (or the body cut from it)
      type(mesh_t), intent(in) :: mesh
      type(body_spec_t), intent(out) :: spec
      type(error_t), allocatable, intent(out) :: error
      !> Where the material and the cards not read are reported
      type(logger_t), intent(in), optional :: log
      integer :: i, k, m, found
      spec = body_spec_of(body_input)
      if (.not. allocated(mesh%materials)) return
      found = 0
      do i = 1, size(body_input%volumes)
         if (len_trim(body_input%volumes(i)) == 0) cycle
         k = mesh%find_group(3, trim(body_input%volumes(i)))
         if (k == 0) cycle
         m = findloc(mesh%materials%volume, mesh%groups(k)%tag, dim=1)
         if (m == 0) cycle
         if (found == 0) found = m
         if (mesh%materials(m)%young /= mesh%materials(found)%young .or. &
            mesh%materials(m)%poisson /= mesh%materials(found)%poisson .or. &
            mesh%materials(m)%density /= mesh%materials(found)%density) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'body "' // trim(body_input%name) // &
               '": its PSOLIDs have different materials, ' // mesh%materials(found)%origin // &
               ' and ' // mesh%materials(m)%origin // '; a body has one material: make ' // &
               'one body per material')
            return
         end if
      end do
      if (found == 0) return
      if (.not. body_input%material_given(1)) spec%young = mesh%materials(found)%young
      if (.not. body_input%material_given(2)) spec%poisson = mesh%materials(found)%poisson
      if (.not. body_input%material_given(3)) spec%density = mesh%materials(found)%density
      if (present(log)) then
         call log%info('mesh', trim(body_input%name) // ': material E = ' // &
            to_str(spec%young, 6) // ' Pa, nu = ' // to_str(spec%poisson, 6) // ', rho = ' // &
            to_str(spec%density, 6) // ' kg/m^3 (' // mesh%materials(found)%origin // &
            ' where &body gives none)')
         if (allocated(mesh%ignored_cards)) then
            if (len(mesh%ignored_cards) > 0) call log%info('mesh', trim(body_input%name) // &
               ': cards not read: ' // mesh%ignored_cards)
         end if
      end if
   end subroutine mesh_body_spec

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
      type(body_spec_t) :: spec
      call read_body_mesh(body_input, mesh_dir, times, mesh, error)
      if (.not. allocated(error)) call mesh_body_spec(body_input, mesh, spec, error, log)
      if (allocated(error)) return
      call compute_body_modes(mesh, spec, interfaces, modes, log, times, &
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

   !> The modes of a body taken from the results file of an earlier run (&body modes_file) instead
   !> of computed (docs/mode_reuse.md): the mesh is read and the body's mass matrix assembled as
   !> for computed modes (the inertia invariants need it), the interfaces are built, and the
   !> fingerprint of what this run would compute (mesh, material, interfaces, modes
   !> specification) must equal the stored one; then the stored frequencies, shapes and
   !> virtual-node rows are the body's. No factorisation, no Lanczos. With num_modes_given the
   !> number of modes must match too; otherwise the file's modes are taken as they are (an
   !> automatic model's selection included). FFRF_IO_ERROR: the file is missing or not HDF5;
   !> FFRF_INPUT_ERROR: it holds no modes of this body, or they depend on something else.
   subroutine reuse_body_modes(body_input, interfaces, modes, num_modes_given, mesh_dir, log, &
         times, body, error, mass_matrix, stiffness_matrix)
      !> Body: mesh file, volumes, material, modes_file
      type(body_input_t), intent(in) :: body_input
      !> The body's interfaces, resolved (ffrf_model_specs)
      type(interface_spec_t), intent(in) :: interfaces(:)
      !> Number of modes, shift, formulation, basis, resolved
      type(modes_spec_t), intent(in) :: modes
      !> modes%num_modes was given for the body (&body num_modes)
      logical, intent(in) :: num_modes_given
      !> Folder relative mesh files are taken from
      character(len=*), intent(in) :: mesh_dir
      type(logger_t), intent(in) :: log
      type(stage_times_t), intent(inout) :: times
      !> Result: as compute_body_modes gives it (solver statistics empty)
      type(body_modes_t), intent(out) :: body
      type(error_t), allocatable, intent(out) :: error
      !> The consistent FE mass matrix of the body
      type(csr_t), intent(out), optional :: mass_matrix
      !> The FE stiffness matrix of the body
      type(csr_t), intent(out), optional :: stiffness_matrix
      type(mesh_t) :: mesh
      type(modes_spec_t) :: geometry_only
      type(stored_modes_t) :: stored
      type(stage_timer_t) :: timer
      type(logger_t) :: quiet
      type(csr_t) :: unused_mass
      type(body_spec_t) :: spec
      character(len=:), allocatable :: file_name, where

      file_name = trim(body_input%modes_file)
      where = 'modes_file "' // file_name // '"'
      call timer%begin()
      call read_stored_modes(file_name, trim(body_input%name), 'modes_file', stored, error)
      if (allocated(error)) return
      call times%add(trim(body_input%name) // ': modes file', timer%seconds())
      ! mesh, mass properties and interfaces, without modes
      geometry_only = modes
      geometry_only%num_modes = 0
      call read_body_mesh(body_input, mesh_dir, times, mesh, error)
      if (.not. allocated(error)) call mesh_body_spec(body_input, mesh, spec, error)
      if (allocated(error)) return
      if (present(stiffness_matrix)) then
         ! K for the geometric stiffness: the assembly of computed modes, without modes
         quiet = log
         quiet%level = LOG_QUIET
         call compute_body_modes(mesh, spec, interfaces, geometry_only, &
            quiet, times, body, error, mass_matrix, stiffness_matrix)
      else if (present(mass_matrix)) then
         call body_without_modes(mesh, spec, interfaces, log, times, body, &
            mass_matrix, error)
      else
         call body_without_modes(mesh, spec, interfaces, log, times, body, &
            unused_mass, error)
      end if
      if (allocated(error)) return
      call check_stored_modes(body_input, body%mesh, body%interfaces, modes, num_modes_given, &
         stored, error)
      if (allocated(error)) return
      body%basis = modes%basis
      body%formulation = modes%formulation
      body%num_static = int(stored%num_static, kind(body%num_static))
      call move_alloc(stored%frequency_hz, body%frequency_hz)
      call move_alloc(stored%shape, body%shape)
      call move_alloc(stored%virtual_node_shape, body%virtual_node_shape)
      body%fingerprint = stored%fingerprint
      call log%info('modes', trim(body_input%name) // ': ' // trim(body_input%mesh_file) // &
         ', ' // to_str(body%mesh%num_nodes) // ' nodes, mass ' // to_str(body%mass, 6) // &
         ' kg; ' // to_str(size(body%frequency_hz)) // ' modes from ' // where // &
         ' (fingerprint ' // stored%fingerprint%total_hash() // ' matches)' // &
         frequency_range(body%frequency_hz) // ' ... ' // to_str(timer%seconds(), 3) // ' s')
   end subroutine reuse_body_modes

   !> The check of stored modes (docs/mode_reuse.md "The check"), shared by the run
   !> (reuse_body_modes) and `ffrf --check`: the fingerprint of what this run would compute for
   !> the body (its mesh as cut from the mesh file, its built interfaces, material, modes
   !> specification) must equal the stored one, and the stored shapes must have the body's
   !> rows. FFRF_INPUT_ERROR naming the first difference, with both values, otherwise.
   subroutine check_stored_modes(body_input, mesh, interfaces, modes, num_modes_given, stored, &
         error)
      !> Body: name, material, modes_file
      type(body_input_t), intent(in) :: body_input
      !> The body cut from its mesh file
      type(mesh_t), intent(in) :: mesh
      !> The body's interfaces, built on `mesh`
      type(interface_t), intent(in) :: interfaces(:)
      !> Number of modes, shift, formulation, basis, resolved
      type(modes_spec_t), intent(in) :: modes
      !> modes%num_modes was given for the body (&body num_modes); otherwise the file's count
      logical, intent(in) :: num_modes_given
      !> The modes as read from body_input%modes_file (read_stored_modes)
      type(stored_modes_t), intent(in) :: stored
      type(error_t), allocatable, intent(out) :: error
      type(modes_spec_t) :: asked
      type(modes_fingerprint_t) :: here
      type(body_spec_t) :: spec
      character(len=:), allocatable :: difference, where
      logical :: same
      integer :: num_dofs

      where = 'modes_file "' // trim(body_input%modes_file) // '"'
      asked = modes
      if (.not. num_modes_given) asked%num_modes = size(stored%frequency_hz)
      call mesh_body_spec(body_input, mesh, spec, error)
      if (allocated(error)) return
      call make_fingerprint(mesh, interfaces, spec, asked, asked%num_modes, here)
      call compare_fingerprints(here, stored%fingerprint, .not. num_modes_given, same, &
         difference)
      if (.not. same) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': ' // difference // &
            '; its modes of body "' // trim(body_input%name) // '" were computed for ' // &
            'another model: give the results file of a run of this body as it is here, or ' // &
            'remove modes_file to compute the modes')
         return
      end if
      num_dofs = 3 * mesh%num_nodes
      if (size(stored%shape, 1) /= num_dofs .or. size(stored%virtual_node_shape, 1) /= &
         6 * size(interfaces)) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ', body "' // &
            trim(body_input%name) // '": shapes of ' // to_str(size(stored%shape, 1)) // &
            ' and ' // to_str(size(stored%virtual_node_shape, 1)) // ' rows for ' // &
            to_str(num_dofs) // ' dofs and ' // to_str(size(interfaces)) // &
            ' interfaces; the file is damaged')
         return
      end if
   end subroutine check_stored_modes

   function frequency_range(frequency_hz) result(text)
      real(dp), intent(in) :: frequency_hz(:)
      character(len=:), allocatable :: text
      text = ''
      if (size(frequency_hz) > 0) text = ', ' // to_str(frequency_hz(1), 6) // ' .. ' // &
         to_str(frequency_hz(size(frequency_hz)), 6) // ' Hz'
   end function frequency_range

end module ffrf_app_body_modes
