!> RBE2/RBE3 matrices, reference-condition checks and dof parsing on synthetic node sets, against
!> identities that hold exactly (to round-off): G F = I6, rigid motions reproduced at the virtual
!> node (also off the centroid, where MSC's full 6-dof fit differs from a plain average), statics
!> of the distributed load f_B = G^T f_V, and the rank diagnostics of collinear nodes.
module test_mpc_rbe
   use ffrf_core_kinds, only: dp, ip
   use ffrf_la_lapack, only: dgesv
   use ffrf_core_error, only: error_t
   use ffrf_la_dense, only: skew
   use ffrf_mpc_rbe2, only: rbe2_matrix, rbe2_pseudo_inverse
   use ffrf_mpc_rbe3, only: rbe3_matrix
   use ffrf_mpc_interface, only: interface_t, dofs_text, MPC_RBE3
   use ffrf_input_interface, only: parse_dofs
   use ffrf_mpc_reference_conditions, only: rc_summary_t, check_reference_conditions
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check
   implicit none
   private
   public :: collect_mpc_rbe

   !> Round-off bound for identities on O(1) matrices with O(100) terms
   real(dp), parameter :: tight = 1.0e-12_dp

contains

   subroutine collect_mpc_rbe(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [ &
         new_unittest('rbe3_g_times_f_is_identity', test_rbe3_gf_identity), &
         new_unittest('rbe3_rigid_motion_off_centroid', test_rbe3_rigid_off_centroid), &
         new_unittest('rbe3_uniform_weights_average', test_rbe3_average), &
         new_unittest('rbe3_load_statics', test_rbe3_load_statics), &
         new_unittest('rbe2_pseudo_inverse', test_rbe2_pseudo_inverse), &
         new_unittest('collinear_nodes_rank', test_collinear_rank), &
         new_unittest('rc_refused_free_rotation', test_rc_free_rotation), &
         new_unittest('rc_refused_collinear_rotation', test_rc_collinear_rotation), &
         new_unittest('rc_hyperstatic_count', test_rc_hyperstatic), &
         new_unittest('parse_dofs', test_parse_dofs)]
   end subroutine collect_mpc_rbe

   !> Nodes on a cylindrical face (radius 0.02, length 0.025 along z) at irregular angles.
   subroutine ring_nodes(xyz)
      real(dp), allocatable, intent(out) :: xyz(:, :)
      integer :: i, j, k
      allocate (xyz(3, 36))
      k = 0
      do j = 0, 2
         do i = 0, 11
            k = k + 1
            xyz(:, k) = [0.02_dp * cos(0.5_dp * i + 0.1_dp * j), &
               0.02_dp * sin(0.5_dp * i + 0.1_dp * j), 0.0125_dp * j - 0.03_dp]
         end do
      end do
   end subroutine ring_nodes

   subroutine test_rbe3_gf_identity(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: xyz(:, :), F(:, :), G(:, :), w(:)
      real(dp) :: direction(3), gf(6, 6)
      logical :: deficient
      integer :: i
      call ring_nodes(xyz)
      w = [(1.0_dp + 0.1_dp * mod(i, 5), i=1, size(xyz, 2))]
      call rbe2_matrix(xyz, [0.001_dp, -0.002_dp, 0.004_dp], F)
      call rbe3_matrix(xyz, w, [0.001_dp, -0.002_dp, 0.004_dp], 0.02_dp, G, deficient, direction, &
         error)
      if (allocated(error)) return
      gf = matmul(G, F)
      do i = 1, 6
         gf(i, i) = gf(i, i) - 1.0_dp
      end do
      call check_close(error, 'max |G F - I6|', maxval(abs(gf)), 0.0_dp, atol=tight)
      if (.not. allocated(error)) call check(error, 'ring nodes are not rank deficient', &
         .not. deficient)
   end subroutine test_rbe3_gf_identity

   !> A rigid motion (t, theta) of the face gives exactly u_V = t + theta x x_V, theta_V = theta
   !> at a virtual node well off the centroid.
   subroutine test_rbe3_rigid_off_centroid(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: xyz(:, :), G(:, :), w(:), q_b(:)
      real(dp) :: direction(3), x_v(3), t(3), theta(3), q_v(6), expected(6)
      logical :: deficient
      integer :: i
      call ring_nodes(xyz)
      w = [(1.0_dp, i=1, size(xyz, 2))]
      x_v = [0.01_dp, 0.03_dp, 0.05_dp]
      t = [1.0e-4_dp, -2.0e-4_dp, 3.0e-4_dp]
      theta = [2.0e-3_dp, 1.0e-3_dp, -4.0e-3_dp]
      allocate (q_b(3 * size(xyz, 2)))
      do i = 1, size(xyz, 2)
         q_b(3 * i - 2:3 * i) = t + matmul(skew(theta), xyz(:, i))
      end do
      call rbe3_matrix(xyz, w, x_v, 0.02_dp, G, deficient, direction, error)
      if (allocated(error)) return
      q_v = matmul(G, q_b)
      expected(1:3) = t + matmul(skew(theta), x_v)
      expected(4:6) = theta
      call check_close(error, 'max |q_V - rigid motion|', maxval(abs(q_v - expected)), 0.0_dp, &
         atol=tight * maxval(abs(expected)))
   end subroutine test_rbe3_rigid_off_centroid

   !> With the virtual node at the (uniformly weighted) centroid, u_V is the plain average of the
   !> node translations and theta_V = J^-1 sum r_i x u_i (theory.md 1.2, decoupled blocks).
   subroutine test_rbe3_average(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: xyz(:, :), G(:, :), w(:), q_b(:)
      real(dp) :: direction(3), x_v(3), q_v(6), moment(3), J(3, 3), r(3), theta(3)
      logical :: deficient
      integer :: i
      integer(ip) :: pivots(3), info
      call ring_nodes(xyz)
      w = [(1.0_dp, i=1, size(xyz, 2))]
      x_v = sum(xyz, dim=2) / size(xyz, 2)
      allocate (q_b(3 * size(xyz, 2)))
      q_b = [(sin(1.3_dp * i), i=1, size(q_b))] * 1.0e-4_dp
      call rbe3_matrix(xyz, w, x_v, 0.02_dp, G, deficient, direction, error)
      if (allocated(error)) return
      q_v = matmul(G, q_b)
      call check_close(error, 'u_V(x) - average', q_v(1) - sum(q_b(1::3)) / size(xyz, 2), &
         0.0_dp, atol=tight * 1.0e-4_dp)
      if (allocated(error)) return
      moment = 0.0_dp
      J = 0.0_dp
      do i = 1, size(xyz, 2)
         r = xyz(:, i) - x_v
         moment = moment + matmul(skew(r), q_b(3 * i - 2:3 * i))
         J = J - matmul(skew(r), skew(r))
      end do
      theta = moment
      call dgesv(3_ip, 1_ip, J, 3_ip, pivots, theta, 3_ip, info)
      call check_close(error, 'theta_V(z) - J^-1 sum r x u', q_v(6) - theta(3), 0.0_dp, &
         atol=tight * maxval(abs(theta)))
   end subroutine test_rbe3_average


   !> A force and moment at the virtual node, distributed as f_B = G^T f_V, keep their resultant
   !> force and moment about the virtual node (virtual work with G F = I).
   subroutine test_rbe3_load_statics(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: xyz(:, :), G(:, :), w(:), f_b(:)
      real(dp) :: direction(3), x_v(3), f_v(6), force(3), moment(3)
      logical :: deficient
      integer :: i
      call ring_nodes(xyz)
      w = [(0.5_dp + mod(i, 3), i=1, size(xyz, 2))]
      x_v = [0.0_dp, 0.0_dp, 0.02_dp]
      f_v = [100.0_dp, -50.0_dp, 20.0_dp, 3.0_dp, -1.0_dp, 7.0_dp]
      call rbe3_matrix(xyz, w, x_v, 0.02_dp, G, deficient, direction, error)
      if (allocated(error)) return
      f_b = matmul(transpose(G), f_v)
      force = 0.0_dp
      moment = 0.0_dp
      do i = 1, size(xyz, 2)
         force = force + f_b(3 * i - 2:3 * i)
         moment = moment + matmul(skew(xyz(:, i) - x_v), f_b(3 * i - 2:3 * i))
      end do
      call check_close(error, 'max |resultant force - F_V| (N)', maxval(abs(force - f_v(1:3))), &
         0.0_dp, atol=tight * 100.0_dp)
      if (.not. allocated(error)) call check_close(error, 'max |resultant moment - M_V| (N m)', &
         maxval(abs(moment - f_v(4:6))), 0.0_dp, atol=tight * 7.0_dp)
   end subroutine test_rbe3_load_statics

   subroutine test_rbe2_pseudo_inverse(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: xyz(:, :), F(:, :), Fplus(:, :)
      real(dp) :: direction(3), pf(6, 6)
      logical :: deficient
      integer :: i
      call ring_nodes(xyz)
      call rbe2_matrix(xyz, [0.0_dp, 0.0_dp, -0.0175_dp], F)
      call rbe2_pseudo_inverse(F, 0.02_dp, Fplus, deficient, direction, error)
      if (allocated(error)) return
      pf = matmul(Fplus, F)
      do i = 1, 6
         pf(i, i) = pf(i, i) - 1.0_dp
      end do
      call check_close(error, 'max |F^+ F - I6|', maxval(abs(pf)), 0.0_dp, atol=tight)
   end subroutine test_rbe2_pseudo_inverse

   !> Nodes on a line along (1, 2, 2)/3: the rotation about that line is flagged as undefined.
   subroutine test_collinear_rank(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: xyz(:, :), G(:, :), F(:, :), Fplus(:, :), w(:)
      real(dp) :: direction(3), axis(3)
      logical :: deficient
      integer :: i
      axis = [1.0_dp, 2.0_dp, 2.0_dp] / 3.0_dp
      allocate (xyz(3, 5))
      do i = 1, 5
         xyz(:, i) = 0.01_dp * i * axis
      end do
      w = [(1.0_dp, i=1, 5)]
      call rbe3_matrix(xyz, w, sum(xyz, dim=2) / 5, 0.02_dp, G, deficient, direction, error)
      if (allocated(error)) return
      call check(error, 'RBE3 on collinear nodes is rank deficient', deficient)
      if (.not. allocated(error)) call check_close(error, '|direction . axis|', &
         abs(dot_product(direction, axis)), 1.0_dp, atol=1.0e-8_dp)
      if (allocated(error)) return
      call rbe2_matrix(xyz, sum(xyz, dim=2) / 5, F)
      call rbe2_pseudo_inverse(F, 0.02_dp, Fplus, deficient, direction, error)
      if (allocated(error)) return
      call check(error, 'RBE2 on collinear nodes is rank deficient', deficient)
   end subroutine test_collinear_rank

   !> Two interfaces on the z axis (like main journals B1, B3) with translations only: the
   !> rotation about z stays free and the message names it.
   subroutine test_rc_free_rotation(error)
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: message
      type(interface_t) :: faces(2)
      type(rc_summary_t) :: summary
      faces(1) = point_interface('B1', [0.0_dp, 0.0_dp, -0.05_dp], [.true., .true., .true., &
         .false., .false., .false.])
      faces(2) = point_interface('B3', [0.0_dp, 0.0_dp, 0.05_dp], [.true., .true., .false., &
         .false., .false., .false.])
      call check_reference_conditions(faces, [0.0_dp, 0.02_dp, 0.0_dp], summary, error)
      if (.not. allocated(error)) then
         call check(error, 'a free rotation is refused', .false.)
         return
      end if
      message = error%message
      call check(error, 'message names the free rotation about z through the axis: ' // &
         message, index(message, 'rotation about an axis along (0, 0, 1) through (0, 0, 0)') > 0)
   end subroutine test_rc_free_rotation

   !> A rotation RC about the line of collinear nodes is a dependent row: refused, naming it.
   subroutine test_rc_collinear_rotation(error)
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: message
      type(interface_t) :: faces(1)
      type(rc_summary_t) :: summary
      faces(1) = point_interface('pin', [0.0_dp, 0.0_dp, 0.0_dp], [.true., .true., .true., &
         .true., .true., .true.])
      faces(1)%rank_deficient = .true.
      faces(1)%undefined_direction = [0.0_dp, 0.0_dp, 1.0_dp]
      call check_reference_conditions(faces, [0.0_dp, 0.0_dp, 0.0_dp], summary, error)
      if (.not. allocated(error)) then
         call check(error, 'a dependent RC row is refused', .false.)
         return
      end if
      message = error%message
      call check(error, 'message names interface and dof: ' // message, &
         index(message, 'interface "pin": reference condition Rz cannot be carried') > 0)
   end subroutine test_rc_collinear_rotation

   !> Table 1 RC set 1 (B1 spherical, B3 universal): 7 conditions, hyperstatic by one.
   subroutine test_rc_hyperstatic(error)
      type(error_t), allocatable, intent(out) :: error
      type(interface_t) :: faces(3)
      type(rc_summary_t) :: summary
      faces(1) = point_interface('B1', [0.0_dp, 0.0_dp, -0.0475_dp], [.true., .true., .true., &
         .false., .false., .false.])
      faces(2) = point_interface('B2', [0.0_dp, 0.045_dp, 0.0_dp], [.false., .false., .false., &
         .false., .false., .false.])
      faces(3) = point_interface('B3', [0.0_dp, 0.0_dp, 0.0475_dp], [.true., .true., .true., &
         .false., .false., .true.])
      call check_reference_conditions(faces, [0.0_dp, 0.02_dp, 0.0_dp], summary, error)
      if (allocated(error)) return
      call check(error, 'RC set 1: 7 conditions, rank 6, redundancy 1', summary%num_rc == 7 .and. &
         summary%rigid_rank == 6 .and. summary%redundancy == 1 .and. .not. summary%free_free)
   end subroutine test_rc_hyperstatic

   subroutine test_parse_dofs(error)
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: message
      logical :: dofs(6)
      call parse_dofs('tx, RZ', dofs, error)
      if (allocated(error)) return
      call check(error, '"tx, RZ" -> Tx Rz', dofs_text(dofs) == 'Tx Rz')
      if (allocated(error)) return
      call parse_dofs('1246', dofs, error)
      if (allocated(error)) return
      call check(error, '"1246" -> Tx Ty Rx Rz', dofs_text(dofs) == 'Tx Ty Rx Rz')
      if (allocated(error)) return
      call parse_dofs('Tx Tw', dofs, error)
      if (.not. allocated(error)) then
         call check(error, '"Tx Tw" is refused', .false.)
         return
      end if
      message = error%message
      call check(error, 'message names the bad dof: ' // message, index(message, '"tw"') > 0)
   end subroutine test_parse_dofs

   function point_interface(name, x_v, rc) result(face)
      character(len=*), intent(in) :: name
      real(dp), intent(in) :: x_v(3)
      logical, intent(in) :: rc(6)
      type(interface_t) :: face
      face%name = name
      face%mpc = MPC_RBE3
      face%virtual_xyz = x_v
      face%length_scale = 0.02_dp
      face%rc = rc
   end function point_interface

end module test_mpc_rbe

program main_mpc_rbe
   use ffrf_testing, only: unittest_t, run_suite
   use test_mpc_rbe, only: collect_mpc_rbe
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_mpc_rbe(tests)
   call run_suite('mpc_rbe', tests)
end program main_mpc_rbe
