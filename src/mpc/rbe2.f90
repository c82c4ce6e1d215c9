!> Rigid MPC (Nastran RBE2 with all six components): every interface node follows the 6-dof
!> virtual node rigidly, small rotations (theory.md 1.1):
!>
!>     u_i = u_V + theta_V x r_i = u_V - skew(r_i) theta_V,   r_i = x_i - x_V
!>     q_B = F q_V,   F_i = [ I3, -skew(r_i) ]   (3 x 6 per node, F is 3 nB x 6)
!>
!> Since q_B lies in range(F), q_V = F^+ q_B exactly, F^+ = (F^T F)^{-1} F^T.
module ffrf_mpc_rbe2
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t
   use ffrf_la_dense, only: skew
   use ffrf_mpc_rigid_fit, only: weighted_rigid_fit
   implicit none
   private
   public :: rbe2_matrix, rbe2_pseudo_inverse

contains

   !> F (3 nB x 6) of q_B = F q_V (Cammarata et al. 2022, RBE2 relation).
   pure subroutine rbe2_matrix(node_xyz, virtual_xyz, F)
      !> Interface node positions, (3, nB)
      real(dp), intent(in) :: node_xyz(:, :)
      !> Virtual node position
      real(dp), intent(in) :: virtual_xyz(3)
      !> F, (3 nB, 6)
      real(dp), allocatable, intent(out) :: F(:, :)
      integer :: i, row
      allocate (F(3 * size(node_xyz, 2), 6))
      do i = 1, size(node_xyz, 2)
         row = 3 * (i - 1)
         F(row + 1:row + 3, 1:3) = reshape([1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, &
            0.0_dp, 0.0_dp, 1.0_dp], [3, 3])
         F(row + 1:row + 3, 4:6) = -skew(node_xyz(:, i) - virtual_xyz)
      end do
   end subroutine rbe2_matrix

   !> F^+ = (F^T F)^{-1} F^T (6 x 3 nB), the unit-weight rigid fit. F^T F is singular iff the
   !> nodes are collinear: then the rotation about that line is undefined and
   !> `undefined_direction` is returned with `rank_deficient` set (pseudo-inverse of F^T F).
   subroutine rbe2_pseudo_inverse(F, length_scale, Fplus, rank_deficient, undefined_direction, &
         error)
      !> F of the interface, (3 nB, 6)
      real(dp), intent(in) :: F(:, :)
      !> Characteristic length that makes rotations comparable with translations (m)
      real(dp), intent(in) :: length_scale
      !> F^+, (6, 3 nB)
      real(dp), allocatable, intent(out) :: Fplus(:, :)
      !> True if F has rank < 6
      logical, intent(out) :: rank_deficient
      !> Rotation axis left undefined (zero if none)
      real(dp), intent(out) :: undefined_direction(3)
      type(error_t), allocatable, intent(out) :: error
      call weighted_rigid_fit(F, spread(1.0_dp, 1, size(F, 1) / 3), length_scale, Fplus, &
         rank_deficient, undefined_direction, error)
   end subroutine rbe2_pseudo_inverse

end module ffrf_mpc_rbe2
