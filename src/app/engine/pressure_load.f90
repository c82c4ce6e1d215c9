!> The engine's in-cylinder gas force as a mechanism load (scene.md "Loads"): a `load_t` of
!> ffrf_mbs_mechanism_loads whose magnitude is pressure_model_t%piston_force(phi) =
!> -(p(phi) - p_ref) pi B^2/4 at the unwrapped crank angle phi.
module ffrf_app_engine_pressure_load
   use ffrf_core_kinds, only: dp
   use ffrf_mbs_mechanism_loads, only: load_t
   use ffrf_app_engine_pressure, only: pressure_model_t
   implicit none
   private
   public :: pressure_force_t

   !> In-cylinder gas force on the piston (scene.md "Loads"): kind LOAD_FORCE, direction +y (the
   !> pressure model gives the force along +y, negative while p > p_ref).
   type, extends(load_t) :: pressure_force_t
      !> Initialised pressure model (pressure_model_t%init)
      type(pressure_model_t) :: model
   contains
      procedure :: magnitude => pressure_magnitude
   end type pressure_force_t

contains

   !> Gas force along +y at the unwrapped crank angle (pressure_model_t%piston_force).
   !> (The mechanism's rotor is the crankshaft: its angle and speed are the crank's.)
   pure function pressure_magnitude(self, t, rotor_angle, rotor_speed) result(value)
      class(pressure_force_t), intent(in) :: self
      !> Time (s)
      real(dp), intent(in) :: t
      !> Crank angle: the mechanism's rotor angle (rad)
      real(dp), intent(in) :: rotor_angle
      !> Crank speed: the mechanism's rotor speed (rad/s)
      real(dp), intent(in) :: rotor_speed
      real(dp) :: value
      value = self%model%piston_force(rotor_angle) + 0.0_dp * (t + rotor_speed)
   end function pressure_magnitude

end module ffrf_app_engine_pressure_load
