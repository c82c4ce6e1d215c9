!> The steps of a generalized-alpha run (ffrf_mbs_generalized_alpha, header "Step" to "Step
!> control"): Newton on the scaled iteration matrix, its factors kept or renewed, the
!> round-off floors of the convergence tests, step cuts, the multiplier alternation check.
submodule (ffrf_mbs_generalized_alpha) ffrf_mbs_generalized_alpha_step
   implicit none

contains

   !> Advance to settings%t_end.
   module procedure galpha_run
      do while (self%t < self%settings%t_end)
         call self%step(system, error)
         if (allocated(error)) return
      end do
   end procedure galpha_run

   module procedure galpha_step
      integer :: before
      before = begin_single_blas()
      call step_once(self, system, error)
      call end_single_blas(before)
   end procedure galpha_step

   !> One accepted step from the last converged state: the step is min(h, t_end - t); on failure
   !> it is cut by step_cut and retried (after one retry with a fresh iteration matrix if the
   !> failed attempt used an old one), down to min_step; the system hook is called at the end.
   subroutine step_once(self, system, error)
      !> The integrator (after init)
      class(galpha_integrator_t), intent(inout) :: self
      !> The mechanical system
      class(dae_system_t), intent(inout) :: system
      type(error_t), allocatable, intent(out) :: error
      type(trial_t) :: trial
      character(len=:), allocatable :: reason
      real(dp) :: start, h_try, remaining
      logical :: converged, used_old, retried, last
      start = wall_time()
      retried = .false.
      do
         remaining = self%settings%t_end - self%t
         ! t accumulates h with round-off (~1e-12 s over 2e4 steps of 1e-4 s): a remainder up
         ! to 1e-6 h more than h is absorbed in the last step rather than left as a sliver
         last = remaining <= self%h * (1.0_dp + 1.0e-6_dp)
         h_try = self%h
         if (last) h_try = remaining
         call attempt(self, system, h_try, retried, trial, converged, used_old, reason, error)
         if (allocated(error)) then
            call add_context(error, 'generalized-alpha step from t = ' // to_str(self%t, 12) &
               // ' s, h = ' // to_str(h_try) // ' s')
            return
         end if
         if (converged) exit
         self%stats%rejected_steps = self%stats%rejected_steps + 1
         self%h_factored = -1.0_dp
         ! Nor keep tangents that may come from a diverging iterate of the failed attempt
         self%tangent_uses = huge(1)
         if (used_old .and. .not. retried) then
            retried = .true.
            cycle
         end if
         retried = .false.
         self%successes = 0
         if (h_try * self%settings%step_cut < self%settings%min_step) then
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'generalized-alpha: no convergence ' // &
               'at t = ' // to_str(self%t, 12) // ' s with step h = ' // to_str(h_try) // &
               ' s, the next cut would go below min_step = ' // to_str(self%settings%min_step) &
               // ' s: ' // reason // '. The state at t = ' // to_str(self%t, 12) // &
               ' s is kept; reduce h, raise max_iterations or check the model near this time')
            self%stats%wall_seconds = self%stats%wall_seconds + wall_time() - start
            return
         end if
         self%h = h_try * self%settings%step_cut
      end do
      call commit(self, trial, h_try, last)
      call check_alternation(self, h_try, last, error)
      if (allocated(error)) then
         self%stats%wall_seconds = self%stats%wall_seconds + wall_time() - start
         return
      end if
      if (self%settings%rank_check_interval > 0) then
         if (mod(self%stats%steps, int(self%settings%rank_check_interval, i8)) == 0) then
            call detect_redundant(self, system, error)
            if (allocated(error)) return
         end if
      end if
      call system%accepted_step(self%t, self%q, self%v, self%qdd, self%lambda, error)
      if (allocated(error)) then
         call add_context(error, 'output hook at t = ' // to_str(self%t, 12) // ' s')
         return
      end if
      self%stats%wall_seconds = self%stats%wall_seconds + wall_time() - start
   end subroutine step_once

   !> Take the converged trial as the new state (theory.md 4.1, step 3 for a_{n+1}).
   subroutine commit(self, trial, h, last)
      type(galpha_integrator_t), intent(inout) :: self
      type(trial_t), intent(in) :: trial
      real(dp), intent(in) :: h
      logical, intent(in) :: last
      real(dp) :: c_af
      c_af = (1.0_dp - self%alpha_f) / (1.0_dp - self%alpha_m)
      if (last) then
         self%t = self%settings%t_end
      else
         self%t = self%t + h
      end if
      self%q = trial%q
      self%v = trial%v
      self%qdd = trial%qdd
      self%a = trial%a_base + c_af * trial%qdd
      self%lambda = trial%lambda
      self%stats%steps = self%stats%steps + 1
      self%stats%h_min = min(self%stats%h_min, h)
      self%stats%max_constraint_violation = max(self%stats%max_constraint_violation, &
         max_abs(trial%phi))
      self%successes = self%successes + 1
      if (self%h < self%settings%h .and. self%successes >= self%settings%grow_after) then
         self%h = min(self%h / self%settings%step_cut, self%settings%h)
         self%successes = 0
      end if
   end subroutine commit

   !> One Newton solve of the step t -> t + h (theory.md 4.1). converged = .false. with a reason
   !> for a numerical failure (the caller cuts the step); error only for a failure of the system.
   subroutine attempt(self, system, h, fresh_start, trial, converged, used_old, reason, error)
      type(galpha_integrator_t), intent(inout) :: self
      class(dae_system_t), intent(inout) :: system
      !> Step (s)
      real(dp), intent(in) :: h
      !> Compute a new iteration matrix at the predictor whatever the policy
      logical, intent(in) :: fresh_start
      !> Trial state; converged values on success
      type(trial_t), intent(inout) :: trial
      !> Whether Newton converged
      logical, intent(out) :: converged
      !> Whether any iteration used factors from an earlier attempt or step
      logical, intent(out) :: used_old
      !> Why it failed
      character(len=:), allocatable, intent(out) :: reason
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: dx(:)
      real(dp) :: c_af, beta_p, gamma_p, bh2, t_new, increment, previous, rate, estimate, clock
      real(dp) :: remaining, previous_residual
      integer :: n, nr, iteration, age
      logical :: need_factor, ok, index2
      n = self%n
      nr = size(self%active)
      index2 = self%settings%constraints == GALPHA_INDEX2 .and. nr > 0
      converged = .false.
      used_old = .false.
      reason = ''
      self%last_increment = huge(1.0_dp)
      self%last_residual = huge(1.0_dp)
      t_new = self%t + h
      c_af = (1.0_dp - self%alpha_f) / (1.0_dp - self%alpha_m)
      bh2 = self%beta * h**2
      beta_p = 1.0_dp / (bh2 * c_af)
      gamma_p = self%gamma / (self%beta * h)
      ! Predictor: q'' = q''_n, lambda = lambda_n; q, v from the Newmark formulas (theory.md 4.1).
      trial%a_base = (self%alpha_f * self%qdd - self%alpha_m * self%a) / (1.0_dp - self%alpha_m)
      trial%qdd = self%qdd
      trial%lambda = self%lambda
      associate (a_new => trial%a_base + c_af * trial%qdd)
         trial%q = self%q + h * self%v + h**2 * ((0.5_dp - self%beta) * self%a + self%beta * a_new)
         trial%v = self%v + h * ((1.0_dp - self%gamma) * self%a + self%gamma * a_new)
      end associate
      ! Index 2: the velocity rows and nu's columns make the order n + 2 nr (theory.md 4.6)
      trial%sparse = merge(n + 2 * nr, n + nr, index2) >= self%settings%sparse_threshold
      if (.not. allocated(trial%r_q)) allocate (trial%r_q(n), trial%phi(self%nc))
      if (.not. trial%sparse .and. .not. allocated(trial%M)) allocate (trial%M(n, n), &
         trial%Phi_q(self%nc, n))
      if (index2 .and. .not. allocated(trial%g)) allocate (trial%g(self%nc))
      if (index2 .and. .not. trial%sparse .and. .not. allocated(trial%B)) &
         allocate (trial%B(n, nr))
      call evaluate(self, system, t_new, trial, 'at the predictor', reason, error)
      if (allocated(error) .or. len(reason) > 0) return
      ! Index 2: the correction direction B = Phi_q^T at the predictor (theory.md 4.6)
      if (index2) call index2_direction(self, h, trial)
      need_factor = fresh_start .or. self%h_factored < 0.0_dp .or. &
         abs(h - self%h_factored) > 1.0e-10_dp * h .or. &
         self%settings%jacobian /= GALPHA_NEWTON_ADAPTIVE .or. .not. self%reuse_factors
      used_old = .not. need_factor
      age = 0
      previous = huge(1.0_dp)
      previous_residual = huge(1.0_dp)
      allocate (dx(merge(n + 2 * nr, n + nr, index2)))
      do iteration = 1, self%settings%max_iterations
         if (need_factor) then
            ! A fresh tangent except at the predictor of a normal step (settings%tangent_reuse)
            call factor(self, system, h, t_new, trial, fresh_start .or. iteration > 1, ok, &
               error)
            if (allocated(error)) return
            if (.not. ok) then
               reason = 'singular iteration matrix (dependent constraints not detected, or a ' &
                  // 'mass matrix singular on the free motions)'
               return
            end if
            age = 0
            need_factor = .false.
         end if
         age = age + 1
         ! Scaled Newton system (theory.md 4.2): [dq; y] with dlambda = S y / (beta h^2).
         dx(:n) = -bh2 * trial%r_q
         dx(n + 1:n + nr) = -self%row_scale * trial%phi(self%active)
         ! Index 2: the velocity rows, g beta h / gamma, scaled as Phi's (theory.md 4.6)
         if (index2) dx(n + nr + 1:) = -self%row_scale * trial%velocity_scale * &
            trial%g(self%active)
         clock = wall_time()
         call solve_iteration(self, dx, error)
         self%stats%solve_seconds = self%stats%solve_seconds + wall_time() - clock
         if (allocated(error)) return
         self%stats%newton_iterations = self%stats%newton_iterations + 1
         if (.not. all_finite(dx)) then
            reason = 'NaN or Inf in the Newton increment'
            return
         end if
         trial%v = trial%v + gamma_p * dx(:n)
         trial%qdd = trial%qdd + beta_p * dx(:n)
         trial%lambda(self%active) = trial%lambda(self%active) + self%row_scale * &
            dx(n + 1:n + nr) / bh2
         ! Index 2: q moves by the Newmark part x and the correction B z (theory.md 4.6), and
         ! the increment test sees that move
         if (index2) dx(:n) = index2_increment(self, trial, dx)
         trial%q = trial%q + dx(:n)
         increment = increment_norm(self, trial, dx(:n + nr), bh2)
         ! Error of the iterate: the increment, or from the contraction rate theta the
         ! estimate theta/(1 - theta) ||dx|| of the remaining ones (Hairer & Wanner, IV.8).
         estimate = increment
         rate = huge(1.0_dp)
         if (iteration >= 2) then
            rate = increment / max(previous, tiny(1.0_dp))
            if (rate < 1.0_dp) estimate = min(increment, rate / (1.0_dp - rate) * increment)
         end if
         ! (not with index 2: the velocity constraints need Phi_q at the new iterate)
         if (rate <= skip_rate .and. .not. index2) then
            ! Converged without evaluating the residual at the new iterate when the increment
            ! passes and so does the residual predicted there, the one at the iterate this
            ! increment started from times theta (Newton contracts the residual as it contracts
            ! the increments), the iteration contracting clearly. Phi alone is evaluated there
            ! (cheap: no mass, force or Jacobian), for the statistics and as a check.
            if (estimate <= 1.0_dp .and. rate * self%last_residual <= 1.0_dp) then
               call system%constraints(trial%q, t_new, trial%phi, error)
               if (allocated(error)) return
               if (all_finite(trial%phi)) then
                  if (constraint_norm(self, trial) <= 1.0_dp) then
                     self%last_increment = increment
                     self%last_residual = rate * self%last_residual
                     converged = .true.
                     self%reuse_factors = age <= self%settings%refactor_iterations
                     return
                  end if
               end if
            end if
         end if
         call evaluate(self, system, t_new, trial, '(force, mass or constraints)', reason, error)
         if (allocated(error) .or. len(reason) > 0) return
         self%last_increment = increment
         self%last_residual = residual_norm(self, trial)
         if (estimate <= 1.0_dp .and. self%last_residual <= 1.0_dp) then
            converged = .true.
            ! Keep the factors for the next step only if they converged here within
            ! refactor_iterations iterations (a stale matrix at the next predictor, where the
            ! multipliers jump, otherwise costs more iterations than a factorisation)
            self%reuse_factors = age <= self%settings%refactor_iterations
            return
         end if
         if (self%settings%jacobian == GALPHA_NEWTON_FULL) then
            need_factor = .true.
         else if (age >= 2 .and. rate > self%settings%refactor_rate) then
            need_factor = .true.
         else if (age >= 2 .and. self%last_residual > 1.0_dp .and. self%last_residual > &
            self%settings%refactor_rate * previous_residual) then
            ! The increments look converged (or sit at their round-off floor, noise_floor)
            ! but the residual test fails and the residual contracts slowly: refactor
            need_factor = .true.
         else if (age >= 2) then
            ! Linear convergence at the rate theta of these factors needs about
            ! log(estimate)/log(1/theta) more iterations; a fresh matrix converges
            ! quadratically. Refactor when that is more than refactor_iterations or more than
            ! the attempt has left (else it fails and the step is retried).
            remaining = log(estimate) / log(1.0_dp / max(rate, tiny(1.0_dp)))
            if (remaining > real(self%settings%refactor_iterations, dp) .or. &
               remaining > real(self%settings%max_iterations - iteration, dp)) &
               need_factor = .true.
         end if
         previous = increment
         previous_residual = self%last_residual
      end do
      reason = 'Newton did not converge in ' // to_str(self%settings%max_iterations) // &
         ' iterations (last weighted residual ' // to_str(self%last_residual) // &
         ', increment ' // to_str(self%last_increment) // '; both must reach 1)'
   end subroutine attempt

   !> Residual of the step at the trial state: r_q = M q'' + Phi_q^T lambda - f, Phi (all rows).
   subroutine evaluate(self, system, t, trial, where, reason, error)
      type(galpha_integrator_t), intent(inout) :: self
      class(dae_system_t), intent(inout) :: system
      real(dp), intent(in) :: t
      type(trial_t), intent(inout) :: trial
      !> Where in the step, for the reason
      character(len=*), intent(in) :: where
      !> Set to 'NaN or Inf in the residual ' // where if the residual is not finite
      character(len=:), allocatable, intent(inout) :: reason
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: f(self%n), inertia(self%n), reaction(self%n), clock, rate(self%nc)
      clock = wall_time()
      if (trial%sparse) then
         call system%mass_sparse(trial%q, trial%M_sparse, error)
      else
         call system%mass(trial%q, trial%M, error)
      end if
      if (allocated(error)) return
      call system%force(trial%q, trial%v, t, f, error)
      if (allocated(error)) return
      if (trial%sparse) then
         call system%constraints_and_jacobian_sparse(trial%q, t, trial%phi, trial%Phi_sparse, &
            error)
      else
         call system%constraints_and_jacobian(trial%q, t, trial%phi, trial%Phi_q, error)
      end if
      if (allocated(error)) return
      call trial_products(trial, .false., inertia, reaction)
      trial%r_q = inertia + reaction - f
      trial%force_scale = max(max_abs(inertia), max_abs(reaction), max_abs(f))
      ! Index 2: the velocity constraints g = Phi_q q' + Phi_t (theory.md 4.6)
      if (allocated(trial%g)) then
         call system%constraint_rate(trial%q, t, rate, error)
         if (allocated(error)) return
         if (trial%sparse) then
            call trial%Phi_sparse%matvec(trial%v, trial%g)
            trial%g = trial%g + rate
         else
            trial%g = matmul(trial%Phi_q, trial%v) + rate
         end if
      end if
      self%stats%residual_evaluations = self%stats%residual_evaluations + 1
      self%stats%residual_seconds = self%stats%residual_seconds + wall_time() - clock
      if (.not. finite_trial(trial)) reason = 'NaN or Inf in the residual ' // where
   end subroutine evaluate

   !> Tangent at the trial state and LU factors of the scaled iteration matrix (theory.md 4.1,
   !> 4.2): D_L S_t D_R = [[M/c + gamma h C_t + beta h^2 K_t, Phi_q^T], [Phi_q, 0]] with
   !> c = (1 - alpha_f)/(1 - alpha_m), K_t = d(M q'')/dq + d(Phi_q^T lambda)/dq - df/dq,
   !> C_t = -df/dq' (kept ones up to settings%tangent_reuse, module header), then the constraint
   !> rows equilibrated (kkt_complete). From order settings%sparse_threshold on the same matrix
   !> is assembled block-sparse (sparse_assemble) and factorised by MUMPS.
   subroutine factor(self, system, h, t, trial, fresh_tangent, ok, error)
      type(galpha_integrator_t), intent(inout) :: self
      class(dae_system_t), intent(inout) :: system
      real(dp), intent(in) :: h, t
      type(trial_t), intent(in) :: trial
      !> Compute K_t and C_t at the trial state even if settings%tangent_reuse allows old ones
      logical, intent(in) :: fresh_tangent
      logical, intent(out) :: ok
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: work(:, :)
      real(dp) :: c_af, clock
      integer(ip) :: info
      integer :: n, nr, order
      logical :: new_tangent, singular
      n = self%n
      nr = size(self%active)
      ! Index 2: the velocity rows and nu's columns (theory.md 4.6)
      order = n + nr
      if (allocated(trial%g)) order = n + 2 * nr
      ok = .false.
      clock = wall_time()
      c_af = (1.0_dp - self%alpha_f) / (1.0_dp - self%alpha_m)
      new_tangent = fresh_tangent .or. self%tangent_uses >= self%settings%tangent_reuse
      if (trial%sparse) then
         new_tangent = new_tangent .or. .not. self%sparse_tangent
      else
         new_tangent = new_tangent .or. .not. allocated(self%tangent_K)
      end if
      if (new_tangent .and. trial%sparse) then
         self%tangent_uses = huge(1)
         self%sparse_tangent = .false.
         call system%tangents_sparse(trial%q, trial%v, trial%qdd, t, trial%lambda, &
            self%sparse_K, self%sparse_C, error)
         if (allocated(error)) return
         self%sparse_tangent = .true.
         self%tangent_uses = 0
         self%stats%tangents = self%stats%tangents + 1
      else if (new_tangent) then
         if (.not. allocated(self%tangent_K)) allocate (self%tangent_K(n, n), &
            self%tangent_C(n, n))
         allocate (work(n, n))
         self%tangent_uses = huge(1)
         call system%stiffness(trial%q, trial%v, t, self%tangent_K, error)
         if (allocated(error)) return
         call system%mass_stiffness(trial%q, trial%qdd, work, error)
         if (allocated(error)) return
         self%tangent_K = self%tangent_K + work
         if (self%nc > 0) then
            call system%constraint_stiffness(trial%q, t, trial%lambda, work, error)
            if (allocated(error)) return
            self%tangent_K = self%tangent_K + work
         end if
         call system%damping(trial%q, trial%v, t, self%tangent_C, error)
         if (allocated(error)) return
         self%tangent_uses = 0
         self%stats%tangents = self%stats%tangents + 1
      end if
      self%tangent_uses = self%tangent_uses + 1
      self%stats%tangent_seconds = self%stats%tangent_seconds + wall_time() - clock
      clock = wall_time()
      self%stats%factorizations = self%stats%factorizations + 1
      self%h_factored = -1.0_dp
      self%stats%matrix_order = order
      if (trial%sparse) then
         ! Sparse LU (MUMPS) of the matrix assembled block-sparse (index 2: with the velocity
         ! rows and nu's columns, index2_sparse_triplets)
         if (.not. associated(self%sparse)) allocate (self%sparse)
         call sparse_assemble(self, h, c_af, trial, singular, error)
         self%stats%sparse_analyses = self%sparse%analyses
         self%stats%sparse_factorizations = self%sparse%factorizations
         if (allocated(self%sparse%irn)) self%stats%sparse_entries = size(self%sparse%irn, &
            kind=i8)
         self%stats%sparse_factor_entries = self%sparse%solver%factor_entries
         self%stats%sparse_mumps_seconds = self%sparse%mumps_seconds
         if (allocated(error)) then
            self%stats%factor_seconds = self%stats%factor_seconds + wall_time() - clock
            return
         end if
         info = merge(1_ip, 0_ip, singular)
      else
         ! The iteration matrix is assembled in the factor storage, kept between
         ! factorisations. (M is screened with the residual, the tangents when computed; a NaN
         ! that got through shows in the Newton increment.)
         if (allocated(self%lu)) then
            if (size(self%lu, 1) /= order) deallocate (self%lu, self%row_scale)
         end if
         if (.not. allocated(self%lu)) allocate (self%lu(order, order), self%row_scale(nr))
         self%lu(:n, :n) = self%beta * h**2 * self%tangent_K + trial%M / c_af + self%gamma * &
            h * self%tangent_C
         if (order == n + nr) then
            call kkt_complete(self%lu, trial%Phi_q, self%active, self%row_scale)
         else
            ! Index 2: nu's blocks around the index-3 matrix (theory.md 4.6)
            call kkt_complete(self%lu(:n + nr, :n + nr), trial%Phi_q, self%active, &
               self%row_scale)
            call index2_blocks(self, h, trial)
         end if
         call kkt_factor(self%lu, self%pivots, info)
      end if
      if (info /= 0) then
         self%stats%factor_seconds = self%stats%factor_seconds + wall_time() - clock
         return
      end if
      ! The floors are magnitudes: they are kept with the tangent they were computed from
      if (new_tangent .or. self%h_floor /= h) call noise_floor(self, h, trial, error)
      if (allocated(error)) return
      self%stats%factor_seconds = self%stats%factor_seconds + wall_time() - clock
      self%h_factored = h
      ok = .true.
   end subroutine factor

   !> Weighted RMS of the increment (Arnold & Hante 2017): dq_i/(atol + rtol |q_i| + 10 e_i) and
   !> dlambda_j/(lambda_atol + rtol |lambda_j| + 10 e_j) over the kept rows, e the round-off
   !> floor of the increment (noise_floor; far below the tolerances unless the system is
   !> ill-conditioned).
   function increment_norm(self, trial, dx, bh2) result(norm)
      type(galpha_integrator_t), intent(in) :: self
      type(trial_t), intent(in) :: trial
      real(dp), intent(in) :: dx(:), bh2
      real(dp) :: norm
      real(dp) :: total
      integer :: n, j
      n = self%n
      associate (s => self%settings, noise => self%increment_floor)
         total = sum((dx(:n) / (s%newton_atol + s%newton_rtol * abs(trial%q) + &
            floor_factor * noise(:n)))**2)
         do j = 1, size(self%active)
            total = total + (self%row_scale(j) * dx(n + j) / bh2 / (s%lambda_atol + &
               s%newton_rtol * abs(trial%lambda(self%active(j))) + &
               floor_factor * noise(n + j)))**2
         end do
      end associate
      norm = sqrt(total / real(max(1, size(dx)), dp))
   end function increment_norm

   !> Residual test: max|r_q,i| / (rtol * force scale + force_atol + 10 e_i) and
   !> max|Phi_j| / (atol + 10 e_j) on the kept rows, e the round-off floors (noise_floor);
   !> <= 1 passes.
   function residual_norm(self, trial) result(norm)
      type(galpha_integrator_t), intent(in) :: self
      type(trial_t), intent(in) :: trial
      real(dp) :: norm
      associate (s => self%settings)
         norm = maxval(abs(trial%r_q) / (s%newton_rtol * trial%force_scale + s%force_atol + &
            floor_factor * self%residual_floor + tiny(1.0_dp)))
      end associate
      norm = max(norm, constraint_norm(self, trial))
   end function residual_norm

   !> Constraint part of the residual test: max|Phi_j| / (atol + 10 e_j) on the kept rows (0
   !> without any); <= 1 passes.
   function constraint_norm(self, trial) result(norm)
      type(galpha_integrator_t), intent(in) :: self
      type(trial_t), intent(in) :: trial
      real(dp) :: norm
      integer :: nr
      nr = size(self%active)
      norm = 0.0_dp
      if (nr > 0) norm = maxval(abs(trial%phi(self%active)) / &
         (self%settings%newton_atol + floor_factor * self%constraint_floor(:nr)))
      ! Index 2: the velocity constraints as position-sized residuals (theory.md 4.6)
      if (nr > 0 .and. allocated(trial%g)) norm = max(norm, maxval(trial%velocity_scale * &
         abs(trial%g(self%active)) / (self%settings%newton_atol + floor_factor * &
         self%constraint_floor(nr + 1:))))
   end function constraint_norm

   !> Whether the residual of a trial is finite.
   logical function finite_trial(trial)
      type(trial_t), intent(in) :: trial
      ! A NaN or Inf in M, f, Phi_q or lambda reaches r_q (NaN * 0 is NaN), and one in Phi reaches
      ! phi: two reductions screen the whole evaluation
      finite_trial = all_finite(trial%r_q) .and. all_finite(trial%phi)
   end function finite_trial

end submodule ffrf_mbs_generalized_alpha_step
