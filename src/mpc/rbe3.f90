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
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_la_dense, only: skew, symmetric_eigen
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
      !> Weights w_i > 0, (nB)
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
      real(dp) :: stws(6, 6), values(6), vectors(6, 6), scale(6), inverse(6, 6), s_i(3, 6)
      integer :: i, k, num_nodes
      num_nodes = size(node_xyz, 2)
      if (any(weights <= 0.0_dp)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'RBE3: weights must be positive')
         return
      end if
      if (length_scale <= 0.0_dp) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'RBE3: non-positive length scale ' // &
            to_str(length_scale))
         return
      end if
      scale = [1.0_dp, 1.0_dp, 1.0_dp, length_scale, length_scale, length_scale]
      ! S^T W S, rotations scaled by the interface size for a dimensionless rank test.
      stws = 0.0_dp
      allocate (G(6, 3 * num_nodes))
      do i = 1, num_nodes
         s_i = node_s_matrix(node_xyz(:, i) - virtual_xyz)
         do k = 1, 6
            s_i(:, k) = s_i(:, k) / scale(k)
         end do
         stws = stws + weights(i) * matmul(transpose(s_i), s_i)
         G(:, 3 * i - 2:3 * i) = weights(i) * transpose(s_i)      ! S^T W, scaled
      end do
      call symmetric_eigen(stws, values, vectors, error)
      if (allocated(error)) return
      rank_deficient = values(1) <= 1.0e-10_dp * values(6)
      undefined_direction = 0.0_dp
      if (rank_deficient) undefined_direction = vectors(4:6, 1) / norm2(vectors(4:6, 1))
      inverse = 0.0_dp
      do k = 1, 6
         if (values(k) > 1.0e-10_dp * values(6)) inverse = inverse + &
            spread(vectors(:, k), 2, 6) * spread(vectors(:, k), 1, 6) / values(k)
      end do
      G = matmul(inverse, G)
      ! Undo the scaling: q_V = diag(1/scale) q_V(scaled).
      do k = 1, 6
         G(k, :) = G(k, :) / scale(k)
      end do
   end subroutine rbe3_matrix

   !> S_i = [I3, -skew(r_i)]: rigid motion of a point at offset r_i from the virtual node.
   pure function node_s_matrix(r) result(s)
      real(dp), intent(in) :: r(3)
      real(dp) :: s(3, 6)
      s = 0.0_dp
      s(1, 1) = 1.0_dp
      s(2, 2) = 1.0_dp
      s(3, 3) = 1.0_dp
      s(:, 4:6) = -skew(r)
   end function node_s_matrix

end module ffrf_mpc_rbe3
