!> Velocities and accelerations made consistent with the constraints of a mechanism
!> (Nikravesh 1988, ch. 7, velocity and acceleration analysis; theory.md 4.3): the index-3
!> generalized-alpha solution satisfies Phi(q, t) = 0 to the Newton tolerance but its v and q''
!> satisfy the hidden constraints
!>     Phi_q v + Phi_t = 0,     Phi_q q'' = g(q, v, t)   (g: ffrf_mbs_mechanism acceleration_rhs)
!> only to O(h^2). `consistent_motion` removes their violation by the minimum-norm corrections
!>     v <- v - Phi_q^+ (Phi_q v + Phi_t),    a <- a - Phi_q^+ (Phi_q a - g(q, v_new, t)),
!> (Phi_q^+ by a rank-revealing least squares, so redundant rows are harmless). For a mechanism
!> whose degrees of freedom are all driven (kinematic analysis) the corrected v and a are the
!> exact ones at the given q; otherwise they are the nearest consistent ones. Output only: the
!> integrator's state is not changed.
module ffrf_mbs_kinematic_projection
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, add_context
   use ffrf_la_dense, only: min_norm_solve
   use ffrf_mbs_mechanism, only: mechanism_t
   implicit none
   private
   public :: consistent_motion

   !> Relative rank tolerance of the least-squares corrections
   real(dp), parameter :: rank_rcond = 1.0e-10_dp

contains

   !> Project v and a onto the velocity and acceleration constraints at (q, t) (module header).
   subroutine consistent_motion(mech, q, t, v, a, error)
      !> The mechanism
      class(mechanism_t), intent(inout) :: mech
      !> Coordinates (consistent positions)
      real(dp), intent(in) :: q(:)
      !> Time (s)
      real(dp), intent(in) :: t
      !> Velocities, corrected in place
      real(dp), intent(inout) :: v(:)
      !> Accelerations q'', corrected in place
      real(dp), intent(inout) :: a(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: Phi_q(:, :), phi_t(:), g(:)
      allocate (Phi_q(mech%num_constraints(), size(q)), phi_t(mech%num_constraints()))
      allocate (g(mech%num_constraints()))
      call mech%constraint_jacobian(q, t, Phi_q, error)
      if (.not. allocated(error)) call mech%constraint_rate(q, t, phi_t, error)
      if (.not. allocated(error)) call correct(Phi_q, phi_t, v, error)
      if (allocated(error)) then
         call add_context(error, 'velocity projection')
         return
      end if
      call mech%acceleration_rhs(q, v, t, g, error)
      if (.not. allocated(error)) call correct(Phi_q, -g, a, error)
      if (allocated(error)) call add_context(error, 'acceleration projection')
   end subroutine consistent_motion

   !> x <- x - dx with the minimum-norm dx of Phi_q dx = Phi_q x + offset (module header).
   subroutine correct(Phi_q, offset, x, error)
      real(dp), intent(in) :: Phi_q(:, :), offset(:)
      real(dp), intent(inout) :: x(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: dx(size(x))
      integer :: rank
      call min_norm_solve(Phi_q, matmul(Phi_q, x) + offset, dx, rank_rcond, rank, error)
      if (.not. allocated(error)) x = x - dx
   end subroutine correct

end module ffrf_mbs_kinematic_projection
