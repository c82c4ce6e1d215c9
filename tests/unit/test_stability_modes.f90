!> Shift-invert Lanczos (ffrf_modes_shift_invert: ARPACK mode 3 on one MUMPS factorisation) with
!> the shift where the factorisation breaks (issue 4, part 2): on or next to an eigenvalue (MUMPS
!> null or tiny pivots) and at or next to zero for a free-free system. References: the closed-form
!> spectra of spring-mass chains (k = 1.7e4 N/m, m = 0.3 kg, as test_modes_shift_invert):
!> fixed-fixed, n masses: lambda_j = 4 k/m sin^2(j pi / (2 (n + 1)));
!> free-free, n masses: lambda_j = 4 k/m sin^2((j - 1) pi / (2 n)), lambda_1 = 0 (rigid).
!> The outcome asserted everywhere is "correct or a clear error, never garbage": every returned
!> eigenvalue within 1e-10 of the closed form (relative), residuals of the flexible pairs within
!> 1e-10 (round-off eps lambda_max / lambda, toolchain.md pitfall 9), and the Sturm count
!> consistent with the shift actually used.
module test_stability_modes
   use ffrf_core_kinds, only: dp, ip, pi
   use ffrf_core_error, only: error_t
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: logger_t, LOG_QUIET
   use ffrf_la_sparse, only: csr_t, csr_from_coo
   use ffrf_modes_shift_invert, only: eigen_options_t, eigen_result_t, solve_shift_invert
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, report
   use ffrf_test_spring_chain, only: chain, no_constraints, spring, mass
   implicit none
   private
   public :: collect_stability_modes

   !> Chain spring stiffness (N/m) and point mass (kg)
   !> Eigenvalue and residual tolerances (module header)
   real(dp), parameter :: rtol_lambda = 1.0e-10_dp, max_residual = 1.0e-10_dp

contains

   !> The suite.
   subroutine collect_stability_modes(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [new_unittest('shift_next_to_an_eigenvalue', test_near_eigenvalue), &
         new_unittest('shift_next_to_an_eigenvalue_constrained', test_near_eigenvalue_kkt), &
         new_unittest('free_free_shift_next_to_zero', test_free_free_near_zero)]
   end subroutine collect_stability_modes

   !> sigma = lambda_3 (1 + delta) on the fixed-fixed chain (n = 100, 6 modes), delta = +-1e-2,
   !> ..., +-1e-16 and 0 (test_modes_shift_invert has delta = 0 only). Measured: for |delta| >=
   !> 1e-11 MUMPS factorises K - sigma M with a tiny but accepted pivot (one factorisation, the
   !> shift kept) and shift-invert converges to the 6 nearest eigenvalues with relative errors
   !> <= 5e-15 and residuals <= 1.5e-13 however close the shift is (the huge 1/(lambda_3 -
   !> sigma) only speeds up lambda_3); for |delta| <= 1e-12 the pivot falls under the null-pivot
   !> threshold (1e-12 of the scaled matrix), the shift is moved once to lambda_3 (1 - 1e-4) and
   !> refactorised (two factorisations). Asserted for every delta: the closed-form eigenvalues to
   !> 1e-10, residuals <= 1e-10, and the Sturm count equal to the closed-form count below the
   !> shift used (for an unmoved shift within 1e-13 of lambda_3, round-off eps lambda_max / lambda_3
   !> = 1e-13 decides the side, and either count is accepted); delta = 1e-8 keeps the shift and
   !> delta = 0, 1e-15 move it (the two sides of the detection).
   subroutine test_near_eigenvalue(error)
      type(error_t), allocatable, intent(out) :: error
      integer(ip), parameter :: n = 100, nev = 6
      type(csr_t) :: K, M, C
      real(dp) :: exact(nev)
      integer :: j
      call chain(n, .true., K, M, error)
      if (allocated(error)) return
      call no_constraints(n, C)
      exact = [(4.0_dp * spring / mass * sin(j * pi / (2.0_dp * (n + 1)))**2, j=1, nev)]
      call shift_sweep('fixed-fixed chain', K, M, C, exact, error)
   end subroutine test_near_eigenvalue

   !> The same fixed-fixed chain written as a free chain of n + 2 masses whose end masses are held
   !> by two constraint rows (C x = 0: x_1 = 0, x_{n+2} = 0), so that the shifted matrix is the
   !> symmetric indefinite KKT matrix [[K - sigma M, C^T], [C, 0]] (MUMPS SYM = 2) with the same
   !> closed-form spectrum; the same sweep and assertions as test_near_eigenvalue (the Sturm
   !> count subtracts the 2 constraint rows from the negative pivots). Measured: as without
   !> constraints, eigenvalues to <= 5e-15 and residuals <= 2e-13 for every delta.
   subroutine test_near_eigenvalue_kkt(error)
      type(error_t), allocatable, intent(out) :: error
      integer(ip), parameter :: n = 100, nev = 6
      type(csr_t) :: K, M, C
      real(dp) :: exact(nev)
      integer :: j
      call chain(n + 2, .false., K, M, error)
      if (allocated(error)) return
      call csr_from_coo(2_ip, n + 2, [1_ip, 2_ip], [1_ip, n + 2], [1.0_dp, 1.0_dp], C, error)
      if (allocated(error)) return
      exact = [(4.0_dp * spring / mass * sin(j * pi / (2.0_dp * (n + 1)))**2, j=1, nev)]
      call shift_sweep('constrained chain (KKT)', K, M, C, exact, error)
   end subroutine test_near_eigenvalue_kkt

   !> The sweep of test_near_eigenvalue on (K, M, C) with closed-form eigenvalues `exact`.
   subroutine shift_sweep(label, K, M, C, exact, error)
      character(len=*), intent(in) :: label
      type(csr_t), intent(in) :: K, M, C
      real(dp), intent(in) :: exact(:)
      type(error_t), allocatable, intent(out) :: error
      type(eigen_result_t) :: result
      real(dp) :: delta, sigma
      integer :: e, s, j, below
      logical :: moved, ambiguous
      character(len=:), allocatable :: where_shift
      do s = -1, 1, 2
         do e = 2, 17
            delta = s * 10.0_dp**(-e)
            if (e == 17) delta = 0.0_dp
            sigma = exact(3) * (1.0_dp + delta)
            call solve(K, M, C, eigen_options_t(num_modes=size(exact, kind=ip), sigma=sigma), &
               result, error)
            if (allocated(error)) then
               error%message = label // ', delta = ' // to_str(delta, 2) // ': ' // error%message
               return
            end if
            moved = result%shift /= sigma
            below = count(exact < result%shift)
            ambiguous = .not. moved .and. abs(delta) < 1.0e-13_dp
            where_shift = 'kept'
            if (moved) where_shift = 'moved to lambda_3 (1 ' // to_str(result%shift / &
               exact(3) - 1.0_dp, 2) // ')'
            call report(label // ', delta = ' // to_str(delta, 2) // ': ' // &
               to_str(result%num_factorisations) // ' factorisation(s), shift ' // where_shift &
               // ', max rel. error ' // to_str(maxval(abs(result%eigenvalues - exact) / exact), &
               2) // ', residual ' // to_str(maxval(result%residuals), 2) // ', Sturm ' // &
               to_str(result%num_below_shift) // ' (closed form ' // to_str(below) // ')')
            do j = 1, size(exact)
               call check_close(error, label // ', delta = ' // to_str(delta, 2) // ': lambda_' &
                  // to_str(j), result%eigenvalues(j), exact(j), rtol=rtol_lambda)
               if (allocated(error)) return
            end do
            call check_close(error, label // ', delta = ' // to_str(delta, 2) // &
               ': max residual', maxval(result%residuals), 0.0_dp, atol=max_residual)
            if (allocated(error)) return
            call check(error, label // ', delta = ' // to_str(delta, 2) // ': Sturm count ' // &
               to_str(result%num_below_shift) // ', closed form ' // to_str(below) // &
               ' below the shift used', result%num_below_shift == below .or. (ambiguous .and. &
               abs(result%num_below_shift - 2.5_dp) < 1.0_dp))
            if (allocated(error)) return
            call check(error, label // ', delta = ' // to_str(delta, 2) // ': a moved shift ' // &
               'costs one more factorisation and lies below lambda_3', (.not. moved .and. &
               result%num_factorisations == 1) .or. (moved .and. &
               result%num_factorisations == 2 .and. result%shift < exact(3)))
            if (allocated(error)) return
            if (e == 8) then
               call check(error, label // ', delta = ' // to_str(delta, 2) // ': shift kept', &
                  .not. moved)
               if (allocated(error)) return
            end if
            if (e >= 15) then
               call check(error, label // ', delta = ' // to_str(delta, 2) // ': shift moved', &
                  moved)
               if (allocated(error)) return
            end if
         end do
      end do
   end subroutine shift_sweep

   !> Free-free chain (n = 300, 6 modes: the rigid one and 5 flexible) with sigma = +-10^-k
   !> lambda_2 (k = 1 .. 12) and sigma = 0 (test_modes_shift_invert uses -lambda_2 / 10 only).
   !> Measured: sigma = 0 and 0 < sigma <= 1e-10 lambda_2 hit a null pivot and the shift moves
   !> once to -1.8e-4 lambda_2 (1e-8 of max K_ii / M_ii); otherwise the shift is kept (SPD
   !> factorisation for sigma < 0, symmetric indefinite for sigma > 0 with the rigid mode below
   !> it). In every case: the rigid eigenvalue |lambda_1| <= 1e-9 lambda_2 (measured <= 1.4e-26),
   !> the flexible ones within 1e-10 of the closed form (measured <= 1.1e-14), their residuals
   !> <= 1e-10 (measured <= 6.5e-12), the Sturm count 1 for a positive shift used, 0 for a
   !> negative one. The rigid mode's own residual, ||K x - lambda M x|| / max(||K x||, |sigma|
   !> ||M x||), is eps lambda_max / |sigma| for a zero mode and reads 3e-11 .. 1 as |sigma| goes
   !> from 0.1 to 1e-12 lambda_2: reported, not asserted (the pair itself is exact; the modal
   !> pipeline skips rigid modes' residuals).
   subroutine test_free_free_near_zero(error)
      type(error_t), allocatable, intent(out) :: error
      integer(ip), parameter :: n = 300, nev = 6
      type(csr_t) :: K, M, C
      type(eigen_result_t) :: result
      real(dp) :: exact(nev), sigma
      integer :: j, e
      character(len=:), allocatable :: label
      call chain(n, .false., K, M, error)
      if (allocated(error)) return
      call no_constraints(n, C)
      exact = [(4.0_dp * spring / mass * sin((j - 1) * pi / (2.0_dp * n))**2, j=1, nev)]
      do e = -12, 12
         sigma = 0.0_dp
         if (e /= 0) sigma = sign(10.0_dp**(-abs(e)), real(e, dp)) * exact(2)
         label = 'free-free chain, sigma = ' // to_str(sigma / exact(2), 2) // ' lambda_2'
         call solve(K, M, C, eigen_options_t(num_modes=nev, sigma=sigma), result, error)
         if (allocated(error)) then
            error%message = label // ': ' // error%message
            return
         end if
         call report(label // ': shift used ' // to_str(result%shift / exact(2), 3) // &
            ' lambda_2 (' // to_str(result%num_factorisations) // ' factorisation(s), SYM ' // &
            to_str(result%sym) // '), lambda_1 / lambda_2 ' // &
            to_str(result%eigenvalues(1) / exact(2), 2) // ', flexible: max rel. error ' // &
            to_str(maxval(abs(result%eigenvalues(2:) - exact(2:)) / exact(2:)), 2) // &
            ', residual ' // to_str(maxval(result%residuals(2:)), 2) // '; rigid residual ' // &
            to_str(result%residuals(1), 2) // ', Sturm ' // to_str(result%num_below_shift))
         call check_close(error, label // ': rigid lambda_1 / lambda_2', &
            result%eigenvalues(1) / exact(2), 0.0_dp, atol=1.0e-9_dp)
         if (allocated(error)) return
         do j = 2, nev
            call check_close(error, label // ': lambda_' // to_str(j), result%eigenvalues(j), &
               exact(j), rtol=rtol_lambda)
            if (allocated(error)) return
         end do
         call check_close(error, label // ': max residual of the flexible pairs', &
            maxval(result%residuals(2:)), 0.0_dp, atol=max_residual)
         if (allocated(error)) return
         call check(error, label // ': Sturm count ' // to_str(result%num_below_shift) // &
            ' at the shift used ' // to_str(result%shift), result%num_below_shift == &
            merge(1, 0, result%shift > 0.0_dp))
         if (allocated(error)) return
      end do
   end subroutine test_free_free_near_zero

   ! ----------------------------------------------------------------------------------------------

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

end module test_stability_modes

program main_stability_modes
   use ffrf_testing, only: unittest_t, run_suite
   use test_stability_modes, only: collect_stability_modes
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_stability_modes(tests)
   call run_suite('stability_modes', tests)
end program main_stability_modes
