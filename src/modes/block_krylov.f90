!> Block shift-invert Lanczos with thick (Krylov-Schur) restarts (docs/theory.md 5.5): the
!> eigenpairs of OP = (K - sigma M)^-1 M on null(C), in the M inner product, from blocks of
!> right-hand sides. A direct solver reads its whole factor once per solve, whatever the number
!> of right-hand sides, so on large factors b right-hand sides cost little more than one (and
!> out-of-core factors are read from disk once per block instead of once per vector).
!>
!> The basis V (M-orthonormal, in null(C)) and M V are kept. Expanding the pending block V_j
!> (columns p+1..p+b):
!>
!>     W = OP V_j,   h = V^T M W (twice: classical Gram-Schmidt with one re-orthogonalisation),
!>     W - V h = V_new R   (Cholesky QR in the M inner product, done twice),
!>
!> so OP V_j = V h + V_new R, the columns p+1..p+b of the block Hessenberg matrix H = V^T M OP V
!> (symmetric in exact arithmetic: OP is M-self-adjoint). Rayleigh-Ritz on the first p columns,
!> H_p Y = Y Theta, gives Ritz pairs (theta, V Y) with OP-residual ||B y|| (B = the rows of H
!> that couple V_p to the pending block), ARPACK's test: ||B y|| <= tol max(eps^(2/3), |theta|)
!> (floored at the rounding level of H, 16 eps max |theta|). A
!> restart keeps the k Ritz vectors of largest |theta| and the pending block; H becomes
!> [diag(theta); B Y_k] and the expansion goes on from the pending block.
module ffrf_modes_block_krylov
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_kinds, only: dp, ip, i8
   use ffrf_core_error, only: error_t, fatal_error, add_context, check_solution, FFRF_INPUT_ERROR, &
      FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: logger_t
   use ffrf_core_interrupt, only: interrupt_t
   use ffrf_la_sparse, only: csr_t, csr_matmat
   use ffrf_la_mumps, only: mumps_solver_t
   use ffrf_la_lapack, only: dgemm, dpotrf, dtrsm
   use ffrf_la_dense, only: symmetric_eigen
   implicit none
   private
   public :: block_krylov_settings_t, block_krylov_stats_t, block_krylov_eigen, &
             default_block_settings, m_cholesky_qr2

   character(len=*), parameter :: stage = 'modes'

   !> Sizes of the block method.
   type :: block_krylov_settings_t
      !> Right-hand sides per solve
      integer(ip) :: block_size = 0
      !> Largest basis Rayleigh-Ritz runs on (columns of V, the pending block not counted)
      integer(ip) :: max_basis = 0
      !> Ritz vectors kept at a restart
      integer(ip) :: kept = 0
   end type block_krylov_settings_t

   !> What the block method did.
   type :: block_krylov_stats_t
      !> Block solves (each with block_size right-hand sides)
      integer(ip) :: num_block_solves = 0
      !> Thick restarts
      integer(ip) :: num_restarts = 0
   end type block_krylov_stats_t

contains

   !> Default sizes for nev wanted pairs in a space of dimension `dimension` (n - constraints):
   !> block b = nev / 2 + 2 in 4..32, basis 8 b (at least 2 nev + 2 b) or `basis` if given
   !> (lanczos_vectors), 2 nev kept at a restart. Measured on the crank at lc = 3 mm (298,161
   !> dofs), 12 modes (docs/performance.md "Large meshes"): b = 8 needs 13 block solves with a basis
   !> of 64 to 96, 15 with 56, 16 with 48; b = 4 needs 17, b = 16 12 to 13 (more right-hand sides
   !> each).
   pure function default_block_settings(nev, basis, dimension) result(settings)
      integer(ip), intent(in) :: nev, basis, dimension
      type(block_krylov_settings_t) :: settings
      settings%block_size = max(4, min(32, (nev + 1) / 2 + 2))
      if (basis > 0) then
         settings%max_basis = basis
      else
         settings%max_basis = max(8 * settings%block_size, 2 * nev + 2 * settings%block_size)
      end if
      settings%max_basis = min(settings%max_basis, dimension - settings%block_size)
      settings%kept = max(nev, min(2 * nev, settings%max_basis - 2 * settings%block_size))
   end function default_block_settings

   !> The nev eigenpairs of OP of largest |theta| (nearest sigma): Ritz vectors z (n x nev, in
   !> the order of decreasing |theta|; not normalised to the caller's convention).
   subroutine block_krylov_eigen(M, nc, nev, settings, tolerance, max_restarts, solver, z, &
         stats, log, error, interrupt, deflate_x, deflate_mx)
      !> Mass matrix (n x n)
      type(csr_t), intent(in) :: M
      !> Constraint rows of the KKT matrix the solver holds (its order is n + nc)
      integer(ip), intent(in) :: nc
      !> Wanted pairs
      integer(ip), intent(in) :: nev
      type(block_krylov_settings_t), intent(in) :: settings
      !> Relative accuracy of theta (ARPACK's tol); <= 0: machine epsilon
      real(dp), intent(in) :: tolerance
      !> Most thick restarts before giving up
      integer(ip), intent(in) :: max_restarts
      !> Factors of the KKT matrix (5.2b) at sigma
      type(mumps_solver_t), intent(inout) :: solver
      real(dp), allocatable, intent(out) :: z(:, :)
      type(block_krylov_stats_t), intent(out) :: stats
      type(logger_t), intent(in) :: log
      type(error_t), allocatable, intent(out) :: error
      !> Checked before every block solve: a run being ended stops here (default: never)
      type(interrupt_t), intent(in), optional :: interrupt
      !> Deflated subspace X (n x d, M-orthonormal, in null(C)) and M X: every OP block is
      !> projected by W = W - X (M X)^T W (theory.md 5.6), so its eigenpairs are never found
      real(dp), intent(in), optional :: deflate_x(:, :), deflate_mx(:, :)
      real(dp), allocatable :: V(:, :), MV(:, :), H(:, :), W(:, :), MW(:, :), R(:, :)
      real(dp), allocatable :: theta(:), Y(:, :), residual(:), coupling(:, :)
      integer(ip), allocatable :: order(:)
      integer(ip) :: n, b, p, cap, k, i, stat, num_converged
      real(dp) :: tol
      real(dp), parameter :: eps23 = epsilon(1.0_dp)**(2.0_dp / 3.0_dp)

      n = M%num_rows
      b = settings%block_size
      cap = settings%max_basis + b
      tol = max(tolerance, epsilon(1.0_dp))
      if (b < 1 .or. settings%max_basis < nev + b .or. settings%kept < nev .or. &
          settings%kept + b > settings%max_basis .or. cap > n) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'block Lanczos: block ' // to_str(b) // &
            ', basis ' // to_str(settings%max_basis) // ', kept ' // to_str(settings%kept) // &
            ' do not fit ' // to_str(nev) // ' modes in dimension ' // to_str(n) // &
            ' (need nev <= kept, kept + block <= basis, nev + block <= basis, basis + block' // &
            ' <= n); use eigensolver = ''arpack'' for so small a problem')
         return
      end if
      allocate (V(n, cap), MV(n, cap), H(cap, cap), W(n, b), MW(n, b), R(b, b), stat=stat)
      if (stat /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'block Lanczos: cannot allocate the ' // &
            'basis of ' // to_str(n) // ' x ' // to_str(cap) // ' (twice: V and M V)')
         return
      end if
      call log%info(stage, 'block Lanczos: ' // to_str(b) // ' right-hand sides per solve, ' // &
         'basis ' // to_str(settings%max_basis) // ', ' // to_str(settings%kept) // &
         ' Ritz vectors kept at a restart')

      ! First block: M-orthonormalised OP X0 (in null(C) whatever X0 is).
      call start_block(W)
      call csr_matmat(M, W, MW)
      call check_interrupt(error)
      if (allocated(error)) return
      call apply_op(solver, n, nc, MW, W, stats, error)
      if (allocated(error)) return
      if (present(deflate_x)) call deflate(W, deflate_x, deflate_mx)
      call csr_matmat(M, W, MW)
      call m_orthonormalise(W, MW, R, error)
      if (allocated(error)) return
      V(:, 1:b) = W
      MV(:, 1:b) = MW
      H = 0.0_dp
      p = 0

      do
         ! Expand by one block, then Rayleigh-Ritz on H_p (|theta| decreasing, OP-residual
         ! ||B y||): stop as soon as the nev wanted pairs have converged.
         call check_interrupt(error)
         if (allocated(error)) return
         call apply_op(solver, n, nc, MV(:, p + 1:p + b), W, stats, error)
         if (allocated(error)) return
         if (present(deflate_x)) then
            call deflate(W, deflate_x, deflate_mx)
            call expand(V, MV, H, p, b, W, MW, M, error, deflate_x, deflate_mx)
         else
            call expand(V, MV, H, p, b, W, MW, M, error)
         end if
         if (allocated(error)) then
            call add_context(error, 'block Lanczos, basis of ' // to_str(p + b) // ' vectors')
            return
         end if
         p = p + b
         if (p < nev) cycle
         call ritz_pairs(H, p, b, theta, Y, residual, order, error)
         if (allocated(error)) return
         num_converged = 0
         do i = 1, nev
            ! dsaupd's test (dsconv): ||B y|| <= tol max(eps^(2/3), |theta|), floored at the
            ! rounding level of H, 16 eps |theta_max| (a shift next to an eigenvalue makes
            ! |theta_max| huge; the far pairs could never reach tol |theta| = eps |theta|)
            if (residual(order(i)) <= max(tol * max(eps23, abs(theta(order(i)))), &
                16.0_dp * epsilon(1.0_dp) * abs(theta(order(1))))) &
               num_converged = num_converged + 1
         end do
         call log%debug(stage, 'block Lanczos: solve ' // to_str(stats%num_block_solves) // &
            ', basis ' // to_str(p) // ', ' // to_str(num_converged) // ' of ' // to_str(nev) &
            // ' converged, largest relative residual ' // &
            to_str(maxval(residual(order(1:nev)) / abs(theta(order(1:nev)))), 3))
         if (num_converged == nev) exit
         if (p + b <= settings%max_basis) cycle
         if (stats%num_restarts >= max_restarts) then
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'block Lanczos: ' // &
               to_str(num_converged) // ' of ' // to_str(nev) // ' eigenvalues converged in ' &
               // to_str(max_restarts) // ' restarts; raise lanczos_vectors (now ' // &
               to_str(settings%max_basis) // ') or use eigensolver = ''arpack''')
            return
         end if

         ! Thick restart: V(:, 1:k) = V_p Y_k (same for M V), the pending block moves to k+1.
         k = settings%kept
         call combine_columns(V, p, Y(:, order(1:k)))
         call combine_columns(MV, p, Y(:, order(1:k)))
         V(:, k + 1:k + b) = V(:, p + 1:p + b)
         MV(:, k + 1:k + b) = MV(:, p + 1:p + b)
         coupling = matmul(H(p + 1:p + b, 1:p), Y(:, order(1:k)))
         H = 0.0_dp
         do i = 1, k
            H(i, i) = theta(order(i))
         end do
         H(k + 1:k + b, 1:k) = coupling
         p = k
         stats%num_restarts = stats%num_restarts + 1
      end do

      allocate (z(n, nev), stat=stat)
      if (stat /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'block Lanczos: cannot allocate ' // &
            to_str(nev) // ' Ritz vectors')
         return
      end if
      Y = Y(:, order(1:nev))
      call dgemm('N', 'N', n, nev, p, 1.0_dp, V, n, Y, p, 0.0_dp, z, n)
      ! Purification (dseupd's for mode 3): z <- OP z / theta = z + V_pending (B y) / theta, one
      ! step of inverse iteration from the Krylov relation OP V_p = V_p H_p + V_pending B, no
      ! solve. It damps the error components along the high modes (theta ~ 0) that the OP
      ! residual ||B y|| hides (lc 6 mm crank, 2 modes: the second's eigen residual 2.8e-8
      ! becomes 1.5e-11 with RC set 1, 2.4e-6 becomes 7.9e-10 free-free)
      coupling = matmul(H(p + 1:p + b, 1:p), Y)
      do i = 1, nev
         coupling(:, i) = coupling(:, i) / theta(order(i))
      end do
      call dgemm('N', 'N', n, nev, b, 1.0_dp, V(:, p + 1:p + b), n, coupling, b, 1.0_dp, z, n)

   contains

      subroutine check_interrupt(error)
         type(error_t), allocatable, intent(out) :: error
         if (.not. present(interrupt)) return
         call interrupt%check('in the block eigen loop after ' // &
            to_str(stats%num_block_solves) // ' block solves', error)
      end subroutine check_interrupt

   end subroutine block_krylov_eigen

   !> W = W - X (M X)^T W, twice (classical Gram-Schmidt with one re-orthogonalisation).
   subroutine deflate(W, X, MX)
      real(dp), intent(inout) :: W(:, :)
      real(dp), intent(in) :: X(:, :), MX(:, :)
      real(dp), allocatable :: coefficients(:, :)
      integer(ip) :: n, d, b, pass
      n = int(size(W, 1), ip)
      b = int(size(W, 2), ip)
      d = int(size(X, 2), ip)
      if (d == 0) return
      allocate (coefficients(d, b))
      do pass = 1, 2
         call dgemm('T', 'N', d, b, n, 1.0_dp, MX, n, W, n, 0.0_dp, coefficients, d)
         call dgemm('N', 'N', n, b, d, -1.0_dp, X, n, coefficients, d, 1.0_dp, W, n)
      end do
   end subroutine deflate

   !> Columns p+1..p+b of H from W = OP V_j: W orthogonalised against V(:, 1:p+b) in the M
   !> inner product (two passes), then M-orthonormalised into the new pending block.
   !> With a deflated subspace the new block is projected again after the Gram-Schmidt passes:
   !> W - V h takes on the round-off components of V along the deflated vectors, and its
   !> normalisation by a small R (near convergence) would amplify them step after step.
   subroutine expand(V, MV, H, p, b, W, MW, M, error, deflate_x, deflate_mx)
      real(dp), intent(inout) :: V(:, :), MV(:, :), H(:, :), W(:, :), MW(:, :)
      integer(ip), intent(in) :: p, b
      type(csr_t), intent(in) :: M
      type(error_t), allocatable, intent(out) :: error
      real(dp), intent(in), optional :: deflate_x(:, :), deflate_mx(:, :)
      real(dp), allocatable :: coefficients(:, :), R(:, :)
      integer(ip) :: n, q, pass
      n = size(V, 1)
      q = p + b
      allocate (coefficients(q, b), R(b, b))
      do pass = 1, 2
         ! h = V^T M W = (M V)^T W; W = W - V h
         call dgemm('T', 'N', q, b, n, 1.0_dp, MV, n, W, n, 0.0_dp, coefficients, q)
         call dgemm('N', 'N', n, b, q, -1.0_dp, V, n, coefficients, q, 1.0_dp, W, n)
         H(1:q, p + 1:p + b) = H(1:q, p + 1:p + b) + coefficients
      end do
      if (present(deflate_x)) call deflate(W, deflate_x, deflate_mx)
      call csr_matmat(M, W, MW)
      call m_orthonormalise(W, MW, R, error)
      if (allocated(error)) return
      V(:, q + 1:q + b) = W
      MV(:, q + 1:q + b) = MW
      H(q + 1:q + b, p + 1:p + b) = R
   end subroutine expand

   !> W = Q R with Q^T M Q = I (Cholesky QR twice, in the M inner product); MW = M W on entry,
   !> M Q on exit.
   subroutine m_orthonormalise(W, MW, R, error)
      real(dp), intent(inout) :: W(:, :), MW(:, :)
      real(dp), intent(out) :: R(:, :)
      type(error_t), allocatable, intent(out) :: error
      integer(ip) :: info, i
      R = 0.0_dp
      do i = 1, int(size(W, 2), ip)
         R(i, i) = 1.0_dp
      end do
      call m_cholesky_qr2(W, MW, info, R)
      if (info /= 0) call fatal_error(error, FFRF_NUMERIC_ERROR, 'block Lanczos: the new ' // &
         'block lost rank (Cholesky of its M-Gram matrix failed at column ' // to_str(info) // &
         '): the Krylov space is (nearly) exhausted; use eigensolver = ''arpack''')
   end subroutine m_orthonormalise

   !> Cholesky QR twice in the M inner product: X (n, d) becomes Q with Q^T M Q = I, MX = M X on
   !> entry is M Q on exit, and R (if present) is multiplied from the left by each pass's
   !> triangular factor. info > 0: the M-Gram matrix is not positive definite at column info
   !> (dependent vectors); X and MX are then partly transformed.
   subroutine m_cholesky_qr2(X, MX, info, R)
      real(dp), intent(inout) :: X(:, :), MX(:, :)
      integer(ip), intent(out) :: info
      real(dp), intent(inout), optional :: R(:, :)
      real(dp), allocatable :: gram(:, :)
      integer(ip) :: n, d, pass, i
      n = int(size(X, 1), ip)
      d = int(size(X, 2), ip)
      allocate (gram(d, d))
      do pass = 1, 2
         call dgemm('T', 'N', d, d, n, 1.0_dp, X, n, MX, n, 0.0_dp, gram, d)
         gram = 0.5_dp * (gram + transpose(gram))
         call dpotrf('U', d, gram, d, info)
         if (info /= 0) return
         do i = 1, d
            gram(i + 1:, i) = 0.0_dp
         end do
         call dtrsm('R', 'U', 'N', 'N', n, d, 1.0_dp, gram, d, X, n)
         call dtrsm('R', 'U', 'N', 'N', n, d, 1.0_dp, gram, d, MX, n)
         if (present(R)) R = matmul(gram, R)
      end do
   end subroutine m_cholesky_qr2

   !> Eigenpairs of the symmetric part of H(1:p, 1:p), the order of decreasing |theta| and the
   !> OP-residual norms ||H(p+1:p+b, 1:p) y||.
   subroutine ritz_pairs(H, p, b, theta, Y, residual, order, error)
      real(dp), intent(in) :: H(:, :)
      integer(ip), intent(in) :: p, b
      real(dp), allocatable, intent(out) :: theta(:), Y(:, :), residual(:)
      integer(ip), allocatable, intent(out) :: order(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: symmetric(:, :), coupling(:, :)
      integer(ip) :: i, j
      symmetric = 0.5_dp * (H(1:p, 1:p) + transpose(H(1:p, 1:p)))
      allocate (theta(p), Y(p, p))
      call symmetric_eigen(symmetric, theta, Y, error)
      if (allocated(error)) then
         call add_context(error, 'block Lanczos, Rayleigh-Ritz')
         return
      end if
      if (.not. all(ieee_is_finite(theta))) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'block Lanczos: NaN or Inf in the ' // &
            'Ritz values; K - sigma M is (nearly) singular: move sigma')
         return
      end if
      coupling = matmul(H(p + 1:p + b, 1:p), Y)
      residual = [(norm2(coupling(:, j)), j=1, p)]
      ! |theta| decreasing (stable insertion sort; p is small)
      order = [(j, j=1, p)]
      do j = 2, p
         i = j
         do while (i > 1)
            if (abs(theta(order(i - 1))) >= abs(theta(order(i)))) exit
            order([i - 1, i]) = order([i, i - 1])
            i = i - 1
         end do
      end do
   end subroutine ritz_pairs

   !> A(:, 1:k) = A(:, 1:p) Y (k = size(Y, 2) <= p), in place, a slab of rows at a time.
   subroutine combine_columns(A, p, Y)
      real(dp), intent(inout) :: A(:, :)
      integer(ip), intent(in) :: p
      real(dp), intent(in) :: Y(:, :)
      integer(ip), parameter :: slab = 2048
      real(dp), allocatable :: part(:, :)
      integer(ip) :: n, k, first, last
      n = size(A, 1)
      k = size(Y, 2)
      allocate (part(slab, k))
      do first = 1, n, slab
         last = min(first + slab - 1, n)
         call dgemm('N', 'N', last - first + 1, k, p, 1.0_dp, A(first:last, 1:p), &
            last - first + 1, Y, p, 0.0_dp, part, slab)
         A(first:last, 1:k) = part(1:last - first + 1, :)
      end do
   end subroutine combine_columns

   !> W = OP X from M X: the KKT solve (5.2b) of the block with zero constraint right-hand sides.
   subroutine apply_op(solver, n, nc, MX, W, stats, error)
      type(mumps_solver_t), intent(inout) :: solver
      integer(ip), intent(in) :: n, nc
      real(dp), intent(in) :: MX(:, :)
      real(dp), intent(out) :: W(:, :)
      type(block_krylov_stats_t), intent(inout) :: stats
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: rhs(:, :)
      integer :: stat
      allocate (rhs(n + nc, size(MX, 2)), stat=stat)
      if (stat /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'block Lanczos: cannot allocate ' // &
            to_str(size(MX, 2)) // ' right-hand sides of ' // to_str(n + nc))
         return
      end if
      rhs(1:n, :) = MX
      rhs(n + 1:, :) = 0.0_dp
      call solver%solve(rhs, error)
      call check_solution(error, 'block Lanczos solve', all(ieee_is_finite(rhs(1:n, :))), &
         'block Lanczos: the KKT solve returned NaN or Inf; K - sigma M is (nearly) ' // &
         'singular: move sigma')
      if (allocated(error)) return
      W = rhs(1:n, :)
      stats%num_block_solves = stats%num_block_solves + 1
   end subroutine apply_op

   !> Deterministic start block in (-0.5, 0.5): Park-Miller minimal standard generator
   !> x <- 16807 x mod (2^31 - 1) from a fixed seed, column after column.
   subroutine start_block(X)
      real(dp), intent(out) :: X(:, :)
      integer(i8), parameter :: modulus = 2147483647_i8, multiplier = 16807_i8
      integer(i8) :: state
      integer :: i, j
      state = 20240611_i8
      do j = 1, size(X, 2)
         do i = 1, size(X, 1)
            state = mod(multiplier * state, modulus)
            X(i, j) = real(state, dp) / real(modulus, dp) - 0.5_dp
         end do
      end do
   end subroutine start_block

end module ffrf_modes_block_krylov
