!> Tests of ffrf_la_mumps and ffrf_la_metis: SPD and indefinite (KKT) solves against
!> manufactured solutions, the inertia INFOG(12) against LAPACK dsyev and against Sylvester's law
!> for a KKT matrix, null-pivot detection on a singular matrix, the METIS permutation, and the
!> error paths. Solve tolerance 1e-10 relative: the matrices here have condition numbers below
!> 1e3, so a backward-stable LDL^T gives errors near 1e-13; 1e-10 leaves room for pivot growth.
module test_la_mumps
   use ffrf_core_kinds, only: dp, ip, i8
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_la_lapack, only: dsyev
   use ffrf_la_metis, only: nested_dissection, pattern_adjacency
   use ffrf_la_mumps, only: mumps_solver_t, MUMPS_SYM_SPD, MUMPS_SYM_INDEFINITE
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, report
   implicit none
   private
   public :: collect_la_mumps

   !> Coordinate-form symmetric test matrix (upper triangle)
   type :: coo_t
      integer(ip) :: n = 0
      integer(ip), allocatable :: irn(:), jcn(:)
      real(dp), allocatable :: val(:)
   end type coo_t

contains

   subroutine collect_la_mumps(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [ &
         new_unittest('spd_laplacian_3d', test_spd_laplacian_3d), &
         new_unittest('kkt_indefinite', test_kkt_indefinite), &
         new_unittest('inertia_vs_dsyev', test_inertia_vs_dsyev), &
         new_unittest('null_pivot_detection', test_null_pivot_detection), &
         new_unittest('metis_permutation', test_metis_permutation), &
         new_unittest('refactorise_same_pattern', test_refactorise_same_pattern), &
         new_unittest('workspace_retry', test_workspace_retry), &
         new_unittest('error_structurally_singular', test_error_structurally_singular), &
         new_unittest('error_bad_input', test_error_bad_input)]
   end subroutine collect_la_mumps

   !> 7-point Laplacian on a 10 x 10 x 10 grid (n = 1000, Dirichlet), SYM = 1, against the
   !> manufactured solution x_i = sin(0.37 i) + 0.1 i / n (b = A x by the COO product); one and
   !> three right-hand sides. cond(A) ~ 50 (eigenvalues 6 +- 6 cos(pi/11) per direction).
   subroutine test_spd_laplacian_3d(error)
      type(error_t), allocatable, intent(out) :: error
      type(coo_t) :: A
      type(mumps_solver_t) :: solver
      real(dp), allocatable :: x(:), b(:), xs(:, :), bs(:, :)
      integer(ip) :: i, j
      call laplacian_3d(10, 10, 10, A)
      allocate (x(A%n), xs(A%n, 3), bs(A%n, 3))
      x = [(sin(0.37_dp * i) + 0.1_dp * i / A%n, i=1, A%n)]
      b = coo_symmetric_product(A, x)
      do j = 1, 3
         xs(:, j) = x * j + cos(real(j, dp))
         bs(:, j) = coo_symmetric_product(A, xs(:, j))
      end do
      call solver%init(MUMPS_SYM_SPD, error)
      if (allocated(error)) return
      call solver%analyse(A%n, A%irn, A%jcn, error=error)
      if (.not. allocated(error)) call solver%factorise(A%val, error)
      if (.not. allocated(error)) call solver%solve(b, error)
      if (.not. allocated(error)) call solver%solve(bs, error)
      if (allocated(error)) then
         call solver%free()
         return
      end if
      call report('n = 1000 Laplacian: ordering ' // to_str(solver%ordering_used) // &
         ', factor entries ' // to_str(solver%factor_entries) // ', negative pivots ' // &
         to_str(solver%num_negative_pivots) // ', error ' // &
         to_str(norm2(b - x) / norm2(x), 3))
      call check(error, 'MUMPS used the given (METIS) ordering, INFOG(7) = ' // &
         to_str(solver%ordering_used), solver%ordering_used == 1 .and. solver%metis_ordering)
      if (.not. allocated(error)) call check(error, 'SPD matrix has no negative pivot', &
         solver%num_negative_pivots == 0)
      if (.not. allocated(error)) call check(error, '4 right-hand sides counted', &
         solver%num_solves == 4_i8)
      call solver%free()
      if (allocated(error)) return
      call check_close(error, 'relative error, one rhs', norm2(b - x) / norm2(x), 0.0_dp, &
         atol=1.0e-10_dp)
      if (allocated(error)) return
      call check_close(error, 'relative error, three rhs', norm2(bs - xs) / norm2(xs), 0.0_dp, &
         atol=1.0e-10_dp)
   end subroutine test_spd_laplacian_3d

   !> KKT matrix [A B^T; B 0], A the 6 x 6 x 6 Laplacian (n = 216), B 4 dense-ish rows (every
   !> third dof, LCG values): solve against a manufactured [x; mu] with SYM = 2. A is SPD and B
   !> has full row rank, so by Sylvester's law the KKT matrix has exactly 4 negative
   !> eigenvalues (inertia = inertia(A) + (m, m, 0) for the Schur complement -B A^-1 B^T).
   subroutine test_kkt_indefinite(error)
      type(error_t), allocatable, intent(out) :: error
      type(coo_t) :: A, kkt
      type(mumps_solver_t) :: solver
      real(dp), allocatable :: x(:), b(:)
      integer(ip), parameter :: m = 4
      integer(ip) :: i
      call laplacian_3d(6, 6, 6, A)
      call append_constraints(A, m, 3_ip, kkt)
      x = [(cos(0.21_dp * i) - 0.3_dp, i=1, kkt%n)]
      b = coo_symmetric_product(kkt, x)
      call solver%init(MUMPS_SYM_INDEFINITE, error)
      if (allocated(error)) return
      call solver%analyse(kkt%n, kkt%irn, kkt%jcn, error=error)
      if (.not. allocated(error)) call solver%factorise(kkt%val, error)
      if (.not. allocated(error)) call solver%solve(b, error)
      if (allocated(error)) then
         call solver%free()
         return
      end if
      call report('KKT n = ' // to_str(kkt%n) // ': negative pivots ' // &
         to_str(solver%num_negative_pivots) // ', delayed pivots ' // &
         to_str(solver%num_delayed_pivots) // ', error ' // to_str(norm2(b - x) / norm2(x), 3))
      call check(error, 'KKT inertia: ' // to_str(solver%num_negative_pivots) // &
         ' negative pivots, expected ' // to_str(m), solver%num_negative_pivots == m)
      call solver%free()
      if (allocated(error)) return
      call check_close(error, 'KKT relative error', norm2(b - x) / norm2(x), 0.0_dp, &
         atol=1.0e-10_dp)
   end subroutine test_kkt_indefinite

   !> A 40 x 40 banded (half-bandwidth 3) symmetric indefinite matrix with LCG entries: MUMPS's
   !> negative-pivot count INFOG(12) equals the number of negative eigenvalues from dense dsyev
   !> (Sylvester's law of inertia for LDL^T). The smallest |eigenvalue| is checked to be well
   !> away from 0 first, so the dense count is unambiguous.
   subroutine test_inertia_vs_dsyev(error)
      type(error_t), allocatable, intent(out) :: error
      integer(ip), parameter :: n = 40, band = 3
      type(coo_t) :: A
      type(mumps_solver_t) :: solver
      real(dp) :: dense(n, n), w(n), work(10 * n)
      integer(ip) :: i, j, k, info, num_negative
      integer(i8) :: state
      state = 12345_i8
      allocate (A%irn(n * (band + 1)), A%jcn(n * (band + 1)), A%val(n * (band + 1)))
      A%n = n
      dense = 0.0_dp
      k = 0
      do i = 1, n
         do j = i, min(n, i + band)
            k = k + 1
            A%irn(k) = i
            A%jcn(k) = j
            A%val(k) = 2.0_dp * lcg(state) - 1.0_dp
            if (i == j) A%val(k) = A%val(k) + 0.5_dp * sign(1.0_dp, A%val(k))
            dense(i, j) = A%val(k)
            dense(j, i) = A%val(k)
         end do
      end do
      A%irn = A%irn(1:k)
      A%jcn = A%jcn(1:k)
      A%val = A%val(1:k)
      call dsyev('N', 'U', n, dense, n, w, work, size(work), info)
      if (info /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'dsyev info = ' // to_str(info))
         return
      end if
      num_negative = count(w < 0.0_dp)
      call check(error, 'reference has no eigenvalue near 0 (min |w| = ' // &
         to_str(minval(abs(w))) // ')', minval(abs(w)) > 1.0e-6_dp)
      if (allocated(error)) return
      call check(error, 'test matrix is indefinite', num_negative > 0 .and. num_negative < n)
      if (allocated(error)) return
      call solver%init(MUMPS_SYM_INDEFINITE, error)
      if (allocated(error)) return
      call solver%analyse(n, A%irn, A%jcn, error=error)
      if (.not. allocated(error)) call solver%factorise(A%val, error)
      if (allocated(error)) then
         call solver%free()
         return
      end if
      call report('dsyev: ' // to_str(num_negative) // ' negative eigenvalues; MUMPS ' // &
         'INFOG(12) = ' // to_str(solver%num_negative_pivots))
      call check(error, 'INFOG(12) = ' // to_str(solver%num_negative_pivots) // &
         ', dsyev count = ' // to_str(num_negative), &
         solver%num_negative_pivots == num_negative)
      call solver%free()
   end subroutine test_inertia_vs_dsyev

   !> Free-free spring chain (n = 50, 1D Neumann Laplacian): singular with a one-dimensional
   !> null space (the constant vector), so null-pivot detection (ICNTL(24) = 1) must report
   !> exactly one null pivot and no negative one (the matrix is positive semi-definite).
   subroutine test_null_pivot_detection(error)
      type(error_t), allocatable, intent(out) :: error
      type(coo_t) :: A
      type(mumps_solver_t) :: solver
      integer(ip), parameter :: n = 50
      integer(ip) :: i, k
      A%n = n
      allocate (A%irn(2 * n - 1), A%jcn(2 * n - 1), A%val(2 * n - 1))
      k = 0
      do i = 1, n
         k = k + 1
         A%irn(k) = i
         A%jcn(k) = i
         A%val(k) = 2.0_dp
         if (i == 1 .or. i == n) A%val(k) = 1.0_dp
         if (i < n) then
            k = k + 1
            A%irn(k) = i
            A%jcn(k) = i + 1
            A%val(k) = -1.0_dp
         end if
      end do
      call solver%init(MUMPS_SYM_INDEFINITE, error, null_pivot_detection=.true., &
                       null_pivot_threshold=1.0e-12_dp)
      if (allocated(error)) return
      call solver%analyse(n, A%irn, A%jcn, error=error)
      if (.not. allocated(error)) call solver%factorise(A%val, error)
      if (allocated(error)) then
         call solver%free()
         return
      end if
      call check(error, 'null pivots = ' // to_str(solver%num_null_pivots) // ', expected 1', &
         solver%num_null_pivots == 1)
      if (.not. allocated(error)) call check(error, 'negative pivots = ' // &
         to_str(solver%num_negative_pivots) // ', expected 0', solver%num_negative_pivots == 0)
      call solver%free()
   end subroutine test_null_pivot_detection

   !> METIS_NodeND on the 12 x 12 x 12 grid graph: perm and iperm are permutations of 1..n and
   !> inverse to each other; factorising with the METIS order (as PERM_IN = iperm) must need
   !> fewer factor entries than the natural order (a band of half-width 144): on a 3D grid
   !> nested dissection fills O(n^(4/3)), a band more (measured 76 024 against 1 331 947).
   subroutine test_metis_permutation(error)
      type(error_t), allocatable, intent(out) :: error
      type(coo_t) :: A
      type(mumps_solver_t) :: solver
      integer(ip), allocatable :: xadj(:), adjncy(:), perm(:), iperm(:), natural(:)
      logical, allocatable :: seen(:)
      integer(i8) :: entries_metis, entries_natural
      integer(ip) :: i
      call laplacian_3d(12, 12, 12, A)
      call pattern_adjacency(A%n, A%irn, A%jcn, xadj, adjncy, error)
      if (allocated(error)) return
      call check(error, 'adjacency has 2 x 3 x 12 x 12 x 11 entries', &
         size(adjncy) == 2 * 3 * 12 * 12 * 11)
      if (allocated(error)) return
      allocate (perm(A%n), iperm(A%n))
      call nested_dissection(A%n, xadj, adjncy, perm, iperm, error)
      if (allocated(error)) return
      allocate (seen(A%n), source=.false.)
      do i = 1, A%n
         if (perm(i) < 1 .or. perm(i) > A%n) exit
         seen(perm(i)) = .true.
      end do
      call check(error, 'perm is a permutation of 1..n', all(seen))
      if (allocated(error)) return
      call check(error, 'iperm(perm(i)) = i', all([(iperm(perm(i)) == i, i=1, A%n)]))
      if (allocated(error)) return

      call solver%init(MUMPS_SYM_SPD, error)
      if (allocated(error)) return
      call solver%analyse(A%n, A%irn, A%jcn, iperm, error)
      if (.not. allocated(error)) call solver%factorise(A%val, error)
      entries_metis = solver%factor_entries
      call solver%free()
      if (allocated(error)) return
      natural = [(i, i=1, A%n)]
      call solver%init(MUMPS_SYM_SPD, error)
      if (allocated(error)) return
      call solver%analyse(A%n, A%irn, A%jcn, natural, error)
      if (.not. allocated(error)) call solver%factorise(A%val, error)
      entries_natural = solver%factor_entries
      call solver%free()
      if (allocated(error)) return
      call report('factor entries: METIS ' // to_str(entries_metis) // ', natural ' // &
         to_str(entries_natural))
      call check(error, 'METIS ordering gives fewer factor entries (' // &
         to_str(entries_metis) // ') than the natural one (' // to_str(entries_natural) // ')', &
         entries_metis < entries_natural)
   end subroutine test_metis_permutation

   !> A second matrix with the same pattern (A + 3 I) goes through factorise again without a new
   !> analysis; the solve matches its own manufactured solution.
   subroutine test_refactorise_same_pattern(error)
      type(error_t), allocatable, intent(out) :: error
      type(coo_t) :: A
      type(mumps_solver_t) :: solver
      real(dp), allocatable :: x(:), b(:)
      integer(ip) :: i
      call laplacian_3d(5, 6, 7, A)
      call solver%init(MUMPS_SYM_SPD, error)
      if (allocated(error)) return
      call solver%analyse(A%n, A%irn, A%jcn, error=error)
      if (.not. allocated(error)) call solver%factorise(A%val, error)
      if (allocated(error)) then
         call solver%free()
         return
      end if
      where (A%irn == A%jcn) A%val = A%val + 3.0_dp
      x = [(1.0_dp / i, i=1, A%n)]
      b = coo_symmetric_product(A, x)
      call solver%factorise(A%val, error)
      if (.not. allocated(error)) call solver%solve(b, error)
      call solver%free()
      if (allocated(error)) return
      call check_close(error, 'relative error after refactorisation', &
         norm2(b - x) / norm2(x), 0.0_dp, atol=1.0e-10_dp)
   end subroutine test_refactorise_same_pattern

   !> Workspace retry: a KKT matrix (1D Laplacian n = 2000, 400 constraint rows of 10 entries)
   !> ordered multipliers first, so their zero pivots are delayed and the fronts outgrow the
   !> analysis estimate; with ICNTL(14) = 0 MUMPS 5.5.1 stops with INFOG(1) = -8/-9 and the
   !> wrapper must retry with a doubled relaxation (observed: 2 retries, ICNTL(14) = 40), then solve
   !> against a manufactured solution to 1e-10.
   subroutine test_workspace_retry(error)
      type(error_t), allocatable, intent(out) :: error
      integer(ip), parameter :: n = 2000, m = 400
      type(coo_t) :: kkt
      type(mumps_solver_t) :: solver
      real(dp), allocatable :: x(:), b(:)
      integer(ip) :: i, r, e
      kkt%n = n + m
      allocate (kkt%irn(2 * n - 1 + 10 * m), kkt%jcn(2 * n - 1 + 10 * m), &
                kkt%val(2 * n - 1 + 10 * m))
      e = 0
      do i = 1, n
         call put(i, i, 2.0_dp)
         if (i < n) call put(i, i + 1, -1.0_dp)
      end do
      do r = 1, m
         do i = 1, 10
            call put(mod(r * 37 + i * 101, n) + 1, n + r, 1.0_dp + 0.1_dp * i)
         end do
      end do
      x = [(sin(0.1_dp * i), i=1, kkt%n)]
      b = coo_symmetric_product(kkt, x)
      call solver%init(MUMPS_SYM_INDEFINITE, error, workspace_percent=0_ip)
      if (allocated(error)) return
      call solver%analyse(kkt%n, kkt%irn, kkt%jcn, [(m + i, i=1, n), (i, i=1, m)], error)
      if (.not. allocated(error)) call solver%factorise(kkt%val, error)
      if (.not. allocated(error)) call solver%solve(b, error)
      if (allocated(error)) then
         call solver%free()
         return
      end if
      call report('workspace retries ' // to_str(solver%num_workspace_retries) // &
         ', final ICNTL(14) = ' // to_str(solver%workspace_percent) // ', delayed pivots ' // &
         to_str(solver%num_delayed_pivots))
      call check(error, 'at least one workspace retry', solver%num_workspace_retries >= 1)
      if (.not. allocated(error)) call check(error, 'KKT inertia: ' // &
         to_str(solver%num_negative_pivots) // ' negative pivots, expected ' // to_str(m), &
         solver%num_negative_pivots == m)
      call solver%free()
      if (allocated(error)) return
      call check_close(error, 'relative error after retries', norm2(b - x) / norm2(x), &
         0.0_dp, atol=1.0e-10_dp)
   contains
      subroutine put(row, col, v)
         integer(ip), intent(in) :: row, col
         real(dp), intent(in) :: v
         e = e + 1
         kkt%irn(e) = row
         kkt%jcn(e) = col
         kkt%val(e) = v
      end subroutine put
   end subroutine test_workspace_retry

   !> A matrix whose third row and column hold no entry at all is structurally singular:
   !> analysis or factorisation must fail with an allocated FFRF_NUMERIC_ERROR naming MUMPS and
   !> "singular", and a solve afterwards must be refused.
   subroutine test_error_structurally_singular(error)
      type(error_t), allocatable, intent(out) :: error
      type(mumps_solver_t) :: solver
      type(error_t), allocatable :: failure
      real(dp) :: b(4)
      call solver%init(MUMPS_SYM_INDEFINITE, error)
      if (allocated(error)) return
      call solver%analyse(4_ip, [1_ip, 1_ip, 2_ip, 4_ip], [1_ip, 2_ip, 2_ip, 4_ip], &
                          error=failure)
      if (.not. allocated(failure)) call solver%factorise([4.0_dp, 1.0_dp, 3.0_dp, 2.0_dp], &
                                                          failure)
      if (.not. allocated(failure)) then
         call solver%free()
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'structurally singular matrix: ' // &
            'expected an error, got none')
         return
      end if
      call report('message: ' // failure%message)
      call check(error, 'error code FFRF_NUMERIC_ERROR', failure%code == FFRF_NUMERIC_ERROR)
      if (.not. allocated(error)) call check(error, 'message names MUMPS and singular: ' // &
         failure%message, index(failure%message, 'MUMPS') > 0 .and. &
         index(failure%message, 'singular') > 0)
      if (allocated(error)) then
         call solver%free()
         return
      end if
      deallocate (failure)
      b = 1.0_dp
      call solver%solve(b, failure)
      call solver%free()
      call check(error, 'solve without factors is refused', allocated(failure))
   end subroutine test_error_structurally_singular

   !> Input errors: an index outside the matrix, a bad sym, a wrong number of values, a
   !> non-permutation, all FFRF_INPUT_ERROR with the offending value in the message.
   subroutine test_error_bad_input(error)
      type(error_t), allocatable, intent(out) :: error
      type(mumps_solver_t) :: solver
      type(error_t), allocatable :: failure
      call solver%init(3_ip, failure)
      call expect(failure, 'sym = 3', error)
      if (allocated(error)) return
      call solver%init(MUMPS_SYM_SPD, error)
      if (allocated(error)) return
      call solver%analyse(3_ip, [1_ip, 2_ip, 4_ip], [1_ip, 2_ip, 3_ip], error=failure)
      call expect(failure, '(4, 3)', error)
      if (allocated(error)) then
         call solver%free()
         return
      end if
      call solver%analyse(3_ip, [1_ip, 2_ip, 3_ip], [1_ip, 2_ip, 3_ip], [1_ip, 1_ip, 2_ip], &
                          failure)
      call expect(failure, 'not a permutation', error)
      if (allocated(error)) then
         call solver%free()
         return
      end if
      call solver%analyse(3_ip, [1_ip, 2_ip, 3_ip], [1_ip, 2_ip, 3_ip], error=error)
      if (allocated(error)) then
         call solver%free()
         return
      end if
      call solver%factorise([1.0_dp, 2.0_dp], failure)
      call expect(failure, '2 values given for a pattern of 3', error)
      call solver%free()
   end subroutine test_error_bad_input

   !> `error` set unless `failure` is an FFRF_INPUT_ERROR whose message contains `words`.
   subroutine expect(failure, words, error)
      type(error_t), allocatable, intent(inout) :: failure
      character(len=*), intent(in) :: words
      type(error_t), allocatable, intent(out) :: error
      if (.not. allocated(failure)) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'expected an error about "' // words // &
            '", got none')
         return
      end if
      if (failure%code /= FFRF_INPUT_ERROR .or. index(failure%message, words) == 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'expected an input error about "' // &
            words // '", got: ' // failure%message)
      end if
      deallocate (failure)
   end subroutine expect

   ! ---------------------------------------------------------------------------------------------

   !> 7-point Laplacian (6 on the diagonal, -1 to each grid neighbour, Dirichlet outside) on an
   !> nx x ny x nz grid, upper triangle.
   subroutine laplacian_3d(nx, ny, nz, A)
      integer, intent(in) :: nx, ny, nz
      type(coo_t), intent(out) :: A
      integer(ip) :: i, j, k, p, e
      A%n = nx * ny * nz
      allocate (A%irn(4 * A%n), A%jcn(4 * A%n), A%val(4 * A%n))
      e = 0
      do k = 1, nz
         do j = 1, ny
            do i = 1, nx
               p = i + nx * (j - 1) + nx * ny * (k - 1)
               call put(p, p, 6.0_dp)
               if (i < nx) call put(p, p + 1, -1.0_dp)
               if (j < ny) call put(p, p + nx, -1.0_dp)
               if (k < nz) call put(p, p + nx * ny, -1.0_dp)
            end do
         end do
      end do
      A%irn = A%irn(1:e)
      A%jcn = A%jcn(1:e)
      A%val = A%val(1:e)
   contains
      subroutine put(r, c, v)
         integer(ip), intent(in) :: r, c
         real(dp), intent(in) :: v
         e = e + 1
         A%irn(e) = r
         A%jcn(e) = c
         A%val(e) = v
      end subroutine put
   end subroutine laplacian_3d

   !> KKT matrix [A B^T; B 0]: B has m rows, row r touching every `stride`-th dof from r, with
   !> LCG values in (0.5, 1.5).
   subroutine append_constraints(A, m, stride, kkt)
      type(coo_t), intent(in) :: A
      integer(ip), intent(in) :: m, stride
      type(coo_t), intent(out) :: kkt
      integer(ip) :: r, j, e, count
      integer(i8) :: state
      state = 777_i8
      count = 0
      do r = 1, m
         count = count + (A%n - r) / stride + 1
      end do
      kkt%n = A%n + m
      allocate (kkt%irn(size(A%irn) + count), kkt%jcn(size(A%irn) + count), &
                kkt%val(size(A%irn) + count))
      e = size(A%irn)
      kkt%irn(1:e) = A%irn
      kkt%jcn(1:e) = A%jcn
      kkt%val(1:e) = A%val
      do r = 1, m
         do j = r, A%n, stride
            e = e + 1
            kkt%irn(e) = j
            kkt%jcn(e) = A%n + r
            kkt%val(e) = 0.5_dp + lcg(state)
         end do
      end do
   end subroutine append_constraints

   !> y = A x for a symmetric matrix stored as one triangle.
   function coo_symmetric_product(A, x) result(y)
      type(coo_t), intent(in) :: A
      real(dp), intent(in) :: x(:)
      real(dp), allocatable :: y(:)
      integer :: e
      allocate (y(A%n), source=0.0_dp)
      do e = 1, size(A%irn)
         y(A%irn(e)) = y(A%irn(e)) + A%val(e) * x(A%jcn(e))
         if (A%irn(e) /= A%jcn(e)) y(A%jcn(e)) = y(A%jcn(e)) + A%val(e) * x(A%irn(e))
      end do
   end function coo_symmetric_product

   !> Park-Miller generator, uniform in (0, 1).
   function lcg(state) result(u)
      integer(i8), intent(inout) :: state
      real(dp) :: u
      state = mod(16807_i8 * state, 2147483647_i8)
      u = real(state, dp) / 2147483647.0_dp
   end function lcg

end module test_la_mumps

program main_la_mumps
   use ffrf_testing, only: unittest_t, run_suite
   use test_la_mumps, only: collect_la_mumps
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_la_mumps(tests)
   call run_suite('test_la_mumps', tests)
end program main_la_mumps
