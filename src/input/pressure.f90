!> Engine data of the in-cylinder pressure model (&pressure; reader in src/input/nml_mechanism.f90,
!> model in src/app/engine/pressure.f90), with the defaults of the reference engine (scene.md).
module ffrf_input_pressure
   use ffrf_core_kinds, only: dp
   implicit none
   private
   public :: pressure_input_t

   !> Engine data of the pressure model; SI units, angles in degrees of the 720 deg cycle. Defaults:
   !> the reference engine of scene.md.
   type :: pressure_input_t
      !> Bore B (m)
      real(dp) :: bore = 0.080_dp
      !> Stroke S = 2 r (m)
      real(dp) :: stroke = 0.090_dp
      !> Conrod length l between the pin centres (m), l > S/2
      real(dp) :: conrod_length = 0.150_dp
      !> Compression ratio r_c = (V_c + V_d) / V_c, > 1
      real(dp) :: compression_ratio = 10.0_dp
      !> Intake pressure (Pa), also p at the start of compression (180 deg)
      real(dp) :: intake_pressure = 1.0e5_dp
      !> Exhaust pressure (Pa), from blow-down at 540 deg to 720 deg
      real(dp) :: exhaust_pressure = 1.05e5_dp
      !> Polytropic exponent n of compression and expansion, > 1
      real(dp) :: polytropic_exponent = 1.32_dp
      !> Wiebe efficiency parameter a (a = 5: 99.3 % burned after the duration)
      real(dp) :: wiebe_a = 5.0_dp
      !> Wiebe form factor m
      real(dp) :: wiebe_m = 2.0_dp
      !> Start of combustion theta_0 (deg of the cycle, firing TDC at 360)
      real(dp) :: combustion_start_deg = 350.0_dp
      !> Combustion duration Dtheta (deg)
      real(dp) :: combustion_duration_deg = 60.0_dp
      !> Heat released per cycle Q (J); negative: tuned so that the peak is target_peak_pressure
      real(dp) :: heat_per_cycle = -1.0_dp
      !> Peak pressure the tuned heat gives (Pa); used when heat_per_cycle < 0
      real(dp) :: target_peak_pressure = 55.0e5_dp
      !> Pressure on the underside of the piston (Pa): force = -(p - p_ref) A
      real(dp) :: reference_pressure = 1.0e5_dp
      !> Largest RK4 step of the closed part (deg); the step is also at most duration / 200
      real(dp) :: step_deg = 0.05_dp
   end type pressure_input_t

end module ffrf_input_pressure
