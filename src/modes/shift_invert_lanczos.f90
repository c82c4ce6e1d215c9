!> Implementation of the shift-invert Lanczos solver of ffrf_modes_shift_invert: KKT assembly,
!> MUMPS factorisation with the SPD/indefinite choice and shift retry, the ARPACK reverse
!> communication loop, and the normalisation and checks of the eigenpairs.
submodule (ffrf_modes_shift_invert) ffrf_modes_shift_invert_lanczos
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_error, only: fatal_error, add_context, FFRF_INPUT_ERROR, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: wall_time
   use ffrf_core_interrupt, only: interrupt_t
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

   !> KKT matrix (5.2b) in MUMPS coordinate form: upper triangle of K - sigma M followed by the
   !> scaled C^T block in rows 1..n, columns n+1..n+num_constraints.
   type :: kkt_t
      integer(ip) :: n = 0
      integer(ip) :: num_constraints = 0
      integer(ip), allocatable :: irn(:), jcn(:)
      real(dp), allocatable :: val(:)
      !> Entries of the K - sigma M part (the first num_upper of irn/jcn/val)
      integer(i8) :: num_upper = 0
      !> Scale of each constraint row in the matrix (max|diag K| / max|C_r|)
      real(dp), allocatable :: row_scale(:)
   end type kkt_t

contains

   !> Eigenpairs of K x = lambda M x, C x = 0 nearest options%sigma (shift-invert Lanczos).
   module subroutine solve_shift_invert(K, M, C, options, result, log, error, &
         constraint_targets, constraint_solutions)
      !> Stiffness matrix, n x n, symmetric, both triangles stored
      type(csr_t), intent(in) :: K
      !> Mass matrix, n x n, symmetric, both triangles, positive definite on null(C)
      type(csr_t), intent(in) :: M
      !> Constraint matrix, num_constraints x n, full row rank; may have no rows
      type(csr_t), intent(in) :: C
      !> Number of modes, shift and solver settings
      type(eigen_options_t), intent(in) :: options
      !> Eigenpairs and statistics
      type(eigen_result_t), intent(out) :: result
      !> Progress log
      type(logger_t), intent(in) :: log
      type(error_t), allocatable, intent(out) :: error
      !> Right-hand sides t of C x = t, (num_constraints, nrhs); needs sigma = 0
      real(dp), intent(in), optional :: constraint_targets(:, :)
      !> Solutions x, (n, nrhs), when constraint_targets is given
      real(dp), allocatable, intent(out), optional :: constraint_solutions(:, :)
      type(kkt_t) :: kkt
      type(mumps_solver_t) :: solver
      type(interrupt_t) :: interrupt
      real(dp) :: t_start, t0, sigma
      real(dp), allocatable :: z(:, :)
      character(len=:), allocatable :: method
      integer(ip) :: n, nc, ncv, j

      t_start = wall_time()
      call check_input(K, M, C, options, n, nc, ncv, error)
      if (allocated(error)) return
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
      result%ncv = ncv
      if (uses_block_method(options, n, nc)) then
         method = 'block method'
      else
         method = 'ncv = ' // to_str(ncv)
      end if
      call log%info(stage, 'shift-invert Lanczos: n = ' // to_str(n) // ', ' // to_str(nc) // &
         ' constraints, ' // to_str(options%num_modes) // ' modes nearest sigma = ' // &
         to_str(options%sigma) // ', ' // method)

      ! One factorisation of the KKT matrix (with fallbacks), then Lanczos on it.
      sigma = options%sigma
      call build_kkt(K, M, C, kkt, error)
      if (allocated(error)) return
      call factorise_shifted(K, M, options, kkt, sigma, solver, result, log, error)
      ! a signal received during the (uninterruptible) analysis and factorisation stops here;
      ! later ones at the eigen loop's checks
      interrupt = interrupt_t(enabled=options%stop_on_signal, ranks=options%parallel)
      if (.not. allocated(error)) call interrupt%check('after the MUMPS factorisation', error)
      if (allocated(error)) then
         call solver%free()
         return
      end if
      result%shift = sigma

      t0 = wall_time()
      if (uses_block_method(options, n, nc)) then
         call block_lanczos(M, options, nc, solver, interrupt, z, result, log, error)
      else
         result%eigensolver = 'arpack'
         call lanczos(M, options, ncv, nc, sigma, solver, interrupt, z, result, log, error)
      end if
      result%time_lanczos = wall_time() - t0
      if (.not. allocated(error) .and. present(constraint_targets)) then
         t0 = wall_time()
         call constraint_solve(solver, kkt, sigma, constraint_targets, constraint_solutions, &
            error)
         result%time_constraint_solves = wall_time() - t0
      end if
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
   end subroutine solve_shift_invert

   !> Sizes and settings; ncv from options (default max(2 nev + 1, 20)) capped by n - nc.
   subroutine check_input(K, M, C, options, n, nc, ncv, error)
      type(csr_t), intent(in) :: K, M, C
      type(eigen_options_t), intent(in) :: options
      integer(ip), intent(out) :: n, nc, ncv
      type(error_t), allocatable, intent(out) :: error
      integer(ip) :: dimension

      n = K%num_rows
      nc = C%num_rows
      ncv = 0
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
      dimension = n - nc
      if (options%num_modes < 1 .or. options%num_modes >= dimension) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'shift-invert: num_modes = ' // &
            to_str(options%num_modes) // ' must lie in 1 .. ' // to_str(dimension - 1) // &
            ' (n - num_constraints - 1 = ' // to_str(n) // ' - ' // to_str(nc) // &
            ' - 1); use a dense solver for so small a problem')
         return
      end if
      if (options%max_iterations < 1) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'shift-invert: max_iterations = ' // &
            to_str(options%max_iterations) // ', must be positive')
         return
      end if
      if (.not. ieee_is_finite(options%sigma)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'shift-invert: sigma is not finite')
         return
      end if
      ncv = arpack_basis_size(options, dimension)
      if (ncv <= options%num_modes) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'shift-invert: ncv = ' // to_str(ncv) // &
            ' must exceed num_modes = ' // to_str(options%num_modes) // &
            '; raise ncv (about 2 num_modes, at most n - num_constraints = ' // &
            to_str(dimension) // ')')
         return
      end if
   end subroutine check_input

   !> Pattern of the KKT matrix: union pattern of K and M (upper triangle, csr_add keeps all
   !> entries whatever their value, so the pattern does not depend on sigma) and C^T scaled row
   !> by row to max|diag K| (toolchain.md pitfall 7; a row scaling keeps null(C)).
   subroutine build_kkt(K, M, C, kkt, error)
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
   subroutine constraint_solve(solver, kkt, sigma, targets, solutions, error)
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
   subroutine factorise_shifted(K, M, options, kkt, sigma, solver, result, log, error)
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
         call shift_values(K, M, sigma, kkt, error)
         if (allocated(error)) return
         call solver%factorise(kkt%val, error)
         result%num_factorisations = result%num_factorisations + 1
         singular = .false.
         if (allocated(error)) then
            if (solver%status /= -10) then
               call add_context(error, 'shift-invert at sigma = ' // to_str(sigma, 12))
               return
            end if
            singular = .true.
            deallocate (error)
         end if
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
   !> solve (5 blocks) and the Ritz vectors.
   pure function eigen_workspace_mb(options, n, nc) result(mb)
      type(eigen_options_t), intent(in) :: options
      integer(ip), intent(in) :: n, nc
      integer(i8) :: mb, columns
      type(block_krylov_settings_t) :: settings
      if (uses_block_method(options, n, nc)) then
         settings = default_block_settings(options%num_modes, options%ncv, n - nc)
         columns = 2 * (settings%max_basis + settings%block_size) + 5 * settings%block_size + &
            options%num_modes
      else
         columns = arpack_basis_size(options, n - nc) + 6 + options%num_modes
      end if
      mb = (8_i8 * int(n + nc, i8) * columns + 1048575_i8) / 1048576_i8
   end function eigen_workspace_mb

   !> ARPACK's ncv: options%ncv, else max(2 num_modes + 1, 20), capped by the constrained
   !> dimension n - nc.
   pure integer(ip) function arpack_basis_size(options, dimension) result(ncv)
      type(eigen_options_t), intent(in) :: options
      integer(ip), intent(in) :: dimension
      if (options%ncv > 0) then
         ncv = options%ncv
      else
         ncv = max(2 * options%num_modes + 1, 20_ip)
      end if
      ncv = min(ncv, dimension)
   end function arpack_basis_size

   !> eigensolver = 'block', or 'auto' on a constrained dimension of AUTO_BLOCK_MIN_DOFS or more.
   pure logical function uses_block_method(options, n, nc)
      type(eigen_options_t), intent(in) :: options
      integer(ip), intent(in) :: n, nc
      select case (options%eigensolver)
      case ('block')
         uses_block_method = .true.
      case ('arpack')
         uses_block_method = .false.
      case default
         uses_block_method = n - nc >= AUTO_BLOCK_MIN_DOFS
      end select
   end function uses_block_method

   !> Block shift-invert Lanczos (ffrf_modes_block_krylov) on the KKT factors; Ritz vectors z.
   subroutine block_lanczos(M, options, nc, solver, interrupt, z, result, log, error)
      type(csr_t), intent(in) :: M
      type(eigen_options_t), intent(in) :: options
      integer(ip), intent(in) :: nc
      type(mumps_solver_t), intent(inout) :: solver
      !> Checked before every block solve
      type(interrupt_t), intent(in) :: interrupt
      real(dp), allocatable, intent(out) :: z(:, :)
      type(eigen_result_t), intent(inout) :: result
      type(logger_t), intent(in) :: log
      type(error_t), allocatable, intent(out) :: error
      type(block_krylov_settings_t) :: settings
      type(block_krylov_stats_t) :: stats
      settings = default_block_settings(options%num_modes, options%ncv, M%num_rows - nc)
      result%eigensolver = 'block'
      result%block_size = settings%block_size
      result%ncv = settings%max_basis
      call block_krylov_eigen(M, nc, options%num_modes, settings, options%tolerance, &
         options%max_iterations, solver, z, stats, log, error, interrupt)
      result%num_solves = solver%num_solves
      result%time_solves = solver%time_solve
      result%num_iterations = stats%num_restarts
      result%num_block_solves = stats%num_block_solves
   end subroutine block_lanczos

   !> ARPACK dsaupd/dseupd, mode 3 with B = M, OP by KKT solves; Ritz vectors z (n x nev).
   !> ARPACK keeps its reverse-communication state in SAVEd variables: one eigenproblem at a
   !> time in the process (a serial section), so that distinct handles may run in threads.
   subroutine lanczos(M, options, ncv, nc, sigma, solver, interrupt, z, result, log, error)
      type(csr_t), intent(in) :: M
      type(eigen_options_t), intent(in) :: options
      integer(ip), intent(in) :: ncv, nc
      real(dp), intent(in) :: sigma
      type(mumps_solver_t), intent(inout) :: solver
      !> Checked before every solve
      type(interrupt_t), intent(in) :: interrupt
      real(dp), allocatable, intent(out) :: z(:, :)
      type(eigen_result_t), intent(inout) :: result
      type(logger_t), intent(in) :: log
      type(error_t), allocatable, intent(out) :: error
      call enter_serial_section(SECTION_ARPACK)
      call lanczos_in_section(M, options, ncv, nc, sigma, solver, interrupt, z, result, log, &
         error)
      call leave_serial_section(SECTION_ARPACK)
   end subroutine lanczos

   !> lanczos inside the ARPACK serial section.
   subroutine lanczos_in_section(M, options, ncv, nc, sigma, solver, interrupt, z, result, &
         log, error)
      type(csr_t), intent(in) :: M
      type(eigen_options_t), intent(in) :: options
      integer(ip), intent(in) :: ncv, nc
      real(dp), intent(in) :: sigma
      type(mumps_solver_t), intent(inout) :: solver
      type(interrupt_t), intent(in) :: interrupt
      real(dp), allocatable, intent(out) :: z(:, :)
      type(eigen_result_t), intent(inout) :: result
      type(logger_t), intent(in) :: log
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: resid(:), v(:, :), workd(:), workl(:), rhs(:), d(:)
      logical, allocatable :: selected(:)
      integer(ip) :: iparam(11), ipntr(11), ido, info, lworkl, n, nev, x0, y0, stat
      real(dp) :: tol

      n = M%num_rows
      nev = options%num_modes
      lworkl = ncv * (ncv + 8)
      allocate (resid(n), v(n, ncv), workd(3 * n), workl(lworkl), selected(ncv), d(nev), &
                z(n, nev), rhs(n + nc), stat=stat)
      if (stat /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: cannot allocate the ' // &
            'Lanczos basis of ' // to_str(n) // ' x ' // to_str(ncv))
         return
      end if
      call start_vector(resid)
      tol = options%tolerance
      iparam = 0
      iparam(1) = 1                       ! exact shifts
      iparam(3) = options%max_iterations
      iparam(4) = 1                       ! block size (must be 1)
      iparam(7) = 3                       ! shift-invert mode
      ipntr = 0
      ido = 0
      info = 1                            ! resid holds the start vector
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
            workd(y0:y0 + n - 1) = rhs(1:n)
         case (1)                         ! M x is in workd(ipntr(3))
            call check_interrupt(error)
            if (allocated(error)) return
            rhs(1:n) = workd(ipntr(3):ipntr(3) + n - 1)
            call kkt_solve(solver, rhs, n, error)
            if (allocated(error)) return
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
      result%num_solves = solver%num_solves
      result%time_solves = solver%time_solve
      result%num_iterations = iparam(3)
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
   subroutine finish_pairs(K, M, C, z, result, error)
      type(csr_t), intent(in) :: K, M, C
      real(dp), intent(inout) :: z(:, :)
      type(eigen_result_t), intent(inout) :: result
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: Kx(:, :), Mx(:, :), lambda(:), gram(:, :), r(:, :)
      integer(ip), allocatable :: order(:)
      real(dp) :: xMx, scale, denominator
      integer(ip) :: n, nev, j, i, stat

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

      ! Ascending order of the Rayleigh quotients (stable insertion sort, nev is small).
      order = [(j, j=1, nev)]
      do j = 2, nev
         i = j
         do while (i > 1)
            if (lambda(order(i - 1)) <= lambda(order(i))) exit
            order([i - 1, i]) = order([i, i - 1])
            i = i - 1
         end do
      end do
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
