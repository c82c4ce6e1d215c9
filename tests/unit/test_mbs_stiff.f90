!> Generalized-alpha (ffrf_mbs_generalized_alpha) on a stiff element whose force is a statically
!> indeterminate reaction: two unit masses on a line joined by a spring of stiffness k and rest
!> length L = 1 m, both positions prescribed,
!>     Phi_1 = x_1 - s(t) = 0,   Phi_2 = x_2 - s(t) - L = 0,   s(t) = A sin(omega t),
!>     m x_1'' + lambda_1 = k (x_2 - x_1 - L),   m x_2'' + lambda_2 = -k (x_2 - x_1 - L),
!> A = 0.5 m, omega = 2 pi rad/s. Exact: x_2 - x_1 = L, the spring is unloaded and
!> lambda_1 = lambda_2 = -m s'' = m A omega^2 sin(omega t): the split of the inertia force
!> between the two rows is fixed only through the spring, as for the constraint rows of a
!> mechanism that are independent only through stiff modal coordinates (test_mbs_flexible_engine).
!> Round-off: x is known to eps |x|, so the spring force is known only to about k eps |x|
!> (0.2 N for k = 1e15), far above the residual tolerance rtol |lambda| = 2e-9 N and the
!> increment tolerance lambda_atol + rtol |lambda|. Before the round-off floors of
!> ffrf_mbs_generalized_alpha (noise_floor) the Newton iterations cycled at that level (x_2
!> toggling by one ulp, the residual at k ulp(x)) and the runs failed for k >= 1e9 (measured:
!> no convergence down to min_step at t = 0.0079 s for k = 1e9, 1e12 and 1e15).
!>
!> Asserted for k = 1e6, 1e9, 1e12, 1e15 N/m (omega_spring h = 1.4 .. 4.5e4 with h = 1e-3 s;
!> 0.25 s, rho_inf = 0.8, newton_atol 1e-12, rtol 1e-10):
!>   - no rejected attempt (measured 0; 500 to 707 Newton iterations);
!>   - the split: |lambda_1 - lambda_2| at 0.25 s within 1e-7 N (measured 2.7e-9 .. 2.1e-8 N,
!>     that is 1e-7 .. 1e-1 times k eps: the floors loosen the tests only where round-off
!>     demands it);
!>   - the mean multiplier against the closed form m A omega^2 sin(omega t) within 2e-5
!>     relative: generalized-alpha's O(h^2) acceleration error for a prescribed motion, the same
!>     for every k (measured 6.95e-6 for all four).
module test_mbs_stiff
   use ffrf_core_kinds, only: dp, pi
   use ffrf_core_error, only: error_t
   use ffrf_core_strings, only: to_str
   use ffrf_mbs_dae_system, only: dae_system_t
   use ffrf_mbs_generalized_alpha, only: galpha_settings_t, galpha_integrator_t
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, report
   implicit none
   private
   public :: collect_mbs_stiff

   !> Mass (kg), rest length (m), amplitude (m) and angular frequency (rad/s) of s(t)
   real(dp), parameter :: mass = 1.0_dp, rest_length = 1.0_dp, amplitude = 0.5_dp
   real(dp), parameter :: omega = 2.0_dp * pi
   !> Tolerances: |lambda_1 - lambda_2| (N); mean multiplier against the closed form, relative
   real(dp), parameter :: split_tolerance = 1.0e-7_dp, mean_tolerance = 2.0e-5_dp

   !> The two masses with prescribed positions and the stiff spring between them.
   type, extends(dae_system_t) :: stiff_pair_t
      !> Spring stiffness (N/m)
      real(dp) :: k = 1.0e12_dp
   contains
      procedure :: num_coordinates => pair_n
      procedure :: num_constraints => pair_nc
      procedure :: mass => pair_mass
      procedure :: force => pair_force
      procedure :: constraints => pair_phi
      procedure :: constraint_jacobian => pair_jac
      procedure :: stiffness => pair_stiffness
      procedure :: constraint_rate => pair_rate
      procedure :: acceleration_rhs => pair_rhs
   end type stiff_pair_t

contains

   !> The suite.
   subroutine collect_mbs_stiff(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [new_unittest('indeterminate_reaction_through_stiff_spring', test_stiff_pair)]
   end subroutine collect_mbs_stiff

   integer function pair_n(self)
      class(stiff_pair_t), intent(in) :: self
      pair_n = 2 + 0 * int(self%k)
   end function pair_n

   integer function pair_nc(self)
      class(stiff_pair_t), intent(in) :: self
      pair_nc = 2 + 0 * int(self%k)
   end function pair_nc

   subroutine pair_mass(self, q, M, error)
      class(stiff_pair_t), intent(inout) :: self
      real(dp), intent(in) :: q(:)
      real(dp), intent(out) :: M(:, :)
      type(error_t), allocatable, intent(out) :: error
      M = 0.0_dp * (q(1) + self%k)
      M(1, 1) = mass
      M(2, 2) = mass
   end subroutine pair_mass

   subroutine pair_force(self, q, v, t, f, error)
      class(stiff_pair_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), v(:)
      real(dp), intent(in) :: t
      real(dp), intent(out) :: f(:)
      type(error_t), allocatable, intent(out) :: error
      f(1) = self%k * (q(2) - q(1) - rest_length) + 0.0_dp * (v(1) + t)
      f(2) = -f(1)
   end subroutine pair_force

   subroutine pair_phi(self, q, t, phi, error)
      class(stiff_pair_t), intent(inout) :: self
      real(dp), intent(in) :: q(:)
      real(dp), intent(in) :: t
      real(dp), intent(out) :: phi(:)
      type(error_t), allocatable, intent(out) :: error
      phi(1) = q(1) - amplitude * sin(omega * t) + 0.0_dp * self%k
      phi(2) = q(2) - amplitude * sin(omega * t) - rest_length
   end subroutine pair_phi

   subroutine pair_jac(self, q, t, Phi_q, error)
      class(stiff_pair_t), intent(inout) :: self
      real(dp), intent(in) :: q(:)
      real(dp), intent(in) :: t
      real(dp), intent(out) :: Phi_q(:, :)
      type(error_t), allocatable, intent(out) :: error
      Phi_q = 0.0_dp * (q(1) + t + self%k)
      Phi_q(1, 1) = 1.0_dp
      Phi_q(2, 2) = 1.0_dp
   end subroutine pair_jac

   !> K_t = -df/dq (exact)
   subroutine pair_stiffness(self, q, v, t, K_t, error)
      class(stiff_pair_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), v(:)
      real(dp), intent(in) :: t
      real(dp), intent(out) :: K_t(:, :)
      type(error_t), allocatable, intent(out) :: error
      K_t = self%k * reshape([1.0_dp, -1.0_dp, -1.0_dp, 1.0_dp], [2, 2]) + &
         0.0_dp * (q(1) + v(1) + t)
   end subroutine pair_stiffness

   !> Phi_t = -s'(t) (exact)
   subroutine pair_rate(self, q, t, phi_t, error)
      class(stiff_pair_t), intent(inout) :: self
      real(dp), intent(in) :: q(:)
      real(dp), intent(in) :: t
      real(dp), intent(out) :: phi_t(:)
      type(error_t), allocatable, intent(out) :: error
      phi_t = -amplitude * omega * cos(omega * t) + 0.0_dp * (q(1) + self%k)
   end subroutine pair_rate

   !> g = -Phi_tt = s''(t) (exact)
   subroutine pair_rhs(self, q, v, t, g, error)
      class(stiff_pair_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), v(:)
      real(dp), intent(in) :: t
      real(dp), intent(out) :: g(:)
      type(error_t), allocatable, intent(out) :: error
      g = -amplitude * omega**2 * sin(omega * t) + 0.0_dp * (q(1) + v(1) + self%k)
   end subroutine pair_rhs

   !> Module header: every stiffness runs without a rejected attempt, the multipliers split
   !> evenly within their round-off and follow the closed form within the scheme's error.
   subroutine test_stiff_pair(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: stiffnesses(4) = [1.0e6_dp, 1.0e9_dp, 1.0e12_dp, 1.0e15_dp]
      type(stiff_pair_t) :: pair
      type(galpha_settings_t) :: settings
      type(galpha_integrator_t) :: integrator
      real(dp) :: exact, split, deviation
      integer :: i
      settings%h = 1.0e-3_dp
      settings%t_end = 0.25_dp
      settings%rho_inf = 0.8_dp
      settings%newton_atol = 1.0e-12_dp
      settings%newton_rtol = 1.0e-10_dp
      do i = 1, size(stiffnesses)
         pair%k = stiffnesses(i)
         call integrator%init(pair, settings, [0.0_dp, rest_length], &
            [amplitude * omega, amplitude * omega], error)
         if (allocated(error)) return
         call integrator%run(pair, error)
         if (allocated(error)) return
         exact = mass * amplitude * omega**2 * sin(omega * integrator%t)
         split = abs(integrator%lambda(1) - integrator%lambda(2))
         deviation = abs(0.5_dp * (integrator%lambda(1) + integrator%lambda(2)) - exact)
         call report('k = ' // to_str(stiffnesses(i), 2) // ' N/m: ' // &
            to_str(integrator%stats%steps) // ' steps, ' // &
            to_str(integrator%stats%rejected_steps) // ' rejected, ' // &
            to_str(integrator%stats%newton_iterations) // ' iterations; lambda(0.25 s) = ' // &
            to_str(integrator%lambda(1), 12) // ', ' // to_str(integrator%lambda(2), 12) // &
            ' N (exact ' // to_str(exact, 12) // ' N): |lambda_1 - lambda_2| = ' // &
            to_str(split, 3) // ' N = ' // to_str(split / (stiffnesses(i) * &
            epsilon(1.0_dp)), 3) // ' k eps, mean - exact = ' &
            // to_str(deviation / exact, 3) // ' relative')
         call check(error, 'k = ' // to_str(stiffnesses(i), 2) // ' N/m: ' // &
            to_str(integrator%stats%rejected_steps) // ' rejected attempts, expected none', &
            integrator%stats%rejected_steps == 0)
         if (allocated(error)) return
         call check_close(error, 'k = ' // to_str(stiffnesses(i), 2) // ' N/m: lambda_1 - ' // &
            'lambda_2 (unloaded spring)', integrator%lambda(1) - integrator%lambda(2), 0.0_dp, &
            atol=split_tolerance)
         if (allocated(error)) return
         call check_close(error, 'k = ' // to_str(stiffnesses(i), 2) // ' N/m: mean ' // &
            'multiplier at 0.25 s vs m A omega^2', 0.5_dp * (integrator%lambda(1) + &
            integrator%lambda(2)), exact, rtol=mean_tolerance)
         if (allocated(error)) return
      end do
   end subroutine test_stiff_pair

end module test_mbs_stiff

program main_mbs_stiff
   use ffrf_testing, only: unittest_t, run_suite
   use test_mbs_stiff, only: collect_mbs_stiff
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_mbs_stiff(tests)
   call run_suite('mbs_stiff', tests)
end program main_mbs_stiff
