!> Craig-Bampton mode basis with interface reduction (Heirman & Desmet, Multibody Syst. Dyn. 24
!> (2010) 219; Exudyn's HCB with RBE3, theory.md 1.3 and 2): the body's motion is spanned by
!>
!>   static constraint modes  X_s: for each virtual-node dof j that is not a reference condition,
!>       the least-strain-energy response to q_V = e_j with every other virtual-node dof held
!>       (the RC dofs included), the MPC relation imposed as constraint equations C_V q = q_V:
!>
!>           [ K     C_V^T ] [ x  ]   [ 0   ]
!>           [ C_V   0     ] [ mu ] = [ e_j ]                                           (CB-1)
!>
!>   fixed-interface modes    X_f: K x = lambda M x subject to C_V x = 0 (every virtual-node dof
!>       held), the lowest num_fixed by shift-invert Lanczos on MUMPS;
!>
!> Both come from one MUMPS factorisation of the KKT matrix at sigma = 0: with every virtual node
!> held, K is positive definite on null(C_V), so (CB-1) is the static problem of the Lanczos
!> shift-invert operator at sigma = 0 and its right-hand sides are solved with the same factors.
!>
!> C_V = [G_1; ...; G_nif] T: the six virtual-node rows of every interface (RBE3: q_V = G q_B;
!> RBE2: q_V = F^+ q_B, which on q_B = F q_V picks the virtual-node coordinate of T) in the
!> reduced coordinates p of the RC matrix q = T p. Rows that vanish identically are virtual-node
!> dofs T has already eliminated (the RC dofs of an RBE2); they are dropped.
!>
!> Every vector of X = [X_s, X_f] has zero RC components, so it lies in the RC-constrained space
!> of the paper's normal modes (theory.md 2) and the body frame stays attached to the RC dofs.
!> The basis is then orthonormalised by Rayleigh-Ritz in span(X):
!>
!>     (X^T K X) v = omega^2 (X^T M X) v,   Psi = X V,   Psi^T M Psi = I,
!>     Psi^T K Psi = diag(omega^2)                                                     (CB-2)
!>
!> so the flexible body (K_ff = diag(omega^2), src/mbs/flexible_body.f90) takes it unchanged.
!> The omega^2 are Ritz values: upper bounds of the RC normal-mode eigenvalues that fall as
!> fixed-interface modes are added; with all of them, span(X) is the whole RC-constrained space
!> (any q with zero RC components is sum_j q_V,j x_j plus a part with q_V = 0) and they are exact.
module ffrf_modes_craig_bampton
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_kinds, only: dp, ip
   use ffrf_core_error, only: error_t, fatal_error, add_context, FFRF_INPUT_ERROR, &
      FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: logger_t, wall_time
   use ffrf_la_sparse, only: csr_t, csr_from_coo, csr_matmul, csr_matvec, csr_row_gram
   use ffrf_la_dense, only: symmetric_eigen
   use ffrf_la_lapack, only: dgemm, dsygv
   use ffrf_mpc_interface, only: interface_t, DOF_NAMES
   use ffrf_mpc_reduction, only: reduction_t, add_virtual_node_row, reduce_rows
   use ffrf_modes_shift_invert, only: eigen_options_t, eigen_result_t, solve_shift_invert, &
      project_null_space
   implicit none
   private
   public :: cb_result_t, virtual_node_rows, rayleigh_ritz, craig_bampton_modes

   character(len=*), parameter :: stage = 'modes'

   !> A Craig-Bampton basis after Rayleigh-Ritz (CB-2), in the reduced coordinates p.
   type :: cb_result_t
      !> Static constraint modes (non-RC virtual-node dofs) and fixed-interface modes
      integer(ip) :: num_static = 0
      integer(ip) :: num_fixed = 0
      !> Ritz values omega^2 (1/s^2), ascending, num_static + num_fixed of them
      real(dp), allocatable :: eigenvalues(:)
      !> Ritz vectors Psi (num_reduced, num_static + num_fixed), Psi^T M Psi = I
      real(dp), allocatable :: vectors(:, :)
      !> ||P (K psi - omega^2 M psi)|| / ||P K psi|| on the RC-constrained space (P onto
      !> null(C_RC)): how far each Ritz vector is from a normal mode (not a solver accuracy)
      real(dp), allocatable :: residuals(:)
      !> max |Psi^T M Psi - I|
      real(dp) :: orthonormality_error = 0.0_dp
      !> Eigenvalues of the fixed-interface modes (1/s^2), ascending
      real(dp), allocatable :: fixed_eigenvalues(:)
      !> Statistics of the fixed-interface Lanczos (ordering, factorisation, solves, ...)
      type(eigen_result_t) :: fixed
      !> Wall seconds: the (CB-1) solves with the shared factors, Rayleigh-Ritz
      real(dp) :: time_static_solves = 0.0_dp
      real(dp) :: time_rayleigh_ritz = 0.0_dp
   end type cb_result_t

contains

   !> The Craig-Bampton basis of a body: num_fixed fixed-interface modes by shift-invert Lanczos
   !> at sigma = 0 (options: its tolerance and ncv; its shift is not used), the static modes
   !> (CB-1) with the same factors, Rayleigh-Ritz (CB-2).
   subroutine craig_bampton_modes(K, M, red, interfaces, num_fixed, options, log, cb, error)
      !> Reduced stiffness and mass T^T K T, T^T M T (both triangles)
      type(csr_t), intent(in) :: K, M
      !> RC matrix q = T p and the RC constraint rows C p = 0
      type(reduction_t), intent(in) :: red
      !> The body's interfaces (G, reference conditions)
      type(interface_t), intent(in) :: interfaces(:)
      !> Number of fixed-interface modes
      integer(ip), intent(in) :: num_fixed
      !> Tolerance and Lanczos size of the fixed-interface solve (num_modes, sigma not used)
      type(eigen_options_t), intent(in) :: options
      !> Progress log
      type(logger_t), intent(in) :: log
      !> Result
      type(cb_result_t), intent(out) :: cb
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: C_v
      type(eigen_options_t) :: fixed_options
      logical, allocatable :: is_rc(:)
      real(dp), allocatable :: X(:, :), targets(:, :), X_s(:, :)
      real(dp) :: t0
      integer(ip) :: n, num_static, r, j

      if (num_fixed < 1) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'Craig-Bampton: num_fixed = ' // &
            to_str(num_fixed) // ' fixed-interface modes, must be at least 1')
         return
      end if
      call virtual_node_rows(interfaces, red, C_v, is_rc, error)
      if (allocated(error)) return
      ! RC rows of RBE3 interfaces stay in C_V, those of RBE2 interfaces are eliminated by T
      if (.not. any([(any(interfaces(r)%rc), r=1, int(size(interfaces), ip))])) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'Craig-Bampton: the body has no reference ' &
            // 'conditions; the static modes would contain its rigid motions. Give the ' // &
            'interfaces an RC set (rc = ...) or use basis = ''rc_normal''')
         return
      end if
      n = K%num_rows
      num_static = int(count(.not. is_rc), ip)
      call log%info(stage, 'Craig-Bampton: ' // to_str(size(is_rc)) // ' virtual-node rows (' &
         // to_str(count(is_rc)) // ' reference conditions held), ' // to_str(num_static) // &
         ' static constraint modes + ' // to_str(num_fixed) // ' fixed-interface modes')

      ! Fixed-interface modes (every virtual-node dof held) at sigma = 0, and with the same
      ! factors the static modes: target 1 on their own non-RC row, 0 on every other row.
      fixed_options = options
      fixed_options%num_modes = num_fixed
      fixed_options%sigma = 0.0_dp
      fixed_options%retry_shift = .false.
      allocate (targets(size(is_rc), num_static), source=0.0_dp)
      j = 0
      do r = 1, int(size(is_rc), ip)
         if (is_rc(r)) cycle
         j = j + 1
         targets(r, j) = 1.0_dp
      end do
      call solve_shift_invert(K, M, C_v, fixed_options, cb%fixed, log, error, &
         constraint_targets=targets, constraint_solutions=X_s)
      if (allocated(error)) then
         call add_context(error, 'Craig-Bampton, fixed-interface and static modes (K must ' // &
            'be positive definite with every virtual node held: a loose part of the mesh?)')
         return
      end if
      cb%fixed_eigenvalues = cb%fixed%eigenvalues
      cb%time_static_solves = cb%fixed%time_constraint_solves
      cb%num_static = num_static
      cb%num_fixed = num_fixed
      call log%info(stage, 'Craig-Bampton: ' // to_str(num_static) // ' static modes with ' // &
         'the Lanczos factors ... ' // to_str(cb%time_static_solves, 3) // ' s')

      ! The basis X = [X_s, X_f]
      allocate (X(n, num_static + num_fixed))
      X(:, 1:num_static) = X_s
      X(:, num_static + 1:) = cb%fixed%vectors

      t0 = wall_time()
      call rayleigh_ritz(K, M, red%C, X, cb%eigenvalues, cb%vectors, cb%residuals, &
         cb%orthonormality_error, error)
      cb%time_rayleigh_ritz = wall_time() - t0
      if (allocated(error)) call add_context(error, 'Craig-Bampton')
   end subroutine craig_bampton_modes

   !> The virtual-node rows C_V = [G_1; ...; G_nif] T in the reduced coordinates, and which rows
   !> are reference conditions. A row that vanishes (relative to the row of G, 1e-10) is a dof T
   !> has eliminated and is dropped. Rows must be independent (6 per non-collinear interface).
   subroutine virtual_node_rows(interfaces, red, C_v, is_rc, error)
      !> The body's interfaces
      type(interface_t), intent(in) :: interfaces(:)
      !> RC matrix (T, or the identity)
      type(reduction_t), intent(in) :: red
      !> Virtual-node rows, (num_rows, red%num_reduced)
      type(csr_t), intent(out) :: C_v
      !> Row is a reference condition (held at zero in every mode)
      logical, allocatable, intent(out) :: is_rc(:)
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: c_reduced
      integer(ip), allocatable :: rows(:), cols(:)
      real(dp), allocatable :: vals(:), gram(:, :), row_norm(:), full_norm(:), values(:), &
         vectors(:, :)
      logical, allocatable :: keep(:), kept_entry(:), rc_all(:)
      character(len=80), allocatable :: labels(:)
      integer(ip) :: num_rows, nnz, r, kept
      integer :: k, d

      num_rows = 6 * int(size(interfaces), ip)
      if (num_rows == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'Craig-Bampton: the body has no ' // &
            'interfaces; a Craig-Bampton basis needs at least one virtual node')
         return
      end if
      nnz = 0
      do k = 1, size(interfaces)
         nnz = nnz + 18 * int(size(interfaces(k)%nodes), ip)
      end do
      allocate (rows(nnz), cols(nnz), vals(nnz), rc_all(num_rows), labels(num_rows), &
         full_norm(num_rows))
      nnz = 0
      r = 0
      do k = 1, size(interfaces)
         associate (f => interfaces(k))
            if (f%rank_deficient) then
               call fatal_error(error, FFRF_INPUT_ERROR, 'Craig-Bampton: the nodes of ' // &
                  'interface "' // f%name // '" are collinear, so its virtual node has no ' // &
                  'rotation about their line; Craig-Bampton needs all six virtual-node ' // &
                  'dofs of every interface (use basis = ''rc_normal'')')
               return
            end if
            do d = 1, 6
               r = r + 1
               rc_all(r) = f%rc(d)
               labels(r) = 'interface "' // f%name // '" ' // DOF_NAMES(d)
               full_norm(r) = norm2(f%G(d, :))
               call add_virtual_node_row(f, d, r, rows, cols, vals, nnz)
            end do
         end associate
      end do
      call reduce_rows(red, num_rows, rows, cols, vals, c_reduced, error)
      if (allocated(error)) return

      ! Drop the rows T has eliminated, keep the others: C_v is the kept rows of c_reduced as
      ! they are (csr_matmul and csr_from_coo sort the columns of a row)
      allocate (keep(num_rows), kept_entry(size(c_reduced%val)))
      do r = 1, num_rows
         keep(r) = norm2(c_reduced%val(c_reduced%row_ptr(r):c_reduced%row_ptr(r + 1) - 1)) > &
            1.0e-10_dp * full_norm(r)
         kept_entry(c_reduced%row_ptr(r):c_reduced%row_ptr(r + 1) - 1) = keep(r)
      end do
      C_v%num_rows = int(count(keep), ip)
      C_v%num_cols = red%num_reduced
      allocate (C_v%row_ptr(C_v%num_rows + 1))
      C_v%row_ptr(1) = 1
      kept = 0
      do r = 1, num_rows
         if (.not. keep(r)) cycle
         kept = kept + 1
         C_v%row_ptr(kept + 1) = C_v%row_ptr(kept) + c_reduced%row_ptr(r + 1) - &
            c_reduced%row_ptr(r)
      end do
      C_v%col = pack(c_reduced%col, kept_entry)
      C_v%val = pack(c_reduced%val, kept_entry)
      is_rc = pack(rc_all, keep)
      labels = pack(labels, keep)

      ! Independent rows: the smallest eigenvalue of the normalised Gram matrix.
      call csr_row_gram(C_v, gram, row_norm)
      allocate (values(kept), vectors(kept, kept))
      call symmetric_eigen(gram, values, vectors, error)
      if (allocated(error)) return
      if (values(1) <= 1.0e-10_dp) then
         r = int(maxloc(abs(vectors(:, 1)), dim=1), ip)
         call fatal_error(error, FFRF_INPUT_ERROR, 'Craig-Bampton: the virtual-node rows ' // &
            'are dependent (smallest Gram eigenvalue ' // to_str(values(1), 3) // ', mostly ' // &
            trim(labels(r)) // '): interfaces share nodes or a face cannot carry all six ' // &
            'dofs; use basis = ''rc_normal''')
      end if
   end subroutine virtual_node_rows

   !> Rayleigh-Ritz in span(X) (CB-2): the columns of X are M-normalised, X^T K X and X^T M X
   !> formed densely (BLAS) and solved by LAPACK dsygv; Psi = X V. Returns the Ritz values
   !> (Rayleigh quotients of Psi), the residuals on null(C) and the M-orthonormality error.
   subroutine rayleigh_ritz(K, M, C, X, lambda, Psi, residuals, orthonormality_error, error)
      !> Stiffness and mass (both triangles), n x n
      type(csr_t), intent(in) :: K, M
      !> Constraint rows the residual is projected off (the RC rows; may have no rows)
      type(csr_t), intent(in) :: C
      !> Basis, (n, nb), linearly independent columns
      real(dp), intent(in) :: X(:, :)
      !> Ritz values, ascending, (nb)
      real(dp), allocatable, intent(out) :: lambda(:)
      !> Ritz vectors, (n, nb), Psi^T M Psi = I
      real(dp), allocatable, intent(out) :: Psi(:, :)
      !> ||P (K psi - lambda M psi)|| / ||P K psi||
      real(dp), allocatable, intent(out) :: residuals(:)
      !> max |Psi^T M Psi - I|
      real(dp), intent(out) :: orthonormality_error
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: Xn(:, :), KX(:, :), MX(:, :), Kr(:, :), Mr(:, :), work(:), &
         KPsi(:, :), MPsi(:, :), r(:, :), gram(:, :)
      real(dp) :: norm_m, query(1)
      integer(ip) :: n, nb, j, info, lwork, stat

      n = int(size(X, 1), ip)
      nb = int(size(X, 2), ip)
      orthonormality_error = 0.0_dp
      if (K%num_rows /= n .or. M%num_rows /= n .or. nb < 1) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'Rayleigh-Ritz: basis ' // to_str(n) // &
            ' x ' // to_str(nb) // ' for K of order ' // to_str(K%num_rows) // ' and M of ' // &
            to_str(M%num_rows) // '; need the order of K and M and at least one column')
         return
      end if
      allocate (Xn(n, nb), KX(n, nb), MX(n, nb), Kr(nb, nb), Mr(nb, nb), lambda(nb), stat=stat)
      if (stat /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'Rayleigh-Ritz: cannot allocate ' // &
            'three ' // to_str(n) // ' x ' // to_str(nb) // ' work arrays')
         return
      end if
      do j = 1, nb
         call csr_matvec(M, X(:, j), MX(:, j))
         norm_m = sqrt(max(dot_product(X(:, j), MX(:, j)), 0.0_dp))
         if (.not. (norm_m > 0.0_dp .and. ieee_is_finite(norm_m))) then
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'Rayleigh-Ritz: basis column ' // &
               to_str(j) // ' has M-norm ' // to_str(norm_m) // '; M must be positive ' // &
               'definite on the basis')
            return
         end if
         Xn(:, j) = X(:, j) / norm_m
         MX(:, j) = MX(:, j) / norm_m
         call csr_matvec(K, Xn(:, j), KX(:, j))
      end do
      call dgemm('T', 'N', nb, nb, n, 1.0_dp, Xn, n, KX, n, 0.0_dp, Kr, nb)
      call dgemm('T', 'N', nb, nb, n, 1.0_dp, Xn, n, MX, n, 0.0_dp, Mr, nb)
      Kr = 0.5_dp * (Kr + transpose(Kr))
      Mr = 0.5_dp * (Mr + transpose(Mr))

      call dsygv(1_ip, 'V', 'U', nb, Kr, nb, Mr, nb, lambda, query, -1_ip, info)
      lwork = max(int(query(1), ip), 3 * nb)
      allocate (work(lwork))
      call dsygv(1_ip, 'V', 'U', nb, Kr, nb, Mr, nb, lambda, work, lwork, info)
      if (info > nb) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'Rayleigh-Ritz: X^T M X is not ' // &
            'positive definite (LAPACK dsygv info = ' // to_str(info) // '): the basis ' // &
            'columns are (nearly) linearly dependent')
         return
      else if (info /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'Rayleigh-Ritz: LAPACK dsygv info = ' // &
            to_str(info))
         return
      end if

      ! Psi = Xn V, K Psi, M Psi; Rayleigh quotients, residuals, orthonormality.
      allocate (Psi(n, nb), KPsi(n, nb), MPsi(n, nb), r(n, 2 * nb), gram(nb, nb), residuals(nb), &
         stat=stat)
      if (stat /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'Rayleigh-Ritz: cannot allocate the ' // &
            'Ritz vectors (' // to_str(n) // ' x ' // to_str(5 * nb) // ')')
         return
      end if
      call dgemm('N', 'N', n, nb, nb, 1.0_dp, Xn, n, Kr, nb, 0.0_dp, Psi, n)
      call dgemm('N', 'N', n, nb, nb, 1.0_dp, KX, n, Kr, nb, 0.0_dp, KPsi, n)
      call dgemm('N', 'N', n, nb, nb, 1.0_dp, MX, n, Kr, nb, 0.0_dp, MPsi, n)
      deallocate (Xn, KX, MX)
      do j = 1, nb
         lambda(j) = dot_product(Psi(:, j), KPsi(:, j)) / dot_product(Psi(:, j), MPsi(:, j))
         r(:, j) = KPsi(:, j) - lambda(j) * MPsi(:, j)
         r(:, nb + j) = KPsi(:, j)
      end do
      if (C%num_rows > 0) then
         if (C%num_cols /= n) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'Rayleigh-Ritz: C has ' // &
               to_str(C%num_cols) // ' columns, K has order ' // to_str(n))
            return
         end if
         call project_null_space(C, r, error)
         if (allocated(error)) return
      end if
      do j = 1, nb
         residuals(j) = norm2(r(:, j)) / max(norm2(r(:, nb + j)), tiny(1.0_dp))
      end do
      call dgemm('T', 'N', nb, nb, n, 1.0_dp, Psi, n, MPsi, n, 0.0_dp, gram, nb)
      do j = 1, nb
         gram(j, j) = gram(j, j) - 1.0_dp
      end do
      orthonormality_error = maxval(abs(gram))
      if (.not. (all(ieee_is_finite(lambda)) .and. all(ieee_is_finite(residuals)))) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'Rayleigh-Ritz: NaN or Inf in the ' // &
            'Ritz pairs')
      end if
   end subroutine rayleigh_ritz

end module ffrf_modes_craig_bampton
