!> Interpolation MPC (Nastran RBE3): the virtual node moves with the weighted least-squares rigid
!> fit of the interface node motions (theory.md 1.2; MSC Nastran RBE3, Code_Aster LIAISON_RBE3):
!>
!>     min_{q_V} sum_i (u_i - S_i q_V)^T W_i (u_i - S_i q_V),   S_i = [ I3, -skew(r_i) ]
!>     q_V = G q_B,   G = (S^T W S)^{-1} S^T W      (6 x 3 nB)
!>
!> The interface nodes of solid elements carry translations only, so W_i = w_i I3 and the
!> characteristic length of Nastran's rotational weights drops out. G F = I6: a rigid motion of
!> the face is reproduced exactly at the virtual node, and the RBE3 adds no stiffness.
module ffrf_mpc_rbe3
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t
   use ffrf_mpc_rbe2, only: rbe2_matrix
   use ffrf_mpc_rigid_fit, only: weighted_rigid_fit
   implicit none
   private
   public :: rbe3_matrix

contains

   !> G (6 x 3 nB) of q_V = G q_B. When S^T W S is singular (collinear nodes: the rotation about
   !> the line is not determined by the nodes), G uses its pseudo-inverse, so that rotation reads
   !> zero, and `undefined_direction` gives the rotation axis that cannot be carried.
   subroutine rbe3_matrix(node_xyz, weights, virtual_xyz, length_scale, G, rank_deficient, &
         undefined_direction, error)
      !> Interface node positions, (3, nB)
      real(dp), intent(in) :: node_xyz(:, :)
      !> Weights w_i, (nB): positive sum, zero and small negative ones allowed (rigid_fit)
      real(dp), intent(in) :: weights(:)
      !> Virtual (reference) node position
      real(dp), intent(in) :: virtual_xyz(3)
      !> Characteristic length that makes rotations comparable with translations (m)
      real(dp), intent(in) :: length_scale
      !> G, (6, 3 nB)
      real(dp), allocatable, intent(out) :: G(:, :)
      !> True if the node set cannot carry all three rotations
      logical, intent(out) :: rank_deficient
      !> Rotation axis left undefined (zero if none)
      real(dp), intent(out) :: undefined_direction(3)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: S(:, :)
      ! S_i = [I3, -skew(r_i)] is the RBE2 row block of node i.
      call rbe2_matrix(node_xyz, virtual_xyz, S)
      call weighted_rigid_fit(S, weights, length_scale, G, rank_deficient, undefined_direction, &
         error)
   end subroutine rbe3_matrix

end module ffrf_mpc_rbe3
