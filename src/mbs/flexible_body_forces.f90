!> The applied and internal forces of a reduced flexible body (ffrf_mbs_flexible_body): elastic
!> and damping forces, strain energy, gravity with its potential and tangent, the geometric
!> stiffness of a preload, and the force tangents.
submodule (ffrf_mbs_flexible_body) ffrf_mbs_flexible_body_forces
   implicit none

contains

   module procedure geometric_matrix
      real(dp) :: p(NUM_CENTRIFUGAL_CASES)
      integer :: load_case
      p = centrifugal_products(omega)
      K_G = 0.0_dp
      do load_case = 1, NUM_CENTRIFUGAL_CASES
         K_G = K_G + p(load_case) * self%geometric_stiffness(:, :, load_case)
      end do
   end procedure geometric_matrix

   module procedure add_geometric_tangents
      real(dp) :: g(self%num_modes, NUM_CENTRIFUGAL_CASES), gp(self%num_modes, 3)
      integer :: nc, load_case
      nc = self%num_coordinates
      do load_case = 1, NUM_CENTRIFUGAL_CASES
         g(:, load_case) = matmul(self%geometric_stiffness(:, :, load_case), q(8:nc))
      end do
      gp = matmul(g, centrifugal_product_jacobian(omega))
      K(8:nc, 8:nc) = K(8:nc, 8:nc) + geometric_matrix(self, omega)
      K(8:nc, 4:7) = K(8:nc, 4:7) - matmul(gp, G_dot)
      C(8:nc, 4:7) = C(8:nc, 4:7) + matmul(gp, G_bar)
   end procedure add_geometric_tangents

   module procedure flexible_body_force_tangents
      integer :: j
      call self%quadratic_velocity_tangents(q, v, K, C)
      do j = 1, self%num_modes
         K(7 + j, 7 + j) = K(7 + j, 7 + j) + self%stiffness(j)
         if (allocated(self%damping)) C(7 + j, 7 + j) = C(7 + j, 7 + j) + self%damping(j)
      end do
   end procedure flexible_body_force_tangents

   module procedure flexible_body_elastic_force
      force = 0.0_dp
      force(8:) = -self%stiffness * q(8:self%num_coordinates) - &
         self%damping * v(8:self%num_coordinates)
   end procedure flexible_body_elastic_force

   module procedure flexible_body_strain_energy
      energy = 0.5_dp * sum(self%stiffness * q(8:self%num_coordinates)**2)
   end procedure flexible_body_strain_energy

   module procedure flexible_body_damping_power
      power = 0.0_dp
      if (allocated(self%damping)) power = sum(self%damping * v(8:self%num_coordinates)**2)
   end procedure flexible_body_damping_power

   module procedure flexible_body_first_moment
      moment = self%mass * self%center_of_mass + matmul(self%m_phit_psi, &
         q(8:self%num_coordinates))
   end procedure flexible_body_first_moment

   module procedure flexible_body_gravity_potential
      energy = -dot_product(gravity, self%mass * q(1:3) + &
         matmul(euler_rotation(q(4:7)), self%first_moment(q)))
   end procedure flexible_body_gravity_potential

   module procedure flexible_body_gravity_force
      real(dp) :: y(3)
      y = matmul(gravity, euler_rotation(q(4:7)))
      gen(1:3) = self%mass * gravity
      gen(4:7) = matmul(cross_product(self%first_moment(q), y), euler_g_bar(q(4:7)))
      gen(8:) = matmul(y, self%m_phit_psi)
   end procedure flexible_body_gravity_force

   module procedure flexible_body_gravity_tangent
      real(dp) :: G_bar(3, 4), y(3), dy(3, 4), moment(3)
      integer :: l, nc
      nc = self%num_coordinates
      G_bar = euler_g_bar(q(4:7))
      y = matmul(gravity, euler_rotation(q(4:7)))
      dy = transposed_rotation_derivative(q(4:7), gravity)
      moment = self%first_moment(q)
      tangent = 0.0_dp
      tangent(4:7, 4:7) = g_bar_transpose_derivative(cross_product(moment, y)) + &
         matmul(transpose(G_bar), matmul(skew3(moment), dy))
      do l = 1, self%num_modes
         tangent(4:7, 7 + l) = matmul(transpose(G_bar), cross_product(self%m_phit_psi(:, l), y))
      end do
      tangent(8:nc, 4:7) = matmul(transpose(self%m_phit_psi), dy)
   end procedure flexible_body_gravity_tangent

end submodule ffrf_mbs_flexible_body_forces
