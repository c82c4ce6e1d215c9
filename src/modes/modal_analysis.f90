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
               ', RC ' // rc_text(f%rc))
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

   !> Shift-invert Lanczos on the reduced system, then psi = T phi and the virtual-node rows.
   subroutine solve_modes(body, modes, red, K_r, M_r, auto_shift_hz, log, times, error, ranks)
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
      type(eigen_options_t) :: options
      type(stage_timer_t) :: timer
      real(dp), allocatable :: psi(:, :), rigid(:, :)
      integer :: num_rigid, first, k, num_modes
      character(len=:), allocatable :: tag

      tag = body%name
      call timer%begin()
      num_rigid = 0
      if (body%basis /= BASIS_CRAIG_BAMPTON) num_rigid = body%rc%num_free
      options%num_modes = modes%num_modes
      if (modes%shift_hz == 0.0_dp) then
         options%sigma = sigma_of_shift(auto_shift_hz)
         call log%info('modes', tag // ': automatic shift ' // to_str(auto_shift_hz, 4) // &
            ' Hz (sigma = ' // to_str(options%sigma, 4) // ' s^-2)')
      else
         options%sigma = sigma_of_shift(modes%shift_hz)
      end if
      options%sturm_check = modes%sturm_check
      if (modes%max_frequency_hz > 0.0_dp) options%max_eigenvalue = &
         sigma_of_shift(modes%max_frequency_hz)
      options%tolerance = modes%tolerance
      options%ncv = int(modes%lanczos_vectors, kind(options%ncv))
      options%parallel = ranks
      options%out_of_core = modes%out_of_core
      options%ooc_directory = modes%ooc_directory
      options%memory_limit_mb = modes%memory_limit_mb
      options%compression_tolerance = modes%compression_tolerance
      options%eigensolver = modes%eigensolver
      options%stop_on_signal = modes%stop_on_signal
      if (body%basis == BASIS_CRAIG_BAMPTON) then
         call solve_craig_bampton(body, options, red, K_r, M_r, log, times, error)
         return
      end if
      if (num_rigid > 0) then
         ! The rigid motions the reference conditions leave free, from the geometry
         call rigid_body_modes(body%mesh%xyz, body%rc, red, rigid, error)
         if (allocated(error)) return
         call solve_shift_invert(K_r, M_r, red%C, options, body%eigen, log, error, rigid=rigid)
      else
         call solve_shift_invert(K_r, M_r, red%C, options, body%eigen, log, error)
      end if
      if (allocated(error)) return
      call times%add(tag // ': ordering', body%eigen%time_ordering)
      call times%add(tag // ': analysis', body%eigen%time_analysis)
      call times%add(tag // ': factorisation', body%eigen%time_factorisation)
      call times%add(tag // ': eigen loop', body%eigen%time_lanczos)
      call times%add(tag // ': Sturm check', body%eigen%time_sturm)
      call times%add(tag // ': eigen check', body%eigen%time_check)

      first = 1
      associate (lambda => body%eigen%eigenvalues)
         if (num_rigid > 0) then
            body%rigid_frequency_hz = [(frequency_of(body%eigen%rigid_eigenvalues(k)), &
               k=1, num_rigid)]
            call log%info('modes', tag // ': ' // to_str(num_rigid) // ' rigid-body modes ' // &
               'from the geometry, deflated (' // to_str(maxval(abs(body%rigid_frequency_hz)), &
               3) // ' Hz at most: round-off of 0)')
            ! Six rigid motions removed exactly: a flexible mode at ~0 Hz is another motion
            ! without strain
            if (lambda(1) < ZERO_ENERGY_FRACTION * sigma_of_shift(-100.0_dp * auto_shift_hz)) then
               call zero_energy_error(body, frequency_of(lambda(1)), count(lambda < &
                  ZERO_ENERGY_FRACTION * sigma_of_shift(-100.0_dp * auto_shift_hz)), error)
               return
            end if
         end if
         num_modes = size(lambda)
         if (any(lambda <= 0.0_dp)) then
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'a constrained mode has a ' // &
               'non-positive eigenvalue ' // to_str(minval(lambda)) // &
               ': the reference conditions do not remove all rigid motions')
            return
         end if
         body%frequency_hz = [(frequency_of(lambda(k)), k=1, size(lambda))]
      end associate
      body%residual = body%eigen%residuals(first:)
      body%orthonormality_error = body%eigen%orthonormality_error
      if (.not. all(ieee_is_finite(body%residual)) .or. maxval(body%residual) > 1.0e-6_dp) then
         if (body%rc%free_free .and. abs(body%eigen%shift) < sigma_of_shift(-auto_shift_hz)) &
            then
            ! A free-free K - sigma M has condition ~ lambda_max / |sigma| near the rigid modes:
            ! before they were deflated (theory.md 5.6) the free-free Tet10 beam's residuals were
            ! 3e-5 at 1 Hz and 4e-7 at 10 Hz; now 3.5e-11 at both (test_stability_free_body),
            ! so this message is a last resort
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'eigenpair residual ' // &
               to_str(maxval(body%residual), 3) // ' exceeds 1e-6: the modes are not ' // &
               'accurate; this free-free body has six rigid-body modes at 0 Hz and the shift ' &
               // to_str(frequency_of(body%eigen%shift), 4) // ' Hz lies closer to them than ' &
               // 'the automatic shift (' // to_str(auto_shift_hz, 4) // ' Hz), so K - sigma M ' &
               // 'is nearly singular; use shift_hz = 0 (automatic) or a shift farther from 0 Hz')
         else
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'eigenpair residual ' // &
               to_str(maxval(body%residual), 3) // ' exceeds 1e-6: the modes are not ' // &
               'accurate; try a shift closer to the wanted frequencies (shift_hz) or a finer ' // &
               'tolerance')
         end if
         return
      end if

      call timer%begin()
      call expand_vectors(red, body%eigen%vectors(:, first:), psi)
      call set_shapes(body, psi)
      call times%add(tag // ': mode shapes', timer%seconds())
      if (len_trim(modes%rc_label) > 0) tag = tag // ', ' // trim(modes%rc_label)
      call log%info('modes', tag // ': ' // &
         to_str(num_modes) // ' modes, ' // to_str(body%frequency_hz(1), 6) // ' .. ' // &
         to_str(body%frequency_hz(num_modes), 6) // ' Hz, max residual ' // &
         to_str(maxval(body%residual), 2) // ', M-orthonormality ' // &
         to_str(body%orthonormality_error, 2) // ' ... ' // to_str(body%eigen%time_total, 3) // &
         ' s')
      do k = 1, num_modes
         call log%debug('modes', '  mode ' // to_str(k) // ': ' // &
            to_str(body%frequency_hz(k), 10) // ' Hz, residual ' // to_str(body%residual(k), 3))
      end do
   end subroutine solve_modes

   !> Craig-Bampton basis (src/modes/craig_bampton.f90): num_modes fixed-interface modes plus
   !> the static constraint modes of the non-RC virtual-node dofs, orthonormalised by
   !> Rayleigh-Ritz so that Psi^T M Psi = I and Psi^T K Psi = diag(omega^2) as the flexible body
   !> expects; body%eigen keeps the fixed-interface solve's statistics.
   subroutine solve_craig_bampton(body, options, red, K_r, M_r, log, times, error)
      type(body_modes_t), intent(inout) :: body
      !> Tolerance, ncv; num_modes = the fixed-interface modes (shift: 0, craig_bampton_modes)
      type(eigen_options_t), intent(in) :: options
      type(reduction_t), intent(in) :: red
      type(csr_t), intent(in) :: K_r, M_r
      type(logger_t), intent(in) :: log
      type(stage_times_t), intent(inout) :: times
      type(error_t), allocatable, intent(out) :: error
      type(cb_result_t) :: cb
      type(stage_timer_t) :: timer
      real(dp), allocatable :: psi(:, :)
      integer :: k, num_modes

      if (body%rc%free_free) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'basis = ''craig_bampton'' needs ' // &
            'reference conditions on the interfaces (the floating frame); this body has ' // &
            'none: give an RC set or use basis = ''rc_normal''')
         return
      end if
      call craig_bampton_modes(K_r, M_r, red, body%interfaces, options%num_modes, options, log, &
         cb, error)
      if (allocated(error)) return
      body%eigen = cb%fixed
      call times%add(body%name // ': ordering', cb%fixed%time_ordering)
      call times%add(body%name // ': analysis', cb%fixed%time_analysis)
      call times%add(body%name // ': factorisation', cb%fixed%time_factorisation)
      call times%add(body%name // ': eigen loop', cb%fixed%time_lanczos)
      call times%add(body%name // ': eigen check', cb%fixed%time_check)
      call times%add(body%name // ': static modes', cb%time_static_solves)
      call times%add(body%name // ': Rayleigh-Ritz', cb%time_rayleigh_ritz)
      if (any(cb%eigenvalues <= 0.0_dp)) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'Craig-Bampton: a Ritz value ' // &
            to_str(minval(cb%eigenvalues)) // ' is not positive: the reference conditions ' // &
            'do not remove all rigid motions')
         return
      end if
      num_modes = size(cb%eigenvalues)
      body%num_static = cb%num_static
      body%frequency_hz = [(frequency_of(cb%eigenvalues(k)), k=1, num_modes)]
      body%fixed_interface_hz = [(frequency_of(cb%fixed_eigenvalues(k)), k=1, &
         size(cb%fixed_eigenvalues))]
      body%residual = cb%residuals
      body%orthonormality_error = cb%orthonormality_error
      if (body%orthonormality_error > 1.0e-8_dp) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'Craig-Bampton: the Ritz vectors are ' // &
            'M-orthonormal only to ' // to_str(body%orthonormality_error, 3) // ' (> 1e-8): ' // &
            'the basis is (nearly) dependent')
         return
      end if

      call timer%begin()
      call expand_vectors(red, cb%vectors, psi)
      call set_shapes(body, psi)
      call times%add(body%name // ': mode shapes', timer%seconds())
      call log%info('modes', body%name // ': Craig-Bampton basis, ' // to_str(cb%num_static) // &
         ' static + ' // to_str(cb%num_fixed) // ' fixed-interface modes (fixed interface ' // &
         to_str(body%fixed_interface_hz(1), 6) // ' .. ' // &
         to_str(body%fixed_interface_hz(size(body%fixed_interface_hz)), 6) // ' Hz): ' // &
         to_str(num_modes) // ' Ritz modes ' // to_str(body%frequency_hz(1), 6) // ' .. ' // &
         to_str(body%frequency_hz(num_modes), 6) // ' Hz, M-orthonormality ' // &
         to_str(body%orthonormality_error, 2))
      do k = 1, num_modes
         call log%debug('modes', '  Ritz mode ' // to_str(k) // ': ' // &
            to_str(body%frequency_hz(k), 10) // ' Hz, distance from a normal mode ' // &
            to_str(body%residual(k), 3))
      end do
   end subroutine solve_craig_bampton

   !> The rigid-body modes of the reduced body (theory.md 5.6): the rigid motions of the mesh
   !> that the reference conditions leave free (rc%free_motions: all six for a free-free body),
   !> u(x) = t + theta x (x - x_ref) at every node, in the reduced coordinates p with T p = u
   !> (ffrf_mpc_reduction: RBE2 faces as the motion of their virtual node, null-space blocks by
   !> projection), checked to lie in the range of T and in null(C) (the RBE3 reference
   !> conditions of the multiplier form), both to 1e-10 relative.
   subroutine rigid_body_modes(xyz, rc, red, rigid, error)
      !> Node positions of the body (3, num_nodes), m
      real(dp), intent(in) :: xyz(:, :)
      !> The RC set's free motions
      type(rc_summary_t), intent(in) :: rc
      !> RC matrix q = T p and constraint rows C p = 0
      type(reduction_t), intent(in) :: red
      !> Rigid-body modes in the reduced coordinates, (num_reduced, rc%num_free)
      real(dp), allocatable, intent(out) :: rigid(:, :)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: q(:, :), cp(:)
      real(dp) :: t(3), theta(3), r(3), residual, row_norm
      integer(ip) :: i, j, p
      integer :: stat
      allocate (q(3 * size(xyz, 2), rc%num_free), stat=stat)
      if (stat /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'rigid-body modes: cannot allocate ' // &
            to_str(rc%num_free) // ' vectors of ' // to_str(3 * size(xyz, 2)))
         return
      end if
      do j = 1, int(rc%num_free, ip)
         t = rc%free_motions(1:3, j)
         theta = rc%free_motions(4:6, j) / rc%length
         do i = 1, int(size(xyz, 2), ip)
            r = xyz(:, i) - rc%reference_point
            q(3 * i - 2:3 * i, j) = t + [theta(2) * r(3) - theta(3) * r(2), &
               theta(3) * r(1) - theta(1) * r(3), theta(1) * r(2) - theta(2) * r(1)]
         end do
      end do
      call reduced_coordinates(red, q, rigid, residual, error)
      if (allocated(error)) return
      if (residual > 1.0e-10_dp) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'rigid-body modes: a rigid motion the ' // &
            'reference conditions leave free is not in the range of the RC matrix T ' // &
            '(relative residual ' // to_str(residual, 3) // ')')
         return
      end if
      if (red%C%num_rows == 0) return
      allocate (cp(red%C%num_rows))
      do j = 1, int(rc%num_free, ip)
         do i = 1, red%C%num_rows
            cp(i) = 0.0_dp
            row_norm = 0.0_dp
            do p = red%C%row_ptr(i), red%C%row_ptr(i + 1) - 1
               cp(i) = cp(i) + red%C%val(p) * rigid(red%C%col(p), j)
               row_norm = row_norm + red%C%val(p)**2
            end do
            cp(i) = abs(cp(i)) / max(sqrt(row_norm) * norm2(rigid(:, j)), tiny(1.0_dp))
         end do
         if (maxval(cp) > 1.0e-10_dp) then
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'rigid-body modes: rigid motion ' // &
               to_str(j) // ' violates a reference-condition row (relative ' // &
               to_str(maxval(cp), 3) // ')')
            return
         end if
      end do
   end subroutine rigid_body_modes

   !> The error of a free body whose spectrum holds motions without strain besides the rigid
   !> ones removed: names the cause found in the mesh (parts joined only at nodes or edges),
   !> else what remains possible.
   subroutine zero_energy_error(body, hz, num_zero, error)
      type(body_modes_t), intent(in) :: body
      !> Frequency of the first flexible mode (Hz)
      real(dp), intent(in) :: hz
      !> Flexible modes at ~0 Hz
      integer, intent(in) :: num_zero
      type(error_t), allocatable, intent(out) :: error
      integer(ip) :: num_parts
      integer(ip), allocatable :: part_of_tet(:)
      character(len=:), allocatable :: text
      text = 'free body: ' // to_str(num_zero) // ' flexible mode(s) at ' // &
         to_str(hz, 3) // ' Hz besides the ' // to_str(body%rc%num_free) // &
         ' rigid-body modes, which are removed exactly from the geometry: the mesh moves ' // &
         'without strain in another way. '
      call face_connected_parts(body%mesh, num_parts, part_of_tet)
      if (num_parts > 1) then
         text = text // 'Its tetrahedra form ' // to_str(num_parts) // ' parts that share ' // &
            'no face, only nodes or edges (a hinge), e.g. tetrahedron ' // &
            to_str(body%mesh%tet_tags(first_of_part(part_of_tet, 2_ip))) // ' in part 2: ' // &
            'join the volumes along faces (BooleanFragments before meshing) or make each ' // &
            'part a body of its own'
      else
         text = text // 'Its tetrahedra share faces (one connected piece, no hinge): ' // &
            'check for elements with no stiffness (E) or a mechanism in the interfaces'
      end if
      call fatal_error(error, FFRF_NUMERIC_ERROR, text)
   end subroutine zero_energy_error

   !> First tetrahedron of part p.
   pure integer(ip) function first_of_part(part_of_tet, p) result(first)
      integer(ip), intent(in) :: part_of_tet(:), p
      integer(ip) :: e
      first = 1
      do e = 1, int(size(part_of_tet), ip)
         if (part_of_tet(e) == p) then
            first = e
            return
         end if
      end do
   end function first_of_part

   !> body%shape = psi (moved) and the virtual-node rows psi_V = G psi_B of every interface.
   subroutine set_shapes(body, psi)
      type(body_modes_t), intent(inout) :: body
      !> Mode shapes (3 num_nodes, num_modes); deallocated on return
      real(dp), allocatable, intent(inout) :: psi(:, :)
      integer :: k, i, num_modes
      num_modes = size(psi, 2)
      call move_alloc(psi, body%shape)
      if (allocated(body%virtual_node_shape)) deallocate (body%virtual_node_shape)
      allocate (body%virtual_node_shape(6 * size(body%interfaces), num_modes))
      do k = 1, size(body%interfaces)
         associate (f => body%interfaces(k))
            do i = 1, num_modes
               body%virtual_node_shape(6 * k - 5:6 * k, i) = matmul(f%G, &
                  gather_dofs(body%shape(:, i), f%nodes))
            end do
         end associate
      end do
   end subroutine set_shapes

   pure function frequency_of(lambda) result(hz)
      real(dp), intent(in) :: lambda
      real(dp) :: hz
      hz = sign(sqrt(abs(lambda)), lambda) / (2.0_dp * pi)
   end function frequency_of

   !> The 3 dofs of each node in `nodes`, in order.
   pure function gather_dofs(q, nodes) result(q_b)
      real(dp), intent(in) :: q(:)
      integer(ip), intent(in) :: nodes(:)
      real(dp) :: q_b(3 * size(nodes))
      integer :: i
      do i = 1, size(nodes)
         q_b(3 * i - 2:3 * i) = q(3 * nodes(i) - 2:3 * nodes(i))
      end do
   end function gather_dofs

   function rc_text(rc) result(text)
      logical, intent(in) :: rc(6)
      character(len=:), allocatable :: text
      text = dofs_text(rc)
      if (len(text) == 0) text = 'none'
   end function rc_text

end module ffrf_modes_modal_analysis
