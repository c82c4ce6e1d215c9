!> A free-free body with its shift at or next to zero (issue 4, part 2): the modal pipeline
!> (ffrf_modes_modal_analysis: Tet10 beam_lc6 mesh, steel cylinder r = 10 mm, L = 200 mm, two
!> RBE3 end interfaces without RCs, 6 flexible modes + the six rigid ones) with shift_hz = 0
!> (automatic: -256.1 Hz, the reference), +1e-6, -1e-3, +-1 and +-10 Hz. Reference for the
!> flexible frequencies: the automatic-shift run (test_modes_beam checks that one against the
!> Timoshenko and torsion closed forms); for the rigid ones, 0 Hz.
!>
!> Since issue 22 the six rigid modes are not searched for: they come from the geometry and are
!> deflated exactly (theory.md 5.6), so every Ritz vector stays M-orthogonal to them whatever
!> the conditioning of K - sigma M near them.
!>
!> Measured (2 shared cores, Release): the automatic shift: rigid modes at <= 0.0013 Hz (their
!> Rayleigh quotients), flexible from 2244.88 Hz, residual 3.5e-11. +1e-6 and -1e-3 Hz: K - sigma
!> M is singular to round-off, MUMPS reports null pivots and the solver moves the shift once to
!> -(2 pi 139.6 Hz)^2 (1e-8 of max K_ii / M_ii; 2 or 3 factorisations, the SPD attempt for
!> sigma < 0 included): flexible frequencies equal to the reference to 4.9e-13, residual 3.6e-11.
!> +-1 Hz: no null pivot but K - sigma M has condition ~ lambda_max / |sigma| = 2e12; before the
!> deflation the Ritz vectors picked up rigid components (residuals 3e-5, the run refused), now
!> residual 3.5e-11 and frequencies to 6.1e-13. +-10 Hz: frequencies to 3.1e-13 (+10 Hz has the
!> six rigid modes below it: Sturm count 6).
!> Asserted: for every shift, the six rigid frequencies <= 1e-5 of the first flexible one, the
!> flexible frequencies equal to the reference's to 1e-10 (round-off eps lambda_max / lambda_1 of
!> the Rayleigh quotients, toolchain.md pitfall 9), the Sturm count 6 for a positive shift used
!> and 0 for a negative one, and a moved shift (negative, more than one factorisation) for
!> +1e-6 and -1e-3.
module test_stability_free_body
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: logger_t, stage_times_t, LOG_QUIET
   use ffrf_input_interface, only: interface_input_t
   use ffrf_input_body, only: body_input_t
   use ffrf_input_modes, only: modes_input_t
   use ffrf_modes_modal_analysis, only: body_modes_t
   use ffrf_app_body_modes, only: compute_input_body_modes
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, report, test_mesh_dir
   implicit none
   private
   public :: collect_stability_free_body

contains

   !> The suite.
   subroutine collect_stability_free_body(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [new_unittest('free_free_beam_shift_next_to_zero', test_free_beam)]
   end subroutine collect_stability_free_body

   !> Module header.
   subroutine test_free_beam(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: shifts(7) = [0.0_dp, 1.0e-6_dp, -1.0e-3_dp, 1.0_dp, -1.0_dp, &
         10.0_dp, -10.0_dp]
      type(body_modes_t) :: body
      real(dp), allocatable :: reference(:)
      type(error_t), allocatable :: failure
      character(len=:), allocatable :: label
      integer :: i
      do i = 1, size(shifts)
         label = 'shift_hz = ' // to_str(shifts(i))
         call beam_modes(shifts(i), body, failure)
         if (allocated(failure)) then
            call move_alloc(failure, error)
            error%message = label // ': ' // error%message
            return
         end if
         if (i == 1) reference = body%frequency_hz
         call report(label // ': shift used ' // to_str(sign(sqrt(abs(body%eigen%shift)), &
            body%eigen%shift) / (2.0_dp * acos(-1.0_dp)), 5) // ' Hz, ' // &
            to_str(body%eigen%num_factorisations) // ' factorisation(s); rigid <= ' // &
            to_str(maxval(abs(body%rigid_frequency_hz)), 2) // ' Hz; flexible ' // &
            to_str(body%frequency_hz(1), 10) // ' .. ' // to_str(body%frequency_hz(6), 10) // &
            ' Hz, max rel. difference ' // to_str(maxval(abs(body%frequency_hz - &
            reference) / reference), 2) // ', residual ' // &
            to_str(maxval(body%residual), 2) // ', Sturm ' // to_str(body%eigen%num_below_shift) &
            // ', ' // to_str(body%eigen%time_total, 3) // ' s')
         call check_close(error, label // ': largest rigid frequency (Hz)', &
            maxval(abs(body%rigid_frequency_hz)), 0.0_dp, atol=1.0e-5_dp * body%frequency_hz(1))
         if (allocated(error)) return
         call check_close(error, label // ': flexible frequencies vs the automatic shift, max ' &
            // 'relative difference', maxval(abs(body%frequency_hz - reference) / &
            reference), 0.0_dp, atol=1.0e-10_dp)
         if (allocated(error)) return
         call check(error, label // ': Sturm count ' // to_str(body%eigen%num_below_shift) // &
            ' at the shift used', body%eigen%num_below_shift == &
            merge(6, 0, body%eigen%shift > 0.0_dp))
         if (allocated(error)) return
         if (i == 2 .or. i == 3) then
            call check(error, label // ': the shift is moved below 0 (null pivots)', &
               body%eigen%shift < 0.0_dp .and. body%eigen%num_factorisations > 1)
            if (allocated(error)) return
         end if
      end do
   end subroutine test_free_beam

   !> Free-free modes of the beam_lc6 mesh (two RBE3 ends, no RC), 6 flexible modes.
   subroutine beam_modes(shift_hz, body, error)
      real(dp), intent(in) :: shift_hz
      type(body_modes_t), intent(out) :: body
      type(error_t), allocatable, intent(out) :: error
      type(body_input_t) :: beam
      type(interface_input_t) :: ends(2)
      type(modes_input_t) :: modes
      type(logger_t) :: log
      type(stage_times_t) :: times
      beam = body_input_t('beam', 'beam_lc6.msh', '', 210.0e9_dp, 0.3_dp, 7850.0_dp)
      beam%volumes(1) = 'beam'
      ends(1)%body = 'beam'
      ends(1)%name = 'end0'
      ends(2)%body = 'beam'
      ends(2)%name = 'end1'
      modes%num_modes = 6
      modes%shift_hz = shift_hz
      log%level = LOG_QUIET
      call compute_input_body_modes(beam, ends, modes, test_mesh_dir(), log, times, body, error)
   end subroutine beam_modes

end module test_stability_free_body

program main_stability_free_body
   use ffrf_testing, only: unittest_t, run_suite
   use test_stability_free_body, only: collect_stability_free_body
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_stability_free_body(tests)
   call run_suite('stability_free_body', tests)
end program main_stability_free_body
