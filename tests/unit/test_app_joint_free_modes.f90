!> The modes the joints leave free (ffrf_app_joint_free_modes, docs/theory.md section 8) on
!> manufactured bodies whose answers are written out by hand:
!> - a shaft on two revolute bearings on the z axis, interface 1 at the origin, interface 2 at
!>   (0, 0, 1), with three candidates (omega^2 = 1, 4, 9): A and C tilt journal 1 (Rx = 1), B
!>   turns journal 2 about the axis (Rz = 1). The bearings hold Rx at journal 1, and the shaft's
!>   own rigid tilt about x, which would take it back, moves journal 2 across the axis, which
!>   the second bearing holds: eta_A + eta_C = 0, one combination is locked; the free modes are
!>   B (omega^2 = 4) and (A - C) / sqrt(2) (omega^2 = (1 + 9) / 2 = 5), free shares 1/2, 1,
!>   1/2; the free modes' shapes are Phi W and leave journal 1's Rx at zero (with one bearing
!>   only, the rigid tilt takes every tilt back: nothing is locked);
!> - a body held by spherical joints to the ground at interface 1 (origin) and interface 2
!>   (1, 0, 0): D moves interface 2 across (u_y = 1), which the body's rigid rotation about z
!>   takes back (so D is free), E stretches it (u_x = 1), which nothing takes back (locked): the
!>   lever arms of the rigid motions count;
!> - a prismatic guide along y at interface 1 (0, 0.2, 0) and a spherical joint at interface 2
!>   (0.1, 0, 0): the guide holds every rotation of interface 1 and its translations across y,
!>   the spherical joint the body's rigid rotations: a mode that slides interface 1 along y is
!>   free, one that twists it about y and one that moves it along x are locked (the rows of the
!>   cylindrical case below plus Ry1 = wy: two combinations no rigid motion reaches);
!> - the prismatic guide with the body turned by 90 degrees about z (&body orientation: body x =
!>   global y, body y = global -x; the guide axis and the ground markers turned with it): the
!>   slide along the guide is still free and the twist locked, since the virtual-node rows are
!>   turned to global (without that, both would be locked: body y would be taken as global y,
!>   across the guide);
!> - a cylindrical joint along y at interface 1 (0, 0.2, 0) and a spherical joint at interface 2
!>   (0.1, 0, 0): the cylinder holds interface 1's translations across y (global x, z) and its
!>   rotations across y (x, z). The body's rigid motions (t, w) change the seven held components
!>   by Ux1 = tx - 0.2 wz, Uz1 = tz + 0.2 wx, Rx1 = wx, Rz1 = wz, U2 = (tx, ty + 0.1 wz,
!>   tz - 0.1 wy); the only combination no rigid motion reaches is Ux1 + 0.2 Rz1 - Ux2 (by
!>   hand: the left null vector of those seven rows). So a mode that slides interface 1 along y
!>   and one that twists it about y are free (the twist is locked by a prismatic guide), one
!>   that moves it along x is locked.
module test_app_joint_free_modes
   use ffrf_core_kinds, only: dp, pi
   use ffrf_core_error, only: error_t
   use ffrf_model_model, only: model_t
   use ffrf_model_mechanism, only: model_joint_t, model_marker_t
   use ffrf_mbs_joints, only: JOINT_REVOLUTE, JOINT_SPHERICAL, JOINT_PRISMATIC, JOINT_CYLINDRICAL
   use ffrf_modes_modal_analysis, only: body_modes_t
   use ffrf_mpc_interface, only: interface_spec_t
   use ffrf_app_joint_free_modes, only: joint_locks_t, joint_free_modes
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check
   use ffrf_core_strings, only: to_str
   implicit none
   private
   public :: collect_app_joint_free_modes

contains

   subroutine collect_app_joint_free_modes(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [new_unittest('revolute_bearing_locks_the_journal_tilt', test_revolute), &
         new_unittest('one_bearing_locks_nothing', test_one_bearing), &
         new_unittest('rigid_motion_takes_back_a_lever_arm', test_lever_arm), &
         new_unittest('prismatic_guide_locks_rotations_cylindrical_not_the_twist', &
            test_prismatic), &
         new_unittest('turned_body_keeps_its_guide', test_turned_guide)]
   end subroutine collect_app_joint_free_modes

   !> One flexible body (model body 1) with interfaces at `xyz` and the joints given, ground
   !> markers at the joint points.
   subroutine make_case(xyz, kinds, interface_of, axes, model, modes)
      real(dp), intent(in) :: xyz(:, :)
      integer, intent(in) :: kinds(:), interface_of(:)
      real(dp), intent(in) :: axes(:, :)
      type(model_t), intent(out) :: model
      type(body_modes_t), intent(out) :: modes
      integer :: j, i
      allocate (model%bodies(1))
      model%bodies(1)%name = 'body'
      model%bodies(1)%motion%position = 0.0_dp
      allocate (model%bodies(1)%interfaces(size(xyz, 2)))
      allocate (model%mechanism%joints(size(kinds)), model%mechanism%markers(size(kinds)))
      do j = 1, size(kinds)
         model%mechanism%markers(j) = model_marker_t(body=0, name='g', &
            position=xyz(:, interface_of(j)))
         model%mechanism%joints(j) = model_joint_t(name='j', kind=kinds(j), body=[0, 1], &
            marker=[j, interface_of(j)], axis=axes(:, j))
      end do
      allocate (modes%interfaces(size(xyz, 2)))
      do i = 1, size(xyz, 2)
         modes%interfaces(i)%virtual_xyz = xyz(:, i)
      end do
   end subroutine make_case

   subroutine test_revolute(error)
      type(error_t), allocatable, intent(out) :: error
      type(model_t) :: model
      type(body_modes_t) :: modes
      type(joint_locks_t) :: locks
      real(dp) :: phi(6, 3), w_expected(3, 2), omega2(3)
      integer :: j
      call make_case(reshape([0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp], [3, 2]), &
         [JOINT_REVOLUTE, JOINT_REVOLUTE], [1, 2], reshape([0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, &
         0.0_dp, 1.0_dp], [3, 2]), model, modes)
      omega2 = [1.0_dp, 4.0_dp, 9.0_dp]
      modes%frequency_hz = sqrt(omega2) / (2.0_dp * pi)
      allocate (modes%virtual_node_shape(12, 3), source=0.0_dp)
      modes%virtual_node_shape(4, 1) = 1.0_dp      ! A: journal 1 Rx
      modes%virtual_node_shape(12, 2) = 1.0_dp     ! B: journal 2 Rz
      modes%virtual_node_shape(4, 3) = 1.0_dp      ! C: journal 1 Rx
      phi = reshape([(real(j, dp), j = 1, 18)], [6, 3])
      modes%shape = phi
      call joint_free_modes(model, 1, modes, locks, error)
      if (allocated(error)) return
      call check(error, 'one locked combination, two free modes', locks%num_locked == 1 .and. &
         size(modes%frequency_hz) == 2)
      if (allocated(error)) return
      call check_close(error, 'free mode 1: B, omega^2 = 4', (2.0_dp * pi * &
         modes%frequency_hz(1))**2, 4.0_dp, rtol=1.0e-12_dp)
      if (.not. allocated(error)) call check_close(error, 'free mode 2: (A - C)/sqrt 2, ' // &
         'omega^2 = 5', (2.0_dp * pi * modes%frequency_hz(2))**2, 5.0_dp, rtol=1.0e-12_dp)
      if (allocated(error)) return
      call check_close(error, 'free shares', maxval(abs(locks%free_share - [0.5_dp, 1.0_dp, &
         0.5_dp])), 0.0_dp, atol=1.0e-12_dp)
      if (allocated(error)) return
      ! W up to the sign fixed by the largest entry (the first of equal ones positive)
      w_expected = reshape([0.0_dp, 1.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, -1.0_dp] * &
         [1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp / sqrt(2.0_dp), 1.0_dp / sqrt(2.0_dp), &
         1.0_dp / sqrt(2.0_dp)], [3, 2])
      call check_close(error, 'combination W', maxval(abs(locks%combination - w_expected)), &
         0.0_dp, atol=1.0e-12_dp)
      if (.not. allocated(error)) call check_close(error, 'shapes Phi W', &
         maxval(abs(modes%shape - matmul(phi, w_expected))), 0.0_dp, atol=1.0e-11_dp)
      if (.not. allocated(error)) call check_close(error, 'journal Rx of the free modes', &
         maxval(abs(modes%virtual_node_shape(4, :))), 0.0_dp, atol=1.0e-14_dp)
   end subroutine test_revolute

   subroutine test_one_bearing(error)
      type(error_t), allocatable, intent(out) :: error
      type(model_t) :: model
      type(body_modes_t) :: modes
      type(joint_locks_t) :: locks
      call make_case(reshape([0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp], [3, 2]), &
         [JOINT_REVOLUTE], [1], reshape([0.0_dp, 0.0_dp, 1.0_dp], [3, 1]), model, modes)
      modes%frequency_hz = [1.0_dp, 2.0_dp, 3.0_dp]
      allocate (modes%virtual_node_shape(12, 3), source=0.0_dp)
      modes%virtual_node_shape(4, 1) = 1.0_dp      ! journal 1 Rx
      modes%virtual_node_shape(12, 2) = 1.0_dp     ! interface 2 Rz
      modes%virtual_node_shape(4, 3) = 1.0_dp      ! journal 1 Rx
      allocate (modes%shape(3, 3), source=1.0_dp)
      call joint_free_modes(model, 1, modes, locks, error)
      if (allocated(error)) return
      call check(error, 'nothing locked: the rigid tilt takes a journal tilt back', &
         locks%num_locked == 0 .and. size(modes%frequency_hz) == 3)
      if (.not. allocated(error)) call check_close(error, 'frequencies kept', &
         maxval(abs(modes%frequency_hz - [1.0_dp, 2.0_dp, 3.0_dp])), 0.0_dp, atol=1.0e-12_dp)
   end subroutine test_one_bearing

   subroutine test_lever_arm(error)
      type(error_t), allocatable, intent(out) :: error
      type(model_t) :: model
      type(body_modes_t) :: modes
      type(joint_locks_t) :: locks
      call make_case(reshape([0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp], [3, 2]), &
         [JOINT_SPHERICAL, JOINT_SPHERICAL], [1, 2], reshape([0.0_dp, 0.0_dp, 1.0_dp, &
         0.0_dp, 0.0_dp, 1.0_dp], [3, 2]), model, modes)
      modes%frequency_hz = [1.0_dp, 2.0_dp]
      allocate (modes%virtual_node_shape(12, 2), source=0.0_dp)
      modes%virtual_node_shape(8, 1) = 1.0_dp      ! D: interface 2 u_y
      modes%virtual_node_shape(7, 2) = 1.0_dp      ! E: interface 2 u_x
      allocate (modes%shape(3, 2), source=1.0_dp)
      call joint_free_modes(model, 1, modes, locks, error)
      if (allocated(error)) return
      call check(error, 'E locked, D free', locks%num_locked == 1 .and. &
         size(modes%frequency_hz) == 1)
      if (.not. allocated(error)) call check_close(error, 'free mode: D', &
         modes%frequency_hz(1), 1.0_dp, rtol=1.0e-12_dp)
      if (.not. allocated(error)) call check_close(error, 'free shares', &
         maxval(abs(locks%free_share - [1.0_dp, 0.0_dp])), 0.0_dp, atol=1.0e-12_dp)
   end subroutine test_lever_arm

   subroutine test_turned_guide(error)
      type(error_t), allocatable, intent(out) :: error
      type(model_t) :: model
      type(body_modes_t) :: modes
      type(joint_locks_t) :: locks
      real(dp) :: turn(3, 3)
      integer :: j
      ! columns: body x -> global y, body y -> global -x, body z -> global z
      turn = reshape([0.0_dp, 1.0_dp, 0.0_dp, -1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, &
         1.0_dp], [3, 3])
      ! the guide along body y is along global -x
      call make_case(reshape([0.0_dp, 0.2_dp, 0.0_dp, 0.1_dp, 0.0_dp, 0.0_dp], [3, 2]), &
         [JOINT_PRISMATIC, JOINT_SPHERICAL], [1, 2], reshape([-1.0_dp, 0.0_dp, 0.0_dp, &
         0.0_dp, 0.0_dp, 1.0_dp], [3, 2]), model, modes)
      model%bodies(1)%motion%orientation = turn
      do j = 1, 2
         model%mechanism%markers(j)%position = matmul(turn, model%mechanism%markers(j)%position)
      end do
      modes%frequency_hz = [1.0_dp, 2.0_dp]
      allocate (modes%virtual_node_shape(12, 2), source=0.0_dp)
      modes%virtual_node_shape(2, 1) = 1.0_dp      ! along the guide (body y)
      modes%virtual_node_shape(5, 2) = 1.0_dp      ! twist about the guide (body y)
      allocate (modes%shape(3, 2), source=1.0_dp)
      call joint_free_modes(model, 1, modes, locks, error)
      if (allocated(error)) return
      call check(error, 'turned: twist locked, slide free', locks%num_locked == 1 .and. &
         size(modes%frequency_hz) == 1)
      if (.not. allocated(error)) call check_close(error, 'turned: free mode: the slide', &
         modes%frequency_hz(1), 1.0_dp, rtol=1.0e-12_dp)
   end subroutine test_turned_guide

   !> The guide case (guide_case) with a prismatic joint (slide free; twist and across locked)
   !> and with a cylindrical one (slide and twist free; across locked).
   subroutine test_prismatic(error)
      type(error_t), allocatable, intent(out) :: error
      type(body_modes_t) :: modes
      type(joint_locks_t) :: locks
      integer, parameter :: kinds(2) = [JOINT_PRISMATIC, JOINT_CYLINDRICAL]
      character(len=*), parameter :: names(2) = ['prismatic  ', 'cylindrical']
      integer :: k, j
      do k = 1, 2
         call guide_case(kinds(k), modes, locks, error)
         if (allocated(error)) return
         call check(error, trim(names(k)) // ': ' // to_str(locks%num_locked) // ' locked, ' // &
            to_str(size(modes%frequency_hz)) // ' free; expected ' // to_str(3 - k) // ', ' // &
            to_str(k), locks%num_locked == 3 - k .and. size(modes%frequency_hz) == k)
         do j = 1, k
            if (.not. allocated(error)) call check_close(error, trim(names(k)) // &
               ': free mode ' // to_str(j) // ' (slide, twist)', modes%frequency_hz(j), &
               real(j, dp), rtol=1.0e-12_dp)
         end do
         if (allocated(error)) return
      end do
   end subroutine test_prismatic

   !> A guide of `kind` along y at interface 1 (0, 0.2, 0), a spherical joint at interface 2
   !> (0.1, 0, 0), and three candidates at 1, 2, 3 Hz that move interface 1 along the guide
   !> (Ty), twist it about the guide (Ry) and move it across (Tx); their joint-free modes.
   subroutine guide_case(kind, modes, locks, error)
      integer, intent(in) :: kind
      type(body_modes_t), intent(out) :: modes
      type(joint_locks_t), intent(out) :: locks
      type(error_t), allocatable, intent(out) :: error
      type(model_t) :: model
      call make_case(reshape([0.0_dp, 0.2_dp, 0.0_dp, 0.1_dp, 0.0_dp, 0.0_dp], [3, 2]), &
         [kind, JOINT_SPHERICAL], [1, 2], reshape([0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, &
         1.0_dp], [3, 2]), model, modes)
      call unit_candidates([2, 5, 1], 2, modes)
      call joint_free_modes(model, 1, modes, locks, error)
   end subroutine guide_case

   !> Candidate k at k Hz moves virtual-node row rows(k) (6 rows per interface) by 1, nothing
   !> else; num_interfaces interfaces.
   subroutine unit_candidates(rows, num_interfaces, modes)
      integer, intent(in) :: rows(:), num_interfaces
      type(body_modes_t), intent(inout) :: modes
      integer :: k
      modes%frequency_hz = [(real(k, dp), k = 1, size(rows))]
      allocate (modes%virtual_node_shape(6 * num_interfaces, size(rows)), source=0.0_dp)
      do k = 1, size(rows)
         modes%virtual_node_shape(rows(k), k) = 1.0_dp
      end do
      allocate (modes%shape(3, size(rows)), source=1.0_dp)
   end subroutine unit_candidates

end module test_app_joint_free_modes

program main_app_joint_free_modes
   use ffrf_testing, only: unittest_t, run_suite
   use test_app_joint_free_modes, only: collect_app_joint_free_modes
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_app_joint_free_modes(tests)
   call run_suite('app_joint_free_modes', tests)
end program main_app_joint_free_modes
