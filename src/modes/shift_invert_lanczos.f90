!> Implementation of the shift-invert Lanczos solver of ffrf_modes_shift_invert: KKT assembly,
!> MUMPS factorisation with the SPD/indefinite choice and shift retry, the ARPACK reverse
!> communication loop, and the normalisation and checks of the eigenpairs.
submodule (ffrf_modes_shift_invert) ffrf_modes_shift_invert_lanczos
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_error, only: fatal_error, add_context, FFRF_INPUT_ERROR, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: wall_time
   use ffrf_core_interrupt, only: interrupt_t
   use ffrf_core_posix, only: signal_test_point
   use ffrf_la_sparse, only: csr_add, csr_upper_coo, csr_matvec, csr_row_gram
   use ffrf_la_mumps, only: mumps_solver_t, mumps_ordering_name, MUMPS_SYM_SPD, &
      MUMPS_SYM_INDEFINITE
   use ffrf_la_arpack, only: dsaupd, dseupd
   use ffrf_core_serial_section, only: enter_serial_section, leave_serial_section, SECTION_ARPACK
   use ffrf_la_lapack, only: dgemm, dposv
   use ffrf_modes_block_krylov, only: block_krylov_settings_t, block_krylov_stats_t, &
      block_krylov_eigen, default_block_settings
   implicit none

   character(len=*), parameter :: stage = 'modes'

contains

   !> Sizes and settings. Without max_eigenvalue num_modes must leave room in the constrained
   !> dimension n - nc - num_rigid; with it num_modes is a cap (the smaller set wins).
   module subroutine check_input(K, M, C, options, num_rigid, n, nc, error)
      type(csr_t), intent(in) :: K, M, C
      type(eigen_options_t), intent(in) :: options
      integer(ip), intent(in) :: num_rigid
      integer(ip), intent(out) :: n, nc
      type(error_t), allocatable, intent(out) :: error
      integer(ip) :: dimension, ncv

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
      if (options%max_iterations < 1) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'shift-invert: max_iterations = ' // &
            to_str(options%max_iterations) // ', must be positive')
         return
      end if
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
      if (options%window_size < 1) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'shift-invert: window_size = ' // &
            to_str(options%window_size) // ', must be positive')
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
   end subroutine check_input

   !> Pattern of the KKT matrix: union pattern of K and M (upper triangle, csr_add keeps all
   !> entries whatever their value, so the pattern does not depend on sigma) and C^T scaled row
   !> by row to max|diag K| (toolchain.md pitfall 7; a row scaling keeps null(C)).
   module subroutine build_kkt(K, M, C, kkt, error)
      type(csr_t), intent(in) :: K, M, C
      type(kkt_t), intent(out) :: kkt
      type(error_t), allocatable, intent(out) :: error
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
   end subroutine build_kkt

   !> x of [[K, C^T], [C, 0]] [x; mu] = [0; t] for each column t of `targets`, with the factors
   !> of the KKT matrix at sigma = 0 (the scaled rows take scaled targets).
   module subroutine constraint_solve(solver, kkt, sigma, targets, solutions, error)
      type(mumps_solver_t), intent(inout) :: solver
      type(kkt_t), intent(in) :: kkt
      !> The shift of the factors (must still be 0 after any retry)
      real(dp), intent(in) :: sigma
      real(dp), intent(in) :: targets(:, :)
      real(dp), allocatable, intent(out) :: solutions(:, :)
      type(error_t), allocatable, intent(out) :: error
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
      if (allocated(error)) then
         call add_context(error, 'shift-invert, static solve with the KKT factors')
         return
      end if
      if (.not. all(ieee_is_finite(rhs))) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: NaN or Inf in the ' // &
            'static solve: K is singular on null(C)')
         return
      end if
      solutions = rhs(1:n, :)
   end subroutine constraint_solve

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
   module subroutine factorise_shifted(K, M, options, kkt, sigma, solver, result, log, error)
      type(csr_t), intent(in) :: K, M
      type(eigen_options_t), intent(in) :: options
      type(kkt_t), intent(inout) :: kkt
      real(dp), intent(inout) :: sigma
      type(mumps_solver_t), intent(inout) :: solver
      type(eigen_result_t), intent(inout) :: result
      type(logger_t), intent(in) :: log
      type(error_t), allocatable, intent(out) :: error
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
   end subroutine factorise_shifted

   !> Symmetric indefinite factorisation at s for its inertia (module header). The Sturm count
   !> of theory.md 5.3: eigenvalues below s = negative pivots - constraint rows.
   module subroutine factorise_count(K, M, options, kkt, s, low, high, solver, result, log, &
         error, count, record_analysis)
      type(csr_t), intent(in) :: K, M
      type(eigen_options_t), intent(in) :: options
      type(kkt_t), intent(inout) :: kkt
      !> Shift; moved inside (low, high) when it is numerically an eigenvalue
      real(dp), intent(inout) :: s
      !> Interval known to hold no eigenvalue near s (its ends may be eigenvalues)
      real(dp), intent(in) :: low, high
      type(mumps_solver_t), intent(inout) :: solver
      type(eigen_result_t), intent(inout) :: result
      type(logger_t), intent(in) :: log
      type(error_t), allocatable, intent(out) :: error
      !> Eigenvalues of the constrained problem below s
      integer(ip), intent(out) :: count
      !> A new analysis records its estimates in result
      logical, intent(in), optional :: record_analysis
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
   end subroutine factorise_count

   !> The permutation that sorts `values` ascending, equal values in their given order (stable
   !> insertion sort: a few dozen Rayleigh quotients).
   pure function ascending_order(values) result(order)
      real(dp), intent(in) :: values(:)
      integer(ip), allocatable :: order(:)
      integer :: i, j
      order = [(int(j, ip), j=1, size(values))]
      do j = 2, size(values)
         i = j
         do while (i > 1)
            if (values(order(i - 1)) <= values(order(i))) exit
            order([i - 1, i]) = order([i, i - 1])
            i = i - 1
         end do
      end do
   end function ascending_order

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
      solver%workspace_mb = eigen_workspace_mb(options, kkt%n, kkt%num_constraints)
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

   !> MB of the eigensolver's vectors while the factors live: ARPACK's basis (ncv), workd (3),
   !> resid, the Ritz vectors and the right-hand side; the block method's V and M V (basis +
   !> block each), the block, its M product, the right-hand sides and their copies in the
   !> solve (5 blocks) and the Ritz vectors. Those of one window (nev = min(num_modes,
   !> window_size)); with windows the deflated vectors and their M products on top (the six
   !> rigid ones and two windows). The returned vectors of a sliced run are not counted.
   pure function eigen_workspace_mb(options, n, nc) result(mb)
      type(eigen_options_t), intent(in) :: options
      integer(ip), intent(in) :: n, nc
      integer(i8) :: mb, columns
      integer(ip) :: nev
      type(block_krylov_settings_t) :: settings
      logical :: windows
      windows = options%max_eigenvalue > 0.0_dp .or. options%num_modes > options%window_size
      nev = options%num_modes
      if (windows) nev = min(options%num_modes, options%window_size) + window_guard(options)
      if (eigensolver_of(options, n, nc) == 'block') then
         settings = default_block_settings(nev, options%ncv, n - nc)
         columns = 2 * (settings%max_basis + settings%block_size) + 5 * settings%block_size + &
            nev
      else
         columns = arpack_basis_size(options, nev, n - nc) + 6 + nev
      end if
      if (windows) columns = columns + 2 * (6 + 2 * nev)
      mb = (8_i8 * int(n + nc, i8) * columns + 1048575_i8) / 1048576_i8
   end function eigen_workspace_mb

   !> ARPACK's ncv for nev wanted pairs: options%ncv when it exceeds nev, else max(2 nev + 1,
   !> 20), capped by the constrained dimension.
   pure integer(ip) function arpack_basis_size(options, nev, dimension) result(ncv)
      type(eigen_options_t), intent(in) :: options
      integer(ip), intent(in) :: nev, dimension
      if (options%ncv > nev .or. (options%ncv > 0 .and. nev == options%num_modes)) then
         ncv = options%ncv
      else
         ncv = max(2 * nev + 1, 20_ip)
      end if
      ncv = min(ncv, dimension)
   end function arpack_basis_size

   !> Guard eigenpairs computed above a window so that its upper boundary can sit in a gap of
   !> the spectrum: a tenth of the window, at least 2.
   pure integer(ip) function window_guard(options) result(guard)
      type(eigen_options_t), intent(in) :: options
      guard = max(2_ip, options%window_size / 10)
   end function window_guard

   !> 'block' for eigensolver = 'block', or 'auto' on a constrained dimension of
   !> AUTO_BLOCK_MIN_DOFS or more; else 'arpack'.
   pure module function eigensolver_of(options, n, nc) result(name)
      type(eigen_options_t), intent(in) :: options
      integer(ip), intent(in) :: n, nc
      character(len=:), allocatable :: name
      select case (options%eigensolver)
      case ('block')
         name = 'block'
      case ('arpack')
         name = 'arpack'
      case default
         name = merge('block ', 'arpack', n - nc >= AUTO_BLOCK_MIN_DOFS)
         name = trim(name)
      end select
   end function eigensolver_of

   !> One eigen solve on the current factors (module header of ffrf_modes_shift_invert).
   module subroutine eigen_window(K, M, options, eigensolver, nev, nc, sigma, solver, &
         interrupt, deflation, z, lambda, result, log, error)
      type(csr_t), intent(in) :: K, M
      type(eigen_options_t), intent(in) :: options
      character(len=*), intent(in) :: eigensolver
      integer(ip), intent(in) :: nev, nc
      real(dp), intent(in) :: sigma
      type(mumps_solver_t), intent(inout) :: solver
      type(interrupt_t), intent(in) :: interrupt
      type(deflation_t), intent(in) :: deflation
      real(dp), allocatable, intent(out) :: z(:, :), lambda(:)
      type(eigen_result_t), intent(inout) :: result
      type(logger_t), intent(in) :: log
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: x(:), kx(:), mx(:), norms(:), raw(:, :)
      integer(ip), allocatable :: order(:)
      integer(i8) :: solves_before
      real(dp) :: time_before
      integer(ip) :: n, j, dimension, ncv
      n = M%num_rows
      solves_before = solver%num_solves
      time_before = solver%time_solve
      dimension = n - nc
      if (allocated(deflation%X)) dimension = dimension - int(size(deflation%X, 2), ip)
      ! 'block if possible' (a recovery): the block method when its sizes fit, else ARPACK;
      ! 'block' as asked refuses a problem too small for it (block_krylov_eigen's message)
      if (eigensolver == 'block' .or. (eigensolver == 'block if possible' .and. &
          block_fits(nev, options%ncv, dimension))) then
         call block_lanczos(M, options, nev, nc, solver, interrupt, deflation, z, result, log, &
            error)
      else
         ncv = arpack_basis_size(options, nev, dimension)
         if (ncv <= nev) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'shift-invert: ncv = ' // to_str(ncv) // &
               ' must exceed ' // to_str(nev) // ' wanted pairs; raise ncv (about twice the ' // &
               'wanted pairs, at most n - num_constraints = ' // to_str(dimension) // ')')
            return
         end if
         result%ncv = ncv
         call lanczos(M, options, nev, ncv, nc, sigma, solver, interrupt, deflation, z, result, &
            log, error)
      end if
      result%num_solves = result%num_solves + (solver%num_solves - solves_before)
      result%time_solves = result%time_solves + (solver%time_solve - time_before)
      if (allocated(error)) return
      if (allocated(deflation%X)) then
         ! what the last projection removes: the round-off the eigen loop let into the basis
         norms = [(norm2(z(:, j)), j=1, nev)]
         raw = z
         call project_deflation(deflation, z)
         call log%debug(stage, 'deflated components removed from the Ritz vectors: ' // &
            to_str(maxval([(norm2(raw(:, j) - z(:, j)) / max(norms(j), tiny(1.0_dp)), &
            j=1, nev)]), 2) // ' of their norm at most')
      end if
      ! Rayleigh quotients of normalised copies (z itself stays as the eigensolver returned it)
      allocate (x(n), kx(n), mx(n), lambda(nev))
      do j = 1, nev
         call csr_matvec(M, z(:, j), mx)
         call csr_matvec(K, z(:, j), kx)
         lambda(j) = dot_product(z(:, j), kx) / max(dot_product(z(:, j), mx), tiny(1.0_dp))
      end do
      order = ascending_order(lambda)
      lambda = lambda(order)
      z = z(:, order)
   end subroutine eigen_window

   !> The block method's default sizes fit nev pairs in the dimension (else ARPACK is used).
   pure logical function block_fits(nev, basis, dimension)
      integer(ip), intent(in) :: nev, basis, dimension
      type(block_krylov_settings_t) :: settings
      settings = default_block_settings(nev, basis, dimension)
      block_fits = settings%block_size >= 1 .and. settings%max_basis >= nev + &
         settings%block_size .and. settings%kept >= nev .and. settings%kept + &
         settings%block_size <= settings%max_basis .and. settings%max_basis + &
         settings%block_size <= dimension
   end function block_fits

   !> y = y - X (M X)^T y, twice.
   module subroutine project_deflation(deflation, y)
      type(deflation_t), intent(in) :: deflation
      real(dp), intent(inout) :: y(:, :)
      real(dp), allocatable :: coefficients(:, :)
      integer(ip) :: n, d, m, pass
      if (.not. allocated(deflation%X)) return
      n = int(size(y, 1), ip)
      d = int(size(deflation%X, 2), ip)
      m = int(size(y, 2), ip)
      if (d == 0 .or. m == 0) return
      allocate (coefficients(d, m))
      do pass = 1, 2
         call dgemm('T', 'N', d, m, n, 1.0_dp, deflation%MX, n, y, n, 0.0_dp, coefficients, d)
         call dgemm('N', 'N', n, m, d, -1.0_dp, deflation%X, n, coefficients, d, 1.0_dp, y, n)
      end do
   end subroutine project_deflation

   !> y = y - X (M X)^T y for one vector, twice (the ARPACK loop).
   subroutine project_vector(deflation, y)
      type(deflation_t), intent(in) :: deflation
      real(dp), contiguous, intent(inout) :: y(:)
      real(dp), allocatable :: coefficients(:)
      integer(ip) :: n, d, pass
      n = int(size(y), ip)
      d = int(size(deflation%X, 2), ip)
      if (d == 0) return
      allocate (coefficients(d))
      do pass = 1, 2
         call dgemm('T', 'N', d, 1_ip, n, 1.0_dp, deflation%MX, n, y, n, 0.0_dp, coefficients, d)
         call dgemm('N', 'N', n, 1_ip, d, -1.0_dp, deflation%X, n, coefficients, d, 1.0_dp, y, n)
      end do
   end subroutine project_vector

   !> Block shift-invert Lanczos (ffrf_modes_block_krylov) on the KKT factors; Ritz vectors z.
   subroutine block_lanczos(M, options, nev, nc, solver, interrupt, deflation, z, result, log, &
         error)
      type(csr_t), intent(in) :: M
      type(eigen_options_t), intent(in) :: options
      integer(ip), intent(in) :: nev, nc
      type(mumps_solver_t), intent(inout) :: solver
      !> Checked before every block solve
      type(interrupt_t), intent(in) :: interrupt
      type(deflation_t), intent(in) :: deflation
      real(dp), allocatable, intent(out) :: z(:, :)
      type(eigen_result_t), intent(inout) :: result
      type(logger_t), intent(in) :: log
      type(error_t), allocatable, intent(out) :: error
      type(block_krylov_settings_t) :: settings
      type(block_krylov_stats_t) :: stats
      integer(ip) :: dimension
      dimension = M%num_rows - nc
      if (allocated(deflation%X)) dimension = dimension - int(size(deflation%X, 2), ip)
      settings = default_block_settings(nev, options%ncv, dimension)
      result%eigensolver = 'block'
      result%block_size = settings%block_size
      result%ncv = settings%max_basis
      if (allocated(deflation%X)) then
         call block_krylov_eigen(M, nc, nev, settings, options%tolerance, &
            options%max_iterations, solver, z, stats, log, error, interrupt, deflation%X, &
            deflation%MX)
      else
         call block_krylov_eigen(M, nc, nev, settings, options%tolerance, &
            options%max_iterations, solver, z, stats, log, error, interrupt)
      end if
      result%num_iterations = result%num_iterations + stats%num_restarts
      result%num_block_solves = result%num_block_solves + stats%num_block_solves
   end subroutine block_lanczos

   !> ARPACK dsaupd/dseupd, mode 3 with B = M, OP by KKT solves; Ritz vectors z (n x nev).
   !> ARPACK keeps its reverse-communication state in SAVEd variables: one eigenproblem at a
   !> time in the process (a serial section), so that distinct handles may run in threads.
   subroutine lanczos(M, options, nev, ncv, nc, sigma, solver, interrupt, deflation, z, result, &
         log, error)
      type(csr_t), intent(in) :: M
      type(eigen_options_t), intent(in) :: options
      integer(ip), intent(in) :: nev, ncv, nc
      real(dp), intent(in) :: sigma
      type(mumps_solver_t), intent(inout) :: solver
      !> Checked before every solve
      type(interrupt_t), intent(in) :: interrupt
      !> Deflated subspace (rigid modes, modes of earlier windows); none when X is unallocated
      type(deflation_t), intent(in) :: deflation
      real(dp), allocatable, intent(out) :: z(:, :)
      type(eigen_result_t), intent(inout) :: result
      type(logger_t), intent(in) :: log
      type(error_t), allocatable, intent(out) :: error
      call enter_serial_section(SECTION_ARPACK)
      call lanczos_in_section(M, options, nev, ncv, nc, sigma, solver, interrupt, deflation, z, &
         result, log, error)
      call leave_serial_section(SECTION_ARPACK)
   end subroutine lanczos

   !> lanczos inside the ARPACK serial section.
   subroutine lanczos_in_section(M, options, nev, ncv, nc, sigma, solver, interrupt, deflation, &
         z, result, log, error)
      type(csr_t), intent(in) :: M
      type(eigen_options_t), intent(in) :: options
      integer(ip), intent(in) :: nev, ncv, nc
      real(dp), intent(in) :: sigma
      type(mumps_solver_t), intent(inout) :: solver
      type(interrupt_t), intent(in) :: interrupt
      type(deflation_t), intent(in) :: deflation
      real(dp), allocatable, intent(out) :: z(:, :)
      type(eigen_result_t), intent(inout) :: result
      type(logger_t), intent(in) :: log
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: resid(:), v(:, :), workd(:), workl(:), rhs(:), d(:)
      logical, allocatable :: selected(:)
      integer(ip) :: iparam(11), ipntr(11), ido, info, lworkl, n, x0, y0, stat
      real(dp) :: tol
      logical :: deflating

      n = M%num_rows
      deflating = allocated(deflation%X)
      lworkl = ncv * (ncv + 8)
      allocate (resid(n), v(n, ncv), workd(3 * n), workl(lworkl), selected(ncv), d(nev), &
                z(n, nev), rhs(n + nc), stat=stat)
      if (stat /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: cannot allocate the ' // &
            'Lanczos basis of ' // to_str(n) // ' x ' // to_str(ncv))
         return
      end if
      call start_vector(resid)
      if (deflating) call project_vector(deflation, resid)
      tol = options%tolerance
      iparam = 0
      iparam(1) = 1                       ! exact shifts
      iparam(3) = options%max_iterations
      iparam(4) = 1                       ! block size (must be 1)
      iparam(7) = 3                       ! shift-invert mode
      ipntr = 0
      ido = 0
      info = 1                            ! resid holds the start vector
      call signal_test_point('lanczos:before')
      do
         call dsaupd(ido, 'G', n, 'LM', nev, tol, resid, ncv, v, n, iparam, ipntr, workd, &
                     workl, lworkl, info)
         x0 = ipntr(1)
         y0 = ipntr(2)
         select case (ido)
         case (-1)                        ! y = OP x = (K - sigma M)^-1 M x on null(C)
            call check_interrupt(error)
            if (allocated(error)) return
            call csr_matvec(M, workd(x0:x0 + n - 1), rhs(1:n))
            call kkt_solve(solver, rhs, n, error)
            if (allocated(error)) return
            if (deflating) call project_vector(deflation, rhs(1:n))
            workd(y0:y0 + n - 1) = rhs(1:n)
         case (1)                         ! M x is in workd(ipntr(3))
            call check_interrupt(error)
            if (allocated(error)) return
            rhs(1:n) = workd(ipntr(3):ipntr(3) + n - 1)
            call kkt_solve(solver, rhs, n, error)
            if (allocated(error)) return
            if (deflating) call project_vector(deflation, rhs(1:n))
            workd(y0:y0 + n - 1) = rhs(1:n)
         case (2)                         ! y = M x
            call csr_matvec(M, workd(x0:x0 + n - 1), workd(y0:y0 + n - 1))
         case (99)
            exit
         case default
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: ARPACK dsaupd ' // &
               'asked for ido = ' // to_str(ido) // ' (not used in mode 3)')
            return
         end select
      end do
      call signal_test_point('lanczos:after')
      result%num_iterations = result%num_iterations + iparam(3)
      call log%debug(stage, 'dsaupd: info = ' // to_str(info) // ', ' // to_str(iparam(5)) // &
         ' converged, ' // to_str(iparam(9)) // ' OP, ' // to_str(iparam(10)) // ' B, ' // &
         to_str(iparam(11)) // ' reorthogonalisation steps')
      if (info /= 0 .or. iparam(5) < nev) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: ' // &
            dsaupd_message(info, iparam(5), nev, ncv, options%max_iterations, n))
         return
      end if

      info = 0
      call dseupd(.true., 'A', selected, d, z, n, sigma, 'G', n, 'LM', nev, tol, resid, ncv, v, &
                  n, iparam, ipntr, workd, workl, lworkl, info)
      if (info /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: ARPACK dseupd info = ' // &
            to_str(info) // ': ' // dseupd_message(info))
         return
      end if

   contains

      subroutine check_interrupt(error)
         type(error_t), allocatable, intent(out) :: error
         if (solver%num_solves == 5) call signal_test_point('lanczos:during')
         call interrupt%check('in the eigen loop (ARPACK) after ' // &
            to_str(solver%num_solves) // ' solves', error)
      end subroutine check_interrupt

   end subroutine lanczos_in_section

   !> rhs(1:n) = M x on entry -> y on exit: solve (5.2b) with zero constraint right-hand side.
   subroutine kkt_solve(solver, rhs, n, error)
      type(mumps_solver_t), intent(inout) :: solver
      real(dp), intent(inout) :: rhs(:)
      integer(ip), intent(in) :: n
      type(error_t), allocatable, intent(out) :: error
      rhs(n + 1:) = 0.0_dp
      call solver%solve(rhs, error)
      if (allocated(error)) then
         call add_context(error, 'shift-invert, Lanczos solve')
         return
      end if
      if (.not. all(ieee_is_finite(rhs(1:n)))) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: the KKT solve returned ' &
            // 'NaN or Inf; K - sigma M is (nearly) singular: move sigma')
      end if
   end subroutine kkt_solve

   !> Deterministic start vector in (-0.5, 0.5): Park-Miller minimal standard generator
   !> x <- 16807 x mod (2^31 - 1) from a fixed seed, so identical runs give identical output.
   subroutine start_vector(resid)
      real(dp), intent(out) :: resid(:)
      integer(i8), parameter :: modulus = 2147483647_i8, multiplier = 16807_i8
      integer(i8) :: state
      integer :: i
      state = 20240611_i8
      do i = 1, size(resid)
         state = mod(multiplier * state, modulus)
         resid(i) = real(state, dp) / real(modulus, dp) - 0.5_dp
      end do
   end subroutine start_vector

   !> Normalise (x^T M x = 1), Rayleigh quotients, sort ascending, residuals (projected onto
   !> null(C)) and M-orthonormality; fills result%eigenvalues/vectors/residuals.
   module subroutine finish_pairs(K, M, C, z, result, error)
      type(csr_t), intent(in) :: K, M, C
      real(dp), intent(inout) :: z(:, :)
      type(eigen_result_t), intent(inout) :: result
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: Kx(:, :), Mx(:, :), lambda(:), gram(:, :), r(:, :)
      integer(ip), allocatable :: order(:)
      real(dp) :: xMx, scale, denominator
      integer(ip) :: n, nev, j, stat

      n = size(z, 1)
      nev = size(z, 2)
      allocate (Kx(n, nev), Mx(n, nev), lambda(nev), gram(nev, nev), r(n, 2 * nev), stat=stat)
      if (stat /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: cannot allocate ' // &
            'the residual work arrays (' // to_str(n) // ' x ' // to_str(3 * nev) // ')')
         return
      end if
      do j = 1, nev
         call csr_matvec(M, z(:, j), Mx(:, j))
         xMx = dot_product(z(:, j), Mx(:, j))
         if (.not. (xMx > 0.0_dp) .or. .not. ieee_is_finite(xMx)) then
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: Ritz vector ' // &
               to_str(j) // ' has x^T M x = ' // to_str(xMx) // '; M must be positive ' // &
               'definite on null(C)')
            return
         end if
         scale = 1.0_dp / sqrt(xMx)
         z(:, j) = z(:, j) * scale
         Mx(:, j) = Mx(:, j) * scale
         call csr_matvec(K, z(:, j), Kx(:, j))
         lambda(j) = dot_product(z(:, j), Kx(:, j))
      end do

      order = ascending_order(lambda)
      result%num_modes = nev
      result%eigenvalues = lambda(order)
      result%vectors = z(:, order)
      Kx = Kx(:, order)
      Mx = Mx(:, order)

      ! Residuals K x - lambda M x and K x, both projected onto null(C).
      do j = 1, nev
         r(:, j) = Kx(:, j) - result%eigenvalues(j) * Mx(:, j)
         r(:, nev + j) = Kx(:, j)
      end do
      if (C%num_rows > 0) then
         call project_null_space(C, r, error)
         if (allocated(error)) return
      end if
      allocate (result%residuals(nev))
      do j = 1, nev
         denominator = max(norm2(r(:, nev + j)), abs(result%shift) * norm2(Mx(:, j)), &
                           tiny(1.0_dp))
         result%residuals(j) = norm2(r(:, j)) / denominator
      end do

      ! M-orthonormality: X^T (M X) - I.
      call dgemm('T', 'N', nev, nev, n, 1.0_dp, result%vectors, n, Mx, n, 0.0_dp, gram, nev)
      do j = 1, nev
         gram(j, j) = gram(j, j) - 1.0_dp
      end do
      result%orthonormality_error = maxval(abs(gram))
      if (.not. all(ieee_is_finite(result%eigenvalues)) .or. &
          .not. all(ieee_is_finite(result%residuals))) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: NaN or Inf in the ' // &
            'eigenpairs; K - sigma M is (nearly) singular: move sigma')
      end if
   end subroutine finish_pairs

   !> Columns of r replaced by their orthogonal projection P r = r - C^T (C C^T)^-1 C r onto
   !> null(C). C has a handful of rows (reference conditions), so C C^T is a small dense matrix,
   !> solved by Cholesky (LAPACK dposv) after scaling the rows to unit norm.
   module subroutine project_null_space(C, r, error)
      !> Constraint rows, full row rank
      type(csr_t), intent(in) :: C
      !> Vectors as columns (C%num_cols rows), projected in place
      real(dp), intent(inout) :: r(:, :)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: gram(:, :), cr(:, :), row_norm(:)
      integer(ip) :: nc, i, p, info
      nc = C%num_rows
      call csr_row_gram(C, gram, row_norm)
      allocate (cr(nc, size(r, 2)))
      ! C r with the normalised rows.
      cr = 0.0_dp
      do i = 1, nc
         do p = C%row_ptr(i), C%row_ptr(i + 1) - 1
            cr(i, :) = cr(i, :) + C%val(p) / row_norm(i) * r(C%col(p), :)
         end do
      end do
      call dposv('U', nc, int(size(r, 2), ip), gram, nc, cr, nc, info)
      if (info /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert, residual projection onto ' &
            // 'null(C): the constraint rows are linearly dependent (dposv info = ' // &
            to_str(info) // ')')
         return
      end if
      ! r -= C^T mu
      do i = 1, nc
         do p = C%row_ptr(i), C%row_ptr(i + 1) - 1
            r(C%col(p), :) = r(C%col(p), :) - C%val(p) / row_norm(i) * cr(i, :)
         end do
      end do
   end subroutine project_null_space

   !> Text for a dsaupd failure: info /= 0 or fewer converged values than wanted.
   function dsaupd_message(info, nconv, nev, ncv, max_iterations, n) result(text)
      integer(ip), intent(in) :: info, nconv, nev, ncv, max_iterations, n
      character(len=:), allocatable :: text
      select case (info)
      case (0, 1)
         text = 'ARPACK dsaupd converged ' // to_str(nconv) // ' of ' // to_str(nev) // &
            ' eigenvalues in max_iterations = ' // to_str(max_iterations) // ' restarts (info = ' &
            // to_str(info) // '); raise max_iterations or ncv (now ' // to_str(ncv) // &
            '), or put sigma nearer the wanted eigenvalues'
      case (3)
         text = 'ARPACK dsaupd info = 3: no shifts could be applied during a restart; ' // &
            'raise ncv (now ' // to_str(ncv) // ', n = ' // to_str(n) // ')'
      case (-1)
         text = 'ARPACK dsaupd info = -1: n = ' // to_str(n) // ' must be positive'
      case (-2)
         text = 'ARPACK dsaupd info = -2: num_modes = ' // to_str(nev) // ' must be positive'
      case (-3)
         text = 'ARPACK dsaupd info = -3: need num_modes < ncv <= n; num_modes = ' // &
            to_str(nev) // ', ncv = ' // to_str(ncv) // ', n = ' // to_str(n)
      case (-4)
         text = 'ARPACK dsaupd info = -4: max_iterations = ' // to_str(max_iterations) // &
            ' must be positive'
      case (-8)
         text = 'ARPACK dsaupd info = -8: the tridiagonal eigenvalue computation (LAPACK ' // &
            'dsteqr) failed; raise ncv or change sigma'
      case (-9)
         text = 'ARPACK dsaupd info = -9: the start vector is zero in the range of OP; ' // &
            'all of R^n is constrained or M is zero on null(C)'
      case (-9999)
         text = 'ARPACK dsaupd info = -9999: could not build a Lanczos factorisation of ' // &
            'size ncv = ' // to_str(ncv) // ' (invariant subspace of dimension ' // &
            to_str(nconv) // '); lower ncv or num_modes'
      case default
         text = 'ARPACK dsaupd info = ' // to_str(info) // ': invalid argument (ARPACK-NG ' // &
            'SRC/dsaupd.f lists the codes)'
      end select
   end function dsaupd_message

   !> Text for a dseupd failure.
   function dseupd_message(info) result(text)
      integer(ip), intent(in) :: info
      character(len=:), allocatable :: text
      select case (info)
      case (-8)
         text = 'the Ritz values of the tridiagonal matrix could not be computed (LAPACK ' // &
            'dsteqr); raise ncv or change sigma'
      case (-9)
         text = 'the tridiagonal eigenvector computation (LAPACK dsteqr) failed; raise ncv'
      case (-14)
         text = 'dsaupd found no eigenvalue to sufficient accuracy; raise max_iterations ' // &
            'or ncv'
      case (-17)
         text = 'dseupd counted a different number of converged Ritz values than dsaupd; ' // &
            'raise ncv or loosen tolerance'
      case default
         text = 'invalid argument (ARPACK-NG SRC/dseupd.f lists the codes)'
      end select
   end function dseupd_message

end submodule ffrf_modes_shift_invert_lanczos
