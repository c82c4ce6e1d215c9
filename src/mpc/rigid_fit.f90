!> Weighted least-squares rigid fit of a node set, shared by RBE2 and RBE3 (theory.md 1.1, 1.2):
!>
!>     G = (F^T W F)^+ F^T W,   F_i = [ I3, -skew(r_i) ],   W = diag(w_i I3)      (6 x 3 nB)
!>
!> With unit weights G = F^+ (RBE2's recovery of q_V from q_B); with the RBE3 weights it is
!> Nastran's RBE3 interpolation. Rotations are scaled by a length so that the rank test of the
!> 6 x 6 normal matrix is dimensionless; a rank-deficient set (collinear nodes) uses the
!> pseudo-inverse, reports the undefined rotation axis, and that rotation reads zero.
!> The weights need not all be positive: consistent area weights give the corners of a flat Tri6
!> face 0 and those of a curved one small values of either sign (theory.md 1.3); G F = I6 holds
!> for any weights whose normal matrix F^T W F is positive (semi-)definite, which is checked.
module ffrf_mpc_rigid_fit
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_la_dense, only: symmetric_eigen
   implicit none
   private
   public :: weighted_rigid_fit

   !> Relative eigenvalue of the scaled normal matrix below which a direction is undefined
   real(dp), parameter :: rank_tolerance = 1.0e-10_dp

contains

   !> G = (F^T W F)^+ F^T W with W_i = w_i I3.
   subroutine weighted_rigid_fit(F, weights, length_scale, G, rank_deficient, &
         undefined_direction, error)
      !> Rigid-motion matrix of the nodes, (3 nB, 6)
      real(dp), intent(in) :: F(:, :)
      !> Node weights w_i, (nB): finite, positive sum (zero and small negative ones allowed)
      real(dp), intent(in) :: weights(:)
      !> Characteristic length that makes rotations comparable with translations (m)
      real(dp), intent(in) :: length_scale
      !> G, (6, 3 nB)
      real(dp), allocatable, intent(out) :: G(:, :)
      !> True if the nodes cannot carry all three rotations
      logical, intent(out) :: rank_deficient
      !> Rotation axis left undefined (zero if none)
      real(dp), intent(out) :: undefined_direction(3)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: normal(6, 6), values(6), vectors(6, 6), scale(6), inverse(6, 6)
      integer :: i, k
      if (.not. (all(abs(weights) <= huge(1.0_dp)) .and. sum(weights) > 0.0_dp)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'rigid fit: the weights must be finite ' // &
            'with a positive sum; their sum is ' // to_str(sum(weights)))
         return
      end if
      if (length_scale <= 0.0_dp) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'rigid fit: non-positive length scale ' // &
            to_str(length_scale))
         return
      end if
      scale = [1.0_dp, 1.0_dp, 1.0_dp, length_scale, length_scale, length_scale]
      ! G holds (F diag(1/scale))^T W until the pseudo-inverse is applied.
      allocate (G(6, size(F, 1)))
      do k = 1, 6
         G(k, :) = F(:, k) / scale(k)
      end do
      do i = 1, size(weights)
         G(:, 3 * i - 2:3 * i) = weights(i) * G(:, 3 * i - 2:3 * i)
      end do
      normal = matmul(G, F)
      do k = 1, 6
         normal(:, k) = normal(:, k) / scale(k)
      end do
      call symmetric_eigen(normal, values, vectors, error)
      if (allocated(error)) return
      if (values(1) < -rank_tolerance * values(6)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'rigid fit: the weights make the normal ' // &
            'matrix indefinite (eigenvalue ' // to_str(values(1) / values(6)) // ' of the ' // &
            'largest); negative weights outweigh the positive ones')
         return
      end if
      rank_deficient = values(1) <= rank_tolerance * values(6)
      undefined_direction = 0.0_dp
      if (rank_deficient) undefined_direction = vectors(4:6, 1) / norm2(vectors(4:6, 1))
      inverse = 0.0_dp
      do k = 1, 6
         if (values(k) > rank_tolerance * values(6)) inverse = inverse + &
            spread(vectors(:, k), 2, 6) * spread(vectors(:, k), 1, 6) / values(k)
      end do
      G = matmul(inverse, G)
      ! Back from the scaled rotations: q_V = diag(1/scale) q_V(scaled).
      do k = 1, 6
         G(k, :) = G(k, :) / scale(k)
      end do
   end subroutine weighted_rigid_fit

end module ffrf_mpc_rigid_fit
