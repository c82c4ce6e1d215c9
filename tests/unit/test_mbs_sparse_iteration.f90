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
!>   entry that turns zero kept in the triplets (the integrator's block pattern only grows)
!>   keeps the analysis and the same agreement;
!> - a singular matrix (a coordinate with neither inertia nor constraint) is reported as
!>   singular, not as an error (the integrator then cuts the step).
!> Through the integrator, on a planar chain of num_masses point masses on rigid rods under
!> gravity (Cartesian coordinates, index 3, released from the horizontal; 200 steps of 1e-3 s):
!> - sparse_threshold = 1 (MUMPS) and the default (dense) give the same trajectory within the
!>   Newton tolerance: each step's iterate passes when the weighted RMS increment is <= 1, so a
!>   coordinate may be off by sqrt(n) (newton_atol + newton_rtol |q|) per step, added over the
!>   steps at most linearly (the scheme is stable): S sqrt(n) (atol + rtol max|q|) = 1.6e-5 m
!>   (measured 5e-16 m; the last mass falls 0.2 m); the same with the stabilized index-2
!>   constraints and rho_inf = 1 (docs/theory.md 4.6: velocity rows and the columns of nu in the
!>   iteration matrix, order n + 2 nr);
!> - block_sparse_t%product_triplets (nu's columns of the index-2 matrix on the sparse path): the
!>   summed triplets of a kept, scaled A X^T over several column groups equal the dense product
!>   exactly (small integers);
!> - the steps run on one BLAS thread and the count is given back (issue 24): with OpenBLAS set to
!>   2 threads before, the output hook sees 1 at every step and 2 is in place after the run (a
!>   BLAS whose threads ffrf does not set: reported, not asserted).
module test_mbs_sparse_iteration
   use ffrf_core_kinds, only: dp, ip, i8
   use ffrf_core_error, only: error_t
   use ffrf_core_strings, only: to_str
   use ffrf_mbs_galpha_linalg, only: kkt_matrix, kkt_factor, kkt_solve, kkt_sparse_t
   use ffrf_mbs_dae_system, only: dae_system_t
   use ffrf_mbs_generalized_alpha, only: galpha_settings_t, galpha_integrator_t, GALPHA_INDEX3, &
      GALPHA_INDEX2
   use ffrf_la_blas_threads, only: set_blas_threads, blas_threads, blas_library_name
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, report
   use ffrf_la_block_sparse, only: block_sparse_t
   implicit none
   private
   public :: collect_mbs_sparse_iteration

   !> Bodies of the chain and coordinates per body
   integer, parameter :: num_bodies = 12, block = 12
   !> Rows per joint
   integer, parameter :: joint_rows = 3
   !> Chain of point masses: masses, mass (kg), rod length (m), gravity (m/s^2)
   integer, parameter :: num_masses = 6
   real(dp), parameter :: point_mass = 0.5_dp, rod = 0.4_dp, gravity = 9.81_dp

   !> Planar chain of point masses joined by rigid rods, the first to the origin: q = (x_k, y_k),
   !> Phi_k = (|q_k - q_{k-1}|^2 - rod^2)/2. The hook records the BLAS threads during the steps.
   type, extends(dae_system_t) :: mass_chain_t
      !> Largest and smallest BLAS thread count the hook saw
      integer :: most_threads = -huge(1), fewest_threads = huge(1)
   contains
      procedure :: num_coordinates => chain_n
      procedure :: num_constraints => chain_nc
      procedure :: mass => chain_mass
      procedure :: force => chain_force
      procedure :: constraints => chain_phi
      procedure :: constraint_jacobian => chain_jac
      procedure :: accepted_step => chain_hook
   end type mass_chain_t

contains

   subroutine collect_mbs_sparse_iteration(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [new_unittest('chain_sparse_equals_dense', test_chain), &
         new_unittest('pattern_grows_and_keeps', test_pattern), &
         new_unittest('singular_reported', test_singular), &
         new_unittest('integrator_chain_sparse_equals_dense', test_integrator_chain), &
         new_unittest('steps_on_one_blas_thread', test_blas_threads), &
         new_unittest('block_product_triplets_equal_dense', test_product_triplets)]
   end subroutine collect_mbs_sparse_iteration

   !> block_sparse_t%product_triplets (nu's columns of the index-2 matrix on the sparse path):
   !> A (5 x 5, column groups 2 + 3, three blocks) times X^T (X 4 x 5, one row group per row,
   !> four blocks), rows 2 and 4 of X kept as columns 1 and 2, rows 1, 3, 5 of A as 1, 2, 3 with
   !> row and column scales, shifted by (1, 2): the summed triplets equal the dense
   !> diag(rs) A(kept, :) X(kept, :)^T diag(cs) entry by entry (exact small integers).
   subroutine test_product_triplets(error)
      type(error_t), allocatable, intent(out) :: error
      type(block_sparse_t) :: A, X
      real(dp) :: A_dense(5, 5), X_dense(4, 5), expected(4, 5), got(4, 5)
      integer, allocatable :: irn(:), jcn(:)
      real(dp), allocatable :: values(:)
      integer :: k, i
      call A%init([1, 3, 6], [1, 3, 6])
      call A%add_block(0, 0, reshape([1.0_dp, 2.0_dp, 3.0_dp, 4.0_dp], [2, 2]))
      call A%add_block(0, 2, reshape([(real(i, dp), i=5, 10)], [2, 3]))
      call A%add_block(2, 2, reshape([(real(i - 20, dp), i=1, 9)], [3, 3]))
      call X%init([1, 2, 3, 4, 5], [1, 3, 6])
      call X%add_block(1, 0, reshape([2.0_dp, -1.0_dp], [1, 2]))
      call X%add_block(1, 2, reshape([1.0_dp, 0.0_dp, 3.0_dp], [1, 3]))
      call X%add_block(3, 2, reshape([-2.0_dp, 5.0_dp, 1.0_dp], [1, 3]))
      call X%add_block(0, 0, reshape([7.0_dp, 7.0_dp], [1, 2]))
      call A%to_dense(A_dense)
      call X%to_dense(X_dense)
      allocate (irn(2), jcn(2), values(2))
      k = 0
      call A%product_triplets(X, 1, 2, irn, jcn, values, k, keep_row=[1, 0, 2, 0, 3], &
         rscale=[1.0_dp, 2.0_dp, 3.0_dp], keep_col=[0, 1, 0, 2], cscale=[10.0_dp, -1.0_dp])
      got = 0.0_dp
      do i = 1, k
         got(irn(i), jcn(i)) = got(irn(i), jcn(i)) + values(i)
      end do
      expected = 0.0_dp
      expected(2:4, 3:4) = matmul(A_dense([1, 3, 5], :), transpose(X_dense([2, 4], :)))
      expected(2:4, 3) = 10.0_dp * expected(2:4, 3)
      expected(2:4, 4) = -expected(2:4, 4)
      expected(3, 3:4) = 2.0_dp * expected(3, 3:4)
      expected(4, 3:4) = 3.0_dp * expected(4, 3:4)
      call check(error, 'A X^T as triplets equals the dense product (max difference ' // &
         to_str(maxval(abs(got - expected))) // ')', maxval(abs(got - expected)) == 0.0_dp &
         .and. maxval(abs(expected)) > 0.0_dp)
   end subroutine test_product_triplets

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
   subroutine compare(kkt, sparse, pattern, what, error)
      real(dp), intent(in) :: kkt(:, :)
      type(kkt_sparse_t), intent(inout) :: sparse
      logical, allocatable, intent(inout) :: pattern(:, :)
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
      call factor_triplets(kkt, pattern, sparse, singular, error)
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

   !> The entries of kkt on `pattern` as triplets, factorised by `sparse`. The pattern grows
   !> by kkt's nonzeros (and holds the diagonal), as the integrator's block pattern only grows:
   !> an entry that turns zero stays in it, so the triplets' positions stay those analysed.
   subroutine factor_triplets(kkt, pattern, sparse, singular, error)
      real(dp), intent(in) :: kkt(:, :)
      logical, allocatable, intent(inout) :: pattern(:, :)
      type(kkt_sparse_t), intent(inout) :: sparse
      logical, intent(out) :: singular
      type(error_t), allocatable, intent(out) :: error
      integer(ip), allocatable :: irn(:), jcn(:)
      real(dp), allocatable :: values(:)
      integer :: m, i, j, k
      m = size(kkt, 1)
      if (.not. allocated(pattern)) then
         allocate (pattern(m, m))
         pattern = .false.
         do i = 1, m
            pattern(i, i) = .true.
         end do
      end if
      pattern = pattern .or. kkt /= 0.0_dp
      allocate (irn(count(pattern)), jcn(count(pattern)), values(count(pattern)))
      k = 0
      do j = 1, m
         do i = 1, m
            if (.not. pattern(i, j)) cycle
            k = k + 1
            irn(k) = int(i, ip)
            jcn(k) = int(j, ip)
            values(k) = kkt(i, j)
         end do
      end do
      call sparse%factor(m, irn, jcn, values, singular, error)
   end subroutine factor_triplets

   subroutine test_chain(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: A(:, :), Phi_q(:, :), kkt(:, :), scale(:)
      type(kkt_sparse_t) :: sparse
      logical, allocatable :: pattern(:, :)
      call chain_system(A, Phi_q)
      call kkt_matrix(A, Phi_q, kkt, scale)
      call compare(kkt, sparse, pattern, 'chain', error)
      if (.not. allocated(error)) call check(error, 'one analysis', sparse%analyses == 1_i8)
      call sparse%free()
   end subroutine test_chain

   subroutine test_pattern(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: A(:, :), Phi_q(:, :), kkt(:, :), scale(:)
      type(kkt_sparse_t) :: sparse
      logical, allocatable :: pattern(:, :)
      integer :: n
      call chain_system(A, Phi_q)
      n = size(A, 1)
      call kkt_matrix(A, Phi_q, kkt, scale)
      call compare(kkt, sparse, pattern, 'first pattern', error)
      if (allocated(error)) return
      ! a coupling between body 1 and the last body appears: outside the pattern
      A(1, n) = 0.3_dp
      A(n, 1) = -0.2_dp
      call kkt_matrix(A, Phi_q, kkt, scale)
      call compare(kkt, sparse, pattern, 'grown pattern', error)
      if (.not. allocated(error)) call check(error, 'grown pattern: a second analysis (' // &
         to_str(sparse%analyses) // ')', sparse%analyses == 2_i8)
      if (allocated(error)) return
      ! an entry inside the pattern turns zero: the pattern is kept
      A(2, 1) = 0.0_dp
      A(1, n) = 0.0_dp
      call kkt_matrix(A, Phi_q, kkt, scale)
      call compare(kkt, sparse, pattern, 'zeroed entries', error)
      if (.not. allocated(error)) call check(error, 'zeroed entries: no new analysis (' // &
         to_str(sparse%analyses) // ')', sparse%analyses == 2_i8)
      call sparse%free()
   end subroutine test_pattern

   subroutine test_singular(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: A(:, :), Phi_q(:, :), kkt(:, :), scale(:)
      type(kkt_sparse_t) :: sparse
      logical, allocatable :: pattern(:, :)
      logical :: singular
      integer :: n
      call chain_system(A, Phi_q)
      n = size(A, 1)
      ! the last coordinate: no inertia, no coupling, no constraint row touches it
      A(n, :) = 0.0_dp
      A(:, n) = 0.0_dp
      call kkt_matrix(A, Phi_q, kkt, scale)
      call factor_triplets(kkt, pattern, sparse, singular, error)
      if (allocated(error)) return
      call check(error, 'singular matrix reported as singular', singular)
      call sparse%free()
   end subroutine test_singular

   !> Integrate the mass chain 200 steps of 1e-3 s from the horizontal at rest, with the
   !> constraint formulation `constraints` (GALPHA_INDEX2: rho_inf = 1).
   subroutine integrate_chain(sparse_threshold, constraints, system, q_end, order, error)
      integer, intent(in) :: sparse_threshold, constraints
      type(mass_chain_t), intent(inout) :: system
      real(dp), allocatable, intent(out) :: q_end(:)
      !> Order of the iteration matrix and whether the sparse LU was used
      integer, intent(out) :: order
      type(error_t), allocatable, intent(out) :: error
      type(galpha_integrator_t) :: integrator
      type(galpha_settings_t) :: settings
      real(dp) :: q0(2 * num_masses), v0(2 * num_masses)
      integer :: k
      do k = 1, num_masses
         q0(2 * k - 1:2 * k) = [rod * k, 0.0_dp]
      end do
      v0 = 0.0_dp
      settings%h = 1.0e-3_dp
      settings%t_end = 0.2_dp
      settings%sparse_threshold = sparse_threshold
      settings%constraints = constraints
      if (constraints == GALPHA_INDEX2) settings%rho_inf = 1.0_dp
      call integrator%init(system, settings, q0, v0, error)
      if (allocated(error)) return
      call integrator%run(system, error)
      if (allocated(error)) return
      q_end = integrator%q
      order = integrator%stats%matrix_order
      if (integrator%stats%sparse_factorizations > 0) order = -order
   end subroutine integrate_chain

   subroutine test_integrator_chain(error)
      type(error_t), allocatable, intent(out) :: error
      type(mass_chain_t) :: sparse_chain, dense_chain
      real(dp), allocatable :: q_sparse(:), q_dense(:)
      real(dp) :: tolerance
      integer :: order_sparse, order_dense, form
      type(galpha_settings_t) :: defaults
      character(len=*), parameter :: names(2) = ['index 3', 'index 2']
      ! index 3 (rho_inf = 0.8) and the stabilized index 2 (rho_inf = 1, theory.md 4.6, whose
      ! iteration matrix has the velocity rows and nu's columns besides)
      do form = GALPHA_INDEX3, GALPHA_INDEX2
         call integrate_chain(1, form, sparse_chain, q_sparse, order_sparse, error)
         if (allocated(error)) return
         call integrate_chain(huge(1), form, dense_chain, q_dense, order_dense, error)
         if (allocated(error)) return
         call check(error, names(form) // ': sparse run used MUMPS, dense run LAPACK (orders ' &
            // to_str(order_sparse) // ', ' // to_str(order_dense) // '; negative: sparse)', &
            order_sparse < 0 .and. order_dense > 0)
         if (allocated(error)) return
         tolerance = 200.0_dp * sqrt(real(size(q_dense), dp)) * (defaults%newton_atol + &
            defaults%newton_rtol * maxval(abs(q_dense)))
         call report('mass chain, ' // names(form) // ', 200 steps: max |q_sparse - ' // &
            'q_dense| = ' // to_str(maxval(abs(q_sparse - q_dense)), 3) // ' m (tolerance ' // &
            to_str(tolerance, 3) // ' m); the last mass fell ' // &
            to_str(-q_dense(2 * num_masses), 3) // ' m; order ' // to_str(order_dense))
         call check_close(error, names(form) // ': sparse against dense trajectory (m)', &
            maxval(abs(q_sparse - q_dense)), 0.0_dp, atol=tolerance)
         if (allocated(error)) return
      end do
   end subroutine test_integrator_chain

   subroutine test_blas_threads(error)
      type(error_t), allocatable, intent(out) :: error
      type(mass_chain_t) :: system
      real(dp), allocatable :: q_end(:)
      integer :: used, before, order
      if (len(blas_library_name()) == 0) then
         call report('the BLAS linked is neither OpenBLAS nor BLIS: its threads are not set, ' &
            // 'nothing to assert')
         return
      end if
      if (blas_library_name() /= 'OpenBLAS') then
         call report('BLAS ' // blas_library_name() // ': thread count not read back, ' // &
            'nothing to assert')
         return
      end if
      before = blas_threads()
      call set_blas_threads(2, used, error)
      if (allocated(error)) return
      if (used < 2) then
         call report('OpenBLAS built for one thread: nothing to assert')
         call set_blas_threads(before, used, error)
         return
      end if
      call integrate_chain(huge(1), GALPHA_INDEX3, system, q_end, order, error)
      if (.not. allocated(error)) call check(error, 'one BLAS thread at every step (seen ' // &
         to_str(system%fewest_threads) // '..' // to_str(system%most_threads) // ')', &
         system%most_threads == 1 .and. system%fewest_threads == 1)
      if (.not. allocated(error)) call check(error, 'two BLAS threads given back (' // &
         to_str(blas_threads()) // ')', blas_threads() == 2)
      if (allocated(error)) return
      call set_blas_threads(before, used, error)
   end subroutine test_blas_threads

   integer function chain_n(self)
      class(mass_chain_t), intent(in) :: self
      chain_n = 2 * num_masses + 0 * self%most_threads
   end function chain_n

   integer function chain_nc(self)
      class(mass_chain_t), intent(in) :: self
      chain_nc = num_masses + 0 * self%most_threads
   end function chain_nc

   subroutine chain_mass(self, q, M, error)
      class(mass_chain_t), intent(inout) :: self
      real(dp), intent(in) :: q(:)
      real(dp), intent(out) :: M(:, :)
      type(error_t), allocatable, intent(out) :: error
      integer :: i
      M = 0.0_dp * q(1) * self%most_threads
      do i = 1, 2 * num_masses
         M(i, i) = point_mass
      end do
   end subroutine chain_mass

   subroutine chain_force(self, q, v, t, f, error)
      class(mass_chain_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), v(:), t
      real(dp), intent(out) :: f(:)
      type(error_t), allocatable, intent(out) :: error
      integer :: k
      f = 0.0_dp * (q + v + t + self%most_threads)
      do k = 1, num_masses
         f(2 * k) = -point_mass * gravity
      end do
   end subroutine chain_force

   subroutine chain_phi(self, q, t, phi, error)
      class(mass_chain_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), t
      real(dp), intent(out) :: phi(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: d(2)
      integer :: k
      do k = 1, num_masses
         d = q(2 * k - 1:2 * k)
         if (k > 1) d = d - q(2 * k - 3:2 * k - 2)
         phi(k) = 0.5_dp * (sum(d**2) - rod**2) + 0.0_dp * t * self%most_threads
      end do
   end subroutine chain_phi

   subroutine chain_jac(self, q, t, Phi_q, error)
      class(mass_chain_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), t
      real(dp), intent(out) :: Phi_q(:, :)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: d(2)
      integer :: k
      Phi_q = 0.0_dp * t * self%most_threads
      do k = 1, num_masses
         d = q(2 * k - 1:2 * k)
         if (k > 1) d = d - q(2 * k - 3:2 * k - 2)
         Phi_q(k, 2 * k - 1:2 * k) = d
         if (k > 1) Phi_q(k, 2 * k - 3:2 * k - 2) = -d
      end do
   end subroutine chain_jac

   !> Records the BLAS threads at every accepted step (the hook runs inside the step).
   subroutine chain_hook(self, t, q, v, qdd, lambda, error)
      class(mass_chain_t), intent(inout) :: self
      real(dp), intent(in) :: t, q(:), v(:), qdd(:), lambda(:)
      type(error_t), allocatable, intent(out) :: error
      integer :: threads
      threads = blas_threads() + 0 * int(t + sum(q) + sum(v) + sum(qdd) + sum(lambda))
      self%most_threads = max(self%most_threads, threads)
      self%fewest_threads = min(self%fewest_threads, threads)
   end subroutine chain_hook

end module test_mbs_sparse_iteration

program main_mbs_sparse_iteration
   use ffrf_testing, only: unittest_t, run_suite
   use test_mbs_sparse_iteration, only: collect_mbs_sparse_iteration
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_mbs_sparse_iteration(tests)
   call run_suite('mbs_sparse_iteration', tests)
end program main_mbs_sparse_iteration
