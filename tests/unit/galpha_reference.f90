!> Generalized-alpha written out for the tests (Chung & Hulbert, J. Appl. Mech. 60 (1993) 371;
!> theory.md 4.1), independent of ffrf_mbs_generalized_alpha: the parameters from rho_inf and the
!> characteristic polynomial of the scheme on the linear oscillator. Shared by
!> test_stability_integrator and test_sim_model_selection.
module ffrf_test_galpha_reference
   use ffrf_core_kinds, only: dp
   implicit none
   private
   public :: galpha_parameters, galpha_characteristic

contains

   !> Chung-Hulbert parameters from rho_inf (theory.md 4.1), written out.
   pure subroutine galpha_parameters(rho_inf, alpha_m, alpha_f, gamma, beta)
      real(dp), intent(in) :: rho_inf
      real(dp), intent(out) :: alpha_m, alpha_f, gamma, beta
      alpha_m = (2.0_dp * rho_inf - 1.0_dp) / (rho_inf + 1.0_dp)
      alpha_f = rho_inf / (rho_inf + 1.0_dp)
      gamma = 0.5_dp + alpha_f - alpha_m
      beta = 0.25_dp * (gamma + 0.5_dp)**2
   end subroutine galpha_parameters

   !> Coefficients c(0:3) of the characteristic polynomial sum c_k z^k of generalized-alpha on
   !> x'' + omega^2 x = 0 with Omega = omega h (z-transform of the scheme):
   !>   [(1 - am) z + am] (z - 1)^2 + Omega^2 [(1 - af) z + af] [beta z^2 + (gamma + 1/2 -
   !>   2 beta) z + (1/2 + beta - gamma)] = 0.
   pure function galpha_characteristic(rho_inf, omega_h) result(c)
      real(dp), intent(in) :: rho_inf, omega_h
      real(dp) :: c(0:3)
      real(dp) :: am, af, gamma, beta, p, r, o2
      call galpha_parameters(rho_inf, am, af, gamma, beta)
      o2 = omega_h**2
      p = gamma + 0.5_dp - 2.0_dp * beta
      r = 0.5_dp + beta - gamma
      c(3) = (1.0_dp - am) + o2 * (1.0_dp - af) * beta
      c(2) = (3.0_dp * am - 2.0_dp) + o2 * ((1.0_dp - af) * p + af * beta)
      c(1) = (1.0_dp - 3.0_dp * am) + o2 * ((1.0_dp - af) * r + af * p)
      c(0) = am + o2 * af * r
   end function galpha_characteristic

end module ffrf_test_galpha_reference
