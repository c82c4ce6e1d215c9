!> The inertia terms of a reduced flexible body (ffrf_mbs_flexible_body, theory.md 3): the
!> mass matrix, the quadratic velocity vector and their tangents from the shape integrals.
submodule (ffrf_mbs_flexible_body) ffrf_mbs_flexible_body_inertia
   implicit none

contains

   !> sum_j z_j B(:, 3j-2:3j) = B (z (x) I3), for B with 3 rows and 3m columns (3 x 3; a
   !> fixed-size result: no heap temporary in the per-evaluation paths).
   pure function times_z(B, z) result(c)
      real(dp), intent(in) :: B(:, :), z(:)
      real(dp) :: c(3, 3)
      integer :: j
      c = 0.0_dp
      do j = 1, size(z)
         c = c + z(j) * B(1:3, 3 * j - 2:3 * j)
      end do
   end function times_z

   !> sum_j z_j B(3j-2:3j, :) = (z (x) I3)^T B, for B with 3m rows (3 x s).
   pure function z_times(z, B) result(c)
      real(dp), intent(in) :: z(:), B(:, :)
      real(dp) :: c(3, size(B, 2))
      integer :: j
      c = 0.0_dp
      do j = 1, size(z)
         c = c + z(j) * B(3 * j - 2:3 * j, :)
      end do
   end function z_times

   !> P = N (z (x) I3) for N with 3m columns (P: size(N, 1) x 3): column c is
   !> sum_k z_k N(:, 3k-3+c), contiguous column updates that vectorise (a subroutine: a function
   !> result of run-time size would go through the heap).
   pure subroutine n_times_z(N, z, P)
      real(dp), intent(in) :: N(:, :), z(:)
      real(dp), intent(out) :: P(:, :)
      integer :: k, c
      P = 0.0_dp
      do k = 1, size(z)
         do c = 1, 3
            P(:, c) = P(:, c) + z(k) * N(:, 3 * k - 3 + c)
         end do
      end do
   end subroutine n_times_z

   !> (z (x) I3)^T N (y (x) I3) = sum_jk z_j y_k N(3j-2:3j, 3k-2:3k) for N with 3m x 3m (3 x 3),
   !> as (z (x) I3)^T P with P = N (y (x) I3).
   pure function z_times_z(z, N, y) result(c)
      real(dp), intent(in) :: z(:), N(:, :), y(:)
      real(dp) :: c(3, 3), P(size(N, 1), 3)
      integer :: j
      call n_times_z(N, y, P)
      c = 0.0_dp
      do j = 1, size(z)
         c = c + z(j) * P(3 * j - 2:3 * j, :)
      end do
   end function z_times_z

   !> Deformed inertia I_thth(zeta) = Theta_u + M_xPsi~ (z(x)I) + (z(x)I)^T M_xPsi~^T
   !> + (z(x)I)^T M_Psi~Psi~ (z(x)I) (theory.md 3.3) = u~^T M u~ (kg m^2).
   pure function deformed_inertia(self, zeta, P) result(inertia)
      class(flexible_body_t), intent(in) :: self
      real(dp), intent(in) :: zeta(:)
      !> N (zeta (x) I3), N = M_Psi~Psi~ (n_times_z), if the caller has it already
      real(dp), intent(in), optional :: P(:, :)
      real(dp) :: inertia(3, 3), x(3, 3)
      integer :: j
      x = times_z(self%m_x_psit, zeta)
      inertia = self%theta_u + x + transpose(x)
      if (present(P)) then
         do j = 1, size(zeta)
            inertia = inertia + zeta(j) * P(3 * j - 2:3 * j, :)
         end do
      else
         inertia = inertia + z_times_z(zeta, self%m_psit_psit, zeta)
      end if
   end function deformed_inertia

   !> First moment skew: m chi~ + M_PhitPsi~ (z(x)I) = skew(int rho u dV) (kg m).
   pure function first_moment_skew(self, zeta) result(s)
      class(flexible_body_t), intent(in) :: self
      real(dp), intent(in) :: zeta(:)
      real(dp) :: s(3, 3)
      s = skew3(self%mass * self%center_of_mass) + times_z(self%m_phit_psit, zeta)
   end function first_moment_skew

   module procedure flexible_body_mass_matrix
      real(dp) :: A(3, 3), G_bar(3, 4), h(3)
      integer :: nc, j, l
      nc = self%num_coordinates
      A = euler_rotation(q(4:7))
      G_bar = euler_g_bar(q(4:7))
      associate (zeta => q(8:nc))
         mass_matrix = 0.0_dp
         do j = 1, 3
            mass_matrix(j, j) = self%mass
         end do
         mass_matrix(1:3, 4:7) = -matmul(A, matmul(first_moment_skew(self, zeta), G_bar))
         mass_matrix(4:7, 4:7) = matmul(transpose(G_bar), &
            matmul(deformed_inertia(self, zeta), G_bar))
         ! Column by column (3-vectors): no m-sized temporaries
         do l = 1, self%num_modes
            mass_matrix(1:3, 7 + l) = matmul(A, self%m_phit_psi(:, l))
            h = self%m_x_psi(:, l)
            do j = 1, self%num_modes
               h = h + zeta(j) * self%m_psit_psi(3 * j - 2:3 * j, l)
            end do
            mass_matrix(4:7, 7 + l) = -matmul(h, G_bar)
         end do
         mass_matrix(8:nc, 8:nc) = self%m_psi_psi
      end associate
      mass_matrix(4:nc, 1:3) = transpose(mass_matrix(1:3, 4:nc))
      mass_matrix(8:nc, 4:7) = transpose(mass_matrix(4:7, 8:nc))
   end procedure flexible_body_mass_matrix

   module procedure flexible_body_quadratic_velocity
      real(dp) :: A(3, 3), G_bar(3, 4), omega(3), w_skew(3, 3), coriolis(3, 3), W_j(3, 3)
      real(dp) :: P(3 * self%num_modes, 3)
      integer :: nc, j, k
      nc = self%num_coordinates
      A = euler_rotation(q(4:7))
      G_bar = euler_g_bar(q(4:7))
      omega = matmul(G_bar, v(4:7))
      w_skew = skew3(omega)
      associate (zeta => q(8:nc), zeta_dot => v(8:nc))
         ! P = N (z (x) I3): the quadratic term of I_thth and the sums in W_j below
         call n_times_z(self%m_psit_psit, zeta, P)
         f_v(1:3) = matmul(A, matmul(w_skew, matmul(first_moment_skew(self, zeta), omega)) + &
            2.0_dp * matmul(times_z(self%m_phit_psit, zeta_dot), omega))
         coriolis = times_z(self%m_x_psit, zeta_dot) + &
            z_times_z(zeta, self%m_psit_psit, zeta_dot)
         f_v(4:7) = -matmul(transpose(G_bar), matmul(w_skew, &
            matmul(deformed_inertia(self, zeta, P), omega)) + 2.0_dp * matmul(coriolis, omega))
         ! W_j = M_xPsi~(:, 3j-2:3j)^T + sum_k z_k N_jk (3 x 3 blocks of the header's W), the
         ! sums being the blocks of P
         do j = 1, self%num_modes
            W_j = transpose(self%m_x_psit(:, 3 * j - 2:3 * j)) + P(3 * j - 2:3 * j, :)
            f_v(7 + j) = dot_product(omega, matmul(W_j, omega))
            do k = 1, self%num_modes
               f_v(7 + j) = f_v(7 + j) + 2.0_dp * zeta_dot(k) * &
                  dot_product(self%m_psit_psi(3 * k - 2:3 * k, j), omega)
            end do
         end do
         ! Geometric stiffening, optional: -K_G(omega) zeta (module header)
         if (allocated(self%geometric_stiffness)) f_v(8:nc) = f_v(8:nc) - &
            matmul(geometric_matrix(self, omega), zeta)
      end associate
   end procedure flexible_body_quadratic_velocity

   module procedure flexible_body_quadratic_velocity_tangents
      real(dp) :: A(3, 3), G_bar(3, 4), G_dot(3, 4), omega(3), w_skew(3, 3), S(3, 3), T(3, 3)
      real(dp) :: inertia(3, 3), coriolis(3, 3), a_vec(3), b_vec(3), a_w(3, 3), b_w(3, 3)
      real(dp) :: a_z(3, self%num_modes), a_zd(3, self%num_modes), b_z(3, self%num_modes)
      real(dp) :: b_zd(3, self%num_modes), c_w(self%num_modes, 3), c_z(self%num_modes, &
         self%num_modes), c_zd(self%num_modes, self%num_modes), W_j(3, 3), D(3, 3)
      integer :: m, nc, j, l
      m = self%num_modes
      nc = self%num_coordinates
      call rotation_rates(q, v, A, G_bar, G_dot, omega)
      w_skew = skew3(omega)
      associate (zeta => q(8:nc), zeta_dot => v(8:nc))
         S = first_moment_skew(self, zeta)
         T = times_z(self%m_phit_psit, zeta_dot)
         inertia = deformed_inertia(self, zeta)
         coriolis = times_z(self%m_x_psit, zeta_dot) + &
            z_times_z(zeta, self%m_psit_psit, zeta_dot)
         a_vec = matmul(w_skew, matmul(S, omega)) + 2.0_dp * matmul(T, omega)
         b_vec = matmul(w_skew, matmul(inertia, omega)) + 2.0_dp * matmul(coriolis, omega)
         a_w = -skew3(matmul(S, omega)) + matmul(w_skew, S) + 2.0_dp * T
         b_w = -skew3(matmul(inertia, omega)) + matmul(w_skew, inertia) + 2.0_dp * coriolis
         c_w = 0.0_dp
         do l = 1, m
            associate (P_l => self%m_phit_psit(:, 3 * l - 2:3 * l), &
               Q_l => self%m_x_psit(:, 3 * l - 2:3 * l))
               a_z(:, l) = matmul(w_skew, matmul(P_l, omega))
               a_zd(:, l) = 2.0_dp * matmul(P_l, omega)
               ! dI/dz_k = Q_l + Q_l^T + sum_j z_j (N_jk + N_kj); dCor/dz_k = sum_l zd_l N_kl;
               ! dCor/dzd_k = Q_l + sum_j z_j N_jk
               D = Q_l + transpose(Q_l)
               do j = 1, m
                  D = D + zeta(j) * (self%m_psit_psit(3 * j - 2:3 * j, 3 * l - 2:3 * l) + &
                     self%m_psit_psit(3 * l - 2:3 * l, 3 * j - 2:3 * j))
               end do
               b_z(:, l) = matmul(w_skew, matmul(D, omega)) + 2.0_dp * &
                  matmul(times_z(self%m_psit_psit(3 * l - 2:3 * l, :), zeta_dot), omega)
               D = Q_l
               do j = 1, m
                  D = D + zeta(j) * self%m_psit_psit(3 * j - 2:3 * j, 3 * l - 2:3 * l)
               end do
               b_zd(:, l) = 2.0_dp * matmul(D, omega)
            end associate
         end do
         do j = 1, m
            W_j = transpose(self%m_x_psit(:, 3 * j - 2:3 * j)) + &
               times_z(self%m_psit_psit(3 * j - 2:3 * j, :), zeta)
            c_w(j, :) = matmul(W_j + transpose(W_j), omega)
            do l = 1, m
               c_w(j, :) = c_w(j, :) + 2.0_dp * zeta_dot(l) * &
                  self%m_psit_psi(3 * l - 2:3 * l, j)
               c_z(j, l) = dot_product(omega, matmul(self%m_psit_psit(3 * j - 2:3 * j, &
                  3 * l - 2:3 * l), omega))
               c_zd(j, l) = 2.0_dp * dot_product(self%m_psit_psi(3 * l - 2:3 * l, j), omega)
            end do
         end do
      end associate
      ! df/dq and df/dv, then the signs of K = -df/dq, C = -df/dv
      K = 0.0_dp
      C = 0.0_dp
      K(1:3, 4:7) = rotated_vector_jacobian(q(4:7), a_vec) - matmul(A, matmul(a_w, G_dot))
      K(1:3, 8:nc) = matmul(A, a_z)
      C(1:3, 4:7) = matmul(A, matmul(a_w, G_bar))
      C(1:3, 8:nc) = matmul(A, a_zd)
      K(4:7, 4:7) = -g_bar_transpose_derivative(b_vec) + &
         matmul(transpose(G_bar), matmul(b_w, G_dot))
      K(4:7, 8:nc) = -matmul(transpose(G_bar), b_z)
      C(4:7, 4:7) = -matmul(transpose(G_bar), matmul(b_w, G_bar))
      C(4:7, 8:nc) = -matmul(transpose(G_bar), b_zd)
      K(8:nc, 4:7) = -matmul(c_w, G_dot)
      K(8:nc, 8:nc) = c_z
      C(8:nc, 4:7) = matmul(c_w, G_bar)
      C(8:nc, 8:nc) = c_zd
      K = -K
      C = -C
      if (allocated(self%geometric_stiffness)) call add_geometric_tangents(self, q, omega, &
         G_bar, G_dot, K, C)
   end procedure flexible_body_quadratic_velocity_tangents

   module procedure g_bar_transpose_derivative
      B(1, 1) = 0.0_dp
      B(1, 2:4) = -2.0_dp * p
      B(2:4, 1) = 2.0_dp * p
      B(2:4, 2:4) = -2.0_dp * skew3(p)
   end procedure g_bar_transpose_derivative

   !> The rotation terms at coordinates q and a rate x (velocities v or accelerations a): A(theta),
   !> G_bar(theta), G_bar(x_theta) and the body-frame rate G_bar x_theta (omega or alpha).
   pure subroutine rotation_rates(q, x, A, G_bar, G_x, rate)
      real(dp), intent(in) :: q(:), x(:)
      real(dp), intent(out) :: A(3, 3), G_bar(3, 4), G_x(3, 4), rate(3)
      A = euler_rotation(q(4:7))
      G_bar = euler_g_bar(q(4:7))
      G_x = euler_g_bar(x(4:7))
      rate = matmul(G_bar, x(4:7))
   end subroutine rotation_rates

   module procedure flexible_body_mass_stiffness
      real(dp) :: rot(3, 3), G_bar(3, 4), G_a(3, 4), S(3, 3), inertia(3, 3), alpha(3), p(3)
      real(dp) :: H(3, self%num_modes), y(3), dy(3, 4), D(3, 3)
      integer :: m, nc, j, l
      m = self%num_modes
      nc = self%num_coordinates
      call rotation_rates(q, a, rot, G_bar, G_a, alpha)
      y = matmul(transpose(rot), a(1:3))
      dy = transposed_rotation_derivative(q(4:7), a(1:3))
      associate (zeta => q(8:nc), a_z => a(8:nc))
         S = first_moment_skew(self, zeta)
         inertia = deformed_inertia(self, zeta)
         H = self%m_x_psi + z_times(zeta, self%m_psit_psi)
         p = matmul(S, y) + matmul(inertia, alpha) - matmul(H, a_z)
         K = 0.0_dp
         K(1:3, 4:7) = rotated_vector_jacobian(q(4:7), -matmul(S, alpha) + &
            matmul(self%m_phit_psi, a_z)) + matmul(rot, matmul(S, G_a))
         K(4:7, 4:7) = g_bar_transpose_derivative(p) + matmul(transpose(G_bar), &
            matmul(S, dy) - matmul(inertia, G_a))
         K(8:nc, 4:7) = matmul(transpose(self%m_phit_psi), dy) + matmul(transpose(H), G_a)
         do l = 1, m
            associate (P_l => self%m_phit_psit(:, 3 * l - 2:3 * l), &
               Q_l => self%m_x_psit(:, 3 * l - 2:3 * l), &
               N_l => self%m_psit_psi(3 * l - 2:3 * l, :))
               K(1:3, 7 + l) = -matmul(rot, matmul(P_l, alpha))
               D = Q_l + transpose(Q_l)
               do j = 1, m
                  D = D + zeta(j) * (self%m_psit_psit(3 * j - 2:3 * j, 3 * l - 2:3 * l) + &
                     self%m_psit_psit(3 * l - 2:3 * l, 3 * j - 2:3 * j))
               end do
               K(4:7, 7 + l) = matmul(transpose(G_bar), matmul(P_l, y) + matmul(D, alpha) - &
                  matmul(N_l, a_z))
               K(8:nc, 7 + l) = -matmul(transpose(N_l), alpha)
            end associate
         end do
      end associate
   end procedure flexible_body_mass_stiffness

end submodule ffrf_mbs_flexible_body_inertia
