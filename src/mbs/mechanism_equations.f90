!> The equations of a mechanism (ffrf_mbs_mechanism, dae_system_t): mass, forces, energies,
!> constraints and their Jacobian, time terms and the acceleration right-hand side, and the
!> helpers the other submodules share (body count, drive normal).
submodule (ffrf_mbs_mechanism) ffrf_mbs_mechanism_equations
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_error, only: fatal_error, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_finite, only: all_finite
   use ffrf_mbs_rotation, only: euler_rotation, rotated_vector_jacobian
   use ffrf_mbs_joints, only: joint_reaction
   use ffrf_mbs_joint_driver, only: driver_terms, driver_hessian
   implicit none

   !> Unit x axis
   real(dp), parameter :: e_x(3) = [1.0_dp, 0.0_dp, 0.0_dp]

contains

   module procedure num_bodies
      num_bodies = 0
      if (allocated(self%bodies)) num_bodies = size(self%bodies)
   end procedure num_bodies

   !> Kinetic energy sum_b v_b^T M_b(q_b) v_b / 2 (J).
   module procedure mechanism_kinetic_energy
      integer :: b, k, nb
      energy = 0.0_dp
      do b = 1, num_bodies(self)
         call body_layout(self, b, k, nb)
         if (nb > 0) energy = energy + self%bodies(b)%body%kinetic_energy(q(k + 1:k + nb), &
            v(k + 1:k + nb))
      end do
   end procedure mechanism_kinetic_energy

   !> Strain energy of the flexible bodies, sum zeta^T K_ff zeta / 2 (J); 0 for rigid ones.
   module procedure mechanism_strain_energy
      integer :: b, k, nb
      energy = 0.0_dp
      do b = 1, num_bodies(self)
         call body_layout(self, b, k, nb)
         energy = energy + self%bodies(b)%body%strain_energy(q(k + 1:k + nb))
      end do
   end procedure mechanism_strain_energy

   !> Power of the applied loads and gravity, Q_applied . v (W): integrated over time it is the
   !> work that enters the energy balance kinetic + strain + dissipated = work.
   module procedure mechanism_applied_power
      real(dp) :: f(self%n)
      power = 0.0_dp
      call self%applied_force(q, v, t, f, error)
      if (allocated(error)) return
      power = dot_product(f, v)
   end procedure mechanism_applied_power

   !> Force and moment of joint j on its two bodies from the multipliers of all rows
   !> (joint_reaction: column 1 on body a at marker a, column 2 on body b at marker b).
   module procedure mechanism_reaction
      associate (jt => self%joints(j))
         call joint_reaction(jt%joint, self%bodies(jt%body_a)%body, &
            self%body_coordinates(q, jt%body_a), self%bodies(jt%body_b)%body, &
            self%body_coordinates(q, jt%body_b), &
            lambda(jt%offset + 1:jt%offset + jt%joint%num_equations), force, moment)
      end associate
   end procedure mechanism_reaction

   !> n.
   module procedure mechanism_num_coordinates
      num = self%n
   end procedure mechanism_num_coordinates

   !> nc (joint rows, drive row, Euler rows).
   module procedure mechanism_num_constraints
      num = self%nc
   end procedure mechanism_num_constraints

   !> The Euler rows.
   module procedure mechanism_protected_rows
      integer :: b
      protect = .false.
      do b = 1, num_bodies(self)
         if (self%bodies(b)%euler_row > 0) protect(self%bodies(b)%euler_row) = .true.
      end do
   end procedure mechanism_protected_rows

   !> M = blockdiag(M_b(q_b)).
   module procedure mechanism_mass
      integer :: b, k, nb
      M = 0.0_dp
      do b = 1, num_bodies(self)
         call body_layout(self, b, k, nb)
         if (nb == 0) cycle
         M(k + 1:k + nb, k + 1:k + nb) = self%bodies(b)%body%mass_matrix(q(k + 1:k + nb))
         ! Only the bodies' blocks can hold a NaN
         if (.not. all_finite(M(k + 1:k + nb, k + 1:k + nb))) then
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'mechanism: mass matrix of body "' // &
               self%bodies(b)%name // '" not finite (NaN coordinates?)')
            return
         end if
      end do
   end procedure mechanism_mass

   !> M = blockdiag(M_b(q_b)), one block per body.
   module procedure mechanism_mass_sparse
      integer :: b, k, nb
      call block_groups(self, M, .false.)
      do b = 1, num_bodies(self)
         call body_layout(self, b, k, nb)
         if (nb == 0) cycle
         call M%add_block(k, k, self%bodies(b)%body%mass_matrix(q(k + 1:k + nb)))
      end do
      if (.not. all_finite(M%values(:M%used))) call fatal_error(error, FFRF_NUMERIC_ERROR, &
         'mechanism: mass matrix not finite (NaN coordinates?)')
   end procedure mechanism_mass_sparse

   !> f = sum_b (f_v + Q_e) + applied loads + gravity.
   module procedure mechanism_force
      integer :: b, k, nb
      call self%applied_force(q, v, t, f, error)
      if (allocated(error)) return
      do b = 1, num_bodies(self)
         call body_layout(self, b, k, nb)
         if (nb == 0) cycle
         associate (body => self%bodies(b)%body)
            f(k + 1:k + nb) = f(k + 1:k + nb) + body%quadratic_velocity(q(k + 1:k + nb), &
               v(k + 1:k + nb)) + body%elastic_force(q(k + 1:k + nb), v(k + 1:k + nb))
         end associate
      end do
   end procedure mechanism_force

   !> Phi: joint equations, drive row, Euler normalisations.
   module procedure mechanism_constraints
      integer :: j
      do j = 1, num_joints(self)
         associate (jt => self%joints(j))
            call jt%joint%residual(self%bodies(jt%body_a)%body, &
               self%body_coordinates(q, jt%body_a), self%bodies(jt%body_b)%body, &
               self%body_coordinates(q, jt%body_b), &
               phi(jt%offset + 1:jt%offset + jt%joint%num_equations))
         end associate
      end do
      call driver_rows(self, q, t, phi)
      call drive_and_euler_rows(self, q, t, phi)
      if (.not. all_finite(phi)) call fatal_error(error, FFRF_NUMERIC_ERROR, &
         'mechanism: constraint residuals not finite at t = ' // to_str(t) // ' s')
   end procedure mechanism_constraints

   !> Phi_q: joint blocks, drive row n^T d(A e_x)/dtheta, Euler rows 2 theta^T.
   module procedure mechanism_constraint_jacobian
      real(dp) :: phi(self%nc)
      call self%constraints_and_jacobian(q, t, phi, Phi_q, error)
      if (allocated(error)) return
      if (.not. all_finite(Phi_q)) call fatal_error(error, FFRF_NUMERIC_ERROR, &
         'mechanism: constraint Jacobian not finite at t = ' // to_str(t) // ' s')
   end procedure mechanism_constraint_jacobian

   !> Phi and Phi_q: one residual_jacobian call per joint, then the drive and Euler rows. Not
   !> checked for NaN here: the integrator checks the residual, which carries any NaN of Phi_q.
   module procedure mechanism_constraints_and_jacobian
      call jacobian_rows(self, q, t, phi, error, dense=Phi_q)
   end procedure mechanism_constraints_and_jacobian

   !> Phi and Phi_q, Phi_q block-sparse: the same rows as the dense Phi_q.
   module procedure mechanism_constraints_and_jacobian_sparse
      call block_groups(self, Phi_q, .true.)
      call jacobian_rows(self, q, t, phi, error, sparse=Phi_q)
   end procedure mechanism_constraints_and_jacobian_sparse

   !> Phi and Phi_q into a dense (nc x n, written in place) or a block-sparse matrix (zero on
   !> entry, its groups set: block_groups).
   subroutine jacobian_rows(self, q, t, phi, error, dense, sparse)
      type(mechanism_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), t
      real(dp), intent(out) :: phi(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp), intent(out), optional :: dense(:, :)
      type(block_sparse_t), intent(inout), optional :: sparse
      real(dp), allocatable :: ja(:, :), jb(:, :)
      integer :: j, ka, kb, na, nb, ne
      if (present(dense)) dense = 0.0_dp
      do j = 1, num_joints(self)
         associate (jt => self%joints(j))
            ne = jt%joint%num_equations
            call pair_layout(self, jt%body_a, jt%body_b, ka, na, kb, nb)
            if (present(dense)) then
               ! The two bodies differ (add_joint), so their column blocks do not overlap:
               ! the joint writes its blocks in place
               call jt%joint%residual_jacobian(self%bodies(jt%body_a)%body, q(ka + 1:ka + na), &
                  self%bodies(jt%body_b)%body, q(kb + 1:kb + nb), &
                  phi(jt%offset + 1:jt%offset + ne), &
                  dense(jt%offset + 1:jt%offset + ne, ka + 1:ka + na), &
                  dense(jt%offset + 1:jt%offset + ne, kb + 1:kb + nb))
            else
               allocate (ja(ne, na), jb(ne, nb))
               call jt%joint%residual_jacobian(self%bodies(jt%body_a)%body, q(ka + 1:ka + na), &
                  self%bodies(jt%body_b)%body, q(kb + 1:kb + nb), &
                  phi(jt%offset + 1:jt%offset + ne), ja, jb)
               call sparse%add_block(jt%offset, ka, ja)
               call sparse%add_block(jt%offset, kb, jb)
               deallocate (ja, jb)
            end if
         end associate
      end do
      call driver_rows(self, q, t, phi, dense, sparse=sparse)
      call drive_and_euler_rows(self, q, t, phi, dense, sparse)
      if (.not. all_finite(phi)) call fatal_error(error, FFRF_NUMERIC_ERROR, &
         'mechanism: constraint residuals not finite at t = ' // to_str(t) // ' s')
   end subroutine jacobian_rows

   !> The drivers' rows of Phi and, if present, of Phi_q (ffrf_mbs_joint_driver), their Phi_t
   !> (phi_t), and (Phi_q v)_q v + Phi_tt + 2 Phi_qt v (accel, with v; other entries untouched).
   subroutine driver_rows(self, q, t, phi, Phi_q, v, phi_t, accel, sparse)
      type(mechanism_t), intent(in) :: self
      real(dp), intent(in) :: q(:)
      real(dp), intent(in) :: t
      real(dp), intent(inout), optional :: phi(:)
      real(dp), intent(inout), optional :: Phi_q(:, :)
      !> Phi_q block-sparse (zero on entry), instead of Phi_q
      type(block_sparse_t), intent(inout), optional :: sparse
      real(dp), intent(in), optional :: v(:)
      real(dp), intent(inout), optional :: phi_t(:), accel(:)
      real(dp), allocatable :: ja(:), jb(:), jaf(:), jbf(:), K_aa(:, :), K_ab(:, :), K_bb(:, :)
      real(dp) :: f(3), value, value_f, value_ff
      integer :: d, ka, kb, na, nb
      if (.not. allocated(self%drivers)) return
      do d = 1, size(self%drivers)
         associate (dr => self%drivers(d), jt => self%joints(self%drivers(d)%joint))
            call pair_layout(self, jt%body_a, jt%body_b, ka, na, kb, nb)
            allocate (ja(na), jb(nb), jaf(na), jbf(nb))
            f = dr%prescribed(t)
            call driver_terms(dr%kind, self%bodies(jt%body_a)%body, q(ka + 1:ka + na), &
               jt%joint%marker_a, self%bodies(jt%body_b)%body, q(kb + 1:kb + nb), &
               jt%joint%marker_b, f(1), value, ja, jb, value_f, value_ff, jaf, jbf)
            if (present(phi)) phi(dr%row) = value
            if (present(Phi_q)) then
               Phi_q(dr%row, ka + 1:ka + na) = ja
               Phi_q(dr%row, kb + 1:kb + nb) = jb
            else if (present(sparse)) then
               call sparse%add_block(dr%row - 1, ka, reshape(ja, [1, na]))
               call sparse%add_block(dr%row - 1, kb, reshape(jb, [1, nb]))
            end if
            if (present(phi_t)) phi_t(dr%row) = f(2) * value_f
            ! Phi_tt + 2 Phi_qt v = f'' Phi_f + f'^2 Phi_ff + 2 f' (dPhi_q/df) v, and the
            ! convective v^T (d^2 Phi/dq^2) v from the exact second derivatives
            if (present(accel)) then
               allocate (K_aa(na, na), K_ab(na, nb), K_bb(nb, nb))
               call driver_hessian(dr%kind, self%bodies(jt%body_a)%body, q(ka + 1:ka + na), &
                  jt%joint%marker_a, self%bodies(jt%body_b)%body, q(kb + 1:kb + nb), &
                  jt%joint%marker_b, f(1), 1.0_dp, K_aa, K_ab, K_bb)
               associate (va => v(ka + 1:ka + na), vb => v(kb + 1:kb + nb))
                  accel(dr%row) = f(3) * value_f + f(2)**2 * value_ff + 2.0_dp * f(2) * &
                     (dot_product(jaf, va) + dot_product(jbf, vb)) + &
                     dot_product(va, matmul(K_aa, va)) + 2.0_dp * dot_product(va, &
                     matmul(K_ab, vb)) + dot_product(vb, matmul(K_bb, vb))
               end associate
               deallocate (K_aa, K_ab, K_bb)
            end if
            deallocate (ja, jb, jaf, jbf)
         end associate
      end do
   end subroutine driver_rows

   !> Drive row n . A(theta) e_x and Euler rows |theta|^2 - 1 of Phi and, if present, their rows
   !> n^T d(A e_x)/dtheta and 2 theta^T of Phi_q (other entries untouched).
   subroutine drive_and_euler_rows(self, q, t, phi, Phi_q, sparse)
      type(mechanism_t), intent(inout) :: self
      real(dp), intent(in) :: q(:)
      real(dp), intent(in) :: t
      real(dp), intent(inout) :: phi(:)
      real(dp), intent(inout), optional :: Phi_q(:, :)
      !> Phi_q block-sparse (zero on entry), instead of Phi_q
      type(block_sparse_t), intent(inout), optional :: sparse
      real(dp) :: f(3), normal(3)
      integer :: b, k
      if (self%drive_row > 0) then
         k = self%bodies(self%drive_body)%offset
         f = self%drive%evaluate(t)
         normal = drive_normal(f(1))
         phi(self%drive_row) = dot_product(normal, matmul(euler_rotation(q(k + 4:k + 7)), e_x))
         if (present(Phi_q)) Phi_q(self%drive_row, k + 4:k + 7) = matmul(normal, &
            rotated_vector_jacobian(q(k + 4:k + 7), e_x))
         if (present(sparse)) call sparse%add_block(self%drive_row - 1, k + 3, &
            reshape(matmul(normal, rotated_vector_jacobian(q(k + 4:k + 7), e_x)), [1, 4]))
      end if
      do b = 1, num_bodies(self)
         if (self%bodies(b)%euler_row == 0) cycle
         k = self%bodies(b)%offset
         phi(self%bodies(b)%euler_row) = dot_product(q(k + 4:k + 7), q(k + 4:k + 7)) - 1.0_dp
         if (present(Phi_q)) Phi_q(self%bodies(b)%euler_row, k + 4:k + 7) = 2.0_dp * &
            q(k + 4:k + 7)
         if (present(sparse)) call sparse%add_block(self%bodies(b)%euler_row - 1, k + 3, &
            reshape(2.0_dp * q(k + 4:k + 7), [1, 4]))
      end do
   end subroutine drive_and_euler_rows

   !> Phi_t: zero except the drive row, f' n_f . A e_x (module header).
   module procedure mechanism_constraint_rate
      real(dp) :: f(3)
      integer :: k
      phi_t = 0.0_dp
      if (self%drive_row > 0) then
         k = self%bodies(self%drive_body)%offset
         f = self%drive%evaluate(t)
         phi_t(self%drive_row) = f(2) * dot_product(drive_normal_rate(f(1)), &
            matmul(euler_rotation(q(k + 4:k + 7)), e_x))
      end if
      call driver_rows(self, q, t, phi_t=phi_t)
      if (.not. all(ieee_is_finite(phi_t))) call fatal_error(error, FFRF_NUMERIC_ERROR, &
         'mechanism: drive law not finite at t = ' // to_str(t) // ' s')
   end procedure mechanism_constraint_rate

   !> g = -(Phi_q v)_q v - 2 Phi_qt v - Phi_tt (module header): analytic on the drive and Euler
   !> rows, central difference in s of Phi_q(q + s v) v on the joint rows.
   module procedure mechanism_acceleration_rhs
      real(dp) :: jac(self%nc, self%n), w_plus(self%nc), w_minus(self%nc), time_part(self%nc)
      real(dp) :: s, vmax, qscale, root3, f(3), theta(4), theta_dot(4), x_axis(3), nf(3)
      integer :: b, k, joint_rows
      g = 0.0_dp
      if (self%nc == 0) return
      joint_rows = sum([(self%joints(k)%joint%num_equations, k = 1, num_joints(self))])
      vmax = 0.0_dp
      if (self%n > 0) vmax = maxval(abs(v))
      if (joint_rows > 0 .and. vmax > 0.0_dp) then
         root3 = epsilon(1.0_dp)**(1.0_dp / 3.0_dp)
         qscale = max(maxval(abs(q)), 1.0_dp)
         s = root3 * qscale / vmax
         call self%constraint_jacobian(q + s * v, t, jac, error)
         if (allocated(error)) return
         w_plus = matmul(jac, v)
         call self%constraint_jacobian(q - s * v, t, jac, error)
         if (allocated(error)) return
         w_minus = matmul(jac, v)
         g(:joint_rows) = -(w_plus(:joint_rows) - w_minus(:joint_rows)) / (2.0_dp * s)
      end if
      if (allocated(self%drivers)) then
         ! v^T (d^2 Phi/dq^2) v + Phi_tt + 2 Phi_qt v of the drivers' rows, exact
         time_part = 0.0_dp
         call driver_rows(self, q, t, v=v, accel=time_part)
         g = g - time_part
      end if
      if (self%drive_row > 0) then
         ! Phi = n(f(t)) . A(theta) e_x: -(n . 2 (A(theta_dot) + I) e_x) - 2 f' n_f . dA e_x
         ! - (f'' n_f - f'^2 n) . A e_x
         k = self%bodies(self%drive_body)%offset
         f = self%drive%evaluate(t)
         theta = q(k + 4:k + 7)
         theta_dot = v(k + 4:k + 7)
         x_axis = matmul(euler_rotation(theta), e_x)
         nf = drive_normal_rate(f(1))
         g(self%drive_row) = -2.0_dp * dot_product(drive_normal(f(1)), &
            matmul(euler_rotation(theta_dot), e_x) + e_x) &
            - 2.0_dp * f(2) * dot_product(nf, matmul(rotated_vector_jacobian(theta, e_x), &
            theta_dot)) - dot_product(f(3) * nf - f(2)**2 * drive_normal(f(1)), x_axis)
      end if
      do b = 1, num_bodies(self)
         if (self%bodies(b)%euler_row == 0) cycle
         k = self%bodies(b)%offset
         g(self%bodies(b)%euler_row) = -2.0_dp * dot_product(v(k + 4:k + 7), v(k + 4:k + 7))
      end do
      if (.not. all(ieee_is_finite(g))) call fatal_error(error, FFRF_NUMERIC_ERROR, &
         'mechanism: acceleration right-hand side not finite at t = ' // to_str(t) // ' s')
   end procedure mechanism_acceleration_rhs

   !> After an accepted step: the state must be finite; the rotor angle becomes the new
   !> unwrapping reference.
   module procedure mechanism_accepted_step
      if (.not. (all(ieee_is_finite(q)) .and. all(ieee_is_finite(v)) .and. &
         all(ieee_is_finite(qdd)) .and. all(ieee_is_finite(lambda)))) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'mechanism: state not finite at t = ' // &
            to_str(t) // ' s; reduce the time step')
         return
      end if
      self%rotor_reference = self%rotor_angle(q)
      call update_torsion_references(self, q)
   end procedure mechanism_accepted_step

   module procedure drive_normal
      normal = [-sin(angle), cos(angle), 0.0_dp]
   end procedure drive_normal

   !> dn/df = (-cos f, -sin f, 0).
   pure function drive_normal_rate(angle) result(rate)
      real(dp), intent(in) :: angle
      real(dp) :: rate(3)
      rate = [-cos(angle), -sin(angle), 0.0_dp]
   end function drive_normal_rate

end submodule ffrf_mbs_mechanism_equations
