!> Constrained normal modes of the reference crank (lc = 8 mm Tet10 mesh, fixture crank_lc8) for
!> the three RC sets of Table 1 with RBE3 and RBE2 interfaces. References: the inertia (Sturm
!> count) of K - sigma M on the constrained space at sigma = (2 pi 100 Hz)^2, an independent
!> check that no rigid motion is left (a free rigid mode would sit at 0 Hz); eigen residuals and
!> M-orthonormality; the zero RC rows of the virtual-node shapes (the frame is attached to them);
!> and, for RBE2, the explicit null-space formulation (B2 = null(D) by LAPACK SVD) as a second
!> method for dropping the constrained virtual dofs (the RBE3 formulations are compared on the
!> smaller beam body in test_modes_beam: their explicit B2 is dense over each interface).
module test_modes_crank
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, add_context
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: logger_t, stage_times_t, LOG_QUIET
   use ffrf_input_interface, only: interface_input_t
   use ffrf_mpc_interface, only: MPC_RBE3
   use ffrf_mpc_rbe2, only: rbe2_matrix
   use ffrf_input_body, only: body_input_t
   use ffrf_input_modes, only: modes_input_t
   use ffrf_modes_modal_analysis, only: body_modes_t
   use ffrf_app_body_modes, only: compute_input_body_modes
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, test_mesh_dir, report
   implicit none
   private
   public :: collect_modes_crank

   !> Forbidden virtual-node dofs of B1, B2, B3 for RC sets 1-3 (Table 1 in scene.md's axes)
   character(len=*), parameter :: RC_SETS(3, 3) = reshape([character(len=20) :: &
      'Tx Ty Tz', '', 'Tx Ty Tz Rz', &
      'Tx Ty Tz', 'Tx', 'Tx Ty', &
      '', 'Tx Ty Tz Rx Ry Rz', ''], [3, 3])

contains

   subroutine collect_modes_crank(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [ &
         new_unittest('rc_sets_rbe3_no_rigid_mode', test_rc_sets_rbe3), &
         new_unittest('rc_sets_rbe2_no_rigid_mode', test_rc_sets_rbe2), &
         new_unittest('null_space_equals_dropping_rbe2', test_formulations_rbe2), &
         new_unittest('rbe2_stiffer_than_rbe3', test_rbe2_stiffer)]
   end subroutine collect_modes_crank

   !> Modes of the crank for RC set `rc_set` with `mpc` interfaces.
   subroutine crank_modes(rc_set, mpc, formulation, num_modes, shift_hz, body, error)
      integer, intent(in) :: rc_set
      character(len=*), intent(in) :: mpc, formulation
      integer, intent(in) :: num_modes
      real(dp), intent(in) :: shift_hz
      type(body_modes_t), intent(out) :: body
      type(error_t), allocatable, intent(out) :: error
      type(body_input_t) :: crank
      type(interface_input_t) :: faces(3)
      type(modes_input_t) :: modes
      type(logger_t) :: log
      type(stage_times_t) :: times
      character(len=2), parameter :: names(3) = ['B1', 'B2', 'B3']
      integer :: k
      crank%name = 'crank'
      crank%mesh_file = 'crank_lc8.msh'
      crank%volumes(1) = 'crank'
      do k = 1, 3
         faces(k)%body = 'crank'
         faces(k)%name = names(k)
         faces(k)%mpc = mpc
         faces(k)%rc = RC_SETS(k, rc_set)
      end do
      modes%num_modes = num_modes
      modes%shift_hz = shift_hz
      modes%formulation = formulation
      log%level = LOG_QUIET
      call compute_input_body_modes(crank, faces, modes, test_mesh_dir(), &
         log, times, body, error)
      if (allocated(error)) call add_context(error, 'RC set ' // to_str(rc_set) // ', ' // mpc)
   end subroutine crank_modes

   !> Sturm count 0 below 100 Hz, residuals <= 1e-7, |psi^T M psi - I| <= 1e-10 (issue
   !> tolerances; round-off floor ~1e-10 on stiff Tet10 meshes, toolchain.md pitfall 9), RC rows
   !> of the virtual-node shapes zero to 1e-9 of the shape scale.
   subroutine check_rc_sets(mpc, error)
      character(len=*), intent(in) :: mpc
      type(error_t), allocatable, intent(out) :: error
      type(body_modes_t) :: body
      integer :: rc_set, k, d
      real(dp) :: scale
      do rc_set = 1, 3
         call crank_modes(rc_set, mpc, 'multipliers', 6, 100.0_dp, body, error)
         if (allocated(error)) return
         call report(mpc // ' RC set ' // to_str(rc_set) // ': f1..f6 = ' // &
            to_str(body%frequency_hz(1), 7) // ' .. ' // to_str(body%frequency_hz(6), 7) // &
            ' Hz, Sturm count below 100 Hz = ' // to_str(body%eigen%num_below_shift))
         call check(error, mpc // ' RC set ' // to_str(rc_set) // ': eigenvalues below 100 Hz ' &
            // '(Sturm count) = ' // to_str(body%eigen%num_below_shift), &
            body%eigen%num_below_shift == 0 .and. body%frequency_hz(1) > 100.0_dp)
         if (.not. allocated(error)) call check_close(error, 'max residual', &
            maxval(body%residual), 0.0_dp, atol=1.0e-7_dp)
         if (.not. allocated(error)) call check_close(error, 'max |psi^T M psi - I|', &
            body%orthonormality_error, 0.0_dp, atol=1.0e-10_dp)
         if (allocated(error)) return
         if (mpc == 'RBE3') call check_gf_identity(body, error)
         if (allocated(error)) return
         scale = maxval(abs(body%shape))
         do k = 1, 3
            do d = 1, 6
               if (.not. body%interfaces(k)%rc(d)) cycle
               call check_close(error, 'RC row of the virtual-node shapes', &
                  maxval(abs(body%virtual_node_shape(6 * (k - 1) + d, :))), 0.0_dp, &
                  atol=1.0e-9_dp * scale)
               if (allocated(error)) return
            end do
         end do
      end do
   end subroutine check_rc_sets

   !> G F = I6 on the real faces B1, B2, B3 of the mesh (curved Tri6 faces, corner and mid-side
   !> nodes, uniform weights): an RBE3 reproduces every rigid motion of its face. Round-off:
   !> measured 2e-14; 1e-12 allows for the condition of the 6 x 6 normal matrix.
   subroutine check_gf_identity(body, error)
      type(body_modes_t), intent(in) :: body
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: F(:, :)
      real(dp) :: gf(6, 6)
      integer :: k, i
      do k = 1, size(body%interfaces)
         associate (face => body%interfaces(k))
            if (face%mpc /= MPC_RBE3) cycle
            call rbe2_matrix(body%mesh%xyz(:, face%nodes), face%virtual_xyz, F)
            gf = matmul(face%G, F)
            do i = 1, 6
               gf(i, i) = gf(i, i) - 1.0_dp
            end do
            call report('face ' // face%name // ': max |G F - I6| = ' // to_str(maxval(abs(gf)), 2))
            call check_close(error, 'face ' // face%name // ' (' // to_str(size(face%nodes)) // &
               ' nodes): max |G F - I6|', maxval(abs(gf)), 0.0_dp, atol=1.0e-12_dp)
            if (allocated(error)) return
         end associate
      end do
   end subroutine check_gf_identity

   subroutine test_rc_sets_rbe3(error)
      type(error_t), allocatable, intent(out) :: error
      call check_rc_sets('RBE3', error)
   end subroutine test_rc_sets_rbe3

   subroutine test_rc_sets_rbe2(error)
      type(error_t), allocatable, intent(out) :: error
      call check_rc_sets('RBE2', error)
   end subroutine test_rc_sets_rbe2

   !> The scalable (multiplier) and explicit (B2 = null(D G), LAPACK) RC matrices give the same
   !> frequencies to 1e-8 relative (issue tolerance; both are exact formulations of one problem).
   subroutine compare_formulations(rc_set, mpc, error)
      integer, intent(in) :: rc_set
      character(len=*), intent(in) :: mpc
      type(error_t), allocatable, intent(out) :: error
      type(body_modes_t) :: scalable, explicit
      integer :: i
      call crank_modes(rc_set, mpc, 'multipliers', 6, -10.0_dp, scalable, error)
      if (.not. allocated(error)) call crank_modes(rc_set, mpc, 'null_space', 6, -10.0_dp, &
         explicit, error)
      if (allocated(error)) return
      do i = 1, 6
         call check_close(error, mpc // ' RC set ' // to_str(rc_set) // ' mode ' // to_str(i) // &
            ' (Hz), null space vs multipliers', explicit%frequency_hz(i), &
            scalable%frequency_hz(i), rtol=1.0e-8_dp)
         if (allocated(error)) return
      end do
      call report(mpc // ' RC set ' // to_str(rc_set) // ': max relative difference ' // &
         to_str(maxval(abs(explicit%frequency_hz - scalable%frequency_hz) / &
         scalable%frequency_hz), 2))
   end subroutine compare_formulations

   subroutine test_formulations_rbe2(error)
      type(error_t), allocatable, intent(out) :: error
      call compare_formulations(1, 'RBE2', error)
   end subroutine test_formulations_rbe2

   !> RBE2 makes the interfaces rigid, RBE3 adds no stiffness: every RBE2 frequency lies above
   !> the RBE3 one of the same RC set (Heirman & Desmet 2010; theory.md 1.3).
   subroutine test_rbe2_stiffer(error)
      type(error_t), allocatable, intent(out) :: error
      type(body_modes_t) :: rigid, interpolated
      call crank_modes(3, 'RBE2', 'multipliers', 6, -10.0_dp, rigid, error)
      if (.not. allocated(error)) call crank_modes(3, 'RBE3', 'multipliers', 6, -10.0_dp, &
         interpolated, error)
      if (allocated(error)) return
      call check(error, 'RBE2 frequencies above RBE3 ones (RC set 3)', &
         all(rigid%frequency_hz > interpolated%frequency_hz))
   end subroutine test_rbe2_stiffer

end module test_modes_crank

program main_modes_crank
   use ffrf_testing, only: unittest_t, run_suite
   use test_modes_crank, only: collect_modes_crank
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_modes_crank(tests)
   call run_suite('modes_crank', tests)
end program main_modes_crank
