!> What a flexible body needs besides its modes when the modes come from a file (&body
!> modes_file, docs/mode_reuse.md): the body cut from its mesh, its consistent mass matrix and
!> mass properties, and its interfaces; no stiffness, no factorisation, no eigen-solve. The
!> results equal those of compute_body_modes (ffrf_modes_modal_analysis) bit for bit, so the
!> fingerprint of the body and the inertia invariants are those of computed modes.
module ffrf_modes_reused_modes
   use ffrf_core_error, only: error_t, add_context
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: logger_t, stage_timer_t, stage_times_t
   use ffrf_mesh_mesh, only: mesh_t, extract_body
   use ffrf_fe_material, only: material_t, check_material
   use ffrf_fe_assembly, only: body_mass_properties
   use ffrf_fe_assembly, only: assemble_mass => assemble_matrices
   use ffrf_la_sparse, only: csr_t
   use ffrf_mpc_interface, only: interface_spec_t, build_interface
   use ffrf_modes_input, only: body_spec_t
   use ffrf_modes_modal_analysis, only: body_modes_t
   implicit none
   private
   public :: body_without_modes

contains

   !> The body of `mesh` (body_spec%volumes) with its mass matrix, mass properties and
   !> interfaces, as compute_body_modes makes them, without stiffness and modes.
   subroutine body_without_modes(mesh, body_spec, interfaces, log, times, body, mass_matrix, &
         error)
      !> The mesh as read
      type(mesh_t), intent(in) :: mesh
      !> Body: name, volumes, material
      type(body_spec_t), intent(in) :: body_spec
      !> The body's interfaces, resolved
      type(interface_spec_t), intent(in) :: interfaces(:)
      type(logger_t), intent(in) :: log
      type(stage_times_t), intent(inout) :: times
      !> Result: mesh, mass properties, interfaces, num_dofs (no modes yet)
      type(body_modes_t), intent(out) :: body
      !> The consistent FE mass matrix of the body
      type(csr_t), intent(out) :: mass_matrix
      type(error_t), allocatable, intent(out) :: error
      type(material_t) :: material
      type(stage_timer_t) :: timer
      character(len=:), allocatable :: mesh_name
      integer :: k

      body%name = trim(body_spec%name)
      material = material_t(body_spec%young, body_spec%poisson, body_spec%density, body%name)
      call check_material(material, error)
      if (allocated(error)) return
      mesh_name = '(in memory)'
      if (allocated(mesh%file_name)) mesh_name = mesh%file_name
      call timer%begin()
      call extract_body(mesh, pack(body_spec%volumes, len_trim(body_spec%volumes) > 0), &
         body%mesh, error)
      if (allocated(error)) return
      call times%add(body%name // ': mesh', timer%seconds())
      call timer%begin()
      call assemble_mass(body%mesh%xyz, body%mesh%tets, body%mesh%tet_tags, material, &
         mass_matrix, error)
      if (allocated(error)) then
         call add_context(error, 'body "' // body%name // '", mesh "' // mesh_name // '"')
         return
      end if
      call body_mass_properties(mass_matrix, body%mesh%xyz, body%mass, body%center_of_mass, &
         body%inertia)
      body%num_dofs = 3 * body%mesh%num_nodes
      call times%add(body%name // ': mass matrix', timer%seconds())
      call log%debug('fe', body%name // ': ' // to_str(body%num_dofs) // ' dofs, mass matrix ' // &
         'only (modes from a file) ... ' // to_str(timer%seconds(), 3) // ' s')
      call timer%begin()
      allocate (body%interfaces(size(interfaces)))
      do k = 1, size(interfaces)
         call build_interface(body%mesh, interfaces(k), body%interfaces(k), error)
         if (allocated(error)) then
            call add_context(error, 'body "' // body%name // '", mesh "' // mesh_name // '"')
            return
         end if
      end do
      call times%add(body%name // ': interfaces', timer%seconds())
   end subroutine body_without_modes

end module ffrf_modes_reused_modes
