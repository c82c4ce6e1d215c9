!> Sparse LU of the integrator's iteration matrix (kkt_sparse_t: MUMPS, unsymmetric; issue 24)
!> against the dense LU (kkt_factor/kkt_solve: LAPACK dgetrf/dgetrs), the integrator's two
!> routes, on the saddle-point matrix of a chain: num_bodies bodies of block coordinates each,
!> every block dense (M/c + beta h^2 K: symmetric, diagonally dominant, plus a skew gyroscopic
!> part gamma h C), coupled only through joint rows (3 per joint: the last 3 coordinates of body
!> k - 1 against the first 3 of body k; the first joint to the ground), equilibrated by
!> kkt_matrix as in the integrator. Entries are deterministic (sin of the indices).
!> Asserted:
!> - the sparse solution's backward error ||S x - b||_inf / (||S||_inf ||x||_inf + ||b||_inf)
!>   <= 1e-13 (a reference independent of the dense route: an LU with threshold pivoting is
!>   backward stable to a modest multiple of n eps = 4e-14 for n = 180; measured 1.2e-16);
!> - the sparse and the dense solutions agree, ||x_s - x_d||_inf <= 1e-10 ||x_d||_inf: each is
!>   within cond(S) times its backward error of the exact solution, and cond(S) is moderate
!>   here (diagonal 1.5 to 2.5 against off-diagonal row sums below 1.2 in every block, the
!>   constraint rows equilibrated); measured 5.7e-16, so 1e-10 leaves five decades of margin;
!> - a new nonzero outside the analysed pattern makes a new analysis and the same agreement; an
!>   entry that turns zero keeps the pattern (no analysis) and the same agreement;
!> - a singular matrix (a coordinate with neither inertia nor constraint) is reported as
!>   singular, not as an error (the integrator then cuts the step).
module test_mbs_sparse_iteration
   use ffrf_core_kinds, only: dp, ip, i8
   use ffrf_core_error, only: error_t
   use ffrf_core_strings, only: to_str
   use ffrf_mbs_galpha_linalg, only: kkt_matrix, kkt_factor, kkt_solve, kkt_sparse_t
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, report
   implicit none
   private
   public :: collect_mbs_sparse_iteration

   !> Bodies of the chain and coordinates per body
   integer, parameter :: num_bodies = 12, block = 12
   !> Rows per joint
   integer, parameter :: joint_rows = 3

contains

   subroutine collect_mbs_sparse_iteration(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [new_unittest('chain_sparse_equals_dense', test_chain), &
         new_unittest('pattern_grows_and_keeps', test_pattern), &
         new_unittest('singular_reported', test_singular)]
   end subroutine collect_mbs_sparse_iteration

   !> The chain's upper-left block A (n x n) and constraint Jacobian Phi_q (nr x n).
   subroutine chain_system(A, Phi_q)
      real(dp), allocatable, intent(out) :: A(:, :), Phi_q(:, :)
      integer :: n, nr, b, i, j, r, first, last
      real(dp) :: value
      n = num_bodies * block
      nr = num_bodies * joint_rows
      allocate (A(n, n), Phi_q(nr, n))
      A = 0.0_dp
      Phi_q = 0.0_dp
      do b = 1, num_bodies
         first = (b - 1) * block
         do j = 1, block
            do i = 1, j
               ! symmetric part: mass-like diagonal, stiffness-like coupling
               value = 0.1_dp * sin(real(i * 7 + j * 3 + b, dp))
               if (i == j) value = 2.0_dp + 0.5_dp * sin(real(b + i, dp))
               A(first + i, first + j) = value
               A(first + j, first + i) = value
            end do
            do i = 1, j - 1
               ! skew (gyroscopic) part: the matrix is not symmetric
               value = 0.05_dp * cos(real(i + 2 * j + b, dp))
               A(first + i, first + j) = A(first + i, first + j) + value
               A(first + j, first + i) = A(first + j, first + i) - value
            end do
         end do
         ! joint b: the first 3 coordinates of body b against the last 3 of body b - 1
         do r = 1, joint_rows
            Phi_q((b - 1) * joint_rows + r, first + r) = 1.0_dp + 0.1_dp * r
            if (b > 1) then
               last = first - joint_rows
               Phi_q((b - 1) * joint_rows + r, last + r) = -(1.0_dp - 0.05_dp * r)
            end if
         end do
      end do
   end subroutine chain_system

   !> A right-hand side of order m.
   function rhs_of(m) result(b)
      integer, intent(in) :: m
      real(dp) :: b(m)
      integer :: i
      b = [(sin(real(i, dp)**2) + 0.1_dp, i=1, m)]
   end function rhs_of

   !> Solve kkt x = b by both routes; compare (module header).
   subroutine compare(kkt, sparse, what, error)
      real(dp), intent(in) :: kkt(:, :)
      type(kkt_sparse_t), intent(inout) :: sparse
      character(len=*), intent(in) :: what
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: lu(:, :), x_dense(:), x_sparse(:), b(:)
      integer(ip), allocatable :: pivots(:)
      integer(ip) :: info
      logical :: singular
      real(dp) :: backward, difference
      allocate (b(size(kkt, 1)))
      b = rhs_of(size(kkt, 1))
      lu = kkt
      call kkt_factor(lu, pivots, info)
      call check(error, what // ': dense LU not singular', info == 0)
      if (allocated(error)) return
      x_dense = b
      call kkt_solve(lu, pivots, x_dense)
      call sparse%factor(kkt, singular, error)
      if (allocated(error)) return
      call check(error, what // ': sparse LU not singular', .not. singular)
      if (allocated(error)) return
      x_sparse = b
      call sparse%solve(x_sparse, error)
      if (allocated(error)) return
      backward = maxval(abs(matmul(kkt, x_sparse) - b)) / (maxval(sum(abs(kkt), dim=2)) * &
         maxval(abs(x_sparse)) + maxval(abs(b)))
      difference = maxval(abs(x_sparse - x_dense)) / maxval(abs(x_dense))
      call report(what // ': order ' // to_str(size(kkt, 1)) // ', backward error ' // &
         to_str(backward, 3) // ', relative difference sparse - dense ' // to_str(difference, 3))
      call check_close(error, what // ': backward error of the sparse solution', backward, &
         0.0_dp, atol=1.0e-13_dp)
      if (allocated(error)) return
      call check_close(error, what // ': sparse against dense solution', difference, 0.0_dp, &
         atol=1.0e-10_dp)
   end subroutine compare

   subroutine test_chain(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: A(:, :), Phi_q(:, :), kkt(:, :), scale(:)
      type(kkt_sparse_t) :: sparse
      call chain_system(A, Phi_q)
      call kkt_matrix(A, Phi_q, kkt, scale)
      call compare(kkt, sparse, 'chain', error)
      if (.not. allocated(error)) call check(error, 'one analysis', sparse%analyses == 1_i8)
      call sparse%free()
   end subroutine test_chain

   subroutine test_pattern(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: A(:, :), Phi_q(:, :), kkt(:, :), scale(:)
      type(kkt_sparse_t) :: sparse
      integer :: n
      call chain_system(A, Phi_q)
      n = size(A, 1)
      call kkt_matrix(A, Phi_q, kkt, scale)
      call compare(kkt, sparse, 'first pattern', error)
      if (allocated(error)) return
      ! a coupling between body 1 and the last body appears: outside the pattern
      A(1, n) = 0.3_dp
      A(n, 1) = -0.2_dp
      call kkt_matrix(A, Phi_q, kkt, scale)
      call compare(kkt, sparse, 'grown pattern', error)
      if (.not. allocated(error)) call check(error, 'grown pattern: a second analysis (' // &
         to_str(sparse%analyses) // ')', sparse%analyses == 2_i8)
      if (allocated(error)) return
      ! an entry inside the pattern turns zero: the pattern is kept
      A(2, 1) = 0.0_dp
      A(1, n) = 0.0_dp
      call kkt_matrix(A, Phi_q, kkt, scale)
      call compare(kkt, sparse, 'zeroed entries', error)
      if (.not. allocated(error)) call check(error, 'zeroed entries: no new analysis (' // &
         to_str(sparse%analyses) // ')', sparse%analyses == 2_i8)
      call sparse%free()
   end subroutine test_pattern

   subroutine test_singular(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: A(:, :), Phi_q(:, :), kkt(:, :), scale(:)
      type(kkt_sparse_t) :: sparse
      logical :: singular
      integer :: n
      call chain_system(A, Phi_q)
      n = size(A, 1)
      ! the last coordinate: no inertia, no coupling, no constraint row touches it
      A(n, :) = 0.0_dp
      A(:, n) = 0.0_dp
      call kkt_matrix(A, Phi_q, kkt, scale)
      call sparse%factor(kkt, singular, error)
      if (allocated(error)) return
      call check(error, 'singular matrix reported as singular', singular)
      call sparse%free()
   end subroutine test_singular

end module test_mbs_sparse_iteration

program main_mbs_sparse_iteration
   use ffrf_testing, only: unittest_t, run_suite
   use test_mbs_sparse_iteration, only: collect_mbs_sparse_iteration
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_mbs_sparse_iteration(tests)
   call run_suite('mbs_sparse_iteration', tests)
end program main_mbs_sparse_iteration
