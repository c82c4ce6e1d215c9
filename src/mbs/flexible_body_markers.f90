!> The markers of a reduced flexible body (ffrf_mbs_flexible_body): a virtual node's deformed
!> frame (times a marker's constant C), its velocity, Jacobians, Hessian and generalized forces.
submodule (ffrf_mbs_flexible_body) ffrf_mbs_flexible_body_markers
   implicit none
   !> marker_part's parts: the rows of a virtual node's translations and of its rotations
   integer, parameter :: MARKER_POSITION = 0, MARKER_ROTATION = 3

contains

   module procedure flexible_body_marker_hessian
      real(dp) :: A(3, 3), E(3, 3), X(3, 3), phi(3), delta, b_p(3), Z(4, 3), y(3, 3)
      real(dp) :: T(3, 3), Z_axes(4, 3, 3), column(4), t_l(3), dt(3, 3), t_plus(3), t_minus(3)
      real(dp) :: shifted(3), W(3, 3)
      logical :: need(3)
      integer :: m, j, l
      integer :: row
      row = 6 * self%marker_node(k)
      ! sum_j w_j . A E C e_j = sum_i (W C^T)(:, i) . A E e_i: the node frame's weights
      if (self%framed(k)) then
         W = matmul(w_axes, transpose(self%marker_frame(:, :, k)))
      else
         W = w_axes
      end if
      m = self%num_modes
      A = euler_rotation(q(4:7))
      phi = marker_part(self, q, k, MARKER_ROTATION)
      E = rotation_vector_matrix(phi)
      b_p = marker_part(self, q, k, MARKER_POSITION)
      H = 0.0_dp
      ! theta-theta
      X = matmul(W, transpose(E))
      do j = 1, 3
         X(:, j) = X(:, j) + w_position * b_p(j)
      end do
      H(4:7, 4:7) = euler_hessian(X)
      ! theta-zeta, mode by mode (3-vectors, no m-sized temporaries)
      T = rotation_vector_tangent(phi)
      Z = theta_gradient_matrix(q(4:7), w_position)
      do j = 1, 3
         need(j) = .not. all(W(:, j) == 0.0_dp)
         if (need(j)) Z_axes(:, :, j) = matmul(theta_gradient_matrix(q(4:7), W(:, j)), &
            skew3(E(:, j)))
      end do
      do l = 1, m
         column = matmul(Z, self%virtual_shapes(row - 5:row - 3, l))
         t_l = matmul(T, self%virtual_shapes(row - 2:row, l))
         do j = 1, 3
            if (need(j)) column = column - matmul(Z_axes(:, :, j), t_l)
         end do
         H(4:7, 7 + l) = column
         H(7 + l, 4:7) = column
      end do
      ! zeta-zeta
      if (any(W /= 0.0_dp)) then
         y = matmul(transpose(A), W)
         do j = 1, 3
            delta = epsilon(1.0_dp)**(1.0_dp / 3.0_dp) * max(abs(phi(j)), 1.0_dp)
            shifted = phi
            shifted(j) = phi(j) + delta
            t_plus = axis_term(shifted)
            shifted(j) = phi(j) - delta
            t_minus = axis_term(shifted)
            dt(:, j) = (t_plus - t_minus) / (2.0_dp * delta)
         end do
         dt = 0.5_dp * (dt + transpose(dt))
         do l = 1, m
            t_l = matmul(dt, self%virtual_shapes(row - 2:row, l))
            do j = 1, m
               H(7 + j, 7 + l) = dot_product(self%virtual_shapes(row - 2:row, j), t_l)
            end do
         end do
      end if
   contains
      !> t(phi) = T(phi)^T sum_j exp(phi~) e_j x y_j.
      pure function axis_term(rotation) result(t)
         real(dp), intent(in) :: rotation(3)
         real(dp) :: t(3)
         real(dp) :: exp_matrix(3, 3)
         integer :: i
         exp_matrix = rotation_vector_matrix(rotation)
         t = 0.0_dp
         do i = 1, 3
            t = t + cross_product(exp_matrix(:, i), y(:, i))
         end do
         t = matmul(transpose(rotation_vector_tangent(rotation)), t)
      end function axis_term
   end procedure flexible_body_marker_hessian

   !> Z(theta, w) (4 x 3) with Z b = d(w . A(theta) b)/dtheta = rotated_vector_jacobian(theta,
   !> b)^T w, linear in b.
   pure function theta_gradient_matrix(theta, w) result(Z)
      real(dp), intent(in) :: theta(4), w(3)
      real(dp) :: Z(4, 3)
      real(dp), parameter :: unit_axes(3, 3) = reshape([1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, &
         1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp], [3, 3])
      integer :: c
      do c = 1, 3
         Z(:, c) = matmul(w, rotated_vector_jacobian(theta, unit_axes(:, c)))
      end do
   end function theta_gradient_matrix

   module procedure flexible_body_marker_force_tangent
      real(dp) :: A(3, 3), G_bar(3, 4), u(3), y(3), n(3), p(3), dy(3, 4), dn(3, 4), phi(3)
      real(dp) :: psi_r(3, self%num_modes), delta, t_plus(3), t_minus(3), shifted(3), dt(3, 3)
      integer :: m, nc, l
      integer :: row
      row = 6 * self%marker_node(k)
      m = self%num_modes
      nc = self%num_coordinates
      A = euler_rotation(q(4:7))
      G_bar = euler_g_bar(q(4:7))
      u = marker_part(self, q, k, MARKER_POSITION)
      y = matmul(transpose(A), force)
      n = matmul(transpose(A), moment)
      p = cross_product(u, y) + n
      dy = transposed_rotation_derivative(q(4:7), force)
      dn = transposed_rotation_derivative(q(4:7), moment)
      psi_r = self%virtual_shapes(row - 2:row, :)
      phi = matmul(psi_r, q(8:nc))
      tangent = 0.0_dp
      tangent(4:7, 4:7) = g_bar_transpose_derivative(p) + matmul(transpose(G_bar), &
         matmul(skew3(u), dy) + dn)
      do l = 1, m
         tangent(4:7, 7 + l) = matmul(transpose(G_bar), &
            cross_product(self%virtual_shapes(row - 5:row - 3, l), y))
      end do
      tangent(8:nc, 4:7) = matmul(transpose(self%virtual_shapes(row - 5:row - 3, :)), dy) &
         + matmul(transpose(psi_r), matmul(transpose(rotation_vector_tangent(phi)), dn))
      if (any(moment /= 0.0_dp)) then
         ! Psi_Vr^T d(T(phi)^T n)/dphi Psi_Vr, the 3 x 3 derivative by central differences
         do l = 1, 3
            delta = epsilon(1.0_dp)**(1.0_dp / 3.0_dp) * max(abs(phi(l)), 1.0_dp)
            shifted = phi
            shifted(l) = phi(l) + delta
            t_plus = matmul(transpose(rotation_vector_tangent(shifted)), n)
            shifted(l) = phi(l) - delta
            t_minus = matmul(transpose(rotation_vector_tangent(shifted)), n)
            dt(:, l) = (t_plus - t_minus) / (2.0_dp * delta)
         end do
         tangent(8:nc, 8:nc) = matmul(transpose(psi_r), matmul(dt, psi_r))
      end if
   end procedure flexible_body_marker_force_tangent

   module procedure transposed_rotation_derivative
      jac = rotated_vector_jacobian([theta(1), -theta(2:4)], x)
      jac(:, 2:4) = -jac(:, 2:4)
   end procedure transposed_rotation_derivative

   module procedure cross_product
      c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
   end procedure cross_product

   module procedure flexible_body_marker_kinematics
      real(dp) :: A(3, 3), u(3), phi(3), E(3, 3), T(3, 3), t_l(3), AE_skew(3, 3, 3)
      integer :: j, l
      integer :: row
      row = 6 * self%marker_node(k)
      A = euler_rotation(q(4:7))
      u = marker_part(self, q, k, MARKER_POSITION)
      phi = marker_part(self, q, k, MARKER_ROTATION)
      E = rotation_vector_matrix(phi)
      if (self%framed(k)) E = matmul(E, self%marker_frame(:, :, k))
      position = q(1:3) + matmul(A, u)
      orientation = matmul(A, E)
      position_jacobian(:, 1:3) = identity3()
      position_jacobian(:, 4:7) = rotated_vector_jacobian(q(4:7), u)
      ! Mode by mode (3-vectors): no m-sized temporaries
      do l = 1, self%num_modes
         position_jacobian(:, 7 + l) = matmul(A, self%virtual_shapes(row - 5:row - 3, l))
      end do
      if (.not. any(need_axes)) return
      T = rotation_vector_tangent(phi)
      do j = 1, 3
         if (.not. need_axes(j)) cycle
         axis_jacobian(:, 1:3, j) = 0.0_dp
         axis_jacobian(:, 4:7, j) = rotated_vector_jacobian(q(4:7), E(:, j))
         AE_skew(:, :, j) = -matmul(A, skew3(E(:, j)))
      end do
      do l = 1, self%num_modes
         t_l = matmul(T, self%virtual_shapes(row - 2:row, l))
         do j = 1, 3
            if (need_axes(j)) axis_jacobian(:, 7 + l, j) = matmul(AE_skew(:, :, j), t_l)
         end do
      end do
   end procedure flexible_body_marker_kinematics

   !> Of virtual node k, in the body frame: its deformed position u_V = x_V + Psi_Vt zeta
   !> (part MARKER_POSITION) or its elastic rotation vector phi = Psi_Vr zeta (part
   !> MARKER_ROTATION, rad).
   pure function marker_part(self, q, k, part) result(u)
      class(flexible_body_t), intent(in) :: self
      real(dp), intent(in) :: q(:)
      integer, intent(in) :: k
      !> MARKER_POSITION or MARKER_ROTATION: the offset of its rows in the node's six
      integer, intent(in) :: part
      real(dp) :: u(3)
      integer :: l
      integer :: row
      row = 6 * (self%marker_node(k) - 1) + part
      if (part == MARKER_POSITION) then
         u = self%virtual_xyz(:, self%marker_node(k))
      else
         u = 0.0_dp
      end if
      do l = 1, self%num_modes
         u = u + q(7 + l) * self%virtual_shapes(row + 1:row + 3, l)
      end do
   end function marker_part

   !> The mode shapes of virtual node k's translations (part MARKER_POSITION) or rotations
   !> (part MARKER_ROTATION), 3 x num_modes.
   pure function marker_shapes(self, k, part) result(shapes)
      class(flexible_body_t), intent(in) :: self
      integer, intent(in) :: k
      !> MARKER_POSITION or MARKER_ROTATION: the offset of its rows in the node's six
      integer, intent(in) :: part
      real(dp) :: shapes(3, self%num_modes)
      integer :: row
      row = 6 * (self%marker_node(k) - 1) + part
      shapes = self%virtual_shapes(row + 1:row + 3, :)
   end function marker_shapes

   module procedure flexible_body_marker_position
      real(dp) :: A(3, 3), u(3)
      A = euler_rotation(q(4:7))
      u = marker_part(self, q, k, MARKER_POSITION)
      r = q(1:3) + matmul(A, u)
   end procedure flexible_body_marker_position

   module procedure flexible_body_marker_orientation
      real(dp) :: A(3, 3), R(3, 3)
      A = euler_rotation(q(4:7))
      R = rotation_vector_matrix(marker_part(self, q, k, MARKER_ROTATION))
      if (self%framed(k)) R = matmul(R, self%marker_frame(:, :, k))
      A_v = matmul(A, R)
   end procedure flexible_body_marker_orientation

   module procedure flexible_body_marker_velocity_jacobian
      real(dp) :: A(3, 3)
      A = euler_rotation(q(4:7))
      jac(:, 1:3) = identity3()
      jac(:, 4:7) = -matmul(A, matmul(skew3(marker_part(self, q, k, MARKER_POSITION)), &
         euler_g_bar(q(4:7))))
      jac(:, 8:) = matmul(A, marker_shapes(self, k, MARKER_POSITION))
   end procedure flexible_body_marker_velocity_jacobian

   module procedure flexible_body_marker_position_jacobian
      jac(:, 1:3) = identity3()
      jac(:, 4:7) = rotated_vector_jacobian(q(4:7), marker_part(self, q, k, MARKER_POSITION))
      jac(:, 8:) = matmul(euler_rotation(q(4:7)), marker_shapes(self, k, MARKER_POSITION))
   end procedure flexible_body_marker_position_jacobian

   module procedure flexible_body_marker_rotation_jacobian
      real(dp) :: A(3, 3)
      A = euler_rotation(q(4:7))
      jac(:, 1:3) = 0.0_dp
      jac(:, 4:7) = matmul(A, euler_g_bar(q(4:7)))
      jac(:, 8:) = matmul(matmul(A, rotation_vector_tangent(marker_part(self, q, k, &
         MARKER_ROTATION))), marker_shapes(self, k, MARKER_ROTATION))
   end procedure flexible_body_marker_rotation_jacobian

   module procedure flexible_body_marker_axis_jacobian
      real(dp) :: A(3, 3), phi(3), b(3)
      A = euler_rotation(q(4:7))
      phi = marker_part(self, q, k, MARKER_ROTATION)
      if (self%framed(k)) then
         b = matmul(rotation_vector_matrix(phi), matmul(self%marker_frame(:, :, k), axis))
      else
         b = matmul(rotation_vector_matrix(phi), axis)
      end if
      jac(:, 1:3) = 0.0_dp
      jac(:, 4:7) = rotated_vector_jacobian(q(4:7), b)
      jac(:, 8:) = -matmul(matmul(A, matmul(skew3(b), rotation_vector_tangent(phi))), &
         marker_shapes(self, k, MARKER_ROTATION))
   end procedure flexible_body_marker_axis_jacobian

   module procedure flexible_body_marker_generalized_force
      real(dp) :: A(3, 3), u(3), y(3), n(3), T(3, 3), Tn(3)
      integer :: l
      ! The header's closed forms (= matmul(force, L_r) + matmul(moment, L_w) without the
      ! 3 x (7+m) Jacobians)
      integer :: row
      row = 6 * self%marker_node(k)
      A = euler_rotation(q(4:7))
      u = marker_part(self, q, k, MARKER_POSITION)
      y = matmul(force, A)
      n = matmul(moment, A)
      T = rotation_vector_tangent(marker_part(self, q, k, MARKER_ROTATION))
      Tn = matmul(n, T)
      gen(1:3) = force
      gen(4:7) = matmul(cross_product(u, y) + n, euler_g_bar(q(4:7)))
      do l = 1, self%num_modes
         gen(7 + l) = dot_product(self%virtual_shapes(row - 5:row - 3, l), y) + &
            dot_product(self%virtual_shapes(row - 2:row, l), Tn)
      end do
   end procedure flexible_body_marker_generalized_force

end submodule ffrf_mbs_flexible_body_markers
