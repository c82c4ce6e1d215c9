!> Tests of ffrf_modes_shift_invert (shift-invert Lanczos on MUMPS, with constraints C x = 0).
!> References: the closed-form spectra of spring-mass chains, and for constrained problems a
!> dense null-space solution (Z = null(C) from LAPACK dgesvd, dsygv on Z^T K Z, Z^T M Z).
!> Tolerances: eigenvalues 1e-10 relative (round-off in the Rayleigh quotient is about
!> eps * lambda_max / lambda, below 1e-11 for these sizes); residuals 1e-10 (same bound,
!> toolchain.md pitfall 9); M-orthonormality 1e-12 (Lanczos with full reorthogonalisation keeps
!> it near 1e-14 after normalisation).
module test_modes_shift_invert
   use ffrf_core_kinds, only: dp, ip, i8, pi
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: logger_t, LOG_QUIET
   use ffrf_la_sparse, only: csr_t, csr_from_coo, csr_to_dense, csr_matvec
   use ffrf_la_lapack, only: dgesvd, dsygv, dgemm
   use ffrf_modes_shift_invert, only: eigen_options_t, eigen_result_t, solve_shift_invert
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, report
   use ffrf_test_spring_chain, only: chain, no_constraints, spring, mass
   implicit none
   private
   public :: collect_modes_shift_invert

   real(dp), parameter :: rtol_lambda = 1.0e-10_dp, max_residual = 1.0e-10_dp, &
                          max_orthonormality = 1.0e-12_dp

contains

   subroutine collect_modes_shift_invert(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [ &
         new_unittest('fixed_fixed_chain', test_fixed_fixed_chain), &
         new_unittest('free_free_chain', test_free_free_chain), &
         new_unittest('constrained_vs_dense', test_constrained_vs_dense), &
         new_unittest('sturm_count', test_sturm_count), &
         new_unittest('shift_on_eigenvalue', test_shift_on_eigenvalue), &
         new_unittest('deterministic', test_deterministic), &
         new_unittest('error_not_converged', test_error_not_converged), &
         new_unittest('error_dependent_constraints', test_error_dependent_constraints), &
         new_unittest('error_bad_input', test_error_bad_input), &
         new_unittest('block_fixed_fixed_chain', test_block_fixed_fixed_chain), &
         new_unittest('block_constrained_vs_dense', test_block_constrained_vs_dense), &
         new_unittest('block_deterministic', test_block_deterministic), &
         new_unittest('block_error_too_small', test_block_error_too_small)]
   end subroutine collect_modes_shift_invert

   !> Fixed-fixed chain of n = 300 masses m and n + 1 springs k: lambda_j = 4 k/m
   !> sin^2(j pi / (2 (n+1))). Lowest 10 with sigma = 0 (symmetric indefinite path, SYM = 2) and
   !> with sigma = -lambda_1 / 2 (K - sigma M positive definite, SPD path, SYM = 1).
   subroutine test_fixed_fixed_chain(error)
      type(error_t), allocatable, intent(out) :: error
      integer(ip), parameter :: n = 300, nev = 10
      type(csr_t) :: K, M, C
      type(eigen_result_t) :: result
      real(dp) :: exact(nev), sigma(2)
      integer(ip) :: j, pass, expected_sym(2)
      call chain(n, .true., K, M, error)
      if (allocated(error)) return
      call no_constraints(n, C)
      exact = [(4.0_dp * spring / mass * sin(j * pi / (2.0_dp * (n + 1)))**2, j=1, nev)]
      sigma = [0.0_dp, -0.5_dp * exact(1)]
      expected_sym = [2, 1]
      do pass = 1, 2
         call solve(K, M, C, eigen_options_t(num_modes=nev, sigma=sigma(pass)), result, error)
         if (allocated(error)) return
         call report('sigma = ' // to_str(sigma(pass)) // ': SYM ' // to_str(result%sym) // &
            ', max rel. error ' // to_str(maxval(abs(result%eigenvalues - exact) / exact), 3) &
            // ', max residual ' // to_str(maxval(result%residuals), 3) // ', orth. ' // &
            to_str(result%orthonormality_error, 3) // ', ' // to_str(result%num_solves) // &
            ' solves')
         call check(error, 'SYM ' // to_str(result%sym) // ' used, expected ' // &
            to_str(expected_sym(pass)), result%sym == expected_sym(pass))
         if (allocated(error)) return
         call check_spectrum(result, exact, error)
         if (allocated(error)) return
         call check(error, 'Sturm count 0 below sigma <= 0, got ' // &
            to_str(result%num_below_shift), result%num_below_shift == 0)
         if (allocated(error)) return
      end do
   end subroutine test_fixed_fixed_chain

   !> Free-free chain (n = 300 masses, n - 1 springs): lambda_j = 4 k/m sin^2((j-1) pi/(2 n)),
   !> j = 1 the rigid mode (0). sigma = -lambda_2 / 10 < 0 (a zero shift would be singular):
   !> |lambda_1| <= 1e-9 lambda_2 (round-off eps lambda_max ~ 4e-12 lambda_2), the others to
   !> 1e-10 relative. The rigid mode's residual is measured against |sigma| ||M x||.
   subroutine test_free_free_chain(error)
      type(error_t), allocatable, intent(out) :: error
      integer(ip), parameter :: n = 300, nev = 10
      type(csr_t) :: K, M, C
      type(eigen_result_t) :: result
      real(dp) :: exact(nev)
      integer(ip) :: j
      call chain(n, .false., K, M, error)
      if (allocated(error)) return
      call no_constraints(n, C)
      exact = [(4.0_dp * spring / mass * sin((j - 1) * pi / (2.0_dp * n))**2, j=1, nev)]
      call solve(K, M, C, eigen_options_t(num_modes=nev, sigma=-0.1_dp * exact(2)), result, &
                 error)
      if (allocated(error)) return
      call report('zero mode ' // to_str(result%eigenvalues(1), 3) // ' (lambda_2 = ' // &
         to_str(exact(2), 6) // '), max residual ' // to_str(maxval(result%residuals), 3))
      call check_close(error, 'rigid-mode eigenvalue / lambda_2', &
         result%eigenvalues(1) / exact(2), 0.0_dp, atol=1.0e-9_dp)
      if (allocated(error)) return
      do j = 2, nev
         call check_close(error, 'free-free lambda_' // to_str(j), result%eigenvalues(j), &
            exact(j), rtol=rtol_lambda)
         if (allocated(error)) return
      end do
      call check_close(error, 'max residual', maxval(result%residuals), 0.0_dp, &
         atol=max_residual)
      if (allocated(error)) return
      call check_close(error, 'M-orthonormality', result%orthonormality_error, 0.0_dp, &
         atol=max_orthonormality)
   end subroutine test_free_free_chain

   !> Free (Neumann) 2D grid Laplacian 15 x 14 (n = 210) with a non-uniform diagonal mass and
   !> three constraint rows: sum m_i x_i = 0 (removes the constant rigid mode) and two rows on
   !> every fourth dof with LCG values. The 8 lowest against the dense null-space reference to
   !> 1e-10; residuals, M-orthonormality and |C x| checked.
   subroutine test_constrained_vs_dense(error)
      type(error_t), allocatable, intent(out) :: error
      integer(ip), parameter :: nev = 8
      type(csr_t) :: K, M, C
      type(eigen_result_t) :: result
      real(dp), allocatable :: reference(:), cx(:)
      real(dp) :: c_norm
      integer(ip) :: j
      call constrained_problem(K, M, C, error)
      if (allocated(error)) return
      call dense_reference(K, M, C, reference, error)
      if (allocated(error)) return
      call solve(K, M, C, eigen_options_t(num_modes=nev, sigma=0.0_dp), result, error)
      if (allocated(error)) return
      call report('constrained: max rel. error ' // to_str(maxval(abs(result%eigenvalues - &
         reference(1:nev)) / reference(1:nev)), 3) // ', max residual ' // &
         to_str(maxval(result%residuals), 3) // ', orth. ' // &
         to_str(result%orthonormality_error, 3) // ', Sturm ' // &
         to_str(result%num_below_shift))
      call check_spectrum(result, reference(1:nev), error)
      if (allocated(error)) return
      allocate (cx(C%num_rows))
      c_norm = maxval(abs(C%val))
      do j = 1, nev
         call csr_matvec(C, result%vectors(:, j), cx)
         call check_close(error, '|C x_' // to_str(j) // '| / (|C| |x|)', &
            norm2(cx) / (c_norm * norm2(result%vectors(:, j))), 0.0_dp, atol=1.0e-12_dp)
         if (allocated(error)) return
      end do
   end subroutine test_constrained_vs_dense

   !> sigma halfway between the 5th and 6th eigenvalue of the constrained problem: the Sturm
   !> count (KKT negative pivots - 3 constraints) must be 5, the dense reference's count below
   !> sigma; the 8 eigenvalues returned are the 8 dense ones nearest sigma.
   subroutine test_sturm_count(error)
      type(error_t), allocatable, intent(out) :: error
      integer(ip), parameter :: nev = 8
      type(csr_t) :: K, M, C
      type(eigen_result_t) :: result
      real(dp), allocatable :: reference(:), nearest(:)
      real(dp) :: sigma
      call constrained_problem(K, M, C, error)
      if (allocated(error)) return
      call dense_reference(K, M, C, reference, error)
      if (allocated(error)) return
      sigma = 0.5_dp * (reference(5) + reference(6))
      call solve(K, M, C, eigen_options_t(num_modes=nev, sigma=sigma), result, error)
      if (allocated(error)) return
      nearest = nearest_sorted(reference, sigma, nev)
      call report('sigma = ' // to_str(sigma) // ': Sturm ' // to_str(result%num_below_shift) &
         // ' (dense ' // to_str(count(reference < sigma)) // '), negative pivots ' // &
         to_str(result%num_negative_pivots) // ', found below ' // &
         to_str(result%num_found_below_shift))
      call check(error, 'Sturm count ' // to_str(result%num_below_shift) // ' = dense count ' &
         // to_str(count(reference < sigma)), &
         result%num_below_shift == count(reference < sigma) .and. result%num_below_shift == 5)
      if (allocated(error)) return
      call check(error, 'KKT negative pivots = 5 + 3 constraints', &
         result%num_negative_pivots == 8)
      if (allocated(error)) return
      call check_spectrum(result, nearest, error)
   end subroutine test_sturm_count

   !> sigma exactly the closed-form lambda_3 of the fixed-fixed chain (n = 100): K - sigma M is
   !> singular to round-off, MUMPS reports a null pivot, the solver moves sigma once (2
   !> factorisations, result%shift < sigma) and the 6 modes nearest lambda_3 (lambda_1..6)
   !> still match the closed form to 1e-10.
   subroutine test_shift_on_eigenvalue(error)
      type(error_t), allocatable, intent(out) :: error
      integer(ip), parameter :: n = 100, nev = 6
      type(csr_t) :: K, M, C
      type(eigen_result_t) :: result
      real(dp) :: exact(nev)
      integer(ip) :: j
      call chain(n, .true., K, M, error)
      if (allocated(error)) return
      call no_constraints(n, C)
      exact = [(4.0_dp * spring / mass * sin(j * pi / (2.0_dp * (n + 1)))**2, j=1, nev)]
      call solve(K, M, C, eigen_options_t(num_modes=nev, sigma=exact(3)), result, error)
      if (allocated(error)) return
      call report('sigma = lambda_3 = ' // to_str(exact(3), 12) // ' moved to ' // &
         to_str(result%shift, 12) // ', ' // to_str(result%num_factorisations) // &
         ' factorisations, Sturm ' // to_str(result%num_below_shift))
      call check(error, 'shift moved below lambda_3 after a null pivot (' // &
         to_str(result%num_factorisations) // ' factorisations)', &
         result%shift < exact(3) .and. result%num_factorisations == 2)
      if (allocated(error)) return
      call check(error, 'Sturm count at the moved shift is 2', result%num_below_shift == 2)
      if (allocated(error)) return
      call check_spectrum(result, exact, error)
   end subroutine test_shift_on_eigenvalue

   !> Two identical runs (constrained problem, sigma between modes) give bitwise-identical
   !> eigenvalues and vectors: fixed start vector, deterministic METIS and sequential MUMPS.
   subroutine test_deterministic(error)
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: K, M, C
      type(eigen_result_t) :: first, second
      type(eigen_options_t) :: options
      call constrained_problem(K, M, C, error)
      if (allocated(error)) return
      options = eigen_options_t(num_modes=6, sigma=1.0_dp)
      call solve(K, M, C, options, first, error)
      if (allocated(error)) return
      call solve(K, M, C, options, second, error)
      if (allocated(error)) return
      call check(error, 'eigenvalues bitwise identical', &
         all(first%eigenvalues == second%eigenvalues))
      if (allocated(error)) return
      call check(error, 'eigenvectors bitwise identical', all(first%vectors == second%vectors))
   end subroutine test_deterministic

   !> One restart with a tiny basis (ncv = num_modes + 1) in the middle of the spectrum cannot
   !> converge 10 modes: an FFRF_NUMERIC_ERROR naming max_iterations and ncv, never a partial
   !> result.
   subroutine test_error_not_converged(error)
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: K, M, C
      type(eigen_result_t) :: result
      type(error_t), allocatable :: failure
      call constrained_problem(K, M, C, error)
      if (allocated(error)) return
      call solve(K, M, C, eigen_options_t(num_modes=10, sigma=3.0_dp, ncv=11, &
                                          max_iterations=1), result, failure)
      if (.not. allocated(failure)) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'expected a convergence error, got ' // &
            to_str(result%num_modes) // ' modes')
         return
      end if
      call report('message: ' // failure%message)
      call check(error, 'message names max_iterations and ncv: ' // failure%message, &
         failure%code == FFRF_NUMERIC_ERROR .and. index(failure%message, 'max_iterations') > 0 &
         .and. index(failure%message, 'ncv') > 0)
   end subroutine test_error_not_converged

   !> Two equal constraint rows make the KKT matrix singular for every sigma: after the one
   !> shift retry, an error that names the dependent constraint rows.
   subroutine test_error_dependent_constraints(error)
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: K, M, C
      type(eigen_result_t) :: result
      type(error_t), allocatable :: failure
      integer(ip), parameter :: n = 50
      integer(ip) :: j
      call chain(n, .true., K, M, error)
      if (allocated(error)) return
      call csr_from_coo(2_ip, n, [1_ip, 1_ip, 2_ip, 2_ip], [3_ip, 7_ip, 3_ip, 7_ip], &
                        [1.0_dp, -2.0_dp, 1.0_dp, -2.0_dp], C, error)
      if (allocated(error)) return
      call solve(K, M, C, eigen_options_t(num_modes=4, sigma=0.0_dp), result, failure)
      if (.not. allocated(failure)) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'expected a singular-KKT error, got ' // &
            to_str(result%num_modes) // ' modes')
         return
      end if
      call report('message: ' // failure%message)
      j = index(failure%message, 'linearly dependent')
      call check(error, 'message names dependent constraint rows: ' // failure%message, &
         failure%code == FFRF_NUMERIC_ERROR .and. j > 0)
   end subroutine test_error_dependent_constraints

   !> Input errors: too many modes for the constrained dimension, a zero constraint row, K and
   !> M of different sizes; all FFRF_INPUT_ERROR with the offending value.
   subroutine test_error_bad_input(error)
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: K, M, C, K_small, M_small
      type(eigen_result_t) :: result
      type(error_t), allocatable :: failure
      call chain(20_ip, .true., K, M, error)
      if (allocated(error)) return
      call chain(19_ip, .true., K_small, M_small, error)
      if (allocated(error)) return
      call csr_from_coo(2_ip, 20_ip, [1_ip, 2_ip], [1_ip, 2_ip], [1.0_dp, 1.0_dp], C, error)
      if (allocated(error)) return
      call solve(K, M, C, eigen_options_t(num_modes=18, sigma=0.0_dp), result, failure)
      call expect(failure, 'num_modes = 18 must lie in 1 .. 17', error)
      if (allocated(error)) return
      call csr_from_coo(2_ip, 20_ip, [1_ip, 2_ip], [1_ip, 2_ip], [1.0_dp, 0.0_dp], C, error)
      if (allocated(error)) return
      call solve(K, M, C, eigen_options_t(num_modes=3, sigma=0.0_dp), result, failure)
      call expect(failure, 'constraint row 2 of 2 is zero', error)
      if (allocated(error)) return
      call no_constraints(20_ip, C)
      call solve(K, M_small, C, eigen_options_t(num_modes=3, sigma=0.0_dp), result, failure)
      call expect(failure, '19 x 19', error)
   end subroutine test_error_bad_input

   ! --- Block shift-invert Lanczos (eigensolver = 'block'), the same references ----------------

   !> Fixed-fixed chain (n = 300) with the block method: the lowest 10 against the closed form
   !> (1e-10), at sigma = 0 (KKT indefinite path) and sigma = -lambda_1 / 2 (SPD path); the
   !> same bounds on residuals and M-orthonormality as ARPACK's (tolerance = machine epsilon).
   subroutine test_block_fixed_fixed_chain(error)
      type(error_t), allocatable, intent(out) :: error
      integer(ip), parameter :: n = 300, nev = 10
      type(csr_t) :: K, M, C
      type(eigen_result_t) :: result
      real(dp) :: exact(nev), sigma(2)
      integer(ip) :: j, pass
      call chain(n, .true., K, M, error)
      if (allocated(error)) return
      call no_constraints(n, C)
      exact = [(4.0_dp * spring / mass * sin(j * pi / (2.0_dp * (n + 1)))**2, j=1, nev)]
      sigma = [0.0_dp, -0.5_dp * exact(1)]
      do pass = 1, 2
         call solve(K, M, C, eigen_options_t(num_modes=nev, sigma=sigma(pass), &
            eigensolver='block'), result, error)
         if (allocated(error)) return
         call report('block, sigma = ' // to_str(sigma(pass)) // ': max rel. error ' // &
            to_str(maxval(abs(result%eigenvalues - exact) / exact), 3) // ', max residual ' // &
            to_str(maxval(result%residuals), 3) // ', orth. ' // &
            to_str(result%orthonormality_error, 3) // ', ' // &
            to_str(result%num_block_solves) // ' solves of ' // to_str(result%block_size))
         call check(error, 'block method used', result%eigensolver == 'block' .and. &
            result%block_size > 1 .and. result%num_block_solves > 0)
         if (allocated(error)) return
         call check_spectrum(result, exact, error)
         if (allocated(error)) return
      end do
   end subroutine test_block_fixed_fixed_chain

   !> Constrained grid problem with the block method: the 8 lowest against the dense null-space
   !> reference (1e-10), |C x| <= 1e-12; and with sigma between the 5th and 6th eigenvalue the 8
   !> nearest sigma on both sides (Ritz values of either sign, ordered by |theta|).
   subroutine test_block_constrained_vs_dense(error)
      type(error_t), allocatable, intent(out) :: error
      integer(ip), parameter :: nev = 8
      type(csr_t) :: K, M, C
      type(eigen_result_t) :: result
      real(dp), allocatable :: reference(:), cx(:)
      real(dp) :: sigma
      integer(ip) :: j
      call constrained_problem(K, M, C, error)
      if (allocated(error)) return
      call dense_reference(K, M, C, reference, error)
      if (allocated(error)) return
      call solve(K, M, C, eigen_options_t(num_modes=nev, sigma=0.0_dp, eigensolver='block'), &
         result, error)
      if (allocated(error)) return
      call report('block, constrained: max rel. error ' // to_str(maxval(abs( &
         result%eigenvalues - reference(1:nev)) / reference(1:nev)), 3) // ', max residual ' &
         // to_str(maxval(result%residuals), 3) // ', ' // to_str(result%num_block_solves) // &
         ' solves')
      call check_spectrum(result, reference(1:nev), error)
      if (allocated(error)) return
      allocate (cx(C%num_rows))
      do j = 1, nev
         call csr_matvec(C, result%vectors(:, j), cx)
         call check_close(error, '|C x_' // to_str(j) // '| / (|C| |x|)', norm2(cx) / &
            (maxval(abs(C%val)) * norm2(result%vectors(:, j))), 0.0_dp, atol=1.0e-12_dp)
         if (allocated(error)) return
      end do
      sigma = 0.5_dp * (reference(5) + reference(6))
      call solve(K, M, C, eigen_options_t(num_modes=nev, sigma=sigma, eigensolver='block'), &
         result, error)
      if (allocated(error)) return
      call check_spectrum(result, nearest_sorted(reference, sigma, nev), error)
   end subroutine test_block_constrained_vs_dense

   !> The block method twice on the same problem: bitwise-identical eigenpairs (fixed start
   !> block, deterministic METIS and MUMPS).
   subroutine test_block_deterministic(error)
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: K, M, C
      type(eigen_result_t) :: first, second
      type(eigen_options_t) :: options
      call constrained_problem(K, M, C, error)
      if (allocated(error)) return
      options = eigen_options_t(num_modes=6, sigma=1.0_dp, eigensolver='block')
      call solve(K, M, C, options, first, error)
      if (allocated(error)) return
      call solve(K, M, C, options, second, error)
      if (allocated(error)) return
      call check(error, 'eigenvalues bitwise identical', &
         all(first%eigenvalues == second%eigenvalues))
      if (allocated(error)) return
      call check(error, 'eigenvectors bitwise identical', all(first%vectors == second%vectors))
   end subroutine test_block_deterministic

   !> A block basis that does not fit the problem (chain of 20 masses, 10 modes: block 7 and a
   !> basis of 56 > n) is an input error naming the ARPACK alternative, never a crash.
   subroutine test_block_error_too_small(error)
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: K, M, C
      type(eigen_result_t) :: result
      type(error_t), allocatable :: failure
      call chain(20_ip, .true., K, M, error)
      if (allocated(error)) return
      call no_constraints(20_ip, C)
      call solve(K, M, C, eigen_options_t(num_modes=10, sigma=0.0_dp, eigensolver='block'), &
         result, failure)
      call expect(failure, 'eigensolver = ''arpack''', error)
   end subroutine test_block_error_too_small

   ! ---------------------------------------------------------------------------------------------

   !> solve_shift_invert with a quiet logger.
   subroutine solve(K, M, C, options, result, error)
      type(csr_t), intent(in) :: K, M, C
      type(eigen_options_t), intent(in) :: options
      type(eigen_result_t), intent(out) :: result
      type(error_t), allocatable, intent(out) :: error
      type(logger_t) :: log
      log%level = LOG_QUIET
      call solve_shift_invert(K, M, C, options, result, log, error)
   end subroutine solve

   !> Eigenvalues against `exact` (rtol 1e-10), residuals <= 1e-10, M-orthonormality <= 1e-12.
   subroutine check_spectrum(result, exact, error)
      type(eigen_result_t), intent(in) :: result
      real(dp), intent(in) :: exact(:)
      type(error_t), allocatable, intent(out) :: error
      integer :: j
      call check(error, to_str(result%num_modes) // ' modes returned, expected ' // &
         to_str(size(exact)), result%num_modes == size(exact) .and. &
         size(result%eigenvalues) == size(exact))
      if (allocated(error)) return
      do j = 1, size(exact)
         call check_close(error, 'lambda_' // to_str(j), result%eigenvalues(j), exact(j), &
            rtol=rtol_lambda)
         if (allocated(error)) return
      end do
      call check_close(error, 'max residual', maxval(result%residuals), 0.0_dp, &
         atol=max_residual)
      if (allocated(error)) return
      call check_close(error, 'M-orthonormality', result%orthonormality_error, 0.0_dp, &
         atol=max_orthonormality)
   end subroutine check_spectrum

   !> Neumann 5-point Laplacian on a 15 x 14 grid (stiffness 1), diagonal mass
   !> m_i = 1 + 0.5 sin(0.3 i), and C with three rows: m^T x = 0 and two LCG rows on every
   !> fourth dof.
   subroutine constrained_problem(K, M, C, error)
      type(csr_t), intent(out) :: K, M, C
      type(error_t), allocatable, intent(out) :: error
      integer(ip), parameter :: nx = 15, ny = 14, n = nx * ny
      integer(ip), allocatable :: rows(:), cols(:)
      real(dp), allocatable :: vals(:), masses(:)
      integer(ip) :: i, j, p, q, r
      integer(i8) :: state
      allocate (rows(0), cols(0), vals(0))
      do j = 1, ny
         do i = 1, nx
            p = i + nx * (j - 1)
            if (i < nx) call spring_pair(p, p + 1)
            if (j < ny) call spring_pair(p, p + nx)
         end do
      end do
      call csr_from_coo(n, n, rows, cols, vals, K, error)
      if (allocated(error)) return
      masses = [(1.0_dp + 0.5_dp * sin(0.3_dp * i), i=1, n)]
      call csr_from_coo(n, n, [(i, i=1, n)], [(i, i=1, n)], masses, M, error)
      if (allocated(error)) return
      rows = [(1_ip, i=1, n)]
      cols = [(i, i=1, n)]
      vals = masses
      state = 4242_i8
      do r = 2, 3
         do q = r, n, 4
            rows = [rows, r]
            cols = [cols, q]
            state = mod(16807_i8 * state, 2147483647_i8)
            vals = [vals, real(state, dp) / 2147483647.0_dp - 0.3_dp]
         end do
      end do
      call csr_from_coo(3_ip, n, rows, cols, vals, C, error)
   contains
      subroutine spring_pair(a, b)
         integer(ip), intent(in) :: a, b
         rows = [rows, a, b, a, b]
         cols = [cols, a, b, b, a]
         vals = [vals, 1.0_dp, 1.0_dp, -1.0_dp, -1.0_dp]
      end subroutine spring_pair
   end subroutine constrained_problem

   !> Dense reference: Z = the last n - rank columns of V from C = U S V^T (dgesvd), then the
   !> eigenvalues (ascending) of Z^T K Z phi = lambda Z^T M Z phi (dsygv).
   subroutine dense_reference(K, M, C, lambda, error)
      type(csr_t), intent(in) :: K, M, C
      real(dp), allocatable, intent(out) :: lambda(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: Kd(:, :), Md(:, :), Cd(:, :), s(:), u(:, :), vt(:, :), z(:, :), &
                               work(:), Kz(:, :), Mz(:, :), t(:, :)
      integer(ip) :: n, nc, nz, info
      n = K%num_rows
      nc = C%num_rows
      nz = n - nc
      call csr_to_dense(K, Kd)
      call csr_to_dense(M, Md)
      call csr_to_dense(C, Cd)
      allocate (s(nc), u(1, 1), vt(n, n), work(10 * n * n), t(n, nz), Kz(nz, nz), Mz(nz, nz))
      call dgesvd('N', 'A', nc, n, Cd, nc, s, u, 1, vt, n, work, size(work), info)
      if (info /= 0 .or. s(nc) < 1.0e-8_dp * s(1)) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'dense reference: dgesvd info = ' // &
            to_str(info) // ', or C rank deficient')
         return
      end if
      z = transpose(vt(nc + 1:n, :))
      call dgemm('N', 'N', n, nz, n, 1.0_dp, Kd, n, z, n, 0.0_dp, t, n)
      call dgemm('T', 'N', nz, nz, n, 1.0_dp, z, n, t, n, 0.0_dp, Kz, nz)
      call dgemm('N', 'N', n, nz, n, 1.0_dp, Md, n, z, n, 0.0_dp, t, n)
      call dgemm('T', 'N', nz, nz, n, 1.0_dp, z, n, t, n, 0.0_dp, Mz, nz)
      allocate (lambda(nz))
      call dsygv(1, 'N', 'U', nz, Kz, nz, Mz, nz, lambda, work, size(work), info)
      if (info /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'dense reference: dsygv info = ' // &
            to_str(info))
      end if
   end subroutine dense_reference

   !> The `count` values of `values` nearest `sigma`, ascending.
   function nearest_sorted(values, sigma, count) result(nearest)
      real(dp), intent(in) :: values(:), sigma
      integer(ip), intent(in) :: count
      real(dp), allocatable :: nearest(:)
      logical, allocatable :: taken(:)
      integer :: j, best
      allocate (taken(size(values)), source=.false.)
      do j = 1, count
         best = minloc(abs(values - sigma), dim=1, mask=.not. taken)
         taken(best) = .true.
      end do
      nearest = pack(values, taken)
   end function nearest_sorted

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

end module test_modes_shift_invert

program main_modes_shift_invert
   use ffrf_testing, only: unittest_t, run_suite
   use test_modes_shift_invert, only: collect_modes_shift_invert
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_modes_shift_invert(tests)
   call run_suite('test_modes_shift_invert', tests)
end program main_modes_shift_invert
