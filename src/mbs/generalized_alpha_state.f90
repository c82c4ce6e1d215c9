!> The integrator's state as flat arrays for checkpoints (export_state) and its restore on
!> restart (import_state): a restored run continues bit for bit; the check of the multipliers'
!> history (check_alternation).
submodule (ffrf_mbs_generalized_alpha) ffrf_mbs_generalized_alpha_state
   implicit none

contains

   !> The whole state of the integrator after a step, everything that influences later steps
   !> (the last converged state, the current step, the kept factors, tangents and round-off
   !> floors, the multiplier history, the counters), as a real and an integer array for a
   !> checkpoint file: import_state on an integrator initialised for the same system continues
   module procedure galpha_export_state
      allocate (reals(0))
      ints = [STATE_LAYOUT, int(self%n, i8), int(self%nc, i8), int(self%tangent_uses, i8), &
         int(self%history_count, i8), int(self%alternation_steps, i8), &
         int(self%successes, i8), merge(1_i8, 0_i8, self%reuse_factors), self%stats%steps, &
         self%stats%rejected_steps, self%stats%newton_iterations, self%stats%factorizations, &
         self%stats%tangents, self%stats%residual_evaluations]
      reals = [self%t, self%h, self%last_increment, self%last_residual, self%h_floor, &
         self%lambda_peak, self%h_factored, self%stats%wall_seconds, &
         self%stats%residual_seconds, self%stats%tangent_seconds, self%stats%factor_seconds, &
         self%stats%solve_seconds, self%stats%h_min, self%stats%max_constraint_violation]
      call put_1d(self%q)
      call put_1d(self%v)
      call put_1d(self%qdd)
      call put_1d(self%a)
      call put_1d(self%lambda)
      call put_1d(self%row_scale)
      call put_1d(self%increment_floor)
      call put_1d(self%residual_floor)
      call put_1d(self%constraint_floor)
      call put_2d(self%lu)
      call put_2d(self%tangent_K)
      call put_2d(self%tangent_C)
      call put_2d(self%lambda_history)
      call put_int(self%active)
      call put_int(self%dropped)
      if (allocated(self%pivots)) then
         ints = [ints, int(size(self%pivots), i8), int(self%pivots, i8)]
      else
         ints = [ints, -1_i8]
      end if

   contains

      subroutine put_1d(x)
         real(dp), allocatable, intent(in) :: x(:)
         if (.not. allocated(x)) then
            ints = [ints, -1_i8]
            return
         end if
         ints = [ints, int(size(x), i8)]
         reals = [reals, x]
      end subroutine put_1d

      subroutine put_2d(x)
         real(dp), allocatable, intent(in) :: x(:, :)
         if (.not. allocated(x)) then
            ints = [ints, -1_i8, -1_i8]
            return
         end if
         ints = [ints, int(size(x, 1), i8), int(size(x, 2), i8)]
         reals = [reals, reshape(x, [size(x)])]
      end subroutine put_2d

      subroutine put_int(x)
         integer, allocatable, intent(in) :: x(:)
         if (.not. allocated(x)) then
            ints = [ints, -1_i8]
            return
         end if
         ints = [ints, int(size(x), i8), int(x, i8)]
      end subroutine put_int

   end procedure galpha_export_state

   module procedure galpha_import_state
      integer :: r, k
      logical :: ok
      ok = size(ints) >= 14 .and. size(reals) >= 14
      if (ok) ok = ints(1) == STATE_LAYOUT .and. ints(2) == self%n .and. ints(3) == self%nc
      if (.not. ok) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'generalized-alpha restart state: not a ' // &
            'state of this system (' // to_str(self%n) // ' coordinates, ' // to_str(self%nc) // &
            ' constraint equations) or of this version of ffrf')
         return
      end if
      self%tangent_uses = int(ints(4))
      self%history_count = int(ints(5))
      self%alternation_steps = int(ints(6))
      self%successes = int(ints(7))
      self%reuse_factors = ints(8) == 1
      self%stats%steps = ints(9)
      self%stats%rejected_steps = ints(10)
      self%stats%newton_iterations = ints(11)
      self%stats%factorizations = ints(12)
      self%stats%tangents = ints(13)
      self%stats%residual_evaluations = ints(14)
      self%t = reals(1)
      self%h = reals(2)
      self%last_increment = reals(3)
      self%last_residual = reals(4)
      self%h_floor = reals(5)
      self%lambda_peak = reals(6)
      self%h_factored = reals(7)
      self%stats%wall_seconds = reals(8)
      self%stats%residual_seconds = reals(9)
      self%stats%tangent_seconds = reals(10)
      self%stats%factor_seconds = reals(11)
      self%stats%solve_seconds = reals(12)
      self%stats%h_min = reals(13)
      self%stats%max_constraint_violation = reals(14)
      r = 14
      k = 14
      call get_1d(self%q)
      call get_1d(self%v)
      call get_1d(self%qdd)
      call get_1d(self%a)
      call get_1d(self%lambda)
      call get_1d(self%row_scale)
      call get_1d(self%increment_floor)
      call get_1d(self%residual_floor)
      call get_1d(self%constraint_floor)
      call get_2d(self%lu)
      ! sparse factors and tangents, if any, belong to another matrix (they are not in the
      ! state): the sparse path starts the next step with a fresh tangent and factorisation
      if (associated(self%sparse)) call self%sparse%free()
      self%sparse_tangent = .false.
      call get_2d(self%tangent_K)
      call get_2d(self%tangent_C)
      call get_2d(self%lambda_history)
      call get_int(self%active)
      call get_int(self%dropped)
      if (ok) then
         if (allocated(self%pivots)) deallocate (self%pivots)
         ok = k + 1 <= size(ints)
         if (ok) then
            k = k + 1
            if (ints(k) >= 0) then
               ok = k + ints(k) <= size(ints)
               if (ok) then
                  allocate (self%pivots(ints(k)))
                  self%pivots = int(ints(k + 1:k + ints(k)), ip)
                  k = k + int(ints(k))
               end if
            end if
         end if
      end if
      if (ok) ok = r == size(reals) .and. k == size(ints)
      ! the sparse path keeps no factors in the state: factorise at the next step
      if (ok .and. allocated(self%active)) then
         if (self%n + size(self%active) >= self%settings%sparse_threshold) &
            self%h_factored = -1.0_dp
      end if
      if (ok) ok = size(self%q) == self%n .and. size(self%v) == self%n .and. &
         size(self%lambda) == self%nc
      if (.not. ok) call fatal_error(error, FFRF_INPUT_ERROR, 'generalized-alpha restart ' // &
         'state: its arrays do not fit this system (' // to_str(self%n) // ' coordinates, ' // &
         to_str(self%nc) // ' constraint equations)')

   contains

      subroutine get_1d(x)
         real(dp), allocatable, intent(inout) :: x(:)
         integer :: m
         if (.not. ok) return
         if (allocated(x)) deallocate (x)
         ok = k + 1 <= size(ints)
         if (.not. ok) return
         k = k + 1
         if (ints(k) < 0) return
         m = int(ints(k))
         ok = r + m <= size(reals)
         if (.not. ok) return
         x = reals(r + 1:r + m)
         r = r + m
      end subroutine get_1d

      subroutine get_2d(x)
         real(dp), allocatable, intent(inout) :: x(:, :)
         integer :: m1, m2
         if (.not. ok) return
         if (allocated(x)) deallocate (x)
         ok = k + 2 <= size(ints)
         if (.not. ok) return
         k = k + 2
         if (ints(k - 1) < 0) return
         m1 = int(ints(k - 1))
         m2 = int(ints(k))
         ok = m1 >= 0 .and. m2 >= 0 .and. r + m1 * m2 <= size(reals)
         if (.not. ok) return
         x = reshape(reals(r + 1:r + m1 * m2), [m1, m2])
         r = r + m1 * m2
      end subroutine get_2d

      subroutine get_int(x)
         integer, allocatable, intent(inout) :: x(:)
         if (.not. ok) return
         if (allocated(x)) deallocate (x)
         ok = k + 1 <= size(ints)
         if (.not. ok) return
         k = k + 1
         if (ints(k) < 0) return
         ok = k + ints(k) <= size(ints)
         if (.not. ok) return
         x = int(ints(k + 1:k + ints(k)))
         k = k + int(ints(k))
      end subroutine get_int

   end procedure galpha_import_state

   !> Weak instability of index-3 generalized-alpha near rho_inf = 1 (Cardona & Geradin 1989;
   !> theory.md 4.3): the multipliers grow as an oscillation that alternates from step to step.
   !> Its amplitude is the fourth difference (lambda_n - 4 lambda_n-1 + 6 lambda_n-2 -
   !> 4 lambda_n-3 + lambda_n-4) / 16 over steps of equal size (exactly A for A (-1)^n, h^4
   !> lambda''''/16 for a smooth history). Above settings%alternation_limit times the largest
   !> |lambda| of the run (and above lambda_atol: round-off multipliers of free bodies' Euler
   !> rows alternate at 1e-18) for alternation_window consecutive steps (a start-up or impact
   !> transient decays by rho_inf per step: 0.8**20 = 1 %; on the flexible engine's first steps
   !> it reaches 0.44 of the small multipliers so far) the integration stops with
   !> FFRF_NUMERIC_ERROR naming rho_inf (the state of the step is kept). Measured
   !> (test_stability_constraints): the 1 m pendulum at h = 1e-2 s reaches 0.25 of |lambda| at
   !> 4-5 s with rho_inf = 0.99 and 0.999 (unchecked, 0.99 went on to lambda = 1400 times the
   !> closed form) while healthy runs stay below 1e-4 (rigid engine, pendulum at 0.8); the
   !> flexible reference engine (rotating link and conrod vibrating at 1.4-12 kHz, h = 1e-4 s) stays
   !> near 0.03 of its largest reaction.
   module procedure check_alternation
      real(dp) :: alternating
      if (self%nc == 0 .or. self%settings%alternation_limit <= 0.0_dp) return
      ! zeroed: the columns after history_count are not yet set, and the restart state
      ! (export_state) writes them to the results file (memcheck: uninitialised bytes written)
      if (.not. allocated(self%lambda_history)) allocate (self%lambda_history(self%nc, 4), &
         source=0.0_dp)
      self%lambda_peak = max(self%lambda_peak, max_abs(self%lambda))
      if (abs(h - self%settings%h) > 1.0e-10_dp * self%settings%h .or. last) then
         self%history_count = 0
         return
      end if
      if (self%history_count == 4) then
         alternating = max_abs(self%lambda - 4.0_dp * self%lambda_history(:, 4) + 6.0_dp * &
            self%lambda_history(:, 3) - 4.0_dp * self%lambda_history(:, 2) + &
            self%lambda_history(:, 1)) / 16.0_dp
         if (alternating > self%settings%alternation_limit * self%lambda_peak .and. &
            alternating > self%settings%lambda_atol) then
            self%alternation_steps = self%alternation_steps + 1
         else
            self%alternation_steps = 0
         end if
         if (self%alternation_steps >= alternation_window) then
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'generalized-alpha: the Lagrange ' // &
               'multipliers alternate from step to step (' // to_str(alternation_window) // &
               ' steps running) with an amplitude of ' // &
               to_str(alternating, 3) // ', ' // to_str(alternating / self%lambda_peak, 3) // &
               ' of the largest |lambda| so far, at t = ' // to_str(self%t, 12) // &
               ' s: the weak instability of index-3 generalized-alpha near rho_inf = 1 ' // &
               '(rho_inf = ' // to_str(self%settings%rho_inf) // ', h = ' // to_str(h) // &
               ' s); lower rho_inf (0.8 is typical) or the step. The state at t = ' // &
               to_str(self%t, 12) // ' s is kept')
            return
         end if
         self%lambda_history(:, 1:3) = self%lambda_history(:, 2:4)
      else
         self%history_count = self%history_count + 1
      end if
      self%lambda_history(:, self%history_count) = self%lambda
   end procedure check_alternation

end submodule ffrf_mbs_generalized_alpha_state
