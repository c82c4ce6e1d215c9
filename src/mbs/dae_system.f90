!> The constrained mechanical system that the generalized-alpha integrator advances (theory.md 4):
!>
!>    M(q) q'' + Phi_q(q, t)^T lambda = f(q, q', t),     Phi(q, t) = 0   (index 3).
!>
!> A mechanism extends `dae_system_t` and implements the deferred basic procedures (sizes, mass,
!> force, constraints, constraint Jacobian). The tangent matrices of the Newton iteration
!> (K_t = -df/dq, C_t = -df/dq', d(Phi_q^T lambda)/dq, d(M a)/dq) and the time terms of the
!> constraints (Phi_t, the acceleration right-hand side) have default implementations by central
!> finite differences, so a new system runs at once; a system overrides them with analytic versions
!> for speed (the test suite checks such an override against these defaults).
!>
!> Finite-difference step: central differences with delta_j = eps**(1/3) max(|x_j|, 1), rounded
!> so that x_j + delta_j - x_j is exact; the truncation error O(delta**2) and the round-off error
!> O(eps/delta) then balance near eps**(2/3) ~ 4e-11 relative to the scale of the function.
!>
!> Every procedure has `error` last: a system may fail (a NaN force, a body out of its table) and
!> the integrator passes the failure up with the time of the step.
module ffrf_mbs_dae_system
   use ffrf_core_kinds, only: dp
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_error, only: error_t, fatal_error, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_la_block_sparse, only: block_sparse_t
   implicit none
   private
   public :: dae_system_t, fd_step
   !> The dense defaults of the block-sparse interface (one block), public for overrides that
   !> fall back to them
   public :: dae_tangents_sparse
   !> The central-difference tangents, public so that a system with analytic overrides can keep
   !> them as a reference path (mechanism_t%analytic_tangents = .false.)
   public :: dae_stiffness_fd, dae_damping_fd, dae_constraint_stiffness_fd, dae_mass_stiffness_fd

   !> A constrained mechanical system M q'' + Phi_q^T lambda = f, Phi = 0 (theory.md section 4).
   type, abstract :: dae_system_t
   contains
      !> Number of generalized coordinates n
      procedure(dae_size), deferred :: num_coordinates
      !> Number of constraint equations nc (redundant ones included)
      procedure(dae_size), deferred :: num_constraints
      !> Mass matrix M(q), n x n
      procedure(dae_mass), deferred :: mass
      !> Generalized forces f(q, q', t): applied + quadratic velocity + elastic, right-hand side
      procedure(dae_force), deferred :: force
      !> Constraint residuals Phi(q, t), nc
      procedure(dae_constraints), deferred :: constraints
      !> Constraint Jacobian Phi_q(q, t), nc x n
      procedure(dae_jacobian), deferred :: constraint_jacobian
      !> Phi and Phi_q in one call (default: `constraints`, then `constraint_jacobian`; a system
      !> whose two share work overrides it)
      procedure :: constraints_and_jacobian => dae_constraints_and_jacobian
      !> K_t = -df/dq, n x n (default: central differences of `force`)
      procedure :: stiffness => dae_stiffness_fd
      !> C_t = -df/dq', n x n (default: central differences of `force`)
      procedure :: damping => dae_damping_fd
      !> d(Phi_q^T lambda)/dq, n x n (default: central differences of `constraint_jacobian`)
      procedure :: constraint_stiffness => dae_constraint_stiffness_fd
      !> d(M(q) a)/dq for a fixed a, n x n (default: central differences of `mass`)
      procedure :: mass_stiffness => dae_mass_stiffness_fd
      !> Phi_t = dPhi/dt, nc (default: central difference in t; exactly 0 if Phi has no t)
      procedure :: constraint_rate => dae_constraint_rate_fd
      !> Acceleration right-hand side g = -(Phi_q q')_q q' - 2 Phi_qt q' - Phi_tt, nc, so that
      !> Phi_q q'' = g on the motion (theory.md 4.3; default: central differences)
      procedure :: acceleration_rhs => dae_acceleration_rhs_fd
      !> The sparse path of the iteration matrix, described in
      !> docs/performance_threads.md "The iteration matrix: dense or sparse LU":
      !> M, Phi_q and the tangents as block-sparse matrices, so
      !> that nothing of size n x n is formed. The defaults call the dense procedures and hold
      !> the result as one block (correct, not sparse); a system with structure overrides them.
      !> M(q) block-sparse (default: `mass`)
      procedure :: mass_sparse => dae_mass_sparse
      !> Phi and Phi_q, Phi_q block-sparse (default: `constraints_and_jacobian`)
      procedure :: constraints_and_jacobian_sparse => dae_constraints_and_jacobian_sparse
      !> K = K_t + d(M a)/dq + d(Phi_q^T lambda)/dq and C = C_t, block-sparse (default:
      !> `stiffness`, `mass_stiffness`, `constraint_stiffness`, `damping`)
      procedure :: tangents_sparse => dae_tangents_sparse
      !> Hook called after every accepted step (and once at the start), for output; default none
      procedure :: accepted_step => dae_accepted_step_none
      !> Constraint rows the redundant-row search must keep (e.g. Euler-parameter
      !> normalisations), nc; default none
      procedure :: protected_rows => dae_protected_rows_none
   end type dae_system_t

   abstract interface
      !> A size of the system.
      function dae_size(self) result(num)
         import :: dae_system_t
         implicit none
         !> The system
         class(dae_system_t), intent(in) :: self
         integer :: num
      end function dae_size

      !> Mass matrix M(q).
      subroutine dae_mass(self, q, M, error)
         import :: dae_system_t, dp, error_t
         implicit none
         !> The system
         class(dae_system_t), intent(inout) :: self
         !> Generalized coordinates, n
         real(dp), intent(in) :: q(:)
         !> Mass matrix, n x n (kg, kg m, kg m^2 by coordinate)
         real(dp), intent(out) :: M(:, :)
         type(error_t), allocatable, intent(out) :: error
      end subroutine dae_mass

      !> Generalized forces f(q, q', t).
      subroutine dae_force(self, q, v, t, f, error)
         import :: dae_system_t, dp, error_t
         implicit none
         !> The system
         class(dae_system_t), intent(inout) :: self
         !> Generalized coordinates, n
         real(dp), intent(in) :: q(:)
         !> Generalized velocities q', n
         real(dp), intent(in) :: v(:)
         !> Time (s)
         real(dp), intent(in) :: t
         !> Generalized forces (applied + quadratic velocity + elastic), n
         real(dp), intent(out) :: f(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine dae_force

      !> Constraint residuals Phi(q, t).
      subroutine dae_constraints(self, q, t, phi, error)
         import :: dae_system_t, dp, error_t
         implicit none
         !> The system
         class(dae_system_t), intent(inout) :: self
         !> Generalized coordinates, n
         real(dp), intent(in) :: q(:)
         !> Time (s)
         real(dp), intent(in) :: t
         !> Constraint residuals, nc
         real(dp), intent(out) :: phi(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine dae_constraints

      !> Constraint Jacobian Phi_q(q, t).
      subroutine dae_jacobian(self, q, t, Phi_q, error)
         import :: dae_system_t, dp, error_t
         implicit none
         !> The system
         class(dae_system_t), intent(inout) :: self
         !> Generalized coordinates, n
         real(dp), intent(in) :: q(:)
         !> Time (s)
         real(dp), intent(in) :: t
         !> dPhi/dq, nc x n
         real(dp), intent(out) :: Phi_q(:, :)
         type(error_t), allocatable, intent(out) :: error
      end subroutine dae_jacobian
   end interface

contains

   !> Central-difference step for the variable x: eps**(1/3) max(|x|, 1), made exactly
   !> representable as (x + delta) - x.
   pure function fd_step(x) result(delta)
      !> Value of the variable
      real(dp), intent(in) :: x
      real(dp) :: delta
      real(dp) :: shifted
      delta = epsilon(1.0_dp)**(1.0_dp / 3.0_dp) * max(abs(x), 1.0_dp)
      shifted = x + delta
      delta = shifted - x
   end function fd_step

   !> K_t = -df/dq by central differences of `force`, column by column.
   subroutine dae_stiffness_fd(self, q, v, t, K_t, error)
      !> The system
      class(dae_system_t), intent(inout) :: self
      !> Generalized coordinates, n
      real(dp), intent(in) :: q(:)
      !> Generalized velocities, n
      real(dp), intent(in) :: v(:)
      !> Time (s)
      real(dp), intent(in) :: t
      !> -df/dq, n x n
      real(dp), intent(out) :: K_t(:, :)
      type(error_t), allocatable, intent(out) :: error
      integer :: j
      do j = 1, size(q)
         call force_difference(self, q, v, t, j, K_t(:, j), error)
         if (allocated(error)) return
      end do
   end subroutine dae_stiffness_fd

   !> C_t = -df/dq' by central differences of `force`, column by column.
   subroutine dae_damping_fd(self, q, v, t, C_t, error)
      !> The system
      class(dae_system_t), intent(inout) :: self
      !> Generalized coordinates, n
      real(dp), intent(in) :: q(:)
      !> Generalized velocities, n
      real(dp), intent(in) :: v(:)
      !> Time (s)
      real(dp), intent(in) :: t
      !> -df/dq', n x n
      real(dp), intent(out) :: C_t(:, :)
      type(error_t), allocatable, intent(out) :: error
      integer :: j
      do j = 1, size(v)
         call force_difference(self, q, v, t, size(q) + j, C_t(:, j), error)
         if (allocated(error)) return
      end do
   end subroutine dae_damping_fd

   !> Column i of -df/dx over x = [q; q'] (i <= n: a coordinate, else a velocity) by a central
   !> difference of `force`: -(f(x + delta e_i) - f(x - delta e_i)) / (2 delta).
   subroutine force_difference(self, q, v, t, i, column, error)
      class(dae_system_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), v(:), t
      integer, intent(in) :: i
      real(dp), intent(out) :: column(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: x_plus(size(q) + size(v)), x_minus(size(q) + size(v)), f_plus(size(q))
      real(dp) :: f_minus(size(q)), delta
      integer :: n
      n = size(q)
      x_plus = [q, v]
      x_minus = x_plus
      delta = fd_step(x_plus(i))
      x_plus(i) = x_plus(i) + delta
      x_minus(i) = x_minus(i) - delta
      call self%force(x_plus(:n), x_plus(n + 1:), t, f_plus, error)
      if (allocated(error)) return
      call self%force(x_minus(:n), x_minus(n + 1:), t, f_minus, error)
      if (allocated(error)) return
      column = -(f_plus - f_minus) / (2.0_dp * delta)
   end subroutine force_difference

   !> Phi(q, t) and Phi_q(q, t): `constraints`, then `constraint_jacobian`.
   subroutine dae_constraints_and_jacobian(self, q, t, phi, Phi_q, error)
      !> The system
      class(dae_system_t), intent(inout) :: self
      !> Coordinates, n
      real(dp), intent(in) :: q(:)
      !> Time (s)
      real(dp), intent(in) :: t
      !> Phi, nc
      real(dp), intent(out) :: phi(:)
      !> Phi_q, nc x n
      real(dp), intent(out) :: Phi_q(:, :)
      type(error_t), allocatable, intent(out) :: error
      call self%constraints(q, t, phi, error)
      if (allocated(error)) return
      call self%constraint_jacobian(q, t, Phi_q, error)
   end subroutine dae_constraints_and_jacobian

   !> d(Phi_q^T lambda)/dq by central differences of `constraint_jacobian`.
   subroutine dae_constraint_stiffness_fd(self, q, t, lambda, K_c, error)
      !> The system
      class(dae_system_t), intent(inout) :: self
      !> Generalized coordinates, n
      real(dp), intent(in) :: q(:)
      !> Time (s)
      real(dp), intent(in) :: t
      !> Lagrange multipliers, nc
      real(dp), intent(in) :: lambda(:)
      !> d(Phi_q^T lambda)/dq, n x n
      real(dp), intent(out) :: K_c(:, :)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: qp(size(q)), jac_plus(size(lambda), size(q)), jac_minus(size(lambda), size(q))
      real(dp) :: delta
      integer :: j
      qp = q
      do j = 1, size(q)
         delta = fd_step(q(j))
         qp(j) = q(j) + delta
         call self%constraint_jacobian(qp, t, jac_plus, error)
         if (allocated(error)) return
         qp(j) = q(j) - delta
         call self%constraint_jacobian(qp, t, jac_minus, error)
         if (allocated(error)) return
         qp(j) = q(j)
         K_c(:, j) = matmul(lambda, jac_plus - jac_minus) / (2.0_dp * delta)
      end do
   end subroutine dae_constraint_stiffness_fd

   !> d(M(q) a)/dq for fixed a by central differences of `mass`.
   subroutine dae_mass_stiffness_fd(self, q, a, K_m, error)
      !> The system
      class(dae_system_t), intent(inout) :: self
      !> Generalized coordinates, n
      real(dp), intent(in) :: q(:)
      !> Acceleration held fixed, n
      real(dp), intent(in) :: a(:)
      !> d(M a)/dq, n x n
      real(dp), intent(out) :: K_m(:, :)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: qp(size(q)), m_plus(size(q), size(q)), m_minus(size(q), size(q)), delta
      integer :: j
      qp = q
      do j = 1, size(q)
         delta = fd_step(q(j))
         qp(j) = q(j) + delta
         call self%mass(qp, m_plus, error)
         if (allocated(error)) return
         qp(j) = q(j) - delta
         call self%mass(qp, m_minus, error)
         if (allocated(error)) return
         qp(j) = q(j)
         K_m(:, j) = matmul(m_plus - m_minus, a) / (2.0_dp * delta)
      end do
   end subroutine dae_mass_stiffness_fd

   !> Phi_t by a central difference in t (exactly zero for a scleronomic Phi).
   subroutine dae_constraint_rate_fd(self, q, t, phi_t, error)
      !> The system
      class(dae_system_t), intent(inout) :: self
      !> Generalized coordinates, n
      real(dp), intent(in) :: q(:)
      !> Time (s)
      real(dp), intent(in) :: t
      !> dPhi/dt, nc
      real(dp), intent(out) :: phi_t(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: phi_plus(size(phi_t)), phi_minus(size(phi_t)), delta
      delta = fd_step(t)
      call self%constraints(q, t + delta, phi_plus, error)
      if (allocated(error)) return
      call self%constraints(q, t - delta, phi_minus, error)
      if (allocated(error)) return
      phi_t = (phi_plus - phi_minus) / (2.0_dp * delta)
   end subroutine dae_constraint_rate_fd

   !> g = -d/ds [Phi_q(q + s q', t + s) q' + Phi_t(q + s q', t + s)] at s = 0
   !>   = -(Phi_q q')_q q' - 2 Phi_qt q' - Phi_tt   (theory.md 4.3), by a central difference in s.
   subroutine dae_acceleration_rhs_fd(self, q, v, t, g, error)
      !> The system
      class(dae_system_t), intent(inout) :: self
      !> Generalized coordinates, n
      real(dp), intent(in) :: q(:)
      !> Generalized velocities, n
      real(dp), intent(in) :: v(:)
      !> Time (s)
      real(dp), intent(in) :: t
      !> Right-hand side of Phi_q q'' = g, nc
      real(dp), intent(out) :: g(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: jac(size(g), size(q)), rate(size(g)), w_plus(size(g)), w_minus(size(g))
      real(dp) :: s, vmax, qscale, root3
      if (size(g) == 0) return
      ! Step s along the path (q + s q', t + s): eps**(1/3) relative in t, reduced so that it
      ! moves q by at most eps**(1/3) of its scale. With the default Phi_t (itself a difference
      ! in t) a rheonomic system gets g to ~eps**(1/3) relative: override Phi_t for better.
      root3 = epsilon(1.0_dp)**(1.0_dp / 3.0_dp)
      vmax = 0.0_dp
      qscale = 1.0_dp
      if (size(q) > 0) then
         vmax = maxval(abs(v))
         qscale = max(maxval(abs(q)), 1.0_dp)
      end if
      s = root3 * max(abs(t), 1.0_dp)
      if (vmax * s > root3 * qscale) s = root3 * qscale / vmax
      call self%constraint_jacobian(q + s * v, t + s, jac, error)
      if (allocated(error)) return
      call self%constraint_rate(q + s * v, t + s, rate, error)
      if (allocated(error)) return
      w_plus = matmul(jac, v) + rate
      call self%constraint_jacobian(q - s * v, t - s, jac, error)
      if (allocated(error)) return
      call self%constraint_rate(q - s * v, t - s, rate, error)
      if (allocated(error)) return
      w_minus = matmul(jac, v) + rate
      g = -(w_plus - w_minus) / (2.0_dp * s)
   end subroutine dae_acceleration_rhs_fd

   !> A dense matrix as one block of S (S set up with one row and one column group if its
   !> groups differ).
   subroutine dense_to_blocks(A, S)
      real(dp), intent(in) :: A(:, :)
      type(block_sparse_t), intent(inout) :: S
      if (.not. S%same_groups([1, size(A, 1) + 1], [1, size(A, 2) + 1])) &
         call S%init([1, size(A, 1) + 1], [1, size(A, 2) + 1])
      call S%zero()
      call S%add_block(0, 0, A)
   end subroutine dense_to_blocks

   !> M(q) from `mass`, as one block.
   subroutine dae_mass_sparse(self, q, M, error)
      class(dae_system_t), intent(inout) :: self
      real(dp), intent(in) :: q(:)                 !< coordinates, n
      type(block_sparse_t), intent(inout) :: M     !< n x n
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: dense(:, :)
      allocate (dense(size(q), size(q)))
      call self%mass(q, dense, error)
      if (.not. allocated(error)) call dense_to_blocks(dense, M)
   end subroutine dae_mass_sparse

   !> Phi and Phi_q from `constraints_and_jacobian`, Phi_q as one block.
   subroutine dae_constraints_and_jacobian_sparse(self, q, t, phi, Phi_q, error)
      class(dae_system_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), t              !< coordinates (n), time (s)
      real(dp), intent(out) :: phi(:)              !< Phi, nc
      type(block_sparse_t), intent(inout) :: Phi_q !< nc x n
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: dense(:, :)
      allocate (dense(size(phi), size(q)))
      call self%constraints_and_jacobian(q, t, phi, dense, error)
      if (.not. allocated(error)) call dense_to_blocks(dense, Phi_q)
   end subroutine dae_constraints_and_jacobian_sparse

   !> K = stiffness + mass_stiffness(a) + constraint_stiffness(lambda) and C = damping, dense,
   !> as one block each.
   subroutine dae_tangents_sparse(self, q, v, a, t, lambda, K, C, error)
      class(dae_system_t), intent(inout) :: self
      !> Coordinates, velocities, accelerations q'' (n), time (s), multipliers (nc)
      real(dp), intent(in) :: q(:), v(:), a(:), t, lambda(:)
      !> d(M a + Phi_q^T lambda - f)/dq and -df/dq', n x n
      type(block_sparse_t), intent(inout) :: K, C
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: total(:, :), work(:, :)
      allocate (total(size(q), size(q)), work(size(q), size(q)))
      call self%stiffness(q, v, t, total, error)
      if (allocated(error)) return
      call self%mass_stiffness(q, a, work, error)
      if (allocated(error)) return
      total = total + work
      if (size(lambda) > 0) then
         call self%constraint_stiffness(q, t, lambda, work, error)
         if (allocated(error)) return
         total = total + work
      end if
      call dense_to_blocks(total, K)
      call self%damping(q, v, t, work, error)
      if (.not. allocated(error)) call dense_to_blocks(work, C)
   end subroutine dae_tangents_sparse

   !> Default hook after an accepted step: no output, only a guard that the state handed to output
   !> is finite (the integrator already checks it; a system that writes output overrides this).
   subroutine dae_accepted_step_none(self, t, q, v, qdd, lambda, error)
      !> The system
      class(dae_system_t), intent(inout) :: self
      !> Time reached (s)
      real(dp), intent(in) :: t
      !> Generalized coordinates, n
      real(dp), intent(in) :: q(:)
      !> Generalized velocities, n
      real(dp), intent(in) :: v(:)
      !> Generalized accelerations q'', n
      real(dp), intent(in) :: qdd(:)
      !> Lagrange multipliers, nc (zero on dropped redundant rows)
      real(dp), intent(in) :: lambda(:)
      type(error_t), allocatable, intent(out) :: error
      if (all(ieee_is_finite(q)) .and. all(ieee_is_finite(v)) .and. all(ieee_is_finite(qdd)) &
         .and. all(ieee_is_finite(lambda)) .and. same_type_as(self, self)) return
      call fatal_error(error, FFRF_NUMERIC_ERROR, 'accepted step at t = ' // to_str(t) // &
         ' s: the state (q, q'', q'''', lambda) is not finite; reduce the time step')
   end subroutine dae_accepted_step_none

   !> No protected constraint rows: the redundant-row search may drop any.
   subroutine dae_protected_rows_none(self, protect)
      !> The system
      class(dae_system_t), intent(in) :: self
      !> .true. for a row that must not be dropped, nc
      logical, intent(out) :: protect(:)
      protect = same_type_as(self, self) .and. .false.
   end subroutine dae_protected_rows_none

end module ffrf_mbs_dae_system
