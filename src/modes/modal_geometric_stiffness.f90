!> Modal geometric stiffness of a reduced flexible body: the centrifugal stress stiffening that
!> linear modal FFRF misses (the "geometric stiffening" of Wallrapp's SID and Simpack, Shabana's
!> geometric centrifugal stiffening; Kane, Ryan & Banerjee, J. Guidance 10 (1987) 139).
!>
!> A body whose frame spins with angular velocity omega (frame components) carries the
!> centrifugal load rho a(x), a(x) = -omega x (omega x x) = sum_c p_c(omega) C_c x, linear in the
!> six products p_c = w_a w_b (ffrf_fe_geometric_stiffness, (G2)), x the mesh coordinates (the
!> body frame of ffrf_mbs_flexible_body has its origin at the mesh origin). For each case c:
!>  1. the static problem K u^(c) = M (C_c x) of the body held by its reference conditions, in
!>     the constrained space of its modes: q = T p with C p = 0 (ffrf_mpc_reduction), solved by
!>     MUMPS on [[T^T K T, C^T], [C, 0]] [p; mu] = [T^T f; 0] (C rows scaled to max|diag K|,
!>     toolchain.md pitfall 7), u^(c) = T p;
!>  2. the element geometric stiffness of its stress, K_G(u^(c)) ((G1), Tet4/Tet10);
!>  3. its projection on the mass-normalised modes, K_G^(c) = Psi^T K_G(u^(c)) Psi (m x m).
!> The modal stiffness of the spinning body is then K_ff + sum_c p_c(omega) K_G^(c)
!> (flexible_body_t%set_geometric_stiffness).
!>
!> What is and is not included. The six centrifugal cases of the frame's rotation about its own
!> origin; the reactions that hold the body are those of its reference conditions, so the RC set
!> should be where the body is held in the mechanism (a cantilever clamped at its hub: the
!> clamp). Not included: the load cases of the angular acceleration (-omega_dot x x) and of the
!> translational acceleration of the frame origin (gravity, a frame origin off the spin axis):
!> their stresses stiffen too, but for the spin-up of a beam clamped on the axis the first is a
!> bending load whose stress is odd over the cross-section (its K_G on the bending modes vanishes
!> to first order) and the second is zero. A free-free body (no RCs) is refused: its centrifugal
!> load is not in equilibrium without inertia relief, which this module does not do.
module ffrf_modes_modal_geometric_stiffness
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_kinds, only: dp, ip
   use ffrf_core_error, only: error_t, fatal_error, add_context, FFRF_INPUT_ERROR, &
      FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: logger_t, stage_timer_t, stage_times_t
   use ffrf_la_sparse, only: csr_t, csr_matvec, csr_transpose, csr_upper_coo
   use ffrf_la_mumps, only: mumps_solver_t, MUMPS_SYM_SPD, MUMPS_SYM_INDEFINITE
   use ffrf_fe_material, only: material_t, check_material
   use ffrf_fe_assembly, only: assemble_stiffness_mass
   use ffrf_fe_geometric_stiffness, only: tet_geometric_stiffness, centrifugal_case_matrix, &
      NUM_CENTRIFUGAL_CASES
   use ffrf_mpc_reduction, only: reduction_t, build_reduction, reduce_matrix, expand_vectors
   use ffrf_modes_input, only: body_spec_t
   use ffrf_modes_modal_analysis, only: body_modes_t
   implicit none
   private
   public :: compute_modal_geometric_stiffness

   !> Largest accepted normwise backward error of the static solutions,
   !> ||K_r p + C^T mu - f_r|| / (||K_r|| ||p|| + ||C|| ||mu|| + ||f_r||) (max norms; a stable
   !> direct solve gives ~eps; the relative residual itself may reach cond(K) eps ~ 1e-8 for a
   !> slender beam under a bending load)
   real(dp), parameter :: static_backward_error = 1.0e-10_dp

contains

   !> The modal geometric stiffness K_G^(c) (m x m x 6) of `body` (its mesh, interfaces, RC set
   !> and modes from compute_body_modes) with the material of `body_spec` (module header).
   subroutine compute_modal_geometric_stiffness(body_spec, body, log, times, &
         geometric_stiffness, error, static_displacement, stiffness_matrix, mass_matrix)
      !> The &body input (material)
      type(body_spec_t), intent(in) :: body_spec
      !> Mesh, interfaces, reference conditions and mass-normalised modes of the body
      type(body_modes_t), intent(in) :: body
      !> Progress log
      type(logger_t), intent(in) :: log
      !> Stage times, appended to
      type(stage_times_t), intent(inout) :: times
      !> K_G^(c), (m, m, 6) in the case order of centrifugal_products; dimensionless for
      !> mass-normalised modes (p_c K_G^(c) adds to K_ff, 1/s^2)
      real(dp), allocatable, intent(out) :: geometric_stiffness(:, :, :)
      type(error_t), allocatable, intent(out) :: error
      !> The static displacements u^(c) (3 num_nodes, 6) per unit p_c (m s^2)
      real(dp), allocatable, intent(out), optional :: static_displacement(:, :)
      !> The body's FE stiffness and consistent mass matrices if the caller has them
      !> (compute_body_modes); else they are assembled here
      type(csr_t), intent(in), optional :: stiffness_matrix, mass_matrix
      type(material_t) :: material
      type(csr_t) :: K, M
      type(reduction_t) :: red
      type(stage_timer_t) :: timer
      real(dp), allocatable :: u(:, :)
      integer :: num_modes
      character(len=:), allocatable :: tag

      tag = trim(body%name)
      num_modes = size(body%shape, 2)
      if (body%rc%free_free) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'body "' // tag // '": the geometric ' // &
            'stiffness needs reference conditions that hold the body (its centrifugal load ' // &
            'goes to them); a free-free body would need inertia relief; give rc on the ' // &
            'interface where the body is held, or geometric_stiffness = .false.')
         return
      end if
      if (num_modes == 0) then
         allocate (geometric_stiffness(0, 0, NUM_CENTRIFUGAL_CASES))
         return
      end if
      call timer%begin()
      material = material_t(body_spec%young, body_spec%poisson, body_spec%density, tag)
      call check_material(material, error)
      if (.not. allocated(error)) then
         if (present(stiffness_matrix) .and. present(mass_matrix)) then
            K = stiffness_matrix
            M = mass_matrix
         else
            call assemble_stiffness_mass(body%mesh%xyz, body%mesh%tets, body%mesh%tet_tags, &
               material, K, M, error)
         end if
      end if
      if (.not. allocated(error)) call build_reduction(body%mesh%num_nodes, body%interfaces, &
         body%formulation, red, error)
      if (.not. allocated(error)) call static_solutions(body, red, K, M, u, error)
      if (allocated(error)) then
         call add_context(error, 'body "' // tag // '", geometric stiffness')
         return
      end if
      call project(body, material, u, geometric_stiffness, error)
      if (allocated(error)) then
         call add_context(error, 'body "' // tag // '", geometric stiffness')
         return
      end if
      if (present(static_displacement)) call move_alloc(u, static_displacement)
      call times%add(tag // ': geometric stiffness', timer%seconds())
      call log%info('modes', tag // ': modal geometric stiffness of the 6 centrifugal load ' // &
         'cases (static solutions held by the RCs, Tet' // to_str(body%mesh%nodes_per_tet) // &
         ' K_G projected on ' // to_str(num_modes) // ' modes) ... ' // &
         to_str(timer%seconds(), 3) // ' s')
   end subroutine compute_modal_geometric_stiffness

   !> u^(c) = T p^(c) with [[T^T K T, C^T], [C, 0]] [p; mu] = [T^T M C_c x; 0] (module header).
   subroutine static_solutions(body, red, K, M, u, error)
      type(body_modes_t), intent(in) :: body
      type(reduction_t), intent(in) :: red
      type(csr_t), intent(in) :: K, M
      real(dp), allocatable, intent(out) :: u(:, :)
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: K_r, Tt
      type(mumps_solver_t) :: solver
      integer(ip), allocatable :: irn(:), jcn(:), upper_irn(:), upper_jcn(:)
      real(dp), allocatable :: val(:), upper_val(:), row_scale(:), f(:, :), f_r(:, :), rhs(:, :)
      real(dp), allocatable :: acceleration(:), r(:)
      real(dp) :: diag_scale, k_norm, c_norm, scale, backward
      integer(ip) :: n_r, nc, row, p, total, e, num_upper
      integer :: c, i

      ! Loads f^(c) = M (C_c x), then T^T f^(c)
      allocate (f(3 * body%mesh%num_nodes, NUM_CENTRIFUGAL_CASES), &
         acceleration(3 * body%mesh%num_nodes))
      do c = 1, NUM_CENTRIFUGAL_CASES
         do i = 1, body%mesh%num_nodes
            acceleration(3 * i - 2:3 * i) = matmul(centrifugal_case_matrix(c), &
               body%mesh%xyz(:, i))
         end do
         call csr_matvec(M, acceleration, f(:, c))
      end do
      call reduce_matrix(red, K, K_r, error)
      if (allocated(error)) return
      n_r = red%num_reduced
      nc = red%C%num_rows
      if (red%is_identity) then
         f_r = f
      else
         allocate (f_r(n_r, NUM_CENTRIFUGAL_CASES))
         call csr_transpose(red%T, Tt)
         do c = 1, NUM_CENTRIFUGAL_CASES
            call csr_matvec(Tt, f(:, c), f_r(:, c))
         end do
      end if

      ! KKT matrix: upper triangle of K_r, then the scaled C^T block (as the eigen solver)
      call csr_upper_coo(K_r, upper_irn, upper_jcn, upper_val)
      num_upper = size(upper_irn, kind=ip)
      diag_scale = 0.0_dp
      do e = 1, num_upper
         if (upper_irn(e) == upper_jcn(e)) diag_scale = max(diag_scale, abs(upper_val(e)))
      end do
      if (diag_scale == 0.0_dp) diag_scale = 1.0_dp
      total = num_upper
      if (nc > 0) total = total + red%C%row_ptr(nc + 1) - 1
      allocate (irn(total), jcn(total), val(total))
      irn(1:num_upper) = upper_irn
      jcn(1:num_upper) = upper_jcn
      val(1:num_upper) = upper_val
      allocate (row_scale(nc))
      e = num_upper
      do row = 1, nc
         row_scale(row) = diag_scale / maxval(abs(red%C%val(red%C%row_ptr(row): &
            red%C%row_ptr(row + 1) - 1)))
         do p = red%C%row_ptr(row), red%C%row_ptr(row + 1) - 1
            e = e + 1
            irn(e) = red%C%col(p)
            jcn(e) = n_r + row
            val(e) = red%C%val(p) * row_scale(row)
         end do
      end do

      if (nc == 0) then
         call solver%init(MUMPS_SYM_SPD, error)
      else
         call solver%init(MUMPS_SYM_INDEFINITE, error)
      end if
      if (.not. allocated(error)) call solver%analyse(n_r + nc, irn, jcn, error=error)
      if (.not. allocated(error)) call solver%factorise(val, error)
      if (.not. allocated(error)) then
         allocate (rhs(n_r + nc, NUM_CENTRIFUGAL_CASES), source=0.0_dp)
         rhs(1:n_r, :) = f_r
         call solver%solve(rhs, error)
      end if
      call solver%free()
      if (allocated(error)) then
         call add_context(error, 'static solutions of the centrifugal load cases (is the ' // &
            'body held by its reference conditions?)')
         return
      end if

      ! Backward error of the static equilibrium on the constrained space:
      ! r = K_r p + C^T mu_scaled - f_r against the sizes of its terms
      k_norm = maxval(abs(val(1:num_upper)))
      c_norm = 0.0_dp
      if (nc > 0) c_norm = maxval(abs(val(num_upper + 1:)))
      allocate (r(n_r))
      do c = 1, NUM_CENTRIFUGAL_CASES
         call csr_matvec(K_r, rhs(1:n_r, c), r)
         r = r - f_r(:, c)
         do row = 1, nc
            do p = red%C%row_ptr(row), red%C%row_ptr(row + 1) - 1
               r(red%C%col(p)) = r(red%C%col(p)) + red%C%val(p) * row_scale(row) * &
                  rhs(n_r + row, c)
            end do
         end do
         scale = k_norm * maxval(abs(rhs(1:n_r, c))) + maxval(abs(f_r(:, c)))
         if (nc > 0) scale = scale + c_norm * maxval(abs(rhs(n_r + 1:, c)))
         backward = maxval(abs(r)) / max(scale, tiny(1.0_dp))
         if (.not. ieee_is_finite(backward) .or. backward > static_backward_error) then
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'centrifugal load case ' // to_str(c) &
               // ': backward error ' // to_str(backward, 3) // ' of the static solution ' // &
               'exceeds ' // to_str(static_backward_error, 2) // '; the stiffness on the RC ' // &
               'space is singular or ill-conditioned (a rigid motion left free?)')
            return
         end if
      end do
      call expand_vectors(red, rhs(1:n_r, :), u)
   end subroutine static_solutions

   !> K_G^(c) = sum_e Psi_e^T K_G,e(u_e^(c)) Psi_e, symmetrised (round-off only).
   subroutine project(body, material, u, geometric_stiffness, error)
      type(body_modes_t), intent(in) :: body
      type(material_t), intent(in) :: material
      real(dp), intent(in) :: u(:, :)
      real(dp), allocatable, intent(out) :: geometric_stiffness(:, :, :)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: xe(:, :), ue(:, :), kg(:, :), psi_e(:, :)
      integer, allocatable :: dofs(:)
      integer :: nen, m, e, a, c
      nen = body%mesh%nodes_per_tet
      m = size(body%shape, 2)
      allocate (geometric_stiffness(m, m, NUM_CENTRIFUGAL_CASES), source=0.0_dp)
      allocate (xe(3, nen), ue(3, nen), kg(3 * nen, 3 * nen), psi_e(3 * nen, m), dofs(3 * nen))
      do e = 1, body%mesh%num_tets()
         do a = 1, nen
            dofs(3 * a - 2:3 * a) = 3 * (body%mesh%tets(a, e) - 1) + [1, 2, 3]
         end do
         xe = body%mesh%xyz(:, body%mesh%tets(:, e))
         psi_e = body%shape(dofs, :)
         do c = 1, NUM_CENTRIFUGAL_CASES
            ue = reshape(u(dofs, c), [3, nen])
            call tet_geometric_stiffness(xe, ue, material, body%mesh%tet_tags(e), kg, error)
            if (allocated(error)) return
            geometric_stiffness(:, :, c) = geometric_stiffness(:, :, c) + &
               matmul(transpose(psi_e), matmul(kg, psi_e))
         end do
      end do
      do c = 1, NUM_CENTRIFUGAL_CASES
         geometric_stiffness(:, :, c) = 0.5_dp * (geometric_stiffness(:, :, c) + &
            transpose(geometric_stiffness(:, :, c)))
      end do
      if (.not. all(ieee_is_finite(geometric_stiffness))) call fatal_error(error, &
         FFRF_NUMERIC_ERROR, 'NaN or Inf in the modal geometric stiffness')
   end subroutine project

end module ffrf_modes_modal_geometric_stiffness
