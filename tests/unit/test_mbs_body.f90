!> The abstract body (ffrf_mbs_body) and its three extensions, ground and rigid body
!> (ffrf_mbs_rigid_body) and reduced flexible body (ffrf_mbs_flexible_body), called through
!> class(body_t) as the mechanism calls them: the energies a body adds to the energy balance
!> (strain_energy, damping_power: zero by default, the modal closed forms for a flexible body)
!> and a flexible body added to a mechanism directly (markers = its interfaces).
!>
!> The flexible body is made by hand: four point masses (lumped mass matrix) at the corners of a
!> tetrahedron, two arbitrary shape vectors with omega = 2 pi [3, 5] rad/s, modal damping ratio
!> xi = 0.02 and one interface at node 1. References, independent of the code under test:
!>     U = sum_j omega_j^2 zeta_j^2 / 2,   P_d = sum_j 2 xi omega_j zeta_dot_j^2,
!> both to 1e-14 relative (a few roundings of a two-term sum).
module test_mbs_body
   use ffrf_core_kinds, only: dp, ip, pi
   use ffrf_core_error, only: error_t
   use ffrf_core_strings, only: to_str
   use ffrf_la_sparse, only: csr_t, csr_from_coo
   use ffrf_mbs_body, only: body_t
   use ffrf_mbs_rigid_body, only: rigid_body_t, ground_t
   use ffrf_mbs_flexible_body, only: flexible_body_t
   use ffrf_mbs_mechanism, only: mechanism_t
   use ffrf_mbs_rotation, only: identity3, euler_from_axis_angle
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check
   implicit none
   private
   public :: collect_mbs_body

   !> Modal circular frequencies of the hand-made flexible body (rad/s)
   real(dp), parameter :: omegas(2) = 2.0_dp * pi * [3.0_dp, 5.0_dp]
   !> Its modal damping ratio
   real(dp), parameter :: xi = 0.02_dp
   !> Relative tolerance of the closed forms (module header)
   real(dp), parameter :: rtol = 1.0e-14_dp

   !> A body of any kind, for an array of them
   type :: any_body_t
      class(body_t), allocatable :: body
   end type any_body_t

contains

   !> The suite.
   subroutine collect_mbs_body(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [new_unittest('energies_through_body_t', test_energies), &
         new_unittest('flexible_body_in_mechanism', test_mechanism)]
   end subroutine collect_mbs_body

   !> The hand-made flexible body of the module header.
   subroutine make_flexible(flexible, error)
      type(flexible_body_t), intent(out) :: flexible
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: M
      real(dp) :: xyz(3, 4), shapes(12, 2), virtual_shapes(6, 2), mdiag(12)
      integer(ip) :: rows(12)
      integer :: i
      xyz = reshape([0.0_dp, 0.0_dp, 0.0_dp, 0.2_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.1_dp, 0.0_dp, &
         0.0_dp, 0.0_dp, 0.3_dp], [3, 4])
      do i = 1, 4
         mdiag(3 * i - 2:3 * i) = 0.5_dp + 0.25_dp * i
      end do
      rows = [(int(i, ip), i=1, 12)]
      call csr_from_coo(12_ip, 12_ip, rows, rows, mdiag, M, error)
      if (allocated(error)) return
      shapes(:, 1) = [0.3_dp, 0.1_dp, -0.2_dp, -0.4_dp, 0.5_dp, 0.1_dp, 0.2_dp, -0.3_dp, 0.6_dp, &
         -0.1_dp, 0.2_dp, -0.5_dp]
      shapes(:, 2) = [-0.2_dp, 0.4_dp, 0.3_dp, 0.1_dp, -0.2_dp, 0.5_dp, -0.6_dp, 0.1_dp, &
         -0.1_dp, 0.3_dp, 0.4_dp, 0.2_dp]
      virtual_shapes = 0.0_dp
      virtual_shapes(1:3, :) = shapes(1:3, :)
      call flexible%init(M, xyz, shapes, omegas**2, virtual_shapes, xyz(:, 1:1), error)
      if (allocated(error)) return
      call flexible%set_modal_damping([xi], error)
   end subroutine make_flexible

   !> Ground (no coordinates), a rigid body and the flexible body, each behind class(body_t):
   !> strain_energy and damping_power are 0 for the ground and the rigid body and the modal closed
   !> forms for the flexible body; a flexible body's markers are its interfaces.
   subroutine test_energies(error)
      type(error_t), allocatable, intent(out) :: error
      type(any_body_t) :: bodies(3)
      type(ground_t) :: ground
      type(rigid_body_t) :: rigid
      type(flexible_body_t) :: flexible
      real(dp), allocatable :: q(:), v(:)
      real(dp) :: zeta(2), zeta_dot(2), expected(2)
      integer :: b, i, n
      character(len=8), parameter :: names(3) = ['ground  ', 'rigid   ', 'flexible']
      call ground%init(reshape([0.0_dp, 0.0_dp, 0.0_dp], [3, 1]), &
         reshape(identity3(), [3, 3, 1]), error)
      if (allocated(error)) return
      call rigid%init(2.0_dp, [0.0_dp, 0.01_dp, 0.0_dp], 1.0e-3_dp * identity3(), &
         reshape([0.0_dp, 0.0_dp, 0.0_dp], [3, 1]), reshape(identity3(), [3, 3, 1]), error)
      if (allocated(error)) return
      call make_flexible(flexible, error)
      if (allocated(error)) return
      allocate (bodies(1)%body, source=ground)
      allocate (bodies(2)%body, source=rigid)
      allocate (bodies(3)%body, source=flexible)
      call check(error, 'flexible body: 9 coordinates and 1 marker (its interface), got ' // &
         to_str(bodies(3)%body%num_coordinates) // ' and ' // &
         to_str(bodies(3)%body%num_markers), &
         bodies(3)%body%num_coordinates == 9 .and. bodies(3)%body%num_markers == 1)
      if (allocated(error)) return
      zeta = [1.0e-3_dp, -2.0e-3_dp]
      zeta_dot = [0.3_dp, 0.7_dp]
      do b = 1, 3
         n = bodies(b)%body%num_coordinates
         q = [(0.1_dp * i, i=1, n)]
         v = [(-0.2_dp * i, i=1, n)]
         if (n >= 7) q(4:7) = euler_from_axis_angle([0.0_dp, 0.0_dp, 1.0_dp], 0.4_dp)
         if (n == 9) then
            q(8:9) = zeta
            v(8:9) = zeta_dot
            expected = [0.5_dp * sum(omegas**2 * zeta**2), sum(2.0_dp * xi * omegas * zeta_dot**2)]
         else
            expected = 0.0_dp
         end if
         call check_close(error, trim(names(b)) // ': strain energy (J)', &
            bodies(b)%body%strain_energy(q), expected(1), rtol=rtol)
         if (allocated(error)) return
         call check_close(error, trim(names(b)) // ': damping power (W)', &
            bodies(b)%body%damping_power(v), expected(2), rtol=rtol)
         if (allocated(error)) return
      end do
   end subroutine test_energies

   !> The flexible body goes into a mechanism as it is (no wrapper): ground (1), rigid body (2),
   !> flexible body (3); the mechanism's strain energy is the flexible body's closed form.
   subroutine test_mechanism(error)
      type(error_t), allocatable, intent(out) :: error
      type(mechanism_t) :: mech
      type(ground_t) :: ground
      type(rigid_body_t) :: rigid
      type(flexible_body_t) :: flexible
      real(dp), allocatable :: q(:)
      real(dp) :: zeta(2)
      integer :: ig, ir, iflex
      call ground%init(reshape([0.0_dp, 0.0_dp, 0.0_dp], [3, 1]), &
         reshape(identity3(), [3, 3, 1]), error)
      if (allocated(error)) return
      call rigid%init(2.0_dp, [0.0_dp, 0.01_dp, 0.0_dp], 1.0e-3_dp * identity3(), &
         reshape([0.0_dp, 0.0_dp, 0.0_dp], [3, 1]), reshape(identity3(), [3, 3, 1]), error)
      if (allocated(error)) return
      call make_flexible(flexible, error)
      if (allocated(error)) return
      call mech%add_body(ground, 'ground', ig, error)
      if (.not. allocated(error)) call mech%add_body(rigid, 'rigid', ir, error)
      if (.not. allocated(error)) call mech%add_body(flexible, 'flexible', iflex, error)
      if (allocated(error)) return
      call check(error, 'mechanism: 7 + 9 coordinates, flexible body third', &
         mech%n == 16 .and. iflex == 3 .and. mech%bodies(iflex)%offset == 7)
      if (allocated(error)) return
      select type (body => mech%bodies(iflex)%body)
      type is (flexible_body_t)
         call check(error, 'mechanism body 3 is the flexible body itself (damping kept)', &
            allocated(body%damping) .and. body%num_modes == 2)
      class default
         call check(error, 'mechanism body 3 is a flexible_body_t', .false.)
      end select
      if (allocated(error)) return
      ! q = [R, theta (rigid); R, theta, zeta (flexible)]
      allocate (q(mech%n), source=0.0_dp)
      q(4:7) = [1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp]
      q(11:14) = [1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp]
      zeta = [2.0e-3_dp, 1.0e-3_dp]
      q(15:16) = zeta
      call check_close(error, 'mechanism strain energy (J)', mech%strain_energy(q), &
         0.5_dp * sum(omegas**2 * zeta**2), rtol=rtol)
   end subroutine test_mechanism

end module test_mbs_body

program main_mbs_body
   use ffrf_testing, only: unittest_t, run_suite
   use test_mbs_body, only: collect_mbs_body
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_mbs_body(tests)
   call run_suite('mbs_body', tests)
end program main_mbs_body
