!> The start of a generalized-alpha run (ffrf_mbs_generalized_alpha, header "Consistent start"):
!> settings checked, redundant rows found, (q0, v0) projected onto Phi = 0 and
!> Phi_q q' + Phi_t = 0 or refused, q''_0 and lambda_0 from the saddle-point system.
submodule (ffrf_mbs_generalized_alpha) ffrf_mbs_generalized_alpha_start
   implicit none

contains

   !> Check the settings, find redundant constraint rows, make (q0, v0) consistent (projection
   !> or refusal) and solve for q''_0 and lambda_0 (theory.md 4.3). Calls system%accepted_step
   !> once at t_start.
   module procedure galpha_init
      integer :: before
      before = begin_single_blas()
      call init_once()
      call end_single_blas(before)

   contains

      !> The work of galpha_init (the host's arguments).
      subroutine init_once()
         real(dp) :: start
         start = wall_time()
         call check_galpha_settings(settings, error)
         if (allocated(error)) return
         self%settings = settings
         call chung_hulbert(settings%rho_inf, self%alpha_m, self%alpha_f, self%gamma, self%beta)
         self%notes = ''
         self%n = system%num_coordinates()
         self%nc = system%num_constraints()
         if (settings%rho_inf >= 1.0_dp .and. self%nc > 0 .and. &
            settings%constraints == GALPHA_INDEX3) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'generalized-alpha settings: rho_inf = 1 ' &
               // '(no numerical damping) is unstable with index-3 constraints (' // &
               to_str(self%nc) // ' constraint equations here): the multipliers grow without ' // &
               'bound; use rho_inf < 1, typically 0.6 to 0.9, or constraints = ''index2''')
            return
         end if
         if (size(q0) /= self%n .or. size(v0) /= self%n) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'generalized-alpha: initial state has ' // &
               to_str(size(q0)) // ' coordinates and ' // to_str(size(v0)) // &
               ' velocities, the system ' // to_str(self%n) // '; pass vectors of its size')
            return
         end if
         self%t = settings%t_start
         self%h = settings%h
         self%q = q0
         self%v = v0
         allocate (self%qdd(self%n), self%a(self%n), self%lambda(self%nc))
         self%lambda = 0.0_dp
         call detect_redundant(self, system, error)
         if (allocated(error)) return
         call consistent_start(self, system, error)
         if (allocated(error)) then
            call add_context(error, 'generalized-alpha start at t = ' // to_str(self%t) // ' s')
            return
         end if
         call system%accepted_step(self%t, self%q, self%v, self%qdd, self%lambda, error)
         if (allocated(error)) return
         self%stats%wall_seconds = wall_time() - start
      end subroutine init_once

   end procedure galpha_init

   !> Consistent start (theory.md 4.3): check/project q and v, then solve
   !> [[M, Phi_q^T], [Phi_q, 0]] [q''_0; lambda_0] = [f; g] on the independent rows; a_0 = q''_0.
   subroutine consistent_start(self, system, error)
      type(galpha_integrator_t), intent(inout) :: self
      class(dae_system_t), intent(inout) :: system
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: phi(:), Phi_q(:, :), rate(:), M(:, :), f(:), g(:), kkt(:, :)
      real(dp), allocatable :: scale(:), rhs(:)
      integer(ip), allocatable :: pivots(:)
      integer(ip) :: info
      real(dp) :: violation, tolerance
      integer :: n, nr, iteration
      n = self%n
      nr = size(self%active)
      allocate (phi(self%nc), Phi_q(self%nc, n), rate(self%nc), M(n, n), f(n), g(self%nc))
      ! Positions: minimum-norm Gauss-Newton projection q <- q - J^T (J J^T)^-1 Phi (J: kept rows).
      tolerance = self%settings%newton_atol
      call system%constraints(self%q, self%t, phi, error)
      if (allocated(error)) return
      violation = max_abs(phi)
      if (violation > tolerance) then
         if (.not. self%settings%project_initial) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'initial positions violate the ' // &
               'constraints: max |Phi_i| = ' // to_str(violation) // ' (row ' // &
               to_str(maxloc(abs(phi), 1)) // ') > newton_atol = ' // to_str(tolerance) // &
               '; assemble consistent positions or set project_initial')
            return
         end if
         do iteration = 1, 30
            call system%constraint_jacobian(self%q, self%t, Phi_q, error)
            if (allocated(error)) return
            call min_norm_correction(Phi_q(self%active, :), phi(self%active), self%q, error)
            if (allocated(error)) return
            call system%constraints(self%q, self%t, phi, error)
            if (allocated(error)) return
            if (max_abs(phi(self%active)) <= 0.01_dp * tolerance) exit
         end do
         if (max_abs(phi) > tolerance .or. .not. all(ieee_is_finite(self%q))) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'projection of the initial positions ' // &
               'failed: max |Phi_i| = ' // to_str(violation) // ' before, ' // &
               to_str(max_abs(phi)) // ' after (redundant rows inconsistent, or a start too ' // &
               'far from the constraint manifold); assemble closer initial positions')
            return
         end if
         call add_note(self, 'initial positions projected onto the constraints: max |Phi| ' &
            // to_str(violation) // ' -> ' // to_str(max_abs(phi)))
      end if
      ! Velocities: v <- v - J^T (J J^T)^-1 (Phi_q v + Phi_t), exact in one correction.
      call system%constraint_jacobian(self%q, self%t, Phi_q, error)
      if (allocated(error)) return
      call system%constraint_rate(self%q, self%t, rate, error)
      if (allocated(error)) return
      phi = matmul(Phi_q, self%v) + rate
      violation = max_abs(phi)
      tolerance = self%settings%newton_atol / self%settings%h
      if (violation > tolerance) then
         if (.not. self%settings%project_initial) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'initial velocities violate the ' // &
               'velocity constraints: max |Phi_q v + Phi_t| = ' // to_str(violation) // &
               ' > newton_atol/h = ' // to_str(tolerance) // &
               '; assemble consistent velocities or set project_initial')
            return
         end if
         call min_norm_correction(Phi_q(self%active, :), phi(self%active), self%v, error)
         if (allocated(error)) return
         phi = matmul(Phi_q, self%v) + rate
         if (max_abs(phi) > tolerance) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'projection of the initial velocities ' &
               // 'failed: max |Phi_q v + Phi_t| = ' // to_str(max_abs(phi)) // &
               ' (redundant velocity constraints inconsistent); check the initial velocities')
            return
         end if
         call add_note(self, 'initial velocities projected onto the constraints: max ' // &
            '|Phi_q v + Phi_t| ' // to_str(violation) // ' -> ' // to_str(max_abs(phi)))
      end if
      ! Accelerations and multipliers.
      call system%mass(self%q, M, error)
      if (allocated(error)) return
      call system%force(self%q, self%v, self%t, f, error)
      if (allocated(error)) return
      call system%acceleration_rhs(self%q, self%v, self%t, g, error)
      if (allocated(error)) return
      call kkt_matrix(M, Phi_q(self%active, :), kkt, scale)
      allocate (rhs(n + nr))
      rhs(:n) = f
      rhs(n + 1:) = scale * g(self%active)
      call kkt_factor(kkt, pivots, info)
      if (info /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'the start matrix [[M, Phi_q^T], ' // &
            '[Phi_q, 0]] is singular (pivot ' // to_str(info) // '): the mass matrix is ' // &
            'singular on the free motions; check masses and inertias')
         return
      end if
      call kkt_solve(kkt, pivots, rhs)
      self%qdd = rhs(:n)
      self%lambda = 0.0_dp
      self%lambda(self%active) = scale * rhs(n + 1:)
      self%a = self%qdd
      if (.not. (all(ieee_is_finite(self%qdd)) .and. all(ieee_is_finite(self%lambda)))) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'initial accelerations or multipliers ' // &
            'are not finite (NaN force or mass?)')
      end if
   end subroutine consistent_start

   !> x <- x - J^T (J J^T)^-1 w (minimum-norm correction; J has independent rows).
   subroutine min_norm_correction(J, w, x, error)
      real(dp), intent(in) :: J(:, :)
      real(dp), intent(in) :: w(:)
      real(dp), intent(inout) :: x(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: gram(size(J, 1), size(J, 1)), y(size(J, 1), 1)
      integer(ip) :: nr, info
      nr = int(size(J, 1), ip)
      if (nr == 0) return
      gram = matmul(J, transpose(J))
      y(:, 1) = w
      call dposv('U', nr, 1_ip, gram, nr, y, nr, info)
      if (info /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'projection onto the constraints: ' // &
            'Phi_q Phi_q^T is singular (dposv info = ' // to_str(info) // '); raise rank_rtol')
         return
      end if
      x = x - matmul(y(:, 1), J)
   end subroutine min_norm_correction

   !> Append one line to the notes.
   subroutine add_note(self, text)
      type(galpha_integrator_t), intent(inout) :: self
      character(len=*), intent(in) :: text
      if (len(self%notes) > 0) then
         self%notes = self%notes // new_line('a') // text
      else
         self%notes = text
      end if
   end subroutine add_note

   !> Find the redundant rows of Phi_q at the current q (find_redundant_rows); when the set
   !> changes, the multipliers of newly dropped rows are zeroed and the factors invalidated.
   module procedure detect_redundant
      real(dp), allocatable :: Phi_q(:, :)
      integer, allocatable :: active(:), dropped(:)
      logical, allocatable :: protect(:)
      character(len=:), allocatable :: list
      integer :: i
      allocate (Phi_q(self%nc, self%n), protect(self%nc))
      call system%protected_rows(protect)
      call system%constraint_jacobian(self%q, self%t, Phi_q, error)
      if (allocated(error)) return
      if (.not. all(ieee_is_finite(Phi_q))) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'generalized-alpha: constraint Jacobian ' &
            // 'not finite at t = ' // to_str(self%t) // ' s')
         return
      end if
      call find_redundant_rows(Phi_q, self%settings%rank_rtol, active, dropped, error, protect)
      if (allocated(error)) return
      if (allocated(self%active)) then
         if (size(active) == size(self%active)) then
            if (all(active == self%active)) return
         end if
      end if
      call move_alloc(active, self%active)
      call move_alloc(dropped, self%dropped)
      self%lambda(self%dropped) = 0.0_dp
      self%history_count = 0
      self%h_factored = -1.0_dp
      self%h_floor = -1.0_dp
      if (size(self%dropped) > 0) then
         list = ''
         do i = 1, size(self%dropped)
            list = list // ' ' // to_str(self%dropped(i))
         end do
         call add_note(self, 'redundant constraints at t = ' // to_str(self%t) // ' s: ' // &
            to_str(size(self%dropped)) // ' of ' // to_str(self%nc) // ' rows dropped (rows' // &
            list // '); their reactions are reported as zero')
      end if
   end procedure detect_redundant

   module procedure max_abs
      largest = 0.0_dp
      if (size(x) > 0) largest = maxval(abs(x))
   end procedure max_abs

end submodule ffrf_mbs_generalized_alpha_start
