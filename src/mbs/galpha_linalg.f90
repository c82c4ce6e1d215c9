!> Dense linear algebra of the generalized-alpha integrator: explicit interfaces to the LAPACK
!> routines it needs beyond ffrf_la_lapack (LU factor/solve, QR with column pivoting), the
!> detection of redundant constraint rows, and the equilibrated saddle-point
!> (KKT) matrix [[A, Phi_q^T], [Phi_q, 0]] shared by the consistent start and the Newton step.
module ffrf_mbs_galpha_linalg
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_kinds, only: dp, ip
   use ffrf_core_error, only: error_t, fatal_error, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   implicit none
   private
   public :: dgetrf, dgetrs, dgeqp3
   public :: find_redundant_rows, kkt_matrix, kkt_complete, kkt_factor, kkt_solve

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
   !> ascending); a zero row is dropped.
   subroutine find_redundant_rows(Phi_q, rtol, active, dropped, error)
      !> Constraint Jacobian, nc x n
      real(dp), intent(in) :: Phi_q(:, :)
      !> Relative tolerance on the diagonal of R (e.g. 1e-9)
      real(dp), intent(in) :: rtol
      !> Independent rows kept in the equations, ascending
      integer, allocatable, intent(out) :: active(:)
      !> Redundant rows dropped from the equations, ascending
      integer, allocatable, intent(out) :: dropped(:)
      type(error_t), allocatable, intent(out) :: error
      !> Column norms this close to the largest (relative) are a tie: far above the round-off of
      !> the norms (1e-15), far below the differences of distinct constraint rows
      real(dp), parameter :: TIE_RTOL = 1.0e-10_dp
      real(dp), allocatable :: at(:, :), norms(:), v(:)
      integer, allocatable :: row_of(:)
      real(dp) :: largest, r11, alpha, beta
      integer :: m, nrow, k, j, pivot, rank
      logical, allocatable :: keep(:)
      nrow = size(Phi_q, 1)
      m = size(Phi_q, 2)
      if (.not. all(ieee_is_finite(Phi_q))) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'redundant-constraint detection: the ' // &
            to_str(nrow) // ' x ' // to_str(m) // ' constraint Jacobian holds a NaN or ' // &
            'infinite entry')
         return
      end if
      allocate (keep(nrow), at(m, nrow), norms(nrow), row_of(nrow), v(m))
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
         pivot = 0
         do j = k, nrow
            if (norms(j) >= (1.0_dp - TIE_RTOL) * largest) then
               if (pivot == 0) then
                  pivot = j
               else if (row_of(j) < row_of(pivot)) then
                  pivot = j
               end if
            end if
         end do
         if (k == 1) r11 = largest
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
      active = pack([(j, j=1, nrow)], keep)
      dropped = pack([(j, j=1, nrow)], .not. keep)
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

end module ffrf_mbs_galpha_linalg
