!> A force element between markers of two bodies (ffrf_mbs_spring_damper, ffrf_mbs_torsion_spring,
!> ffrf_mbs_bushing): what the mechanism needs to assemble any kind of them in one loop
!> (mechanism_force_elements.f90): its two bodies, and its generalized forces on them or their
!> tangents. Each kind keeps its own state type (length, angle, deflections) for sensors and
!> output. A new kind extends force_element_t and implements `bodies` and `terms`.
module ffrf_mbs_force_element
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t
   use ffrf_mbs_body, only: body_t
   implicit none
   private
   public :: force_element_t, marker_pair_forces

   !> A force element between two bodies (no components of its own: each kind names its ends).
   type, abstract :: force_element_t
   contains
      !> Mechanism indices [body a, body b]
      procedure(element_bodies), deferred :: bodies
      !> Generalized forces Q or tangents K = -dQ/dx, C = -dQ/dv over x = [q_a; q_b]
      procedure(element_terms), deferred :: terms
   end type force_element_t

   abstract interface
      !> Mechanism indices of the element's two bodies, [a, b].
      pure function element_bodies(self) result(bodies)
         import :: force_element_t
         implicit none
         !> The element
         class(force_element_t), intent(in) :: self
         integer :: bodies(2)
      end function element_bodies

      !> Its generalized forces Q on body a (first size(q_a) rows) and body b (Q present), or
      !> the tangents K = -dQ/dx and C = -dQ/dv, x = [q_a; q_b] (K and C present), at body a's
      !> and body b's coordinates and velocities (q_a, v_a; q_b, v_b: the bodies' own, empty for
      !> the ground) at time t (s, for messages). A state the element cannot act in (a spring
      !> of zero length, a non-finite force) is a numeric error.
      subroutine element_terms(self, body_a, q_a, v_a, body_b, q_b, v_b, t, error, Q, K, C)
         import :: force_element_t, body_t, error_t, dp
         implicit none
         class(force_element_t), intent(in) :: self
         class(body_t), intent(in) :: body_a, body_b
         real(dp), intent(in) :: q_a(:), v_a(:), q_b(:), v_b(:), t
         type(error_t), allocatable, intent(out) :: error
         real(dp), intent(out), optional :: Q(:), K(:, :), C(:, :)
      end subroutine element_terms
   end interface

contains

   !> Generalized forces of an action-reaction pair: the global force F and moment M on
   !> marker_a of body a (L_r,a^T F + L_w,a^T M) and -F, -M on marker_b of body b; zero for a
   !> body without coordinates (the ground). For the force elements between two markers.
   pure subroutine marker_pair_forces(body_a, q_a, marker_a, body_b, q_b, marker_b, force, &
      moment, f_a, f_b)
      !> Body a, its coordinates and marker
      class(body_t), intent(in) :: body_a
      real(dp), intent(in) :: q_a(:)
      integer, intent(in) :: marker_a
      !> Body b, its coordinates and marker
      class(body_t), intent(in) :: body_b
      real(dp), intent(in) :: q_b(:)
      integer, intent(in) :: marker_b
      !> Force (N) and moment (N m) on marker a, global
      real(dp), intent(in) :: force(3), moment(3)
      !> Generalized forces (size of q_a and q_b)
      real(dp), intent(out) :: f_a(:), f_b(:)
      f_a = 0.0_dp
      f_b = 0.0_dp
      if (size(q_a) > 0) f_a = body_a%marker_generalized_force(q_a, marker_a, force, moment)
      if (size(q_b) > 0) f_b = body_b%marker_generalized_force(q_b, marker_b, -force, -moment)
   end subroutine marker_pair_forces

end module ffrf_mbs_force_element
