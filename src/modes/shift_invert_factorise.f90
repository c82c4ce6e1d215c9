!> ffrf_modes_shift_invert: sizes and settings checked, the KKT matrix assembled and factorised
!> at a shift (SPD or indefinite, a shift moved off an eigenvalue, inertia counts, memory
!> estimates), constrained solves on the factors.
submodule (ffrf_modes_shift_invert:ffrf_modes_shift_invert_lanczos) ffrf_modes_shift_invert_factorise
   implicit none

contains

   !> Sizes and settings. Without max_eigenvalue num_modes must leave room in the constrained
   !> dimension n - nc - num_rigid; with it num_modes is a cap (the smaller set wins).
   module procedure check_input
      !> The settings that count something and must be positive
      character(len=*), parameter :: COUNT_SETTINGS(2) = [character(len=14) :: &
         'max_iterations', 'window_size']
      integer(ip) :: dimension, ncv, counts(2)
      integer :: setting

      n = K%num_rows
      nc = C%num_rows
      if (n < 1 .or. K%num_cols /= n .or. M%num_rows /= n .or. M%num_cols /= n) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'shift-invert: K is ' // &
            to_str(K%num_rows) // ' x ' // to_str(K%num_cols) // ' and M ' // &
            to_str(M%num_rows) // ' x ' // to_str(M%num_cols) // &
            '; both must be the same non-empty square size')
         return
      end if
      if (.not. (allocated(K%row_ptr) .and. allocated(K%col) .and. allocated(K%val) .and. &
                 allocated(M%row_ptr) .and. allocated(M%col) .and. allocated(M%val))) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'shift-invert: K or M has unallocated ' // &
            'CSR arrays')
         return
      end if
      if (nc < 0 .or. (nc > 0 .and. C%num_cols /= n)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'shift-invert: C is ' // to_str(nc) // &
            ' x ' // to_str(C%num_cols) // ', must have n = ' // to_str(n) // ' columns')
         return
      end if
      if (nc > 0 .and. .not. (allocated(C%row_ptr) .and. allocated(C%col) .and. &
                              allocated(C%val))) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'shift-invert: C has ' // to_str(nc) // &
            ' rows but unallocated CSR arrays')
         return
      end if
      dimension = n - nc - num_rigid
      if (options%num_modes < 1 .or. (options%max_eigenvalue <= 0.0_dp .and. &
          options%num_modes >= dimension)) then
         if (num_rigid > 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'shift-invert: num_modes = ' // &
               to_str(options%num_modes) // ' must lie in 1 .. ' // to_str(dimension - 1) // &
               ' (n - num_constraints - rigid modes - 1 = ' // to_str(n) // ' - ' // &
               to_str(nc) // ' - ' // to_str(num_rigid) // ' - 1); use a dense solver for ' // &
               'so small a problem')
         else
            call fatal_error(error, FFRF_INPUT_ERROR, 'shift-invert: num_modes = ' // &
               to_str(options%num_modes) // ' must lie in 1 .. ' // to_str(dimension - 1) // &
               ' (n - num_constraints - 1 = ' // to_str(n) // ' - ' // to_str(nc) // &
               ' - 1); use a dense solver for so small a problem')
         end if
         return
      end if
      counts = [options%max_iterations, options%window_size]
      do setting = 1, size(counts)
         if (counts(setting) < 1) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'shift-invert: ' // &
               trim(COUNT_SETTINGS(setting)) // ' = ' // to_str(counts(setting)) // &
               ', must be positive')
            return
         end if
      end do
      if (.not. ieee_is_finite(options%sigma) .or. .not. ieee_is_finite(options%max_eigenvalue)) &
         then
         call fatal_error(error, FFRF_INPUT_ERROR, 'shift-invert: sigma or max_eigenvalue is ' // &
            'not finite')
         return
      end if
      if (options%max_eigenvalue > 0.0_dp .and. options%sigma >= options%max_eigenvalue) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'shift-invert: sigma = ' // &
            to_str(options%sigma) // ' is not below max_eigenvalue = ' // &
            to_str(options%max_eigenvalue) // '; the windows run from sigma up')
         return
      end if
      ! A given basis size must exceed the modes of a single window (with slicing, windows
      ! whose nev reaches it take the automatic size)
      if (options%max_eigenvalue <= 0.0_dp .and. options%num_modes <= options%window_size .and. &
          options%ncv > 0) then
         ncv = arpack_basis_size(options, options%num_modes, dimension)
         if (ncv <= options%num_modes) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'shift-invert: ncv = ' // to_str(ncv) // &
               ' must exceed num_modes = ' // to_str(options%num_modes) // &
               '; raise ncv (about 2 num_modes, at most n - num_constraints = ' // &
               to_str(dimension) // ')')
            return
         end if
      end if
   end procedure check_input

   !> Pattern of the KKT matrix: union pattern of K and M (upper triangle, csr_add keeps all
   !> entries whatever their value, so the pattern does not depend on sigma) and C^T scaled row
   !> by row to max|diag K| (toolchain.md pitfall 7; a row scaling keeps null(C)).
   module procedure build_kkt
      type(csr_t) :: A
      integer(ip), allocatable :: irn(:), jcn(:)
      real(dp), allocatable :: val(:)
      real(dp) :: diag_scale, row_max
      integer(i8) :: total, e
      integer(ip) :: n, nc, r, p, stat

      n = K%num_rows
      nc = C%num_rows
      call csr_add(1.0_dp, K, 0.0_dp, M, A, error)
      if (allocated(error)) return
      call csr_upper_coo(A, irn, jcn, val)
      kkt%n = n
      kkt%num_constraints = nc
      kkt%num_upper = size(irn, kind=i8)
      total = kkt%num_upper
      if (nc > 0) total = total + int(C%row_ptr(nc + 1) - 1, i8)
      if (total > int(huge(1_ip), i8)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'shift-invert: the KKT matrix has ' // &
            to_str(total) // ' entries, beyond 32-bit MUMPS index arrays')
         return
      end if
      allocate (kkt%irn(total), kkt%jcn(total), kkt%val(total), stat=stat)
      if (stat /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: cannot allocate the ' // &
            'KKT matrix of ' // to_str(total) // ' entries')
         return
      end if
      kkt%irn(1:kkt%num_upper) = irn
      kkt%jcn(1:kkt%num_upper) = jcn
      kkt%val(1:kkt%num_upper) = val
      if (nc == 0) return

      diag_scale = 0.0_dp
      do e = 1, kkt%num_upper
         if (irn(e) == jcn(e)) diag_scale = max(diag_scale, abs(val(e)))
      end do
      if (diag_scale == 0.0_dp) diag_scale = 1.0_dp
      allocate (kkt%row_scale(nc))
      e = kkt%num_upper
      do r = 1, nc
         row_max = 0.0_dp
         do p = C%row_ptr(r), C%row_ptr(r + 1) - 1
            row_max = max(row_max, abs(C%val(p)))
         end do
         if (row_max == 0.0_dp) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'shift-invert: constraint row ' // &
               to_str(r) // ' of ' // to_str(nc) // ' is zero; remove it (C must have full ' // &
               'row rank)')
            return
         end if
         do p = C%row_ptr(r), C%row_ptr(r + 1) - 1
            if (C%col(p) < 1 .or. C%col(p) > n) then
               call fatal_error(error, FFRF_INPUT_ERROR, 'shift-invert: constraint row ' // &
                  to_str(r) // ' has column ' // to_str(C%col(p)) // ' outside 1..' // &
                  to_str(n))
               return
            end if
            e = e + 1
            kkt%irn(e) = C%col(p)
            kkt%jcn(e) = n + r
            kkt%val(e) = C%val(p) * (diag_scale / row_max)
         end do
         kkt%row_scale(r) = diag_scale / row_max
      end do
   end procedure build_kkt

   !> x of [[K, C^T], [C, 0]] [x; mu] = [0; t] for each column t of `targets`, with the factors
   !> of the KKT matrix at sigma = 0 (the scaled rows take scaled targets).
   module procedure constraint_solve
      real(dp), allocatable :: rhs(:, :)
      integer(ip) :: n, r, stat
      n = kkt%n
      if (sigma /= 0.0_dp) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: the shift moved to ' // &
            to_str(sigma) // ', so the factors are not those of the static problem')
         return
      end if
      allocate (rhs(n + kkt%num_constraints, size(targets, 2)), source=0.0_dp, stat=stat)
      if (stat /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: cannot allocate ' // &
            to_str(size(targets, 2)) // ' static right-hand sides')
         return
      end if
      do r = 1, kkt%num_constraints
         rhs(n + r, :) = targets(r, :) * kkt%row_scale(r)
      end do
      call solver%solve(rhs, error)
      call check_solution(error, 'shift-invert, static solve with the KKT factors', &
         all(ieee_is_finite(rhs)), 'shift-invert: NaN or Inf in the static solve: K is ' // &
         'singular on null(C)')
      if (allocated(error)) return
      solutions = rhs(1:n, :)
   end procedure constraint_solve

   !> Values of K - sigma M in the KKT pattern (the C^T block stays).
   subroutine shift_values(K, M, sigma, kkt, error)
      type(csr_t), intent(in) :: K, M
      real(dp), intent(in) :: sigma
      type(kkt_t), intent(inout) :: kkt
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: A
      integer(ip), allocatable :: irn(:), jcn(:)
      real(dp), allocatable :: val(:)
      call csr_add(1.0_dp, K, -sigma, M, A, error)
      if (allocated(error)) return
      call csr_upper_coo(A, irn, jcn, val)
      if (size(val, kind=i8) /= kkt%num_upper) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: pattern of K - sigma M ' &
            // 'changed with sigma (internal error)')
         return
      end if
      kkt%val(1:kkt%num_upper) = val
   end subroutine shift_values

   !> Analyse and factorise the KKT matrix at `sigma`. SPD (SYM = 1) is tried when there are no
   !> constraints and sigma < 0; negative pivots send it to SYM = 2. Null pivots (sigma on an
   !> eigenvalue) or a singular matrix move sigma once, if allowed, and refactorise.
   module procedure factorise_shifted
      integer(ip) :: sym, nc, attempt
      logical :: singular, moved, success
      real(dp) :: sigma_new

      nc = kkt%num_constraints
      if (nc == 0 .and. sigma < 0.0_dp) then
         sym = MUMPS_SYM_SPD
      else
         sym = MUMPS_SYM_INDEFINITE
      end if
      call start_solver(kkt, sym, options, solver, result, log, error)
      if (allocated(error)) return

      moved = .false.
      success = .false.
      do attempt = 1, 4
         call factorise_at(K, M, sigma, kkt, solver, 'shift-invert at sigma', singular, error)
         result%num_factorisations = result%num_factorisations + 1
         if (allocated(error)) return
         result%time_factorisation = solver%time_factorisation
         call log%info(stage, 'MUMPS factorisation (SYM = ' // to_str(sym) // ', sigma = ' // &
            to_str(sigma, 8) // '): ' // to_str(solver%time_factorisation, 3) // ' s, ' // &
            to_str(real(solver%factor_entries, dp) / 1.0e6_dp, 4) // ' M factor entries, ' // &
            to_str(solver%memory_used_mb) // ' MB, ' // to_str(solver%num_negative_pivots) // &
            ' negative and ' // to_str(solver%num_null_pivots) // ' null pivots')
         if (solver%compression_tolerance > 0.0_dp) call log%info(stage, 'block low-rank ' // &
            'factors: ' // to_str(real(solver%compressed_factor_entries, dp) / 1.0e6_dp, 4) // &
            ' M entries stored (' // to_str(100.0_dp * real(solver%compressed_factor_entries, &
            dp) / real(max(solver%factor_entries, 1_i8), dp), 3) // ' % of full rank), ' // &
            to_str(solver%factor_flops_done, 3) // ' flops done')

         ! SPD attempt on an indefinite matrix: redo as symmetric indefinite.
         if (sym == MUMPS_SYM_SPD .and. (singular .or. solver%num_negative_pivots > 0)) then
            call log%note(stage, 'K - sigma M is not positive definite at sigma = ' // &
               to_str(sigma) // ' (' // to_str(solver%num_negative_pivots) // &
               ' negative pivots); refactorising as symmetric indefinite (SYM = 2)')
            sym = MUMPS_SYM_INDEFINITE
            call solver%free()
            call start_solver(kkt, sym, options, solver, result, log, error)
            if (allocated(error)) return
            cycle
         end if

         if (.not. singular .and. solver%num_null_pivots == 0) then
            success = .true.
            exit
         end if
         if (.not. options%retry_shift .or. moved) exit
         sigma_new = moved_shift(K, M, sigma)
         call log%note(stage, 'sigma = ' // to_str(sigma, 12) // ' is numerically an ' // &
            'eigenvalue (' // to_str(solver%num_null_pivots) // ' null pivots, MUMPS ' // &
            'INFOG(1) = ' // to_str(solver%status) // '); moved to ' // to_str(sigma_new, 12) &
            // ' and refactorising')
         sigma = sigma_new
         moved = .true.
      end do
      if (.not. success) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: K - sigma M is ' // &
            'singular on the constrained space at sigma = ' // to_str(sigma, 12) // &
            ' (' // to_str(solver%num_null_pivots) // ' null pivots, MUMPS INFOG(1) = ' // &
            to_str(solver%status) // ', ' // to_str(result%num_factorisations) // &
            ' factorisations): sigma is an eigenvalue, or the constraint rows are linearly ' // &
            'dependent, or a dof has neither stiffness nor mass; move sigma or check C')
         return
      end if

      result%sym = sym
      result%factor_entries = solver%factor_entries
      result%num_negative_pivots = solver%num_negative_pivots
      result%factor_memory_mb = solver%memory_used_mb
      result%compressed_factor_entries = solver%compressed_factor_entries
      result%num_below_shift = solver%num_negative_pivots - nc
      if (result%num_below_shift < 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: the KKT matrix has ' // &
            to_str(solver%num_negative_pivots) // ' negative pivots, fewer than the ' // &
            to_str(nc) // ' constraint rows; C is rank deficient')
         return
      end if
   end procedure factorise_shifted

   !> Symmetric indefinite factorisation at s for its inertia (module header). The Sturm count
   !> of theory.md 5.3: eigenvalues below s = negative pivots - constraint rows.
   module procedure factorise_count
      real(dp), parameter :: fractions(3) = [0.75_dp, 0.25_dp, 0.9_dp]
      type(eigen_result_t) :: scratch
      real(dp) :: t0
      integer :: attempt
      logical :: singular
      count = 0
      t0 = wall_time()
      if (.not. solver%is_analysed() .or. solver%sym /= MUMPS_SYM_INDEFINITE) then
         ! A new analysis (the SPD one of the eigen shift cannot count negative pivots); its
         ! estimates stay those of the eigen shift's in the result
         call solver%free()
         if (present(record_analysis)) then
            if (record_analysis) then
               call start_solver(kkt, MUMPS_SYM_INDEFINITE, options, solver, result, log, error)
            else
               call start_solver(kkt, MUMPS_SYM_INDEFINITE, options, solver, scratch, log, error)
            end if
         else
            call start_solver(kkt, MUMPS_SYM_INDEFINITE, options, solver, scratch, log, error)
         end if
         if (allocated(error)) return
      end if
      do attempt = 0, size(fractions)
         call factorise_at(K, M, s, kkt, solver, 'shift-invert, inertia at s', singular, error)
         result%num_count_factorisations = result%num_count_factorisations + 1
         if (allocated(error)) return
         if (.not. singular .and. solver%num_null_pivots == 0) exit
         if (attempt == size(fractions)) then
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: K - s M is singular ' // &
               'at every shift tried in (' // to_str(low, 12) // ', ' // to_str(high, 12) // &
               '), last s = ' // to_str(s, 12) // ' (' // to_str(solver%num_null_pivots) // &
               ' null pivots): the constraint rows are linearly dependent or a dof has ' // &
               'neither stiffness nor mass; check C')
            return
         end if
         call log%note(stage, 's = ' // to_str(s, 12) // ' is numerically an eigenvalue (' // &
            to_str(solver%num_null_pivots) // ' null pivots, MUMPS INFOG(1) = ' // &
            to_str(solver%status) // '); moved to ' // &
            to_str(low + fractions(attempt + 1) * (high - low), 12))
         s = low + fractions(attempt + 1) * (high - low)
      end do
      count = solver%num_negative_pivots - kkt%num_constraints
      result%time_sturm = result%time_sturm + (wall_time() - t0)
      if (count < 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: the KKT matrix has ' // &
            to_str(solver%num_negative_pivots) // ' negative pivots, fewer than the ' // &
            to_str(kkt%num_constraints) // ' constraint rows; C is rank deficient')
         return
      end if
      call log%debug(stage, 'inertia at s = ' // to_str(s, 10) // ': ' // &
         to_str(solver%num_negative_pivots) // ' negative pivots - ' // &
         to_str(kkt%num_constraints) // ' constraint rows = ' // to_str(count) // &
         ' eigenvalues below s (' // to_str(solver%time_factorisation, 3) // ' s)')
   end procedure factorise_count

   !> Factorise K - s M in the KKT matrix's pattern. MUMPS's "numerically singular" (INFOG(1) =
   !> -10: s is an eigenvalue to round-off) comes back as `singular`, for the caller to move s;
   !> any other failure is an error naming `what` and s.
   subroutine factorise_at(K, M, s, kkt, solver, what, singular, error)
      type(csr_t), intent(in) :: K, M
      real(dp), intent(in) :: s
      type(kkt_t), intent(inout) :: kkt
      type(mumps_solver_t), intent(inout) :: solver
      character(len=*), intent(in) :: what
      logical, intent(out) :: singular
      type(error_t), allocatable, intent(out) :: error
      singular = .false.
      call shift_values(K, M, s, kkt, error)
      if (allocated(error)) return
      call solver%factorise(kkt%val, error)
      if (.not. allocated(error)) return
      if (solver%status /= -10) then
         call add_context(error, what // ' = ' // to_str(s, 12))
         return
      end if
      singular = .true.
      deallocate (error)
   end subroutine factorise_at

   !> init + analyse (METIS ordering) of the KKT pattern, with null-pivot detection on.
   subroutine start_solver(kkt, sym, options, solver, result, log, error)
      type(kkt_t), intent(in) :: kkt
      integer(ip), intent(in) :: sym
      type(eigen_options_t), intent(in) :: options
      type(mumps_solver_t), intent(inout) :: solver
      type(eigen_result_t), intent(inout) :: result
      type(logger_t), intent(in) :: log
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: memory_error
      call solver%init(sym, error, null_pivot_detection=.true., &
                       null_pivot_threshold=options%null_pivot_threshold, &
                       parallel=options%parallel)
      if (allocated(error)) return
      call solver%set_memory_options(error, options%out_of_core, options%ooc_directory, &
         options%compression_tolerance, options%memory_limit_mb)
      if (allocated(error)) then
         call add_context(error, 'shift-invert')
         return
      end if
      call solver%analyse(kkt%n + kkt%num_constraints, kkt%irn, kkt%jcn, error=error)
      if (allocated(error)) then
         call add_context(error, 'shift-invert')
         return
      end if
      result%time_ordering = solver%time_ordering
      result%time_analysis = solver%time_analysis
      call log%info(stage, 'METIS ordering ' // to_str(solver%time_ordering, 3) // &
         ' s, MUMPS analysis ' // to_str(solver%time_analysis, 3) // ' s (order ' // &
         to_str(kkt%n + kkt%num_constraints) // ', ' // to_str(size(kkt%irn)) // &
         ' entries, MUMPS used ordering: ' // mumps_ordering_name(solver%ordering_used) // &
         ', estimated ' // to_str(real(solver%estimated_factor_entries, dp) / 1.0e6_dp, 4) // &
         ' M factor entries)')
      ! The memory check before the factorisation (theory: MUMPS's analysis estimates) counts
      ! the eigensolver's vectors too
      solver%workspace_mb = eigen_workspace_mb(options, kkt%n, kkt%num_constraints, &
         solver%ranks())
      call solver%check_memory(memory_error)
      call record_memory_estimates(solver, result, log)
      if (allocated(memory_error)) then
         call move_alloc(memory_error, error)
         call add_context(error, 'shift-invert')
      end if
   end subroutine start_solver

   !> The analysis's estimates into the result, and one log line with them before factorising.
   subroutine record_memory_estimates(solver, result, log)
      type(mumps_solver_t), intent(in) :: solver
      type(eigen_result_t), intent(inout) :: result
      type(logger_t), intent(in) :: log
      character(len=:), allocatable :: text
      result%estimated_factor_entries = solver%estimated_factor_entries
      result%estimated_flops = solver%estimated_flops
      result%estimated_memory_incore_mb = solver%estimated_memory_incore_max_mb
      result%estimated_memory_incore_total_mb = solver%estimated_memory_incore_total_mb
      result%estimated_memory_ooc_mb = solver%estimated_memory_ooc_max_mb
      result%estimated_memory_ooc_total_mb = solver%estimated_memory_ooc_total_mb
      result%estimated_memory_blr_mb = merge(solver%estimated_memory_blr_ooc_mb, &
         solver%estimated_memory_blr_incore_mb, solver%out_of_core)
      result%predicted_memory_mb = solver%predicted_memory_mb
      result%memory_limit_mb = solver%checked_limit_mb
      result%out_of_core = solver%out_of_core
      result%compression_tolerance = solver%compression_tolerance
      text = 'MUMPS estimates: ' // to_str(real(solver%estimated_flops, dp), 3) // &
         ' flops, memory ' // to_str(solver%estimated_memory_incore_max_mb) // &
         ' MB in-core (INFOG(16)), ' // to_str(solver%estimated_memory_ooc_max_mb) // &
         ' MB out-of-core (INFOG(26))'
      if (solver%compression_tolerance > 0.0_dp) text = text // ', low-rank ' // &
         to_str(solver%estimated_memory_blr_incore_mb) // ' MB in-core (INFOG(36)), ' // &
         to_str(solver%estimated_memory_blr_ooc_mb) // ' MB out-of-core (INFOG(38)), ' // &
         'CNTL(7) = ' // to_str(solver%compression_tolerance, 3)
      text = text // '; this run: ' // solver%memory_options_text() // ', ' // &
         to_str(solver%predicted_memory_mb) // ' MB'
      if (solver%out_of_core) text = text // ' (files in ' // solver%ooc_directory // ', ~' // &
         to_str(nint(solver%estimated_disk_mb)) // ' MB)'
      if (solver%checked_limit_mb > 0) then
         text = text // ' + ' // to_str(solver%resident_memory_mb) // ' MB resident + ' // &
            to_str(solver%workspace_mb) // ' MB of eigensolver vectors, limit ' // &
            to_str(solver%checked_limit_mb) // ' MB'
      else
         text = text // ', no memory limit'
      end if
      call log%info(stage, text)
   end subroutine record_memory_estimates

   !> A shift moved off an eigenvalue: down by 1e-4 |sigma|, at least 1e-8 of the eigenvalue
   !> scale max(K_ii / M_ii) (so sigma = 0 on a free-free body goes slightly negative).
   function moved_shift(K, M, sigma) result(moved)
      type(csr_t), intent(in) :: K, M
      real(dp), intent(in) :: sigma
      real(dp) :: moved
      real(dp) :: scale, kii, mii
      integer(ip) :: i, p
      scale = 0.0_dp
      do i = 1, K%num_rows
         kii = 0.0_dp
         mii = 0.0_dp
         do p = K%row_ptr(i), K%row_ptr(i + 1) - 1
            if (K%col(p) == i) kii = K%val(p)
         end do
         do p = M%row_ptr(i), M%row_ptr(i + 1) - 1
            if (M%col(p) == i) mii = M%val(p)
         end do
         if (mii > 0.0_dp) scale = max(scale, abs(kii) / mii)
      end do
      moved = sigma - max(1.0e-4_dp * abs(sigma), 1.0e-8_dp * scale)
      if (moved == sigma) moved = sigma - max(abs(sigma), 1.0_dp) * 1.0e-4_dp
   end function moved_shift

end submodule ffrf_modes_shift_invert_factorise
