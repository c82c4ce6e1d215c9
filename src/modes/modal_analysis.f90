!> Constrained normal modes of one flexible body (Cammarata et al. 2022, "Methodology"):
!> mesh -> Tet4/Tet10 K and M -> interfaces reduced to virtual nodes (RBE2/RBE3) -> reference
!> conditions D q_V = 0 -> RC matrix T (and constraint rows C) -> (T^T K T) phi = w^2 (T^T M T) phi
!> by shift-invert Lanczos on one MUMPS factorisation -> psi = T phi, mass-normalised.
!> With modes%basis = BASIS_CRAIG_BAMPTON the basis is instead the Craig-Bampton one of
!> src/modes/craig_bampton.f90 (static constraint modes + fixed-interface modes, Rayleigh-Ritz).
module ffrf_modes_modal_analysis
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_kinds, only: dp, ip, i8, pi
   use ffrf_core_error, only: error_t, fatal_error, add_context, FFRF_INPUT_ERROR, &
      FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: logger_t, stage_timer_t, stage_times_t
   use ffrf_mesh_mesh, only: mesh_t, extract_body, face_connected_parts
   use ffrf_fe_material, only: material_t, check_material
   use ffrf_fe_assembly, only: assemble_stiffness_mass, body_mass_properties
   use ffrf_la_sparse, only: csr_t
   use ffrf_core_parallel, only: parallel_t, current_ranks
   use ffrf_mpc_interface, only: interface_spec_t, interface_t, build_interface, mpc_name, &
      dofs_text
   use ffrf_mpc_reference_conditions, only: rc_summary_t, check_reference_conditions
   use ffrf_mpc_reduction, only: reduction_t, build_reduction, reduce_matrix, expand_vectors, &
      FORMULATION_NONE, formulation_name, reduced_coordinates
   use ffrf_modes_input, only: body_spec_t, modes_spec_t, BASIS_NONE, BASIS_CRAIG_BAMPTON
   use ffrf_modes_shift_invert, only: eigen_options_t, eigen_result_t, solve_shift_invert
   use ffrf_modes_craig_bampton, only: cb_result_t, craig_bampton_modes
   use ffrf_modes_fingerprint, only: modes_fingerprint_t, make_fingerprint
   implicit none
   private
   public :: body_modes_t, compute_body_modes, sigma_of_shift

   !> A flexible eigenvalue below this fraction of the body's wave eigenvalue (2 pi f_wave)^2,
   !> f_wave = sqrt(E/rho)/L, is a motion without strain (a slender beam's first bending mode
   !> sits near 1e-4 of it, a loose part or a hinge at round-off, below 1e-12)
   real(dp), parameter :: ZERO_ENERGY_FRACTION = 1.0e-8_dp

   !> The reduced flexible body: mesh, interfaces, RC set and its constrained normal modes.
   type :: body_modes_t
      !> Body name
      character(len=:), allocatable :: name
      !> The body's mesh (only its nodes and elements)
      type(mesh_t) :: mesh
      !> Interfaces with their virtual nodes and MPC matrices
      type(interface_t), allocatable :: interfaces(:)
      !> Mass (kg), centre of mass (m), inertia about the centre of mass (kg m^2)
      real(dp) :: mass = 0.0_dp, center_of_mass(3) = 0.0_dp, inertia(3, 3) = 0.0_dp
      !> What the RC set does (rank, hyperstatic redundancy, free-free)
      type(rc_summary_t) :: rc
      !> FORMULATION_MULTIPLIERS or FORMULATION_NULL_SPACE (ffrf_mpc_reduction); FORMULATION_NONE
      !> when no modes were asked
      integer :: formulation = FORMULATION_NONE
      !> Mode basis: BASIS_RC_NORMAL or BASIS_CRAIG_BAMPTON (ffrf_modes_input); BASIS_NONE when
      !> no modes were asked
      integer :: basis = BASIS_NONE
      !> Craig-Bampton: static constraint modes in the basis (0 for 'rc_normal')
      integer(ip) :: num_static = 0
      !> Craig-Bampton: frequencies of the fixed-interface modes (Hz); empty for 'rc_normal'
      real(dp), allocatable :: fixed_interface_hz(:)
      !> Sizes: nodal dofs, reduced coordinates, constraint rows, stored entries of K
      integer(ip) :: num_dofs = 0, num_reduced = 0, num_constraints = 0
      integer(i8) :: stiffness_nnz = 0
      !> Natural frequencies of the flexible modes (Hz), ascending (Craig-Bampton: the Ritz
      !> frequencies of the orthonormalised basis, upper bounds of the RC normal modes')
      real(dp), allocatable :: frequency_hz(:)
      !> Frequencies of the skipped rigid modes of a free-free body (Hz, ~0)
      real(dp), allocatable :: rigid_frequency_hz(:)
      !> Mass-normalised mode shapes, (3 num_nodes, num_modes)
      real(dp), allocatable :: shape(:, :)
      !> Virtual-node motion of each mode, (6 num_interfaces, num_modes): [u; theta] per interface
      real(dp), allocatable :: virtual_node_shape(:, :)
      !> ||K phi - lambda M phi|| / ||K phi|| of each mode on the constrained space (Craig-
      !> Bampton: the distance of each Ritz vector from a normal mode, not a solver accuracy)
      real(dp), allocatable :: residual(:)
      !> max |Psi^T M Psi - I|
      real(dp) :: orthonormality_error = 0.0_dp
      !> Eigen solver statistics (Craig-Bampton: of the fixed-interface modes)
      type(eigen_result_t) :: eigen
      !> What the modes depend on (mesh, material, interfaces, modes specification), stored
      !> with them so that a later run can reuse them (ffrf_modes_fingerprint); not set when no
      !> modes were computed
      type(modes_fingerprint_t) :: fingerprint
   end type body_modes_t

   interface
      !> Shift-invert Lanczos on the reduced system, then psi = T phi and the virtual-node rows.
      module subroutine solve_modes(body, modes, red, K_r, M_r, auto_shift_hz, log, times, error, &
                                    ranks)
         type(body_modes_t), intent(inout) :: body
         type(modes_spec_t), intent(in) :: modes
         type(reduction_t), intent(in) :: red
         type(csr_t), intent(in) :: K_r, M_r
         !> Shift used when modes%shift_hz = 0 (Hz, negative)
         real(dp), intent(in) :: auto_shift_hz
         type(logger_t), intent(in) :: log
         type(stage_times_t), intent(inout) :: times
         type(error_t), allocatable, intent(out) :: error
         !> The ranks MUMPS runs on
         type(parallel_t), intent(in) :: ranks
      end subroutine solve_modes
   end interface

contains

   !> Automatic shift (Hz, negative): 1 % of sqrt(E/rho)/L, L the body's bounding-box diagonal.
   !> Every eigenvalue lies above a negative sigma, so the modes nearest sigma are the lowest
   !> ones; a sigma this far from zero keeps K - sigma M well conditioned even for a free-free
   !> body (cond ~ lambda_max/|sigma|: with sigma = -(2 pi 10 Hz)^2 a free-free Tet10 beam's
   !> Ritz vectors pick up rigid-mode round-off at the 1e-6 residual level, at this shift 1e-10).
   pure function automatic_shift_hz(xyz, material) result(shift_hz)
      real(dp), intent(in) :: xyz(:, :)
      type(material_t), intent(in) :: material
      real(dp) :: shift_hz, diagonal
      diagonal = norm2(maxval(xyz, dim=2) - minval(xyz, dim=2))
      shift_hz = -0.01_dp * sqrt(material%young / material%density) / max(diagonal, tiny(1.0_dp))
   end function automatic_shift_hz

   !> sigma = sign(f) (2 pi f)^2 for a shift given as a frequency f (Hz).
   pure function sigma_of_shift(shift_hz) result(sigma)
      real(dp), intent(in) :: shift_hz
      real(dp) :: sigma
      sigma = sign((2.0_dp * pi * shift_hz)**2, shift_hz)
   end function sigma_of_shift

   !> Compute the constrained normal modes of one body. With modes%num_modes = 0 no modes
   !> are computed: the body gets its mesh, mass properties and interfaces (a rigid body with the
   !> mesh's exact mass, e.g. a rigid reference in a mechanism run).
   !>
   !> `mesh` is the mesh as read (from a Gmsh file by the caller, or built in memory); the body is
   !> cut from it here by body_spec%volumes (extract_body), so a mesh holding several bodies can
   !> be passed as it is. Messages name the mesh by mesh%file_name when it is set.
   !>
   !> MPI build: every rank of `parallel` (default: the ranks of the run, current_ranks) calls
   !> with the same arguments; the element loop and MUMPS are shared, and every rank returns
   !> the same body (docs/mpi.md "MPI build and runs").
   subroutine compute_body_modes(mesh, body_spec, interfaces, modes, log, times, &
         body, error, mass_matrix, stiffness_matrix, parallel)
      !> The mesh as read: nodes, tetrahedra, physical groups
      type(mesh_t), intent(in) :: mesh
      !> Body: name, volumes, material
      type(body_spec_t), intent(in) :: body_spec
      !> The body's interfaces, resolved; body%interfaces(k) and the k-th virtual node of the
      !> mode shapes are interfaces(k) (the marker handle of the interface is k)
      type(interface_spec_t), intent(in) :: interfaces(:)
      !> Number of modes, shift, formulation, basis
      type(modes_spec_t), intent(in) :: modes
      !> Progress log
      type(logger_t), intent(in) :: log
      !> Stage times, appended to
      type(stage_times_t), intent(inout) :: times
      !> Result
      type(body_modes_t), intent(out) :: body
      type(error_t), allocatable, intent(out) :: error
      !> The consistent FE mass matrix of the body (for the inertia invariants of FFRF)
      type(csr_t), intent(out), optional :: mass_matrix
      !> The FE stiffness matrix of the body (for its geometric stiffness: no second assembly)
      type(csr_t), intent(out), optional :: stiffness_matrix
      !> The ranks sharing the work (MPI build); default current_ranks()
      type(parallel_t), intent(in), optional :: parallel
      type(parallel_t) :: ranks
      type(material_t) :: material
      type(csr_t) :: K, M, K_r, M_r
      type(reduction_t) :: red
      type(stage_timer_t) :: timer
      character(len=:), allocatable :: tag, mesh_name
      integer :: i_if, n_if

      body%name = trim(body_spec%name)
      tag = body%name
      if (present(parallel)) then
         ranks = parallel
      else
         ranks = current_ranks()
      end if
      material = material_t(body_spec%young, body_spec%poisson, body_spec%density, &
         body%name)
      call check_material(material, error)
      if (allocated(error)) return

      ! Mesh
      call timer%begin()
      mesh_name = '(in memory)'
      if (allocated(mesh%file_name)) mesh_name = mesh%file_name
      call extract_body(mesh, &
         pack(body_spec%volumes, len_trim(body_spec%volumes) > 0), body%mesh, error)
      if (allocated(error)) return
      call times%add(tag // ': mesh', timer%seconds())
      call log%info('mesh', tag // ': ' // mesh_name // ', ' // to_str(body%mesh%num_nodes) // &
         ' nodes, ' // to_str(body%mesh%num_tets()) // ' Tet' // &
         to_str(body%mesh%nodes_per_tet) // ' ... ' // to_str(timer%seconds(), 3) // ' s')

      ! Stiffness and mass
      call timer%begin()
      call assemble_stiffness_mass(body%mesh%xyz, body%mesh%tets, body%mesh%tet_tags, material, &
         K, M, error, ranks)
      if (allocated(error)) then
         call add_context(error, 'body "' // body%name // '", mesh "' // mesh_name // '"')
         return
      end if
      call body_mass_properties(M, body%mesh%xyz, body%mass, body%center_of_mass, body%inertia)
      if (present(mass_matrix)) mass_matrix = M
      if (present(stiffness_matrix)) stiffness_matrix = K
      body%num_dofs = 3 * body%mesh%num_nodes
      body%stiffness_nnz = int(K%row_ptr(K%num_rows + 1) - 1, i8)
      call times%add(tag // ': assembly', timer%seconds())
      call log%info('fe', tag // ': ' // to_str(body%num_dofs) // ' dofs, ' // &
         to_str(body%stiffness_nnz) // ' entries in K ... ' // to_str(timer%seconds(), 3) // ' s')
      call log%info('fe', tag // ': mass ' // to_str(body%mass, 6) // ' kg, centre of mass (' // &
         to_str(body%center_of_mass(1), 4) // ', ' // to_str(body%center_of_mass(2), 4) // ', ' // &
         to_str(body%center_of_mass(3), 4) // ') m, inertia about it diag (' // &
         to_str(body%inertia(1, 1), 4) // ', ' // to_str(body%inertia(2, 2), 4) // ', ' // &
         to_str(body%inertia(3, 3), 4) // ') kg m^2')

      ! Interfaces and reference conditions
      call timer%begin()
      n_if = size(interfaces)
      allocate (body%interfaces(n_if))
      do i_if = 1, n_if
         call build_interface(body%mesh, interfaces(i_if), body%interfaces(i_if), error)
         if (allocated(error)) then
            call add_context(error, 'body "' // body%name // '", mesh "' // mesh_name // '"')
            return
         end if
         associate (f => body%interfaces(i_if))
            call log%info('mpc', tag // ', ' // f%name // ': ' // mpc_name(f%mpc) // ', ' // &
               to_str(size(f%nodes)) // ' nodes, area ' // to_str(f%area, 6) // &
               ' m^2, virtual node (' // to_str(f%virtual_xyz(1), 6) // ', ' // &
               to_str(f%virtual_xyz(2), 6) // ', ' // to_str(f%virtual_xyz(3), 6) // ')' // &
               ', RC ' // dofs_text(f%rc, none='none'))
            if (f%rank_deficient .and. .not. any(f%rc(4:6))) call log%note('mpc', tag // ', ' // &
               f%name // ': nodes are collinear; the virtual-node rotation about that line ' // &
               'is undefined and reads zero')
         end associate
      end do
      body%basis = modes%basis
      allocate (body%fixed_interface_hz(0))
      if (modes%num_modes == 0) then
         allocate (body%shape(body%num_dofs, 0), body%virtual_node_shape(6 * n_if, 0))
         allocate (body%frequency_hz(0), body%residual(0))
         body%formulation = FORMULATION_NONE
         body%basis = BASIS_NONE
         call times%add(tag // ': interfaces', timer%seconds())
         call log%info('modes', tag // ': no modes asked: rigid body with the mass ' // &
            'properties of its mesh, markers at its virtual nodes')
         return
      end if
      call check_reference_conditions(body%interfaces, body%center_of_mass, body%rc, error)
      if (allocated(error)) then
         call add_context(error, 'body "' // body%name // '", mesh "' // mesh_name // '"')
         return
      end if
      if (body%rc%free_free) then
         call log%info('rc', tag // ': no reference conditions: free-free modes (mean ' // &
            'axes), the six rigid-body modes come from the geometry and are deflated')
      else
         call log%info('rc', tag // ': ' // to_str(body%rc%num_rc) // &
            ' reference conditions, all six rigid motions removed')
      end if
      if (body%rc%redundancy > 0) call log%note('rc', tag // ': the RC set is hyperstatic: ' // &
         to_str(body%rc%num_rc) // ' conditions for 6 rigid motions, so ' // &
         to_str(body%rc%redundancy) // ' condition(s) also constrain the deformation (this ' // &
         'changes the modes; statically determinate sets have exactly 6)')

      body%formulation = modes%formulation
      call build_reduction(body%mesh%num_nodes, body%interfaces, body%formulation, red, error)
      if (allocated(error)) then
         call add_context(error, 'body "' // body%name // '", mesh "' // mesh_name // '"')
         return
      end if
      if (.not. red%is_identity) then
         ! T^T K T and T^T M T; the full matrices are not needed afterwards.
         call reduce_matrix(red, K, K_r, error)
         if (.not. allocated(error)) call reduce_matrix(red, M, M_r, error)
         if (allocated(error)) return
         K = csr_t()
         M = csr_t()
      end if
      body%num_reduced = red%num_reduced
      body%num_constraints = red%C%num_rows
      call times%add(tag // ': interfaces and RC matrix', timer%seconds())
      call log%info('rc', tag // ': RC matrix (' // formulation_name(body%formulation) // '): ' &
         // to_str(red%num_reduced) // ' reduced coordinates, ' // to_str(red%C%num_rows) // &
         ' constraint rows ... ' // to_str(timer%seconds(), 3) // ' s')

      if (red%is_identity) then
         call solve_modes(body, modes, red, K, M, automatic_shift_hz(body%mesh%xyz, &
            material), log, times, error, ranks)
      else
         call solve_modes(body, modes, red, K_r, M_r, automatic_shift_hz(body%mesh%xyz, &
            material), log, times, error, ranks)
      end if
      if (allocated(error)) then
         call add_context(error, 'body "' // body%name // '", mesh "' // mesh_name // '"')
         return
      end if
      ! num_modes as asked (Craig-Bampton stores the static modes on top)
      call make_fingerprint(body%mesh, body%interfaces, body_spec, modes, modes%num_modes, &
         body%fingerprint)
   end subroutine compute_body_modes

end module ffrf_modes_modal_analysis
