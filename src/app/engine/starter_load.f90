!> The engine's starter motor as a mechanism load (scene.md "Loads"): a `load_t` of
!> ffrf_mbs_mechanism_loads on the crankshaft, the mechanism's rotor, whose speed omega it reads.
module ffrf_app_engine_starter_load
   use ffrf_core_kinds, only: dp
   use ffrf_mbs_mechanism_loads, only: load_t
   implicit none
   private
   public :: starter_torque_t

   !> Starter motor (scene.md): T = T0 (1 - omega / omega_0) for t <= t_off and only while
   !> positive; kind LOAD_TORQUE about +z, omega the crank (rotor) speed.
   type, extends(load_t) :: starter_torque_t
      !> Stall torque T0 (N m)
      real(dp) :: stall_torque = 40.0_dp
      !> No-load speed omega_0 (rad/s)
      real(dp) :: free_speed = 157.0_dp
      !> Switch-off time t_off (s)
      real(dp) :: switch_off = 0.5_dp
   contains
      procedure :: magnitude => starter_magnitude
   end type starter_torque_t

contains

   !> max(0, T0 (1 - omega/omega_0)) for t <= t_off, else 0.
   pure function starter_magnitude(self, t, rotor_angle, rotor_speed) result(value)
      class(starter_torque_t), intent(in) :: self
      !> Time (s)
      real(dp), intent(in) :: t
      !> Crank angle: the mechanism's rotor angle (rad)
      real(dp), intent(in) :: rotor_angle
      !> Crank speed: the mechanism's rotor speed (rad/s)
      real(dp), intent(in) :: rotor_speed
      real(dp) :: value
      value = 0.0_dp * rotor_angle
      if (t <= self%switch_off) value = max(0.0_dp, self%stall_torque * &
         (1.0_dp - rotor_speed / self%free_speed))
   end function starter_magnitude

end module ffrf_app_engine_starter_load
