!> Estimates of the automatic model that hold for any scene (moved from
!> ffrf_app_engine_model_selection, which re-exports them; ffrf_app_scene_model uses them):
!> the time-step ladder, generalized-alpha's periodic forced response and its period error and
!> algorithmic damping at w h, and the jointed masses' share of a mode's modal mass.
module ffrf_app_model_estimates
   use ffrf_core_kinds, only: dp, ip
   use ffrf_la_lapack, only: dgeev
   use ffrf_mbs_generalized_alpha, only: chung_hulbert
   implicit none
   private
   public :: STEP_LADDER, galpha_response, galpha_mode, jointed_mass_share

   !> Mantissas of the time-step ladder (times powers of ten)
   real(dp), parameter :: STEP_LADDER(10) = [1.0_dp, 1.25_dp, 1.6_dp, 2.0_dp, 2.5_dp, 3.2_dp, &
      4.0_dp, 5.0_dp, 6.4_dp, 8.0_dp]

contains

   !> mu_j = A_j / (1 + A_j), A_j = sum_i m_i |u_ji|^2: the jointed masses' share of the modal
   !> mass (ffrf_app_engine_model_selection, 2).
   pure function jointed_mass_share(virtual_node_shape, attached_mass) result(share)
      real(dp), intent(in) :: virtual_node_shape(:, :), attached_mass(:)
      real(dp) :: share(size(virtual_node_shape, 2))
      real(dp) :: added
      integer :: j, i
      do j = 1, size(share)
         added = 0.0_dp
         do i = 1, size(attached_mass)
            added = added + attached_mass(i) * sum(virtual_node_shape(6 * i - 5:6 * i - 3, j)**2)
         end do
         share(j) = added / (1.0_dp + added)
      end do
   end function jointed_mass_share

   !> Generalized-alpha's periodic response to x'' + 2 zeta w x' + w^2 x = w^2 e^(i Omega t)
   !> (Chung-Hulbert, rho_inf; force at t_(n+1-alpha_f)), as a multiple of the static one: the
   !> steady state S of s_(n+1) = A s_n + b f_(n+1) + c f_n with f_n = e^(i Omega n h).
   !> w = 0 (a free mass, x'' = -Omega^2-normalised force) gives the ratio to the exact
   !> -1/Omega^2 response instead.
   pure function galpha_response(w, zeta, omega, h, rho_inf) result(response)
      real(dp), intent(in) :: w, zeta, omega, h, rho_inf
      complex(dp) :: response
      real(dp) :: a(3, 3), b(3), c(3), unit(3)
      complex(dp) :: z, m(3, 3), rhs(3)
      integer :: j
      do j = 1, 3
         unit = 0.0_dp
         unit(j) = 1.0_dp
         a(:, j) = galpha_step(unit, 0.0_dp, 0.0_dp, w, zeta, h, rho_inf)
      end do
      b = galpha_step([0.0_dp, 0.0_dp, 0.0_dp], 0.0_dp, 1.0_dp, w, zeta, h, rho_inf)
      c = galpha_step([0.0_dp, 0.0_dp, 0.0_dp], 1.0_dp, 0.0_dp, w, zeta, h, rho_inf)
      z = cmplx(cos(omega * h), sin(omega * h), dp)
      m = -a
      do j = 1, 3
         m(j, j) = m(j, j) + z
      end do
      rhs = z * b + c
      response = solve3(m, rhs)
      ! w > 0: the static response to w^2 e^(i Omega t) is 1; a free mass: -1/Omega^2
      if (w <= 0.0_dp) response = response * (-omega**2)
   end function galpha_response

   !> One generalized-alpha step (Chung-Hulbert, rho_inf) of the state (x, v, a) of
   !> x'' + 2 zeta w x' + w^2 x = g(t) with g = w^2 f (w > 0) or f (w = 0), f0 = f(t_n),
   !> f1 = f(t_(n+1)):
   !>    (1 - alpha_m) a1 + alpha_m a0 = g_(n+1-alpha_f) - w^2 x_(n+1-alpha_f)
   !>       - 2 zeta w v_(n+1-alpha_f),
   !>    x1 = x0 + h v0 + h^2 ((1/2 - beta) a0 + beta a1),  v1 = v0 + h ((1 - gamma) a0 + gamma a1)
   pure function galpha_step(s, f0, f1, w, zeta, h, rho_inf) result(next)
      real(dp), intent(in) :: s(3), f0, f1, w, zeta, h, rho_inf
      real(dp) :: next(3), alpha_m, alpha_f, gamma, beta, w2, scale, a1, x_part, v_part
      call chung_hulbert(rho_inf, alpha_m, alpha_f, gamma, beta)
      w2 = w**2
      scale = merge(w2, 1.0_dp, w > 0.0_dp)
      x_part = s(1) + (1.0_dp - alpha_f) * (h * s(2) + h**2 * (0.5_dp - beta) * s(3))
      v_part = s(2) + (1.0_dp - alpha_f) * h * (1.0_dp - gamma) * s(3)
      a1 = (scale * ((1.0_dp - alpha_f) * f1 + alpha_f * f0) - alpha_m * s(3) - w2 * x_part - &
         2.0_dp * zeta * w * v_part) / (1.0_dp - alpha_m + (1.0_dp - alpha_f) * (w2 * beta * &
         h**2 + 2.0_dp * zeta * w * gamma * h))
      next(1) = s(1) + h * s(2) + h**2 * ((0.5_dp - beta) * s(3) + beta * a1)
      next(2) = s(2) + h * ((1.0_dp - gamma) * s(3) + gamma * a1)
      next(3) = a1
   end function galpha_step

   !> The numerical frequency (as a ratio to the exact one) and the algorithmic damping ratio of
   !> generalized-alpha on x'' + w^2 x = 0 at w h, from the complex eigenvalue pair lambda of
   !> its amplification matrix: w~ h = arg(lambda), damping -ln|lambda| / arg(lambda). A pair
   !> that has turned real (w h beyond the method's oscillatory range) gives ratio 1e3, damping 1
   !> (the mode is filtered out: quasi-static).
   subroutine galpha_mode(omega_h, rho_inf, frequency_ratio, damping)
      real(dp), intent(in) :: omega_h, rho_inf
      real(dp), intent(out) :: frequency_ratio, damping
      real(dp) :: amplification(3, 3), unit(3), wr(3), wi(3), work(64), dummy(1, 1), angle
      integer(ip) :: info
      integer :: j, k
      frequency_ratio = 1.0_dp
      damping = 0.0_dp
      if (omega_h <= 0.0_dp) return
      ! free vibration, h = 1, w = omega_h
      do j = 1, 3
         unit = 0.0_dp
         unit(j) = 1.0_dp
         amplification(:, j) = galpha_step(unit, 0.0_dp, 0.0_dp, omega_h, 0.0_dp, 1.0_dp, &
            rho_inf)
      end do
      call dgeev('N', 'N', 3_ip, amplification, 3_ip, wr, wi, dummy, 1_ip, dummy, 1_ip, work, &
         64_ip, info)
      k = maxloc(wi, dim=1)
      if (info /= 0 .or. wi(k) <= 0.0_dp) then
         frequency_ratio = 1.0e3_dp
         damping = 1.0_dp
         return
      end if
      angle = atan2(wi(k), wr(k))
      frequency_ratio = angle / omega_h
      damping = max(-log(hypot(wr(k), wi(k))), 0.0_dp) / angle
   end subroutine galpha_mode

   !> First component of the solution of a complex 3x3 system (Cramer's rule).
   pure function solve3(m, rhs) result(x1)
      complex(dp), intent(in) :: m(3, 3), rhs(3)
      complex(dp) :: x1, replaced(3, 3)
      replaced = m
      replaced(:, 1) = rhs
      x1 = det3(replaced) / det3(m)
   end function solve3

   pure function det3(m) result(d)
      complex(dp), intent(in) :: m(3, 3)
      complex(dp) :: d
      d = m(1, 1) * (m(2, 2) * m(3, 3) - m(2, 3) * m(3, 2)) - m(1, 2) * (m(2, 1) * m(3, 3) - &
         m(2, 3) * m(3, 1)) + m(1, 3) * (m(2, 1) * m(3, 2) - m(2, 2) * m(3, 1))
   end function det3

end module ffrf_app_model_estimates
