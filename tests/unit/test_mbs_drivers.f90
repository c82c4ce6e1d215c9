!> Laws over time (ffrf_mbs_time_function), drivers of joints (ffrf_mbs_joint_driver) and loads
!> over time (timed_load_t), against independent references:
!> - time functions against closed forms: a not-a-knot cubic spline through 7 points of a cubic
!>   reproduces it, its derivatives and its integral (round-off, 2e-13 relative); derivatives of
!>   every kind against central differences; the smooth step's integral against Kane's spin-up
!>   law; a periodic table repeats (g(t + P) = g(t)) and its spline has equal g', g'' at the wrap;
!>   the integral of a periodic table against composite Simpson quadrature; bad tables refused;
!> - a rigid link (m, L) on a revolute joint to the ground under gravity, its angle driven (speed
!>   a smooth step 0 -> 3 rad/s over 0.4 s, then constant): the driving torque against
!>   tau = I_O theta'' + m g (L/2) cos(theta), I_O = m L^2/3; the joint angle against the law;
!>   the energy balance W = T + V - T_0 - V_0 (W: gravity's and the driver's work);
!> - a mass on a prismatic joint with a spring k to the ground, its travel driven by a smooth step
!>   0 -> 0.1 m: the driving force against F = m s'' + k s;
!> - Phi_q, Phi_t and the acceleration right-hand side of the driver rows against central
!>   differences of the mechanism's own constraints;
!> - a free mass under a force given by a table (a ramp 0 -> F_0 over T, held): x(t) against
!>   F_0 t^3 / (6 m T), then x(T) + x'(T)(t - T) + F_0 (t - T)^2 / (2 m);
!> - a driver on a spherical joint and on an unknown joint refused.
module test_mbs_drivers
   use ffrf_core_kinds, only: dp, pi
   use ffrf_core_error, only: error_t
   use ffrf_core_strings, only: to_str
   use ffrf_core_kinds, only: ip
   use ffrf_la_sparse, only: csr_t, csr_from_coo
   use ffrf_mbs_rigid_body, only: rigid_body_t, ground_t
   use ffrf_mbs_flexible_body, only: flexible_body_t
   use ffrf_mbs_mechanism, only: mechanism_t
   use ffrf_mbs_joints, only: JOINT_REVOLUTE, JOINT_PRISMATIC, JOINT_SPHERICAL
   use ffrf_mbs_joint_driver, only: joint_driver_t
   use ffrf_mbs_time_function, only: time_function_t, new_time_function
   use ffrf_mbs_mechanism_loads, only: timed_load_t, LOAD_FORCE
   use ffrf_mbs_spring_damper, only: spring_damper_t
   use ffrf_mbs_generalized_alpha, only: galpha_settings_t, galpha_integrator_t
   use ffrf_mbs_energy_balance, only: energy_balance_t
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, report
   implicit none
   private
   public :: collect_mbs_drivers

   real(dp), parameter :: identity(3, 3) = reshape([1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, &
      0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp], [3, 3])
   !> Pendulum: mass (kg), length (m), gravity (m/s^2), final speed (rad/s), spin-up time (s)
   real(dp), parameter :: link_mass = 2.0_dp, link_length = 0.5_dp, gravity = 9.81_dp
   real(dp), parameter :: final_speed = 3.0_dp, spin_time = 0.4_dp

contains

   !> The suite.
   subroutine collect_mbs_drivers(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [new_unittest('spline_reproduces_cubic', test_spline_cubic), &
         new_unittest('derivatives_vs_differences', test_derivatives), &
         new_unittest('smooth_step_is_spin_up', test_smooth_step), &
         new_unittest('periodic_table', test_periodic), &
         new_unittest('bad_tables_refused', test_bad_tables), &
         new_unittest('driver_time_terms', test_driver_time_terms), &
         new_unittest('driven_pendulum_torque_energy', test_pendulum), &
         new_unittest('prismatic_spring_force', test_prismatic), &
         new_unittest('table_force_on_free_mass', test_table_load), &
         new_unittest('driver_joint_refused', test_driver_refused)]
   end subroutine collect_mbs_drivers

   !> p(t) = 1 - 2 t + 0.5 t^2 + 3 t^3 and its derivatives, integral from 0.
   pure function cubic(t) result(p)
      real(dp), intent(in) :: t
      real(dp) :: p(4)
      p = [1.0_dp - 2.0_dp * t + 0.5_dp * t**2 + 3.0_dp * t**3, -2.0_dp + t + 9.0_dp * t**2, &
         1.0_dp + 18.0_dp * t, t - t**2 + t**3 / 6.0_dp + 0.75_dp * t**4]
   end function cubic

   !> Not-a-knot spline through 7 unevenly spaced points of a cubic: value, g', g'' and the
   !> integral at 40 times inside equal the cubic's to 2e-13 relative (round-off of the 7 x 7
   !> solve; measured 1.6e-14).
   subroutine test_spline_cubic(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: times(7) = [0.0_dp, 0.1_dp, 0.25_dp, 0.3_dp, 0.55_dp, 0.8_dp, 1.0_dp]
      type(time_function_t) :: fun
      real(dp) :: y(7), g(3), p(4), worst, t
      integer :: i
      do i = 1, 7
         p = cubic(times(i))
         y(i) = p(1)
      end do
      call new_time_function('table', 'test', fun, error, times=times, values=y, &
         interpolation='cubic', beyond='hold')
      if (allocated(error)) return
      worst = 0.0_dp
      do i = 1, 40
         t = 0.999_dp * real(i, dp) / 40.0_dp
         g = fun%evaluate(t)
         p = cubic(t)
         worst = max(worst, maxval(abs([g, fun%integral(t)] - p) / max(1.0_dp, abs(p))))
      end do
      call report('spline vs cubic: largest relative difference ' // to_str(worst, 3))
      call check_close(error, 'spline reproduces the cubic', worst, 0.0_dp, atol=2.0e-13_dp)
   end subroutine test_spline_cubic

   !> g' and g'' of every kind against central differences of g and g' (step 1e-6 s: error
   !> ~1e-10 of the scale), the integral's derivative against g; at 9 generic times (asserted
   !> 3e-9, g' errors scaled by 1/10 and g'' by 1/100; measured 3.3e-10).
   subroutine test_derivatives(error)
      type(error_t), allocatable, intent(out) :: error
      type(time_function_t) :: funs(6)
      real(dp), parameter :: h = 1.0e-6_dp
      real(dp) :: gp(3), gm(3), g(3), t, worst
      integer :: k, i
      call new_time_function('constant_speed', 'test', funs(1), error, initial=0.3_dp, &
         speed=2.0_dp)
      if (.not. allocated(error)) call new_time_function('ramp', 'test', funs(2), error, &
         initial=1.0_dp, final=-2.0_dp, t_start=0.1_dp, duration=0.5_dp)
      if (.not. allocated(error)) call new_time_function('smooth_step', 'test', funs(3), error, &
         initial=1.0_dp, final=4.0_dp, t_start=0.2_dp, duration=0.6_dp)
      if (.not. allocated(error)) call new_time_function('table', 'test', funs(4), error, &
         times=[0.0_dp, 0.3_dp, 0.5_dp, 0.9_dp], values=[0.0_dp, 1.0_dp, 0.5_dp, 2.0_dp], &
         interpolation='linear', beyond='hold')
      if (.not. allocated(error)) call new_time_function('table', 'test', funs(5), error, &
         times=[0.0_dp, 0.3_dp, 0.5_dp, 0.9_dp, 1.2_dp], values=[0.0_dp, 1.0_dp, 0.5_dp, &
         2.0_dp, 1.0_dp], interpolation='cubic', beyond='hold')
      if (.not. allocated(error)) call new_time_function('table', 'test', funs(6), error, &
         times=[0.0_dp, 0.2_dp, 0.5_dp, 0.7_dp], values=[1.0_dp, 3.0_dp, -1.0_dp, 1.0_dp], &
         interpolation='cubic', beyond='periodic')
      if (allocated(error)) return
      worst = 0.0_dp
      do k = 1, size(funs)
         do i = 1, 9
            t = 0.137_dp * real(i, dp) + 0.011_dp
            g = funs(k)%evaluate(t)
            gp = funs(k)%evaluate(t + h)
            gm = funs(k)%evaluate(t - h)
            worst = max(worst, abs(g(2) - (gp(1) - gm(1)) / (2.0_dp * h)) / 10.0_dp, &
               abs(g(3) - (gp(2) - gm(2)) / (2.0_dp * h)) / 100.0_dp, &
               abs(g(1) - (funs(k)%integral(t + h) - funs(k)%integral(t - h)) / (2.0_dp * h)))
         end do
      end do
      call report('derivatives and integral vs central differences: worst ' // to_str(worst, 3))
      call check_close(error, 'derivatives vs differences', worst, 0.0_dp, atol=3.0e-9_dp)
   end subroutine test_derivatives

   !> Smooth step of the speed 0 -> Omega_s over T, integrated: Kane's spin-up angle
   !> theta = (Omega_s/T)(t^2/2 + (T/(2 pi))^2 (cos(2 pi t/T) - 1)), then Omega_s T/2 +
   !> Omega_s (t - T), to 5e-14 relative (measured 4.4e-15).
   subroutine test_smooth_step(error)
      type(error_t), allocatable, intent(out) :: error
      type(time_function_t) :: fun
      real(dp), parameter :: omega_s = 4.0_dp, ramp = 15.0_dp
      real(dp) :: t, theta, worst
      integer :: i
      call new_time_function('smooth_step', 'test', fun, error, initial=0.0_dp, final=omega_s, &
         t_start=0.0_dp, duration=ramp)
      if (allocated(error)) return
      worst = 0.0_dp
      do i = 1, 20
         t = real(i, dp)
         if (t <= ramp) then
            theta = omega_s / ramp * (0.5_dp * t**2 + (ramp / (2.0_dp * pi))**2 * &
               (cos(2.0_dp * pi * t / ramp) - 1.0_dp))
         else
            theta = 0.5_dp * omega_s * ramp + omega_s * (t - ramp)
         end if
         worst = max(worst, abs(fun%integral(t) - theta) / theta)
      end do
      call report('smooth step integral vs spin-up law: ' // to_str(worst, 3))
      call check_close(error, 'smooth step integral = spin-up angle', worst, 0.0_dp, &
         atol=5.0e-14_dp)
   end subroutine test_smooth_step

   !> Periodic cubic table (period 0.7 s): g(t + 3P) = g(t) to 1e-12; g' and g'' continuous at
   !> the wrap (t_1 + 1e-9 against t_n - 1e-9: 9e-7 and 1e-5, the slope times 2e-9; measured
   !> 9.4e-8 and 1.5e-6); the integral over 0 .. 2.3 s
   !> against composite Simpson on 23000 intervals (1e-10 relative).
   subroutine test_periodic(error)
      type(error_t), allocatable, intent(out) :: error
      type(time_function_t) :: fun
      real(dp) :: a(3), b(3), simpson, t, h, worst
      integer :: i, n
      call new_time_function('table', 'test', fun, error, times=[0.0_dp, 0.2_dp, 0.5_dp, &
         0.7_dp], values=[1.0_dp, 3.0_dp, 0.0_dp, 1.0_dp], interpolation='cubic', &
         beyond='periodic')
      if (allocated(error)) return
      worst = 0.0_dp
      do i = 1, 20
         t = 0.033_dp * i
         a = fun%evaluate(t)
         b = fun%evaluate(t + 2.1_dp)
         worst = max(worst, maxval(abs(a - b)) / 100.0_dp)
      end do
      call check_close(error, 'periodic repetition', worst, 0.0_dp, atol=1.0e-12_dp)
      if (allocated(error)) return
      a = fun%evaluate(1.0e-9_dp)
      b = fun%evaluate(0.7_dp - 1.0e-9_dp)
      call report('wrap: g'' ' // to_str(a(2), 10) // ' / ' // to_str(b(2), 10) // ', g'''' ' // &
         to_str(a(3), 10) // ' / ' // to_str(b(3), 10))
      call check_close(error, 'g'' continuous at the wrap', a(2), b(2), atol=9.0e-7_dp)
      if (.not. allocated(error)) call check_close(error, 'g'''' continuous at the wrap', a(3), &
         b(3), atol=1.0e-5_dp)
      if (allocated(error)) return
      n = 23000
      h = 2.3_dp / n
      simpson = 0.0_dp
      do i = 0, n
         a = fun%evaluate(i * h)
         simpson = simpson + merge(1.0_dp, merge(4.0_dp, 2.0_dp, mod(i, 2) == 1), &
            i == 0 .or. i == n) * a(1)
      end do
      simpson = simpson * h / 3.0_dp
      call report('periodic integral ' // to_str(fun%integral(2.3_dp), 14) // ', Simpson ' // &
         to_str(simpson, 14))
      call check_close(error, 'periodic integral vs Simpson', fun%integral(2.3_dp), simpson, &
         rtol=1.0e-10_dp)
   end subroutine test_periodic

   !> Decreasing, equal times, one point, value count, periodic end, zero duration: refused with
   !> the place named.
   subroutine test_bad_tables(error)
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: refused
      type(time_function_t) :: fun
      call new_time_function('table', 'here', fun, refused, times=[0.0_dp, 0.2_dp, 0.1_dp], &
         values=[1.0_dp, 2.0_dp, 3.0_dp])
      call expect(refused, 'table_time(3) = 0.1 s is not after table_time(2)')
      if (allocated(error)) return
      call new_time_function('table', 'here', fun, refused, times=[0.0_dp, 0.0_dp], &
         values=[1.0_dp, 2.0_dp])
      call expect(refused, 'the times must increase strictly')
      if (allocated(error)) return
      call new_time_function('table', 'here', fun, refused, times=[0.0_dp], values=[1.0_dp])
      call expect(refused, 'a table of 1 points')
      if (allocated(error)) return
      call new_time_function('table', 'here', fun, refused, times=[0.0_dp, 1.0_dp], &
         values=[1.0_dp])
      call expect(refused, 'give one value per time')
      if (allocated(error)) return
      call new_time_function('table', 'here', fun, refused, times=[0.0_dp, 1.0_dp], &
         values=[1.0_dp, 2.0_dp], beyond='periodic')
      call expect(refused, 'a periodic table must end at its first value')
      if (allocated(error)) return
      call new_time_function('ramp', 'here', fun, refused, duration=0.0_dp)
      call expect(refused, 'duration = 0')
   contains
      subroutine expect(refused, text)
         type(error_t), allocatable, intent(inout) :: refused
         character(len=*), intent(in) :: text
         call check(error, 'refused with "' // text // '"', allocated(refused))
         if (allocated(error)) return
         call report('refused: ' // refused%message)
         call check(error, 'message "' // refused%message // '" names "' // text // '"', &
            index(refused%message, text) > 0 .and. index(refused%message, 'here: ') == 1)
         deallocate (refused)
      end subroutine expect
   end subroutine test_bad_tables

   !> Ground (markers: pivot, spring anchor) and a rigid body; the joint (revolute or
   !> prismatic) between ground marker 1 and body marker 1; the driver's law.
   subroutine build(kind, law, rate, mech, error, with_spring, swap)
      integer, intent(in) :: kind
      type(time_function_t), intent(in) :: law
      logical, intent(in) :: rate
      type(mechanism_t), intent(out) :: mech
      type(error_t), allocatable, intent(out) :: error
      !> Add the spring; the body as the joint's body 1 (the ground as body 2)
      logical, intent(in), optional :: with_spring, swap
      type(ground_t) :: ground
      type(rigid_body_t) :: link
      type(joint_driver_t) :: driver
      type(spring_damper_t) :: spring
      real(dp) :: frames(3, 3, 2), inertia(3, 3)
      integer :: ig, il
      frames(:, :, 1) = identity
      frames(:, :, 2) = identity
      call ground%init(reshape([0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, -1.0_dp], [3, 2]), &
         frames, error)
      if (allocated(error)) return
      inertia = 0.0_dp
      inertia(1, 1) = 1.0e-4_dp
      inertia(2, 2) = link_mass * link_length**2 / 12.0_dp
      inertia(3, 3) = link_mass * link_length**2 / 12.0_dp
      call link%init(link_mass, [0.5_dp * link_length, 0.0_dp, 0.0_dp], inertia, &
         reshape([0.0_dp, 0.0_dp, 0.0_dp], [3, 1]), frames(:, :, 1:1), error)
      if (allocated(error)) return
      call mech%add_body(ground, 'ground', ig, error)
      if (.not. allocated(error)) call mech%add_body(link, 'link', il, error)
      if (present(swap)) then
         if (.not. allocated(error)) call mech%add_joint(kind, 'pivot', il, 1, ig, 1, error)
      else
         if (.not. allocated(error)) call mech%add_joint(kind, 'pivot', ig, 1, il, 1, error)
      end if
      if (allocated(error)) return
      if (present(with_spring)) then
         spring%name = 'spring'
         spring%body_a = ig
         spring%marker_a = 2
         spring%body_b = il
         spring%marker_b = 1
         spring%stiffness = 400.0_dp
         spring%free_length = 1.0_dp
         call mech%add_spring(spring, error)
         if (allocated(error)) return
      end if
      driver%name = 'motor'
      driver%joint = 1
      driver%law = law
      driver%rate = rate
      call mech%add_driver(driver, error)
   end subroutine build

   !> Driver rows of the pendulum (rate law) and of the prismatic slider, each also with the
   !> moving body as the joint's body 1, and of a hand-made flexible body (2 modes that move and
   !> turn its virtual node), at a state moved off the constraints: Phi_q against central
   !> differences of Phi (h = 1e-6: 1e-9; measured 1.2e-10), Phi_t against d Phi/dt (1e-8 of f';
   !> 2.8e-10), g against -d/ds [Phi_q(q + s v, t + s) v + Phi_t] (1e-8 of the scale
   !> f'^2 + |v|^2 = 11; 1.0e-8), the row's second derivatives (Newton tangent, with lambda_d =
   !> 1.3 alone) against the mechanism's central differences of Phi_q^T lambda
   !> (analytic_tangents = .false.; entries O(1): 1.5e-10 rigid, measured 1.4e-11; 6e-10
   !> flexible, whose marker Hessian has a 3 x 3 difference itself, measured 6.3e-11). The
   !> tolerances are the differences' error bounds (h^2 times a third derivative + eps/h),
   !> one per quantity for all six cases; the smallest cases measure far below them.
   subroutine test_driver_time_terms(error)
      type(error_t), allocatable, intent(out) :: error
      type(time_function_t) :: law
      type(mechanism_t) :: mech
      integer :: kind
      call new_time_function('smooth_step', 'test', law, error, initial=0.5_dp, final=3.0_dp, &
         t_start=0.0_dp, duration=0.4_dp)
      if (allocated(error)) return
      do kind = 1, 6
         if (kind >= 5) then
            call build_flexible(merge(JOINT_REVOLUTE, JOINT_PRISMATIC, kind == 5), law, mech, &
               error)
            if (allocated(error)) return
            call check_terms(trim(merge('revolute ', 'prismatic', kind == 5)) // &
               ', flexible body 2', 6.0e-10_dp)
            if (allocated(error)) return
            cycle
         end if
         if (kind <= 2) then
            call build(merge(JOINT_REVOLUTE, JOINT_PRISMATIC, kind == 1), law, kind == 1, mech, &
               error)
         else
            call build(merge(JOINT_REVOLUTE, JOINT_PRISMATIC, kind == 3), law, kind == 3, mech, &
               error, swap=.true.)
         end if
         if (allocated(error)) return
         call check_terms(trim(merge('revolute ', 'prismatic', mod(kind, 2) == 1)) // &
            trim(merge(', moving body 1', '               ', kind > 2)), 1.5e-10_dp)
         if (allocated(error)) return
      end do
   contains
      subroutine check_terms(what, hessian_tolerance)
         character(len=*), intent(in) :: what
         !> Tolerance of the Hessian against the differences
         real(dp), intent(in) :: hessian_tolerance
         real(dp), allocatable :: q(:), v(:), phi_p(:), phi_m(:), jac(:, :), jac2(:, :)
         real(dp), allocatable :: rate(:), g(:), w_p(:), w_m(:), r_p(:), r_m(:)
         real(dp), allocatable :: lambda(:), K_exact(:, :), K_fd(:, :)
         real(dp) :: h, t, worst(4)
         integer :: n, nc, j
         n = mech%num_coordinates()
         nc = mech%num_constraints()
         allocate (q(n), v(n), phi_p(nc), phi_m(nc), jac(nc, n), jac2(nc, n), rate(nc), g(nc), &
            w_p(nc), w_m(nc), r_p(nc), r_m(nc), lambda(nc), K_exact(n, n), K_fd(n, n))
         t = 0.13_dp
         do j = 1, n
            q(j) = 0.1_dp * cos(1.7_dp * j)
            v(j) = 0.7_dp * sin(2.3_dp * j)
         end do
         q(4:7) = [0.9_dp, 0.1_dp, -0.2_dp, 0.3_dp]
         if (n > 7) q(8:) = 0.01_dp * q(8:)
         h = 1.0e-6_dp
         call mech%constraint_jacobian(q, t, jac, error)
         if (allocated(error)) return
         do j = 1, n
            q(j) = q(j) + h
            call mech%constraints(q, t, phi_p, error)
            q(j) = q(j) - 2.0_dp * h
            if (.not. allocated(error)) call mech%constraints(q, t, phi_m, error)
            if (allocated(error)) return
            q(j) = q(j) + h
            jac2(:, j) = (phi_p - phi_m) / (2.0_dp * h)
         end do
         worst(1) = maxval(abs(jac - jac2))
         call mech%constraint_rate(q, t, rate, error)
         if (.not. allocated(error)) call mech%constraints(q, t + h, phi_p, error)
         if (.not. allocated(error)) call mech%constraints(q, t - h, phi_m, error)
         if (allocated(error)) return
         worst(2) = maxval(abs(rate - (phi_p - phi_m) / (2.0_dp * h)))
         call mech%acceleration_rhs(q, v, t, g, error)
         if (allocated(error)) return
         call mech%constraint_jacobian(q + h * v, t + h, jac2, error)
         if (.not. allocated(error)) call mech%constraint_rate(q + h * v, t + h, r_p, error)
         if (allocated(error)) return
         w_p = matmul(jac2, v) + r_p
         call mech%constraint_jacobian(q - h * v, t - h, jac2, error)
         if (.not. allocated(error)) call mech%constraint_rate(q - h * v, t - h, r_m, error)
         if (allocated(error)) return
         w_m = matmul(jac2, v) + r_m
         worst(3) = maxval(abs(g + (w_p - w_m) / (2.0_dp * h)))
         ! Newton tangent of the driver row alone: analytic against the mechanism's differences
         lambda = 0.0_dp
         lambda(mech%drivers(1)%row) = 1.3_dp
         call mech%constraint_stiffness(q, t, lambda, K_exact, error)
         if (allocated(error)) return
         mech%analytic_tangents = .false.
         call mech%constraint_stiffness(q, t, lambda, K_fd, error)
         mech%analytic_tangents = .true.
         if (allocated(error)) return
         worst(4) = maxval(abs(K_exact - K_fd))
         call report(what // ': |Phi_q - FD| ' // to_str(worst(1), 3) // ', |Phi_t - FD| ' // &
            to_str(worst(2), 3) // ', |g - FD| ' // to_str(worst(3), 3) // &
            ', |K_c - FD| ' // to_str(worst(4), 3) // ' (largest entry ' // &
            to_str(maxval(abs(K_exact)), 3) // ')')
         call check_close(error, what // ' driver Hessian', worst(4), 0.0_dp, &
            atol=hessian_tolerance)
         if (allocated(error)) return
         call check_close(error, what // ' Phi_q', worst(1), 0.0_dp, atol=1.0e-9_dp)
         if (.not. allocated(error)) call check_close(error, what // ' Phi_t', worst(2), 0.0_dp, &
            atol=1.0e-8_dp)
         if (.not. allocated(error)) call check_close(error, what // ' g', worst(3), 0.0_dp, &
            atol=1.0e-8_dp * (9.0_dp + sum(v**2)))
      end subroutine check_terms
   end subroutine test_driver_time_terms

   !> Ground and a hand-made flexible body (4 nodes, 2 modes whose virtual node at the origin
   !> translates and turns); the joint between ground marker 1 and the virtual node, driven by law.
   subroutine build_flexible(kind, law, mech, error)
      integer, intent(in) :: kind
      type(time_function_t), intent(in) :: law
      type(mechanism_t), intent(out) :: mech
      type(error_t), allocatable, intent(out) :: error
      type(ground_t) :: ground
      type(flexible_body_t) :: flexible
      type(joint_driver_t) :: driver
      type(csr_t) :: M
      real(dp) :: xyz(3, 4), shapes(12, 2), virtual_shapes(6, 2), mdiag(12), frames(3, 3, 1)
      integer(ip) :: rows(12)
      integer :: i, ig, ib
      xyz = reshape([0.0_dp, 0.0_dp, 0.0_dp, 0.2_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.1_dp, 0.0_dp, &
         0.0_dp, 0.0_dp, 0.3_dp], [3, 4])
      do i = 1, 4
         mdiag(3 * i - 2:3 * i) = 0.5_dp + 0.25_dp * i
      end do
      rows = [(int(i, ip), i=1, 12)]
      call csr_from_coo(12_ip, 12_ip, rows, rows, mdiag, M, error)
      if (allocated(error)) return
      shapes(:, 1) = [0.3_dp, 0.1_dp, -0.2_dp, -0.4_dp, 0.5_dp, 0.1_dp, 0.2_dp, -0.3_dp, 0.6_dp, &
         -0.1_dp, 0.2_dp, -0.5_dp]
      shapes(:, 2) = [-0.2_dp, 0.4_dp, 0.3_dp, 0.1_dp, -0.2_dp, 0.5_dp, -0.6_dp, 0.1_dp, &
         -0.1_dp, 0.3_dp, 0.4_dp, 0.2_dp]
      virtual_shapes(1:3, :) = shapes(1:3, :)
      virtual_shapes(4:6, 1) = [0.4_dp, -0.3_dp, 0.7_dp]
      virtual_shapes(4:6, 2) = [-0.5_dp, 0.2_dp, 0.3_dp]
      call flexible%init(M, xyz, shapes, [2500.0_dp, 14400.0_dp], virtual_shapes, xyz(:, 1:1), &
         error)
      if (allocated(error)) return
      frames(:, :, 1) = identity
      call ground%init(reshape([0.0_dp, 0.0_dp, 0.0_dp], [3, 1]), frames, error)
      if (.not. allocated(error)) call mech%add_body(ground, 'ground', ig, error)
      if (.not. allocated(error)) call mech%add_body(flexible, 'beam', ib, error)
      if (.not. allocated(error)) call mech%add_joint(kind, 'pivot', ig, 1, ib, 1, error)
      if (allocated(error)) return
      driver%name = 'motor'
      driver%joint = 1
      driver%law = law
      call mech%add_driver(driver, error)
   end subroutine build_flexible

   !> Integrate a built mechanism from q0 (assembled) to t_end with step h; per step call `each`.
   subroutine integrate(mech, q0, h, t_end, rho_inf, each, error)
      type(mechanism_t), intent(inout) :: mech
      real(dp), intent(in) :: q0(:), h, t_end, rho_inf
      interface
         subroutine each(integrator, error)
            import :: galpha_integrator_t, error_t
            type(galpha_integrator_t), intent(in) :: integrator
            type(error_t), allocatable, intent(out) :: error
         end subroutine each
      end interface
      type(error_t), allocatable, intent(out) :: error
      type(galpha_settings_t) :: settings
      type(galpha_integrator_t) :: integrator
      real(dp), allocatable :: q(:), v(:)
      integer :: n
      q = q0
      allocate (v(size(q)))
      call mech%assemble(q, 0.0_dp, error)
      if (.not. allocated(error)) call mech%initial_velocities(q, 0.0_dp, v, error)
      if (allocated(error)) return
      settings%h = h
      settings%t_end = t_end + 10.0_dp * h
      settings%rho_inf = rho_inf
      settings%newton_atol = 1.0e-12_dp
      settings%newton_rtol = 1.0e-12_dp
      call integrator%init(mech, settings, q, v, error)
      if (allocated(error)) return
      call each(integrator, error)
      do n = 1, nint(t_end / h)
         if (allocated(error)) return
         call integrator%step(mech, error)
         if (allocated(error)) return
         call each(integrator, error)
      end do
   end subroutine integrate

   !> Driven pendulum (module header), h = 1e-3 s and 5e-4 s, 0.8 s, rho_inf = 0.8: the angle
   !> equals the law (the only degree of freedom is driven: Newton tolerance, 1e-10 rad); the
   !> driving torque against the closed form, largest error over the run relative to max |tau|
   !> (O(h^2) in index 3: asserted 1.5e-4 at 1e-3 s, measured 1.4e-5, and order 2 +- 0.3
   !> between the steps, measured 2.0); the energy balance D = W - (T + V - T_0 - V_0) against 0
   !> relative to the driver's gross work (asserted 3e-6; measured 2.6e-7 and 6.5e-8).
   subroutine test_pendulum(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: steps(2) = [1.0e-3_dp, 5.0e-4_dp]
      type(time_function_t) :: law
      type(mechanism_t) :: mech
      type(energy_balance_t) :: balance
      real(dp) :: q0(7), worst_tau(2), worst_angle, tau_max, gross, work_before
      real(dp) :: order
      integer :: i
      call new_time_function('smooth_step', 'test', law, error, initial=0.0_dp, &
         final=final_speed, t_start=0.0_dp, duration=spin_time)
      if (allocated(error)) return
      do i = 1, 2
         call build(JOINT_REVOLUTE, law, .true., mech, error)
         if (allocated(error)) return
         mech%gravity = [0.0_dp, -gravity, 0.0_dp]
         q0 = [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp]
         worst_tau(i) = 0.0_dp
         worst_angle = 0.0_dp
         tau_max = 0.0_dp
         gross = 0.0_dp
         call integrate(mech, q0, steps(i), 0.8_dp, 0.8_dp, each_step, error)
         if (allocated(error)) return
         call report('h = ' // to_str(steps(i)) // ': max |tau - closed form| / max |tau| ' // &
            to_str(worst_tau(i) / tau_max, 3) // ' (max |tau| ' // to_str(tau_max, 6) // &
            ' N m), max angle error ' // to_str(worst_angle, 3) // ' rad, D / |W|_1 ' // &
            to_str(balance%numerical_dissipation / gross, 3) // ', W ' // &
            to_str(balance%work, 8) // ' J')
         call check_close(error, 'driven angle', worst_angle, 0.0_dp, atol=1.0e-10_dp)
         if (.not. allocated(error)) call check_close(error, 'energy balance D / |W|_1', &
            balance%numerical_dissipation / gross, 0.0_dp, atol=3.0e-6_dp)
         if (allocated(error)) return
      end do
      call check_close(error, 'torque error at h = 1e-3 s', worst_tau(1) / tau_max, 0.0_dp, &
         atol=1.5e-4_dp)
      if (allocated(error)) return
      order = log(worst_tau(1) / worst_tau(2)) / log(2.0_dp)
      call report('order of the torque error ' // to_str(order, 4))
      call check_close(error, 'order of the torque error', order, 2.0_dp, atol=0.3_dp)
   contains
      subroutine each_step(integrator, error)
         type(galpha_integrator_t), intent(in) :: integrator
         type(error_t), allocatable, intent(out) :: error
         real(dp) :: state(3), f(3), tau
         if (integrator%t == 0.0_dp) then
            call balance%init(mech, integrator%t, integrator%q, integrator%v, error, &
               lambda=integrator%lambda)
            return
         end if
         work_before = balance%work
         call balance%update(mech, integrator%t, integrator%q, integrator%v, error, &
            lambda=integrator%lambda)
         if (allocated(error)) return
         gross = gross + abs(balance%work - work_before)
         state = mech%driver_state(1, integrator%q, integrator%v, integrator%lambda)
         f = mech%drivers(1)%prescribed(integrator%t)
         tau = link_mass * link_length**2 / 3.0_dp * f(3) + link_mass * gravity * &
            0.5_dp * link_length * cos(f(1))
         tau_max = max(tau_max, abs(tau))
         worst_tau(i) = max(worst_tau(i), abs(state(3) - tau))
         worst_angle = max(worst_angle, abs(atan2(sin(state(1) - f(1)), cos(state(1) - f(1)))))
      end subroutine each_step
   end subroutine test_pendulum

   !> Mass (2 kg) on a prismatic joint along z, a spring k = 400 N/m from the ground anchor 1 m
   !> below (free length 1 m, so its force is -k s), its speed driven by a smooth step 0 -> 0.5
   !> m/s over 0.3 s (quantity rate), to 0.5 s, h = 5e-4 s: the driving force against
   !> m s'' + k s, largest error relative to the largest force (asserted 1e-5; measured
   !> 1.8e-6). Prescribing the travel itself by a smooth step (s''' jumps at its ends) leaves an
   !> O(h s''' jump) oscillation of the index-3 accelerations and multipliers (measured 4.7e-3
   !> of the force at this h): the integrator's, not the driver's.
   subroutine test_prismatic(error)
      type(error_t), allocatable, intent(out) :: error
      type(time_function_t) :: law
      type(mechanism_t) :: mech
      real(dp) :: q0(7), worst, force_max
      call new_time_function('smooth_step', 'test', law, error, initial=0.0_dp, final=0.5_dp, &
         t_start=0.0_dp, duration=0.3_dp)
      if (allocated(error)) return
      call build(JOINT_PRISMATIC, law, .true., mech, error, with_spring=.true.)
      if (allocated(error)) return
      q0 = [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp]
      worst = 0.0_dp
      force_max = 0.0_dp
      call integrate(mech, q0, 5.0e-4_dp, 0.5_dp, 0.8_dp, each_step, error)
      if (allocated(error)) return
      call report('prismatic: max |F - (m s'''' + k s)| / max |F| ' // &
         to_str(worst / force_max, 3) // ' (max |F| ' // to_str(force_max, 6) // ' N)')
      call check_close(error, 'driving force', worst / force_max, 0.0_dp, atol=1.0e-5_dp)
   contains
      subroutine each_step(integrator, error)
         type(galpha_integrator_t), intent(in) :: integrator
         type(error_t), allocatable, intent(out) :: error
         real(dp) :: state(3), f(3), force
         if (integrator%t == 0.0_dp) return
         state = mech%driver_state(1, integrator%q, integrator%v, integrator%lambda)
         f = mech%drivers(1)%prescribed(integrator%t)
         force = link_mass * f(3) + 400.0_dp * f(1)
         force_max = max(force_max, abs(force))
         worst = max(worst, abs(state(3) - force))
         if (abs(state(1) - f(1)) > 1.0e-10_dp) call check(error, 'travel follows the law', &
            .false.)
      end subroutine each_step
   end subroutine test_prismatic

   !> A free rigid body of 2 kg pushed along x by a load 10 N * table (ramp 0 -> 1 over 0.1 s,
   !> held), to 0.3 s, h = 1e-4 s, rho_inf = 0.8: x(t) against the closed form (module header),
   !> largest error relative to x(0.3 s) (asserted 2.5e-7; measured 2.9e-8).
   subroutine test_table_load(error)
      type(error_t), allocatable, intent(out) :: error
      type(mechanism_t) :: mech
      type(rigid_body_t) :: mass
      type(timed_load_t) :: load
      real(dp), parameter :: force = 10.0_dp, ramp = 0.1_dp, m = 2.0_dp
      real(dp) :: q0(7), worst, x_end, frames(3, 3, 1)
      integer :: ib
      frames(:, :, 1) = identity
      call mass%init(m, [0.0_dp, 0.0_dp, 0.0_dp], 0.1_dp * identity, &
         reshape([0.0_dp, 0.0_dp, 0.0_dp], [3, 1]), frames, error)
      if (.not. allocated(error)) call mech%add_body(mass, 'mass', ib, error)
      if (allocated(error)) return
      load%kind = LOAD_FORCE
      load%body = ib
      load%marker = 1
      load%direction = [1.0_dp, 0.0_dp, 0.0_dp]
      load%value = force
      call new_time_function('table', 'test', load%law, error, times=[0.0_dp, ramp], &
         values=[0.0_dp, 1.0_dp], interpolation='linear', beyond='hold')
      if (.not. allocated(error)) call mech%add_load(load, error)
      if (allocated(error)) return
      q0 = [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp]
      worst = 0.0_dp
      call integrate(mech, q0, 1.0e-4_dp, 0.3_dp, 0.8_dp, each_step, error)
      if (allocated(error)) return
      x_end = exact(0.3_dp)
      call report('table force: max |x - closed form| / x(0.3 s) ' // to_str(worst / x_end, 3))
      call check_close(error, 'free mass under a table force', worst / x_end, 0.0_dp, &
         atol=2.5e-7_dp)
   contains
      subroutine each_step(integrator, error)
         type(galpha_integrator_t), intent(in) :: integrator
         type(error_t), allocatable, intent(out) :: error
         if (.false.) call check(error, '', .true.)
         worst = max(worst, abs(integrator%q(1) - exact(integrator%t)))
      end subroutine each_step
      pure real(dp) function exact(t)
         real(dp), intent(in) :: t
         real(dp) :: a
         a = force / m
         if (t <= ramp) then
            exact = a * t**3 / (6.0_dp * ramp)
         else
            exact = a * ramp**2 / 6.0_dp + a * ramp / 2.0_dp * (t - ramp) + a / 2.0_dp * &
               (t - ramp)**2
         end if
      end function exact
   end subroutine test_table_load

   !> A driver of a spherical joint and of joint 7 (none): refused, naming the driver and the joint.
   subroutine test_driver_refused(error)
      type(error_t), allocatable, intent(out) :: error
      type(time_function_t) :: law
      type(mechanism_t) :: mech
      type(joint_driver_t) :: driver
      type(error_t), allocatable :: refused
      call new_time_function('constant_speed', 'test', law, error, speed=1.0_dp)
      if (allocated(error)) return
      call build(JOINT_SPHERICAL, law, .false., mech, refused)
      call check(error, 'driver on a spherical joint refused', allocated(refused))
      if (allocated(error)) return
      call report('refused: ' // refused%message)
      call check(error, 'message names the joint kind', index(refused%message, &
         'joint "pivot" is spherical; a driver needs a revolute or prismatic joint') > 0)
      if (allocated(error)) return
      deallocate (refused)
      call build(JOINT_REVOLUTE, law, .false., mech, error)
      if (allocated(error)) return
      driver%name = 'second'
      driver%joint = 7
      driver%law = law
      call mech%add_driver(driver, refused)
      call check(error, 'driver of joint 7 refused', allocated(refused))
      if (allocated(error)) return
      call check(error, 'message names the joint number', index(refused%message, &
         'driver "second": the mechanism has no joint 7') > 0)
   end subroutine test_driver_refused

end module test_mbs_drivers

program main_mbs_drivers
   use ffrf_testing, only: unittest_t, run_suite
   use test_mbs_drivers, only: collect_mbs_drivers
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_mbs_drivers(tests)
   call run_suite('mbs_drivers', tests)
end program main_mbs_drivers
