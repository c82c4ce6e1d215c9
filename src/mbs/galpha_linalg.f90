!> Dense linear algebra of the generalized-alpha integrator: explicit interfaces to the LAPACK
!> routines it needs beyond ffrf_la_lapack (LU factor/solve, QR with column pivoting), the
!> detection of redundant constraint rows, and the equilibrated saddle-point
!> (KKT) matrix [[A, Phi_q^T], [Phi_q, 0]] shared by the consistent start and the Newton step,
!> and the sparse LU of that matrix (kkt_sparse_t, MUMPS) for large mechanisms.
module ffrf_mbs_galpha_linalg
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_kinds, only: dp, ip, i8
   use ffrf_core_error, only: error_t, fatal_error, add_context, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_la_mumps, only: mumps_solver_t, MUMPS_UNSYMMETRIC
   implicit none
   private
   public :: dgetrf, dgetrs, dgeqp3
   public :: find_redundant_rows, kkt_matrix, kkt_complete, kkt_factor, kkt_solve
   public :: kkt_sparse_t

   !> INFOG(1) of MUMPS for a numerically singular matrix (MUMPS 5.5 user guide, section 8)
   integer(ip), parameter :: MUMPS_SINGULAR = -10_ip

   !> Sparse LU of the equilibrated iteration matrix by MUMPS (unsymmetric, SYM = 0: the
   !> gyroscopic and load tangents make it so), for mechanisms whose iteration matrix is large
   !> and sparse: a chain of flexible bodies has one dense block per body, coupled only through
   !> the rows of its joints, so the dense LU costs O(N^3) for N bodies and the sparse one
   !> O(N). The integrator assembles the matrix as triplets (block-sparse, never dense);
   !> `factor` keeps MUMPS's analysis (METIS ordering, JOB = 1) while the triplets' rows and
   !> columns are those analysed (the block pattern only grows: a new block of the system, or
   !> another set of kept constraint rows, means a new analysis). Do not copy a live one
   !> (MUMPS holds pointers): the integrator keeps it behind a pointer.
   type :: kkt_sparse_t
      !> The MUMPS instance (analysed, factorised)
      type(mumps_solver_t) :: solver
      !> Order of the analysed matrix
      integer :: order = 0
      !> The pattern given to MUMPS (1-based row and column of each entry; duplicates are
      !> summed) and its values
      integer(ip), allocatable :: irn(:), jcn(:)
      real(dp), allocatable :: values(:)
      !> Analyses (pattern changes) and numerical factorisations so far
      integer(i8) :: analyses = 0, factorizations = 0
      !> Seconds in MUMPS's analyses and numerical factorisations (JOB = 1, 2)
      real(dp) :: mumps_seconds = 0.0_dp
   contains
      !> Factorise the (assembled, equilibrated) iteration matrix given as triplets
      procedure :: factor => kkt_sparse_factor
      !> Factorise again the matrix of the last `factor` (after the factors were released)
      procedure :: refactor => kkt_sparse_refactor
      !> Solve with the factors; the right-hand side is overwritten by the solution
      procedure :: solve => kkt_sparse_solve
      !> Whether factors are ready
      procedure :: is_factorised => kkt_sparse_is_factorised
      !> Release MUMPS's memory
      procedure :: free => kkt_sparse_free
   end type kkt_sparse_t

   interface
      !> LU factorisation with partial pivoting, A = P L U.
      subroutine dgetrf(m, n, a, lda, ipiv, info)
         import :: dp, ip
         implicit none
         integer(ip), intent(in) :: m, n, lda
         real(dp), intent(inout) :: a(lda, *)
         integer(ip), intent(out) :: ipiv(*), info
      end subroutine dgetrf

      !> Solve A X = B with the factors of dgetrf.
      subroutine dgetrs(trans, n, nrhs, a, lda, ipiv, b, ldb, info)
         import :: dp, ip
         implicit none
         character, intent(in) :: trans
         integer(ip), intent(in) :: n, nrhs, lda, ldb
         real(dp), intent(in) :: a(lda, *)
         integer(ip), intent(in) :: ipiv(*)
         real(dp), intent(inout) :: b(ldb, *)
         integer(ip), intent(out) :: info
      end subroutine dgetrs

      !> QR factorisation with column pivoting, A P = Q R (|R_kk| non-increasing).
      subroutine dgeqp3(m, n, a, lda, jpvt, tau, work, lwork, info)
         import :: dp, ip
         implicit none
         integer(ip), intent(in) :: m, n, lda, lwork
         real(dp), intent(inout) :: a(lda, *)
         integer(ip), intent(inout) :: jpvt(*)
         real(dp), intent(out) :: tau(*), work(*)
         integer(ip), intent(out) :: info
      end subroutine dgeqp3
   end interface

contains

   !> Linearly dependent rows of the constraint Jacobian Phi_q (nc x n), by QR with column
   !> pivoting of the row-normalised Phi_q^T (Businger-Golub; theory.md 4.3): at each step the
   !> remaining column of largest norm is the pivot, and row k is independent while
   !> |R_kk| > rtol |R_11|. Ties are broken by row order, not by round-off: every column whose norm
   !> is within TIE_RTOL of the largest counts as largest, and the earliest row among them is
   !> taken. LAPACK's dgeqp3, used before, let the BLAS kernel's rounding choose between rows of
   !> equal norm, so one main bearing's axial row or the other's was dropped on different
   !> processors (tests/TOLERANCES.md, "Regression references"). Plain loops, no BLAS: the same
   !> operations on every processor. The kept rows are `active`, the others `dropped` (both
   !> ascending); a zero row is dropped. Rows flagged in `protect` (e.g. Euler-parameter
   !> normalisations) must stay: when the search drops one of them (a dependent set that holds it,
   !> as the self-stress of an over-constrained loop, Bricard's mechanism, does), it is run again
   !> with the protected rows taken as pivots first, so the dropped rows are joint rows; a case
   !> whose first search keeps them all is not affected.
   subroutine find_redundant_rows(Phi_q, rtol, active, dropped, error, protect)
      !> Constraint Jacobian, nc x n
      real(dp), intent(in) :: Phi_q(:, :)
      !> Relative tolerance on the diagonal of R (e.g. 1e-9)
      real(dp), intent(in) :: rtol
      !> Independent rows kept in the equations, ascending
      integer, allocatable, intent(out) :: active(:)
      !> Redundant rows dropped from the equations, ascending
      integer, allocatable, intent(out) :: dropped(:)
      type(error_t), allocatable, intent(out) :: error
      !> Rows that must not be dropped, nc (default: none)
      logical, intent(in), optional :: protect(:)
      !> Column norms this close to the largest (relative) are a tie: far above the round-off of
      !> the norms (1e-15), far below the differences of distinct constraint rows
      real(dp), parameter :: TIE_RTOL = 1.0e-10_dp
      real(dp), allocatable :: at(:, :), norms(:), v(:)
      integer, allocatable :: row_of(:)
      real(dp) :: largest, r11, alpha, beta
      integer :: m, nrow, k, j, pivot, rank
      logical, allocatable :: keep(:), first(:)
      nrow = size(Phi_q, 1)
      m = size(Phi_q, 2)
      if (.not. all(ieee_is_finite(Phi_q))) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'redundant-constraint detection: the ' // &
            to_str(nrow) // ' x ' // to_str(m) // ' constraint Jacobian holds a NaN or ' // &
            'infinite entry')
         return
      end if
      allocate (keep(nrow), at(m, nrow), norms(nrow), row_of(nrow), v(m), first(nrow))
      first = .false.
      call pivoted_qr()
      if (present(protect)) then
         if (any(protect .and. .not. keep)) then
            first = protect
            call pivoted_qr()
         end if
      end if
      active = pack([(j, j=1, nrow)], keep)
      dropped = pack([(j, j=1, nrow)], .not. keep)

   contains

      !> The pivoted QR of the row-normalised Phi_q^T into keep; a column of a `first` row is
      !> the pivot while one of them is independent (with no `first` row: plain pivoting).
      subroutine pivoted_qr()
         logical :: preferred
         keep = .false.
         do j = 1, nrow
            largest = maxval(abs(Phi_q(j, :)))
            at(:, j) = 0.0_dp
            if (largest > 0.0_dp) at(:, j) = Phi_q(j, :) / largest
            row_of(j) = j
         end do
         rank = 0
         r11 = 0.0_dp
         do k = 1, min(m, nrow)
            ! norms of the remaining columns below row k-1 of R, recomputed (no downdating)
            do j = k, nrow
               norms(j) = norm2(at(k:, j))
            end do
            largest = maxval(norms(k:nrow))
            if (k == 1) r11 = largest
            ! a first row still independent of the pivots taken is preferred
            preferred = .false.
            do j = k, nrow
               if (first(row_of(j)) .and. norms(j) > rtol * r11) preferred = .true.
            end do
            if (preferred) largest = maxval(norms(k:nrow), &
               mask=[(first(row_of(j)), j=k, nrow)])
            pivot = 0
            do j = k, nrow
               if (preferred .and. .not. first(row_of(j))) cycle
               if (norms(j) >= (1.0_dp - TIE_RTOL) * largest) then
                  if (pivot == 0) then
                     pivot = j
                  else if (row_of(j) < row_of(pivot)) then
                     pivot = j
                  end if
               end if
            end do
            if (.not. largest > rtol * r11) exit
            if (pivot /= k) then
               v = at(:, k)
               at(:, k) = at(:, pivot)
               at(:, pivot) = v
               j = row_of(k)
               row_of(k) = row_of(pivot)
               row_of(pivot) = j
            end if
            rank = k
            ! Householder reflection H = I - beta v v^T mapping at(k:, k) to (alpha, 0, ...)
            alpha = -sign(largest, at(k, k))
            v(k:) = at(k:, k)
            v(k) = v(k) - alpha
            beta = dot_product(v(k:), v(k:))
            if (beta > 0.0_dp) then
               beta = 2.0_dp / beta
               do j = k + 1, nrow
                  at(k:, j) = at(k:, j) - (beta * dot_product(v(k:), at(k:, j))) * v(k:)
               end do
            end if
            at(k, k) = alpha
            at(k + 1:, k) = 0.0_dp
         end do
         do k = 1, rank
            keep(row_of(k)) = .true.
         end do
      end subroutine pivoted_qr
   end subroutine find_redundant_rows

   !> Equilibrated saddle-point matrix [[A, Phi_q^T S], [S Phi_q, 0]] with the diagonal row scale
   !> S = diag(scale), scale_i = max|diag A| / max_j |Phi_q(i, j)|, so that both blocks have the
   !> magnitude of A (theory.md 4.2: the remaining conditioning is then O(1)). The unknowns are
   !> [x; y] with the multipliers lambda = S y, and the constraint right-hand side is S b.
   subroutine kkt_matrix(A, Phi_q, kkt, scale)
      !> Upper-left block, n x n (mass matrix or the scaled iteration block)
      real(dp), intent(in) :: A(:, :)
      !> Independent constraint rows, nr x n
      real(dp), intent(in) :: Phi_q(:, :)
      !> The (n + nr) square matrix
      real(dp), allocatable, intent(out) :: kkt(:, :)
      !> Row scale of the constraint block, nr
      real(dp), allocatable, intent(out) :: scale(:)
      integer :: n, nr, i
      n = size(A, 1)
      nr = size(Phi_q, 1)
      allocate (kkt(n + nr, n + nr), scale(nr))
      kkt(:n, :n) = A
      call kkt_complete(kkt, Phi_q, [(i, i=1, nr)], scale)
   end subroutine kkt_matrix

   !> The constraint blocks of kkt_matrix around an upper-left block already in kkt(:n, :n):
   !> rows `rows` of Phi_q (nr of them, n = size(kkt, 1) - nr), each scaled to the largest
   !> diagonal entry of the block; the lower-right block zero. In place: no copy of the n x n
   !> block nor of the selected rows.
   pure subroutine kkt_complete(kkt, Phi_q, rows, scale)
      !> The (n + nr) square matrix, its (:n, :n) block set on entry
      real(dp), intent(inout) :: kkt(:, :)
      !> Constraint Jacobian, all rows (nc x n)
      real(dp), intent(in) :: Phi_q(:, :)
      !> The independent rows of Phi_q to use, nr
      integer, intent(in) :: rows(:)
      !> Row scale of the constraint block, nr
      real(dp), intent(out) :: scale(:)
      real(dp) :: reference, row_max
      integer :: n, nr, i, j
      nr = size(rows)
      n = size(kkt, 1) - nr
      reference = 0.0_dp
      do i = 1, n
         reference = max(reference, abs(kkt(i, i)))
      end do
      if (reference <= 0.0_dp) reference = 1.0_dp
      do i = 1, nr
         row_max = 0.0_dp
         do j = 1, n
            row_max = max(row_max, abs(Phi_q(rows(i), j)))
         end do
         scale(i) = 1.0_dp
         if (row_max > 0.0_dp) scale(i) = reference / row_max
      end do
      do j = 1, n
         do i = 1, nr
            kkt(n + i, j) = scale(i) * Phi_q(rows(i), j)
         end do
      end do
      do i = 1, nr
         kkt(:n, n + i) = kkt(n + i, :n)
      end do
      kkt(n + 1:, n + 1:) = 0.0_dp
   end subroutine kkt_complete

   !> LU factors of a square matrix in place (dgetrf); info > 0 means singular. The pivot array
   !> is (re)allocated only when its size differs.
   subroutine kkt_factor(kkt, pivots, info)
      !> Matrix on entry, its LU factors on exit
      real(dp), intent(inout) :: kkt(:, :)
      !> Row interchanges
      integer(ip), allocatable, intent(inout) :: pivots(:)
      !> dgetrf status: 0 success, > 0 exactly singular pivot
      integer(ip), intent(out) :: info
      integer(ip) :: m
      m = int(size(kkt, 1), ip)
      if (allocated(pivots)) then
         if (size(pivots) /= m) deallocate (pivots)
      end if
      if (.not. allocated(pivots)) allocate (pivots(m))
      info = 0
      if (m == 0) return
      call dgetrf(m, m, kkt, m, pivots, info)
   end subroutine kkt_factor

   !> Solve with the factors of kkt_factor; the right-hand side is overwritten by the solution.
   subroutine kkt_solve(lu, pivots, rhs)
      !> LU factors
      real(dp), intent(in) :: lu(:, :)
      !> Row interchanges
      integer(ip), intent(in) :: pivots(:)
      !> Right-hand side on entry, solution on exit
      real(dp), intent(inout) :: rhs(:)
      integer(ip) :: m, info
      m = int(size(lu, 1), ip)
      if (m == 0) return
      call dgetrs('N', m, 1_ip, lu, m, pivots, rhs, m, info)
   end subroutine kkt_solve

   !> Sparse LU factors (MUMPS) of the square matrix of order m given by the triplets (irn,
   !> jcn, values); analysed again only when the triplets' rows and columns differ from the
   !> last ones. `singular` when MUMPS finds the matrix numerically singular (INFOG(1) = -10;
   !> the dense path's dgetrf info > 0): the integrator then cuts the step.
   subroutine kkt_sparse_factor(self, m, irn, jcn, values, singular, error)
      class(kkt_sparse_t), intent(inout) :: self
      !> Order
      integer, intent(in) :: m
      !> Rows, columns (1-based) and values of the entries (a position may repeat: summed)
      integer(ip), intent(in) :: irn(:), jcn(:)
      real(dp), intent(in) :: values(:)
      !> Whether MUMPS found it numerically singular
      logical, intent(out) :: singular
      type(error_t), allocatable, intent(out) :: error
      logical :: same
      singular = .false.
      same = allocated(self%irn) .and. self%order == m
      if (same) same = size(self%irn) == size(irn)
      if (same) same = all(self%irn == irn) .and. all(self%jcn == jcn)
      if (.not. same) then
         self%irn = irn
         self%jcn = jcn
         self%order = m
         call self%solver%free()
         call self%solver%init(MUMPS_UNSYMMETRIC, error)
         if (.not. allocated(error)) call self%solver%analyse(int(m, ip), self%irn, self%jcn, &
            error=error)
         if (allocated(error)) then
            call add_context(error, 'sparse LU of the iteration matrix (order ' // &
               to_str(m) // ', ' // to_str(size(irn)) // ' entries)')
            deallocate (self%irn)
            return
         end if
         self%analyses = self%analyses + 1
         self%mumps_seconds = self%mumps_seconds + self%solver%time_ordering + &
            self%solver%time_analysis
      end if
      self%values = values
      call self%refactor(singular, error)
   end subroutine kkt_sparse_factor

   !> Numerical factorisation of the values kept by the last `factor` (analysed pattern).
   subroutine kkt_sparse_refactor(self, singular, error)
      class(kkt_sparse_t), intent(inout) :: self
      !> Whether MUMPS found it numerically singular
      logical, intent(out) :: singular
      type(error_t), allocatable, intent(out) :: error
      singular = .false.
      if (.not. allocated(self%values)) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'sparse LU of the iteration matrix: ' // &
            'no matrix to factorise (internal: factor before solve)')
         return
      end if
      call self%solver%factorise(self%values, error)
      self%factorizations = self%factorizations + 1
      self%mumps_seconds = self%mumps_seconds + self%solver%time_factorisation
      if (allocated(error)) then
         if (self%solver%status == MUMPS_SINGULAR) then
            deallocate (error)
            singular = .true.
         else
            call add_context(error, 'sparse LU of the iteration matrix (order ' // &
               to_str(self%order) // ')')
         end if
      end if
   end subroutine kkt_sparse_refactor

   !> Solve with the factors of kkt_sparse_factor; the right-hand side is overwritten.
   subroutine kkt_sparse_solve(self, rhs, error)
      class(kkt_sparse_t), intent(inout) :: self
      !> Right-hand side on entry, solution on exit
      real(dp), intent(inout) :: rhs(:)
      type(error_t), allocatable, intent(out) :: error
      if (size(rhs) == 0) return
      call self%solver%solve(rhs, error)
      if (allocated(error)) call add_context(error, 'sparse solve with the iteration matrix')
   end subroutine kkt_sparse_solve

   !> Whether factors are ready for solve.
   logical function kkt_sparse_is_factorised(self) result(ready)
      class(kkt_sparse_t), intent(in) :: self
      ready = self%solver%is_factorised()
   end function kkt_sparse_is_factorised

   !> Release MUMPS's memory and the pattern.
   subroutine kkt_sparse_free(self)
      class(kkt_sparse_t), intent(inout) :: self
      call self%solver%free()
      if (allocated(self%irn)) deallocate (self%irn, self%jcn)
      if (allocated(self%values)) deallocate (self%values)
   end subroutine kkt_sparse_free

end module ffrf_mbs_galpha_linalg
