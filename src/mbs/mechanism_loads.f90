!> Applied loads and driving laws of a mechanism (ffrf_mbs_mechanism; scene.md "Loads").
!>
!> A load acts on one body at one of its markers, either as a force along a fixed global direction
!> (LOAD_FORCE) or as a moment about a fixed global axis (LOAD_TORQUE). Its magnitude is a
!> function of the time t, the rotor angle phi (rad, unwrapped over many revolutions) and the
!> rotor speed omega = dphi/dt (rad/s) that the mechanism measures on its rotor body (0 without
!> one; ffrf_mbs_mechanism set_rotor). `load_t` is the extension point for applied loads: each
!> kind of load is a small type that extends it and implements `magnitude(t, phi, omega)`; the
!> mechanism applies magnitude * direction at the marker, differentiates it for the Newton
!> tangent (the marker force exactly, the magnitude's dependence on phi and omega through
!> `magnitude_rates`, a central difference unless the load overrides it with its exact
!> derivatives) and counts its power Q . v in the energy balance. Applications register their own
!> kinds with add_load (an application's own loads live with it, under src/app/). General
!> laws kept here:
!>
!> | type                 | magnitude                                                      |
!> |----------------------|----------------------------------------------------------------|
!> | constant_load_t      | value                                                          |
!> | drag_torque_t        | -c omega |omega|  (= -c omega^2 for omega >= 0, always opposing) |
!> | timed_load_t         | value g(t), g a time function (ffrf_mbs_time_function: ramp,    |
!> |                      | smooth step, table ...; docs/mechanisms.md "Laws over time")   |
!>
!> The generalized force of a load on its body is L_r^T F + L_w^T M (theory.md 3.5; body_t
!> marker_generalized_force) and its power is F . r_dot + M . omega = Q . v.
!>
!> A driving law f(t) prescribes a body's rotation about the global z axis (a rheonomic
!> constraint in ffrf_mbs_mechanism); `drive_law_t%evaluate(t)` returns f, f' and f''.
module ffrf_mbs_mechanism_loads
   use ffrf_core_kinds, only: dp
   use ffrf_mbs_dae_system, only: fd_step
   use ffrf_mbs_time_function, only: time_function_t
   implicit none
   private
   public :: load_t, constant_load_t, drag_torque_t, timed_load_t
   public :: drive_law_t, polynomial_drive_t
   public :: LOAD_FORCE, LOAD_TORQUE

   !> Load kind: a force along `direction` at the marker
   integer, parameter :: LOAD_FORCE = 1
   !> Load kind: a moment about `direction` on the body (at the marker, for a flexible body)
   integer, parameter :: LOAD_TORQUE = 2

   !> A force or moment of magnitude magnitude(t, phi, omega) along a fixed global direction.
   type, abstract :: load_t
      !> LOAD_FORCE or LOAD_TORQUE
      integer :: kind = LOAD_FORCE
      !> Mechanism index of the loaded body (as add_body returned it)
      integer :: body = 0
      !> Marker of the body where the force acts (a moment on a rigid body does not depend on it)
      integer :: marker = 1
      !> Unit global direction of the force, or axis of the moment (normalised by add_load)
      real(dp) :: direction(3) = [0.0_dp, 0.0_dp, 1.0_dp]
      !> Name for messages
      character(len=32) :: name = 'load'
   contains
      !> Signed magnitude along direction (N or N m)
      procedure(load_magnitude), deferred :: magnitude
      !> d(magnitude)/d(rotor angle) and d(magnitude)/d(rotor speed), for the Newton tangent;
      !> the default is a central difference of magnitude, a load may give exact ones
      procedure :: magnitude_rates => load_magnitude_rates
      !> value * direction as the force (LOAD_FORCE) or the moment (LOAD_TORQUE); the other 0
      procedure :: vectors => load_vectors
   end type load_t

   abstract interface
      !> Magnitude of a load (N or N m) from the time and the rotor state.
      pure function load_magnitude(self, t, rotor_angle, rotor_speed) result(value)
         import :: load_t, dp
         implicit none
         !> The load
         class(load_t), intent(in) :: self
         !> Time (s)
         real(dp), intent(in) :: t
         !> Rotor angle, unwrapped (rad)
         real(dp), intent(in) :: rotor_angle
         !> Rotor speed (rad/s)
         real(dp), intent(in) :: rotor_speed
         real(dp) :: value
      end function load_magnitude
   end interface

   !> A load of constant magnitude.
   type, extends(load_t) :: constant_load_t
      !> Magnitude (N or N m)
      real(dp) :: value = 0.0_dp
   contains
      procedure :: magnitude => constant_magnitude
   end type constant_load_t

   !> A load value * g(t) over time (g: ffrf_mbs_time_function; it does not depend on the rotor).
   type, extends(load_t) :: timed_load_t
      !> Scale of g (N or N m per unit of g)
      real(dp) :: value = 1.0_dp
      !> The time function g
      type(time_function_t) :: law
   contains
      procedure :: magnitude => timed_magnitude
      procedure :: magnitude_rates => timed_magnitude_rates
   end type timed_load_t

   !> Quadratic drag torque (docs/scene.md "Loads": the external load): T = -c omega |omega| about +z, omega the
   !> rotor speed (= -c omega^2 while omega >= 0; the |omega| keeps it opposing the motion if the
   !> rotor ever turns back).
   type, extends(load_t) :: drag_torque_t
      !> Coefficient c (N m s^2)
      real(dp) :: coefficient = 3.6e-4_dp
   contains
      procedure :: magnitude => drag_magnitude
   end type drag_torque_t

   !> A prescribed rotation f(t) about z (rad) with its first two time derivatives.
   type, abstract :: drive_law_t
   contains
      !> [f, f', f''] at t (rad, rad/s, rad/s^2)
      procedure(drive_evaluate), deferred :: evaluate
   end type drive_law_t

   abstract interface
      !> The law and its derivatives.
      pure function drive_evaluate(self, t) result(f)
         import :: drive_law_t, dp
         implicit none
         !> The law
         class(drive_law_t), intent(in) :: self
         !> Time (s)
         real(dp), intent(in) :: t
         real(dp) :: f(3)
      end function drive_evaluate
   end interface

   !> f(t) = angle + speed t + acceleration t^2 / 2 (constant speed when acceleration = 0).
   type, extends(drive_law_t) :: polynomial_drive_t
      !> Angle at t = 0 (rad)
      real(dp) :: angle = 0.0_dp
      !> Speed at t = 0 (rad/s)
      real(dp) :: speed = 0.0_dp
      !> Constant angular acceleration (rad/s^2)
      real(dp) :: acceleration = 0.0_dp
   contains
      procedure :: evaluate => polynomial_evaluate
   end type polynomial_drive_t

contains

   !> Central differences of the magnitude in the rotor angle and speed (steps fd_step: the
   !> tangent's default; exact for magnitudes linear in them).
   pure subroutine load_magnitude_rates(self, t, rotor_angle, rotor_speed, d_angle, d_speed)
      class(load_t), intent(in) :: self
      !> Time (s)
      real(dp), intent(in) :: t
      !> Rotor angle (rad) and speed (rad/s)
      real(dp), intent(in) :: rotor_angle, rotor_speed
      !> d(magnitude)/d(angle) (per rad) and d(magnitude)/d(speed) (per rad/s)
      real(dp), intent(out) :: d_angle, d_speed
      real(dp) :: da, ds
      da = fd_step(rotor_angle)
      ds = fd_step(rotor_speed)
      d_angle = (self%magnitude(t, rotor_angle + da, rotor_speed) - &
         self%magnitude(t, rotor_angle - da, rotor_speed)) / (2.0_dp * da)
      d_speed = (self%magnitude(t, rotor_angle, rotor_speed + ds) - &
         self%magnitude(t, rotor_angle, rotor_speed - ds)) / (2.0_dp * ds)
   end subroutine load_magnitude_rates

   !> value * direction as the force (LOAD_FORCE) or as the moment (LOAD_TORQUE); the other is 0.
   pure subroutine load_vectors(self, value, force, moment)
      class(load_t), intent(in) :: self
      !> Magnitude (N or N m)
      real(dp), intent(in) :: value
      !> Force (N) and moment (N m), global
      real(dp), intent(out) :: force(3), moment(3)
      force = 0.0_dp
      moment = 0.0_dp
      if (self%kind == LOAD_FORCE) then
         force = value * self%direction
      else
         moment = value * self%direction
      end if
   end subroutine load_vectors

   !> value.
   pure function constant_magnitude(self, t, rotor_angle, rotor_speed) result(value)
      class(constant_load_t), intent(in) :: self
      !> Time (s)
      real(dp), intent(in) :: t
      !> Rotor angle (rad)
      real(dp), intent(in) :: rotor_angle
      !> Rotor speed (rad/s)
      real(dp), intent(in) :: rotor_speed
      real(dp) :: value
      value = self%value + 0.0_dp * (t + rotor_angle + rotor_speed)
   end function constant_magnitude

   !> value g(t).
   pure function timed_magnitude(self, t, rotor_angle, rotor_speed) result(value)
      class(timed_load_t), intent(in) :: self
      !> Time (s)
      real(dp), intent(in) :: t
      !> Rotor angle (rad)
      real(dp), intent(in) :: rotor_angle
      !> Rotor speed (rad/s)
      real(dp), intent(in) :: rotor_speed
      real(dp) :: value
      real(dp) :: g(3)
      g = self%law%evaluate(t)
      value = self%value * g(1) + 0.0_dp * (rotor_angle + rotor_speed)
   end function timed_magnitude

   !> 0, 0: a load over time does not depend on the rotor.
   pure subroutine timed_magnitude_rates(self, t, rotor_angle, rotor_speed, d_angle, d_speed)
      class(timed_load_t), intent(in) :: self
      !> Time (s)
      real(dp), intent(in) :: t
      !> Rotor angle (rad) and speed (rad/s)
      real(dp), intent(in) :: rotor_angle, rotor_speed
      !> d(magnitude)/d(angle) and d(magnitude)/d(speed)
      real(dp), intent(out) :: d_angle, d_speed
      d_angle = 0.0_dp * (t + rotor_angle + self%value)
      d_speed = 0.0_dp * rotor_speed
   end subroutine timed_magnitude_rates

   !> -c omega |omega|.
   pure function drag_magnitude(self, t, rotor_angle, rotor_speed) result(value)
      class(drag_torque_t), intent(in) :: self
      !> Time (s)
      real(dp), intent(in) :: t
      !> Rotor angle (rad)
      real(dp), intent(in) :: rotor_angle
      !> Rotor speed (rad/s)
      real(dp), intent(in) :: rotor_speed
      real(dp) :: value
      value = -self%coefficient * rotor_speed * abs(rotor_speed) + 0.0_dp * (t + rotor_angle)
   end function drag_magnitude

   !> [angle + speed t + acceleration t^2/2, speed + acceleration t, acceleration].
   pure function polynomial_evaluate(self, t) result(f)
      class(polynomial_drive_t), intent(in) :: self
      !> Time (s)
      real(dp), intent(in) :: t
      real(dp) :: f(3)
      f = [self%angle + self%speed * t + 0.5_dp * self%acceleration * t**2, &
         self%speed + self%acceleration * t, self%acceleration]
   end function polynomial_evaluate

end module ffrf_mbs_mechanism_loads
