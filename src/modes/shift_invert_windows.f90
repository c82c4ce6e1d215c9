!> ffrf_modes_shift_invert: solve_shift_invert, the windows one after the other (the method in
!> shift_invert_spectrum.f90, its parent, which holds the helpers).
submodule (ffrf_modes_shift_invert:ffrf_modes_shift_invert_spectrum) ffrf_modes_shift_invert_windows
   implicit none

contains

   !> Eigenpairs of K x = lambda M x, C x = 0 (module header of ffrf_modes_shift_invert).
   module procedure solve_shift_invert
      type(kkt_t) :: kkt
      type(mumps_solver_t) :: solver
      type(interrupt_t) :: interrupt
      type(deflation_t) :: null_vectors
      type(known_t) :: known
      real(dp) :: t_start, t0, sturm_before, sigma, s, lambda_max
      real(dp), allocatable :: z(:, :)
      character(len=:), allocatable :: method, eigensolver
      integer(ip) :: n, nc, j, num_rigid, target, count_max, num_below_max
      integer(ip), allocatable :: kept(:)
      logical :: slicing
      !> The shift the solver holds the factors of
      real(dp) :: factored_at

      t_start = wall_time()
      num_rigid = 0
      if (present(rigid)) num_rigid = int(size(rigid, 2), ip)
      call check_input(K, M, C, options, num_rigid, n, nc, error)
      if (allocated(error)) return
      if (present(rigid)) then
         if (size(rigid, 1) /= n) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'shift-invert: the rigid modes have ' // &
               to_str(size(rigid, 1)) // ' rows for n = ' // to_str(n))
            return
         end if
      end if
      if (present(constraint_targets)) then
         if (options%sigma /= 0.0_dp .or. size(constraint_targets, 1) /= nc .or. &
            .not. present(constraint_solutions)) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'shift-invert: constraint targets ' // &
               'need sigma = 0 (now ' // to_str(options%sigma) // '), one row per ' // &
               'constraint (' // to_str(size(constraint_targets, 1)) // ' rows for ' // &
               to_str(nc) // ') and constraint_solutions')
            return
         end if
      end if
      result%n = n
      result%num_constraints = nc
      result%num_rigid = num_rigid
      slicing = options%max_eigenvalue > 0.0_dp
      eigensolver = eigensolver_of(options, n, nc)
      if (eigensolver == 'block') then
         method = 'block method'
      else
         result%ncv = single_window_ncv(options, n - nc - num_rigid)
         method = 'ncv = ' // to_str(result%ncv)
      end if
      if (slicing) then
         call log%info(stage, 'shift-invert Lanczos: n = ' // to_str(n) // ', ' // to_str(nc) &
            // ' constraints, every mode from sigma = ' // to_str(options%sigma) // &
            ' up to lambda = ' // to_str(options%max_eigenvalue) // ' (at most ' // &
            to_str(options%num_modes) // '), windows of ' // to_str(options%window_size) // &
            ' modes, ' // eigensolver)
      else
         call log%info(stage, 'shift-invert Lanczos: n = ' // to_str(n) // ', ' // to_str(nc) &
            // ' constraints, ' // to_str(options%num_modes) // ' modes nearest sigma = ' // &
            to_str(options%sigma) // ', ' // method)
      end if

      call build_kkt(K, M, C, kkt, error)
      if (allocated(error)) return
      if (num_rigid > 0) then
         call null_vector_deflation(K, M, rigid, null_vectors, result, log, error)
         if (allocated(error)) return
      end if
      interrupt = interrupt_t(enabled=options%stop_on_signal, ranks=options%parallel)

      ! The first factorisation: at sigma (SPD when possible); for slicing, first the count at
      ! the upper bound (how many modes there are), then sigma, both symmetric indefinite.
      sigma = options%sigma
      target = options%num_modes
      count_max = 0
      if (slicing) then
         lambda_max = options%max_eigenvalue
         s = lambda_max
         call factorise_count(K, M, options, kkt, s, lambda_max, &
            lambda_max + STURM_MARGIN * (lambda_max - sigma), solver, result, log, error, &
            count_max, record_analysis=.true.)
         if (allocated(error)) then
            call solver%free()
            return
         end if
         lambda_max = s
         num_below_max = count_max - num_rigid
         call log%info(stage, 'Sturm count at the upper bound ' // to_str(lambda_max, 8) // &
            ' (' // to_str(frequency_of(lambda_max), 6) // ' Hz): ' // to_str(count_max) // &
            ' eigenvalues below it' // rigid_text(num_rigid))
         if (num_below_max < 1) then
            call solver%free()
            call fatal_error(error, FFRF_INPUT_ERROR, 'no mode below the upper bound ' // &
               to_str(frequency_of(lambda_max), 6) // ' Hz (lambda = ' // &
               to_str(lambda_max, 6) // '): the inertia of K - s M there counts ' // &
               to_str(count_max) // ' eigenvalues below it' // rigid_text(num_rigid) // &
               '; raise max_frequency_hz above the first mode')
            return
         end if
         target = min(num_below_max, options%num_modes, n - nc - num_rigid - 1)
         if (target < num_below_max) call log%info(stage, to_str(num_below_max) // &
            ' modes lie below the upper bound; num_modes = ' // to_str(options%num_modes) // &
            ' keeps the lowest ' // to_str(target) // ' (the smaller set)')
         call check_interrupt('before the factorisation at sigma')
         if (allocated(error)) return
         s = sigma
         t0 = result%time_sturm
         call factorise_count(K, M, options, kkt, s, sigma - 1.0e-3_dp * max(abs(sigma), &
            1.0e-8_dp * lambda_max), sigma, solver, result, log, error, j)
         ! the eigen shift's factorisation, not a count's
         result%time_sturm = t0
         if (allocated(error)) then
            call solver%free()
            return
         end if
         sigma = s
         result%num_count_factorisations = result%num_count_factorisations - 1
         result%num_factorisations = result%num_factorisations + 1
         call record_factors(solver, j, result)
         call log%info(stage, 'MUMPS factorisation (SYM = 2, sigma = ' // to_str(sigma, 8) // &
            '): ' // to_str(solver%time_factorisation, 3) // ' s, ' // &
            to_str(real(solver%factor_entries, dp) / 1.0e6_dp, 4) // ' M factor entries, ' // &
            to_str(solver%memory_used_mb) // ' MB, ' // to_str(solver%num_negative_pivots) // &
            ' negative pivots')
      else
         call factorise_shifted(K, M, options, kkt, sigma, solver, result, log, error)
      end if
      ! a signal received during the (uninterruptible) analysis and factorisation stops here;
      ! later ones at the eigen loop's checks
      if (.not. allocated(error)) call check_interrupt('after the MUMPS factorisation')
      if (allocated(error)) then
         call solver%free()
         return
      end if
      result%shift = sigma
      factored_at = sigma
      result%sturm_shift = sigma
      result%sturm_count = result%num_below_shift
      result%sturm_shift_low = sigma
      result%sturm_count_low = result%num_below_shift
      if (present(constraint_targets)) then
         t0 = wall_time()
         call constraint_solve(solver, kkt, sigma, constraint_targets, constraint_solutions, &
            error)
         result%time_constraint_solves = wall_time() - t0
         if (allocated(error)) then
            call solver%free()
            return
         end if
      end if

      t0 = wall_time()
      sturm_before = result%time_sturm
      call find_modes(error)
      result%time_lanczos = wall_time() - t0 - (result%time_sturm - sturm_before)
      call solver%free()
      if (allocated(error)) return
      if (result%eigensolver == 'block') then
         call log%info(stage, 'block Lanczos: ' // to_str(result%num_iterations) // &
            ' restarts, ' // to_str(result%num_block_solves) // ' solves of ' // &
            to_str(result%block_size) // ' right-hand sides (' // &
            to_str(result%time_solves, 3) // ' s in MUMPS), ' // &
            to_str(result%time_lanczos, 3) // ' s')
      else
         call log%info(stage, 'Lanczos: ' // to_str(result%num_iterations) // ' restarts, ' // &
            to_str(result%num_solves) // ' solves (' // to_str(result%time_solves, 3) // &
            ' s in MUMPS), ' // to_str(result%time_lanczos, 3) // ' s')
      end if

      t0 = wall_time()
      z = known%z(:, kept)
      deallocate (known%z)
      call finish_pairs(K, M, C, z, result, error)
      result%time_check = wall_time() - t0
      if (allocated(error)) return
      result%num_found_below_shift = count(result%eigenvalues < result%shift)
      if (result%num_found_below_shift > result%num_below_shift) then
         call log%note(stage, 'Sturm count ' // to_str(result%num_below_shift) // &
            ' eigenvalues below the shift, but ' // to_str(result%num_found_below_shift) // &
            ' returned ones lie below it; check the constraints (full row rank?)')
      end if
      do j = 1, result%num_modes
         call log%debug(stage, '  mode ' // to_str(j) // ': lambda = ' // &
            to_str(result%eigenvalues(j), 12) // ', residual ' // &
            to_str(result%residuals(j), 3))
      end do
      result%time_total = wall_time() - t_start
      call log%info(stage, to_str(result%num_modes) // ' eigenvalues ' // &
         to_str(result%eigenvalues(1), 8) // ' .. ' // &
         to_str(result%eigenvalues(result%num_modes), 8) // ', max residual ' // &
         to_str(maxval(result%residuals), 2) // ', M-orthonormality ' // &
         to_str(result%orthonormality_error, 2) // ', Sturm ' // &
         to_str(result%num_below_shift) // ' below shift ... ' // to_str(result%time_total, 3) &
         // ' s')

   contains

      !> The windows, their counts and recoveries; `kept` the columns of known%z returned.
      subroutine find_modes(error)
         type(error_t), allocatable, intent(out) :: error
         real(dp), allocatable :: zw(:, :), lambda(:)
         logical, allocatable :: take(:)
         real(dp) :: b, low, high, scale
         integer(ip) :: count_b, count_s, window, remaining, k, nev, expected, have, jb, i
         logical :: last, windows, proven

         ! Windows when more modes are wanted than one window holds (from the bottom of the
         ! spectrum up: only when nothing but the deflated null vectors lies below sigma)
         windows = slicing .or. (target > options%window_size .and. &
            result%num_below_shift == rigid_between(-huge(1.0_dp), sigma))
         call grow(known, n, target + 8_ip, error)
         if (allocated(error)) return
         b = sigma
         count_b = result%num_below_shift
         window = 0
         do
            remaining = target - known%count
            if (remaining <= 0) exit
            window = window + 1
            result%num_windows = window
            if (windows) then
               k = min(options%window_size, remaining)
            else
               k = remaining
            end if
            last = k == remaining
            nev = k
            if (.not. last) nev = k + max(2_ip, options%window_size / 10)
            nev = min(nev, n - nc - num_rigid - 1)
            call solve_window(nev, b, window, window - 2, zw, lambda, error)
            if (allocated(error)) return
            ! Eigenpairs below the window's lower boundary are known already (deflated or
            ! farther away): only window 1 keeps them (a positive sigma's nearest modes)
            if (window > 1) then
               take = lambda >= b
               zw = zw(:, pack([(i, i=1, int(size(lambda), ip))], take))
               lambda = pack(lambda, take)
               if (size(lambda) == 0) then
                  call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: window ' // &
                     to_str(window) // ' at s = ' // to_str(b, 10) // ' found no eigenvalue ' // &
                     'above it; raise lanczos_vectors')
                  return
               end if
            end if
            if (window == 1 .and. lambda(1) < sigma) then
               ! A positive shift with modes below it: close the window below its lowest
               ! eigenvalue too (one more factorisation)
               scale = STURM_MARGIN * max(abs(lambda(size(lambda)) - lambda(1)), &
                  abs(lambda(1)), tiny(1.0_dp))
               b = lambda(1) - scale
               call count_at(b, lambda(1) - 2.0_dp * scale, lambda(1), count_b, error)
               if (allocated(error)) return
               result%sturm_shift_low = b
               result%sturm_count_low = count_b
            end if
            proven = .true.
            if (.not. last) then
               ! Boundary in the widest relative gap of the window's top quarter (and its
               ! guard pairs): the next shift
               call boundary(lambda, max(1_ip, k - k / 4), jb, error)
               if (allocated(error)) return
               low = lambda(jb)
               high = lambda(jb + 1)
               s = 0.5_dp * (low + high)
               call count_at(s, low, high, count_s, error)
               if (allocated(error)) return
            else if (slicing .and. target == num_below_max) then
               s = lambda_max
               count_s = count_max
            else if (options%sturm_check) then
               scale = STURM_MARGIN * max(lambda(size(lambda)) - min(sigma, lambda(1)), &
                  abs(lambda(size(lambda))), tiny(1.0_dp))
               low = lambda(size(lambda))
               high = low + 2.0_dp * scale
               s = low + scale
               call count_at(s, low, high, count_s, error)
               if (allocated(error)) return
            else
               proven = .false.
            end if
            if (.not. proven) then
               result%sturm_checked = .false.
               call add_known(known, zw, lambda, window, error)
               if (allocated(error)) return
               cycle
            end if
            take = lambda < s
            call add_known(known, zw(:, pack([(i, i=1, int(size(lambda), ip))], take)), &
               pack(lambda, take), window, error)
            if (allocated(error)) return
            expected = count_s - count_b - rigid_between(b, s)
            have = count(known%lambda(1:known%count) >= b .and. &
               known%lambda(1:known%count) < s)
            if (have < expected) then
               call recover(b, count_b, s, count_s, expected, window, error)
               if (allocated(error)) return
               have = expected
            else if (have > expected) then
               call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: ' // to_str(have) // &
                  ' eigenpairs found in [' // to_str(b, 10) // ', ' // to_str(s, 10) // &
                  '), but the inertia counts ' // to_str(expected) // &
                  '; the constraint rows are dependent or the null vectors given are not ' // &
                  'null vectors of K')
               return
            end if
            if (last .and. window == 1) then
               call log%info(stage, 'Sturm check: the inertia at s = ' // to_str(s, 8) // &
                  ' (' // to_str(frequency_of(s), 6) // ' Hz) counts ' // to_str(count_s) // &
                  ' eigenvalues below it' // rigid_text(rigid_between(b, s)) // ', and ' // &
                  to_str(have) // ' modes were found above the shift (' // &
                  to_str(frequency_of(b), 6) // ' Hz): none missing (' // &
                  to_str(result%time_sturm, 3) // ' s)')
            else
               call log%info(stage, 'window ' // to_str(window) // ': ' // to_str(have) // &
                  ' modes in [' // to_str(frequency_of(b), 6) // ', ' // &
                  to_str(frequency_of(s), 6) // ') Hz, proven by the inertia (' // &
                  to_str(count_s) // ' eigenvalues below ' // to_str(frequency_of(s), 6) // &
                  ' Hz)')
            end if
            result%sturm_checked = .true.
            result%sturm_shift = s
            result%sturm_count = count_s
            b = s
            count_b = count_s
         end do
         call select_returned(error)
      end subroutine find_modes

      !> The returned columns of known: the target nearest sigma (the lowest when sigma is below
      !> them), plus the rest of a multiplet the target cuts through. When known pairs are left
      !> out above them, the Sturm check moves into the gap below those (one more count).
      subroutine select_returned(error)
         type(error_t), allocatable, intent(out) :: error
         integer(ip), allocatable :: order(:)
         real(dp), allocatable :: distance(:)
         integer(ip) :: keep, count_s
         real(dp) :: low, high
         distance = abs(known%lambda(1:known%count) - sigma)
         order = ascending_order(distance)
         keep = min(target, known%count)
         do while (keep < known%count)
            ! the next one belongs to the multiplet of a kept one?
            if (.not. any(abs(known%lambda(order(keep + 1)) - known%lambda(order(1:keep))) <= &
                MULTIPLET_RTOL * max(abs(known%lambda(order(keep + 1))), abs(sigma)))) exit
            keep = keep + 1
         end do
         result%num_multiplet_extra = max(0_ip, keep - target)
         if (keep > target) call log%note(stage, 'num_modes = ' // to_str(target) // &
            ' cuts through a multiplet at ' // to_str(frequency_of(known%lambda(order(keep))), &
            8) // ' Hz; returning ' // to_str(keep) // ' modes so that it stays whole')
         kept = order(1:keep)
         if (keep == known%count .or. .not. result%sturm_checked) return
         if (any(known%lambda(order(keep + 1:known%count)) < sigma)) return
         ! Known pairs above the returned ones were counted at the Sturm shift: prove the
         ! returned set alone, with a shift in the gap above its top
         low = maxval(known%lambda(kept))
         high = minval(known%lambda(order(keep + 1:known%count)))
         s = 0.5_dp * (low + high)
         call count_at(s, low, high, count_s, error)
         if (allocated(error)) return
         if (count_s - result%sturm_count_low - rigid_between(result%sturm_shift_low, s) /= &
             keep) then
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: the inertia at s = ' // &
               to_str(s, 10) // ' counts ' // to_str(count_s) // ' eigenvalues below it, ' // &
               'not the ' // to_str(keep) // ' returned ones above ' // &
               to_str(result%sturm_shift_low, 10) // ' (+ ' // &
               to_str(result%sturm_count_low + rigid_between(result%sturm_shift_low, s)) // &
               ' below it and null vectors); the count is inconsistent')
            return
         end if
         result%sturm_shift = s
         result%sturm_count = count_s
      end subroutine select_returned

      !> nev eigenpairs nearest `shift` (the factorised one) in the complement of the null
      !> vectors and of the known pairs from window `first_window` on; ascending.
      subroutine solve_window(nev, shift, window, first_window, zw, lambda, error, solver_name)
         integer(ip), intent(in) :: nev, window, first_window
         real(dp), intent(in) :: shift
         real(dp), allocatable, intent(out) :: zw(:, :), lambda(:)
         type(error_t), allocatable, intent(out) :: error
         character(len=*), intent(in), optional :: solver_name
         type(deflation_t) :: deflation
         character(len=:), allocatable :: name
         name = eigensolver
         if (present(solver_name)) name = solver_name
         call deflation_of(M, null_vectors, known, first_window, deflation, error)
         if (allocated(error)) return
         call eigen_window(K, M, options, name, nev, nc, shift, solver, interrupt, deflation, &
            zw, lambda, result, log, error)
         if (allocated(error)) then
            if (window > 1) call add_context(error, 'window ' // to_str(window) // ' at s = ' &
               // to_str(shift, 10))
         end if
      end subroutine solve_window

      !> The missing eigenpairs of [lo, hi): everything known from two windows below on is
      !> deflated, so the pairs nearest a shift at either end of the interval not yet known are
      !> missing ones (or lie outside it, dropped). Rounds alternate the end (the upper one
      !> first, where a multiplet cut by the window's top lies; the lower one refactorised) and
      !> the eigensolver (the block method first: a block of b vectors sees b members of a
      !> multiple eigenvalue, a single vector one and the others only through rounding), with
      !> the missing count of vectors, then twice as many each round. The solver ends at hi.
      subroutine recover(lo, count_lo, hi, count_hi, expected, window, error)
         real(dp), intent(in) :: lo, hi
         integer(ip), intent(in) :: count_lo, count_hi, expected, window
         type(error_t), allocatable, intent(out) :: error
         real(dp), allocatable :: zr(:, :), lr(:)
         logical, allocatable :: take(:)
         character(len=:), allocatable :: name
         real(dp) :: at, moved
         integer(ip) :: have, round, nev_r, i, before, recount
         have = count(known%lambda(1:known%count) >= lo .and. known%lambda(1:known%count) < hi)
         do round = 1, MAX_RECOVERIES
            if (have >= expected) exit
            result%num_recoveries = result%num_recoveries + 1
            name = trim(merge('block if possible', 'arpack           ', &
               mod((round + 1) / 2, 2) == 1))
            if (round <= 2) then
               nev_r = expected - have
            else
               nev_r = int(2**(round - 2), ip) * (expected - have + 1_ip)
            end if
            nev_r = min(nev_r, n - nc - num_rigid - int(known%count, ip) - 1)
            at = merge(hi, lo, mod(round, 2) == 1)
            if (factored_at /= at) then
               moved = at
               call count_at(moved, at - STURM_MARGIN * abs(hi - lo), at, recount, error)
               if (allocated(error)) return
               if (recount /= merge(count_hi, count_lo, mod(round, 2) == 1) .or. &
                   moved /= at) then
                  call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: the inertia ' // &
                     'at s = ' // to_str(at, 12) // ' counts ' // to_str(recount) // &
                     ' eigenvalues now and ' // to_str(merge(count_hi, count_lo, &
                     mod(round, 2) == 1)) // ' before; the factorisation is not reproducible')
                  return
               end if
            end if
            call log%note(stage, 'Sturm check: the inertia counts ' // to_str(expected) // &
               ' eigenvalues in [' // to_str(frequency_of(lo), 6) // ', ' // &
               to_str(frequency_of(hi), 6) // ') Hz, ' // to_str(have) // ' were found; ' // &
               'recovery ' // to_str(round) // ': ' // to_str(nev_r) // ' more vectors (' // &
               name // ') at ' // to_str(frequency_of(at), 6) // ' Hz with the ' // &
               to_str(known%count) // ' known modes deflated')
            call solve_window(nev_r, at, window, window - 2, zr, lr, error, name)
            if (allocated(error)) return
            take = lr >= lo .and. lr < hi
            before = known%count
            call add_known(known, zr(:, pack([(i, i=1, int(size(lr), ip))], take)), &
               pack(lr, take), window, error)
            if (allocated(error)) return
            have = have + (known%count - before)
         end do
         if (have /= expected) then
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: spectrum incomplete: ' &
               // 'the inertia counts ' // to_str(expected) // ' eigenvalues in [' // &
               to_str(frequency_of(lo), 8) // ', ' // to_str(frequency_of(hi), 8) // &
               ') Hz, ' // to_str(have) // ' were found after ' // to_str(MAX_RECOVERIES) // &
               ' recoveries; lower tolerance or raise lanczos_vectors')
            return
         end if
         if (factored_at /= hi) then
            moved = hi
            call count_at(moved, hi, hi, recount, error)
            if (allocated(error)) return
         end if
         call log%note(stage, 'Sturm check: recovered, ' // to_str(have) // ' modes in [' // &
            to_str(frequency_of(lo), 6) // ', ' // to_str(frequency_of(hi), 6) // ') Hz')
      end subroutine recover

      !> The inertia at s (moved inside (low, high) if it is an eigenvalue): count below s.
      subroutine count_at(s, low, high, count, error)
         real(dp), intent(inout) :: s
         real(dp), intent(in) :: low, high
         integer(ip), intent(out) :: count
         type(error_t), allocatable, intent(out) :: error
         count = 0
         call check_interrupt('before the inertia factorisation at ' // &
            to_str(frequency_of(s), 6) // ' Hz')
         if (allocated(error)) return
         call factorise_count(K, M, options, kkt, s, low, high, solver, result, log, error, &
            count)
         if (.not. allocated(error)) factored_at = s
      end subroutine count_at

      !> Deflated null vectors with eigenvalue 0 in [lo, hi)
      pure integer(ip) function rigid_between(lo, hi) result(num)
         real(dp), intent(in) :: lo, hi
         num = 0
         if (lo < 0.0_dp .and. hi > 0.0_dp) num = num_rigid
      end function rigid_between

      subroutine check_interrupt(where)
         character(len=*), intent(in) :: where
         call interrupt%check(where, error)
      end subroutine check_interrupt

   end procedure solve_shift_invert

end submodule ffrf_modes_shift_invert_windows
