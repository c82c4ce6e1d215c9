!> Sparse direct solver, symmetric (and unsymmetric: MUMPS_UNSYMMETRIC, the integrator's
!> iteration matrix): a wrapper around Debian's sequential double-precision MUMPS 5.5
!> (libdmumps_seq). Only this module sees `DMUMPS_STRUC`. Explicit phases (theory.md 5.4):
!>
!>     init(sym) -> analyse(n, irn, jcn [, perm]) -> factorise(values) -> solve(rhs) ... -> free()
!>
!> A new matrix with the same pattern goes back to `factorise`. The ordering is METIS nested
!> dissection computed here and passed as PERM_IN with ICNTL(7) = 1, because Debian's MUMPS is
!> built without METIS (toolchain.md, pitfall 1); INFOG(7) tells which ordering MUMPS used.
!> MUMPS prints nothing (ICNTL(1:4)); errors INFOG(1) < 0 become `error_t` with the MUMPS code,
!> its meaning and the fix. Workspace errors (-8, -9) are retried with ICNTL(14) doubled.
!>
!> The sequential library needs no MPI_Init: its stub MPI_INITIALIZED returns .true. and ignores
!> the communicator, so COMM is set to the stub's MPI_COMM_WORLD value without including mpif.h.
!> In the MPI build (-DFFRF_MPI=ON, Debian's MPI MUMPS) COMM is the run's communicator
!> (ffrf_core_parallel, given to `init`): on more than one rank every rank gives its share of
!> the entries (distributed assembled input, ICNTL(18) = 3: a contiguous slice of the arrays,
!> which every rank holds whole), PERM_IN and the right-hand sides are given on the host
!> (rank 0), and the solution is broadcast so every rank leaves `solve` with the same x.
!> INFOG (status, inertia, sizes) is global: every rank takes the same branches.
!> OpenBLAS threads are left as the environment sets them (OPENBLAS_NUM_THREADS).
!>
!> Memory (issue 12): `set_memory_options` (after init, before analyse) chooses out-of-core
!> factors (ICNTL(22)), block low-rank factors (ICNTL(35) = 2, CNTL(7), with iterative refinement)
!> and a memory limit; `analyse` records MUMPS's estimates and `factorise` refuses a
!> factorisation predicted above the limit (`check_memory`) before MUMPS allocates it.
module ffrf_la_mumps
   use ffrf_core_kinds, only: dp, ip, i8
   use ffrf_core_error, only: error_t, fatal_error, add_context, FFRF_INPUT_ERROR, &
      FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: wall_time
   use ffrf_core_posix, only: hold_signals, release_signals, signal_test_point
   use ffrf_core_memory, only: available_memory_mb, resident_memory_mb
   use ffrf_la_metis, only: pattern_nested_dissection
   use ffrf_core_serial_section, only: enter_serial_section, leave_serial_section, SECTION_MUMPS
   use ffrf_core_parallel, only: parallel_t, solver_communicator, check_solver_ready
   implicit none
   private
   public :: mumps_solver_t, mumps_ordering_name
   public :: MUMPS_SYM_SPD, MUMPS_SYM_INDEFINITE, MUMPS_UNSYMMETRIC

   include 'dmumps_struc.h'

   !> SYM = 1: symmetric positive definite (LDL^T without pivoting)
   integer(ip), parameter :: MUMPS_SYM_SPD = 1
   !> SYM = 2: general symmetric, e.g. indefinite KKT systems (LDL^T with 1x1/2x2 pivots)
   integer(ip), parameter :: MUMPS_SYM_INDEFINITE = 2
   !> SYM = 0: unsymmetric (LU with threshold pivoting; every entry given, both triangles),
   !> e.g. the integrator's iteration matrix of a large mechanism (gyroscopic and load terms)
   integer(ip), parameter :: MUMPS_UNSYMMETRIC = 0

   integer, parameter :: phase_empty = 0, phase_initialised = 1, phase_analysed = 2, &
                         phase_factorised = 3
   !> Workspace relaxation retries on INFOG(1) = -8/-9, each doubling ICNTL(14)
   integer, parameter :: max_workspace_retries = 2
   !> What to do when the factors do not fit (memory check, MUMPS errors -5/-7/-8/-9/-13)
   character(len=*), parameter :: MEMORY_REMEDIES = 'more ranks (the MPI build: mpirun -np N), ' &
      // 'out-of-core factors (&modes out_of_core = .true.), block low-rank compression ' // &
      '(&modes compression_tolerance = 1e-8), or a coarser mesh'
   !> Iterative-refinement steps of each solve with block low-rank factors (ICNTL(10))
   integer, parameter :: BLR_REFINEMENT_STEPS = 2
   !> INFOG(1) of a factorisation refused by the memory check (not a MUMPS code)
   integer, parameter, public :: MUMPS_STATUS_MEMORY_LIMIT = -1000

   interface
      !> The MUMPS driver (double precision): one call per JOB.
      subroutine dmumps(id)
         import :: dmumps_struc
         implicit none
         type(dmumps_struc), intent(inout) :: id
      end subroutine dmumps

      !> What INFOG(1) < 0 means and what to do (MUMPS 5.5 user guide, section 8).
      module function describe_status(info1, info2) result(text)
         integer, intent(in) :: info1, info2
         character(len=:), allocatable :: text
      end function describe_status

      !> MUMPS sizes: a negative value counts millions (INFOG(9), (20), (29)).
      module pure function mumps_count(value) result(count)
         integer, intent(in) :: value
         integer(i8) :: count
      end function mumps_count

      !> Deallocate the arrays this wrapper hands to MUMPS (never MUMPS's own).
      module subroutine release_user_arrays(id)
         type(dmumps_struc), intent(inout) :: id
      end subroutine release_user_arrays

      !> One MUMPS call, one thread at a time: the sequential MUMPS 5.5 keeps state in module
      !> variables (DMUMPS_LOAD's flop counters among them), so concurrent instances corrupt each
      !> other even on distinct DMUMPS_STRUC (serial_section.c).
      module subroutine serial_dmumps(id)
         type(DMUMPS_STRUC), intent(inout) :: id
      end subroutine serial_dmumps
   end interface

   !> A sparse symmetric matrix factorised by MUMPS, ready for repeated solves. Do not copy a
   !> live solver (the MUMPS instance holds pointers); call `free` before `init` again.
   type :: mumps_solver_t
      !> MUMPS_SYM_SPD or MUMPS_SYM_INDEFINITE
      integer(ip) :: sym = 0
      !> Matrix order
      integer(ip) :: n = 0
      !> Number of entries given (one triangle, duplicates are summed by MUMPS)
      integer(i8) :: nnz = 0
      !> Ordering MUMPS used, INFOG(7): 0 AMD, 1 given (PERM_IN), 2 AMF, 3 SCOTCH, 4 PORD,
      !> 5 METIS, 6 QAMD
      integer(ip) :: ordering_used = -1
      !> .true. when PERM_IN came from METIS_NodeND in `analyse`
      logical :: metis_ordering = .false.
      !> Estimated entries in the factors after analysis, INFOG(20)
      integer(i8) :: estimated_factor_entries = 0
      !> Entries in the factors, INFOG(29)
      integer(i8) :: factor_entries = 0
      !> Real workspace holding the factors, INFOG(9)
      integer(i8) :: factor_storage = 0
      !> Negative pivots, INFOG(12) (exact: ICNTL(13) = 1, no ScaLAPACK root); null pivots are
      !> not counted here when null-pivot detection is on
      integer(ip) :: num_negative_pivots = 0
      !> Null pivots found by null-pivot detection (ICNTL(24) = 1), INFOG(28); else 0
      integer(ip) :: num_null_pivots = 0
      !> Delayed pivots, INFOG(13) (many: numerically hard indefinite matrix)
      integer(ip) :: num_delayed_pivots = 0
      !> Order of the largest frontal matrix, INFOG(11)
      integer(ip) :: max_front_size = 0
      !> MB allocated by MUMPS during factorisation, INFOG(18)
      integer(ip) :: memory_allocated_mb = 0
      !> MB effectively used during factorisation, INFOG(21)
      integer(ip) :: memory_used_mb = 0
      !> Floating-point operations of the elimination, RINFOG(3)
      real(dp) :: factor_flops = 0.0_dp
      !> Workspace relaxation in percent, ICNTL(14), after any automatic increase
      integer(ip) :: workspace_percent = 0
      !> Factorisations repeated because the workspace was too small (-8/-9)
      integer(ip) :: num_workspace_retries = 0
      !> Seconds in METIS_NodeND (0 when the ordering was given)
      real(dp) :: time_ordering = 0.0_dp
      !> Seconds in the MUMPS analysis (JOB = 1)
      real(dp) :: time_analysis = 0.0_dp
      !> Seconds in the last numerical factorisation (JOB = 2, retries included)
      real(dp) :: time_factorisation = 0.0_dp
      !> Seconds in all solves since the last factorisation
      real(dp) :: time_solve = 0.0_dp
      !> Right-hand sides solved since the last factorisation
      integer(i8) :: num_solves = 0
      !> Last INFOG(1): 0 success, > 0 warning (MUMPS user guide, section 8)
      integer(ip) :: status = 0
      ! Memory options (set_memory_options) and the analysis's estimates (MUMPS 5.5 user
      ! guide, section 8: INFO/INFOG after JOB = 1), checked against the limit in `factorise`
      !> Out-of-core factorisation: factors written to files in ooc_directory, ICNTL(22) = 1
      logical :: out_of_core = .false.
      !> Folder of the out-of-core files (OOC_TMPDIR); MUMPS removes them at `free` (JOB = -2)
      character(len=:), allocatable :: ooc_directory
      !> Block low-rank dropping tolerance CNTL(7) with ICNTL(35) = 2 (BLR factors used in the
      !> solve); 0 = full-rank factors (MUMPS's default, bitwise the former results)
      real(dp) :: compression_tolerance = 0.0_dp
      !> Memory limit of this process in MB: -1 automatic (resident + MemAvailable at the
      !> check), 0 none, > 0 the limit
      integer(i8) :: memory_limit_mb = 0
      !> Estimated MB of MUMPS data for the in-core full-rank factorisation: this process
      !> INFO(15), max over processes INFOG(16), sum INFOG(17)
      integer(i8) :: estimated_memory_incore_mb = 0, estimated_memory_incore_max_mb = 0, &
                     estimated_memory_incore_total_mb = 0
      !> Same for the out-of-core full-rank factorisation: INFO(17), INFOG(26), INFOG(27)
      integer(i8) :: estimated_memory_ooc_mb = 0, estimated_memory_ooc_max_mb = 0, &
                     estimated_memory_ooc_total_mb = 0
      !> Same with low-rank factors (compression on; assumes ICNTL(38), 60 % of the full-rank
      !> factors by default): in-core max/sum INFOG(36)/(37), out-of-core INFOG(38)/(39)
      integer(i8) :: estimated_memory_blr_incore_mb = 0, estimated_memory_blr_incore_total_mb = 0, &
                     estimated_memory_blr_ooc_mb = 0, estimated_memory_blr_ooc_total_mb = 0
      !> Estimated flops of the elimination, RINFOG(1); estimated disk MB (out-of-core),
      !> RINFOG(15)
      real(dp) :: estimated_flops = 0.0_dp, estimated_disk_mb = 0.0_dp
      !> The estimate for the chosen options (MB of MUMPS data in this process), the resident
      !> memory and the limit at the last check (MB); limit 0 when no check was made
      integer(i8) :: predicted_memory_mb = 0, resident_memory_mb = 0, checked_limit_mb = 0
      !> MB the caller allocates next to the factors while they live (the eigensolver's
      !> vectors), counted in the memory check
      integer(i8) :: workspace_mb = 0
      !> Entries in the factors after block low-rank compression, INFOG(35) (= factor_entries
      !> without compression); flops done, RINFOG(14)
      integer(i8) :: compressed_factor_entries = 0
      real(dp) :: factor_flops_done = 0.0_dp
      !> .true. once `check_memory` ran for the current analysis (refactorisations skip it: the
      !> resident memory then holds the previous factors)
      logical, private :: memory_checked = .false.
      integer, private :: phase = phase_empty
      !> The ranks MUMPS runs on (one process unless given to init)
      type(parallel_t), private :: parallel
      !> This rank's slice first:last of the entries (distributed input, more than one rank)
      integer(i8), private :: first_entry = 1, last_entry = 0
      type(dmumps_struc), allocatable, private :: id
   contains
      procedure :: init => mumps_solver_init
      procedure :: analyse => mumps_solver_analyse
      procedure :: factorise => mumps_solver_factorise
      procedure, private :: mumps_solver_solve_one
      procedure, private :: mumps_solver_solve_many
      generic :: solve => mumps_solver_solve_one, mumps_solver_solve_many
      procedure :: is_factorised => mumps_solver_is_factorised
      procedure :: is_analysed => mumps_solver_is_analysed
      procedure :: ranks => mumps_solver_ranks
      procedure :: free => mumps_solver_free
      procedure :: set_memory_options => mumps_solver_set_memory_options
      procedure :: check_memory => mumps_solver_check_memory
      procedure :: memory_remedies => mumps_solver_memory_remedies
      procedure :: memory_options_text
   end type mumps_solver_t

   interface
      !> Symbolic analysis (JOB = 1) of the pattern (irn, jcn): one triangle of a symmetric matrix
      !> (entries given in both triangles are summed by MUMPS). Without `perm` a METIS nested-
      !> dissection ordering of the pattern is computed and passed as PERM_IN (ICNTL(7) = 1).
      module subroutine mumps_solver_analyse(self, n, irn, jcn, perm, error)
         class(mumps_solver_t), intent(inout) :: self
         !> Matrix order
         integer(ip), intent(in) :: n
         !> Row index of each entry, 1-based
         integer(ip), intent(in) :: irn(:)
         !> Column index of each entry, 1-based
         integer(ip), intent(in) :: jcn(:)
         !> Optional elimination order: variable i is eliminated at step perm(i) (MUMPS PERM_IN)
         integer(ip), intent(in), optional :: perm(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine mumps_solver_analyse

      !> Numerical factorisation (JOB = 2) of the matrix with the analysed pattern and `values`
      !> (same order as irn/jcn). Retries up to twice with ICNTL(14) doubled on INFOG(1) = -8/-9.
      module subroutine mumps_solver_factorise(self, values, error)
         class(mumps_solver_t), intent(inout) :: self
         !> Matrix entries, one per (irn(k), jcn(k)) given to `analyse`
         real(dp), intent(in) :: values(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine mumps_solver_factorise

      !> Memory options, after `init` and before `analyse` (compression must be known to the
      !> analysis). Absent arguments keep their current values (defaults: in-core, full rank, no
      !> limit). The out-of-core files go to `ooc_directory` (default: TMPDIR, else the current
      !> folder) with the prefix ffrf_ooc_; MUMPS deletes them in `free` (JOB = -2), also after an
      !> error, but a killed process (SIGKILL, out-of-memory killer) leaves them behind.
      module subroutine mumps_solver_set_memory_options(self, error, out_of_core, ooc_directory, &
                                                        compression_tolerance, memory_limit_mb)
         class(mumps_solver_t), intent(inout) :: self
         type(error_t), allocatable, intent(out) :: error
         !> Out-of-core factorisation (ICNTL(22) = 1)
         logical, intent(in), optional :: out_of_core
         !> Folder of the out-of-core files; blank: TMPDIR, else '.'
         character(len=*), intent(in), optional :: ooc_directory
         !> BLR dropping tolerance CNTL(7) in [0, 1); 0 = full-rank factors
         real(dp), intent(in), optional :: compression_tolerance
         !> Memory limit in MB: -1 automatic (MemAvailable), 0 none, > 0 the limit
         integer(i8), intent(in), optional :: memory_limit_mb
      end subroutine mumps_solver_set_memory_options

      !> Refuse a factorisation whose predicted memory exceeds the limit: resident memory of the
      !> process + the analysis's estimate for the chosen options (predicted_memory_mb) + the
      !> caller's workspace_mb against
      !> memory_limit_mb (automatic: resident + MemAvailable). Called by `factorise` once per
      !> analysis; no limit (0) or an unreadable /proc makes it a no-op.
      module subroutine mumps_solver_check_memory(self, error)
         class(mumps_solver_t), intent(inout) :: self
         type(error_t), allocatable, intent(out) :: error
      end subroutine mumps_solver_check_memory
   end interface

contains

   !> Start a MUMPS instance (JOB = -1) for a symmetric matrix, silenced, exact inertia on.
   subroutine mumps_solver_init(self, sym, error, null_pivot_detection, null_pivot_threshold, &
                                workspace_percent, parallel)
      class(mumps_solver_t), intent(out) :: self
      !> MUMPS_SYM_SPD (1), MUMPS_SYM_INDEFINITE (2) or MUMPS_UNSYMMETRIC (0: both triangles)
      integer(ip), intent(in) :: sym
      type(error_t), allocatable, intent(out) :: error
      !> Detect null pivots (ICNTL(24) = 1); their number is `num_null_pivots`. Default .false.
      logical, intent(in), optional :: null_pivot_detection
      !> Null-pivot threshold relative to the max-norm of the (scaled) matrix, CNTL(3) > 0;
      !> default 0 = MUMPS's own, eps * 1e-5 * ||A||
      real(dp), intent(in), optional :: null_pivot_threshold
      !> Workspace relaxation ICNTL(14) in percent; default MUMPS's (20, or 5 for SPD)
      integer(ip), intent(in), optional :: workspace_percent
      !> The ranks to factorise and solve on (MPI build); default one process
      type(parallel_t), intent(in), optional :: parallel

      if (sym /= MUMPS_SYM_SPD .and. sym /= MUMPS_SYM_INDEFINITE .and. &
         sym /= MUMPS_UNSYMMETRIC) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'MUMPS init: sym = ' // to_str(sym) // &
            ', must be 1 (symmetric positive definite), 2 (symmetric indefinite) or 0 ' // &
            '(unsymmetric)')
         return
      end if
      call check_solver_ready(error)
      if (allocated(error)) return
      if (present(parallel)) self%parallel = parallel
      allocate (self%id)
      associate (id => self%id)
         call nullify_user_pointers(id)
         id%comm = solver_communicator(self%parallel)
         id%par = 1
         id%sym = sym
         id%job = -1
         call serial_dmumps(id)
         if (id%infog(1) < 0) then
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'MUMPS initialisation (JOB = -1): ' // &
               describe_status(id%infog(1), id%infog(2)))
            deallocate (self%id)
            return
         end if
         ! Silence: no error, diagnostic or global output, print level 0
         id%icntl(1) = -1
         id%icntl(2) = -1
         id%icntl(3) = -1
         id%icntl(4) = 0
         ! No ScaLAPACK root: exact inertia in INFOG(12) (theory.md 5.3)
         id%icntl(13) = 1
         if (present(null_pivot_detection)) then
            if (null_pivot_detection) id%icntl(24) = 1
         end if
         if (present(null_pivot_threshold)) id%cntl(3) = null_pivot_threshold
         if (present(workspace_percent)) id%icntl(14) = workspace_percent
         if (sym == MUMPS_UNSYMMETRIC) then
            ! The unsymmetric caller (the integrator's iteration matrix) equilibrates its rows
            ! itself: no scaling (ICNTL(8) = 0) and no maximum-transversal column permutation
            ! (ICNTL(6) = 0); on the 16-link chain of benchmark_threads a factorisation took
            ! 3.5 ms instead of 4.7 ms (one pair of runs on a loaded machine), with the same
            ! solutions to round-off (test_mbs_sparse_iteration)
            id%icntl(8) = 0
            id%icntl(6) = 0
         end if
         self%workspace_percent = id%icntl(14)
      end associate
      self%sym = sym
      self%phase = phase_initialised
   end subroutine mumps_solver_init

   !> Solve A x = b (JOB = 3) with the current factors; `rhs` holds b on entry and x on exit.
   subroutine mumps_solver_solve_one(self, rhs, error)
      class(mumps_solver_t), intent(inout) :: self
      !> Right-hand side b on entry, solution x on exit (size n)
      real(dp), intent(inout) :: rhs(:)
      type(error_t), allocatable, intent(out) :: error
      call solve_columns(self, rhs, 1_ip, error)
   end subroutine mumps_solver_solve_one

   !> Solve A X = B for the columns of B (JOB = 3); `rhs` holds B on entry and X on exit.
   subroutine mumps_solver_solve_many(self, rhs, error)
      class(mumps_solver_t), intent(inout) :: self
      !> Right-hand sides (n x nrhs) on entry, solutions on exit
      real(dp), intent(inout) :: rhs(:, :)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: flat(:)
      if (size(rhs, 1) /= self%n .and. self%phase == phase_factorised) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'MUMPS solve: right-hand sides have ' // &
            to_str(size(rhs, 1)) // ' rows, the matrix has order ' // to_str(self%n))
         return
      end if
      if (size(rhs, 2) == 0) return
      flat = reshape(rhs, [size(rhs)])
      call solve_columns(self, flat, int(size(rhs, 2), ip), error)
      if (allocated(error)) return
      rhs = reshape(flat, shape(rhs))
   end subroutine mumps_solver_solve_many

   !> .true. once `factorise` succeeded (and until `free` or a failed `factorise`).
   pure function mumps_solver_is_factorised(self) result(ready)
      class(mumps_solver_t), intent(in) :: self
      logical :: ready
      ready = self%phase == phase_factorised
   end function mumps_solver_is_factorised

   !> .true. once `analyse` succeeded (and until `free`): `factorise` may be called.
   pure function mumps_solver_is_analysed(self) result(ready)
      class(mumps_solver_t), intent(in) :: self
      logical :: ready
      ready = self%phase >= phase_analysed
   end function mumps_solver_is_analysed

   !> The ranks the solver runs on (given to `init`; one process by default): the callers that
   !> distribute their vectors over the same ranks (the PARPACK eigen loop).
   pure function mumps_solver_ranks(self) result(parallel)
      class(mumps_solver_t), intent(in) :: self
      type(parallel_t) :: parallel
      parallel = self%parallel
   end function mumps_solver_ranks

   !> Release the factors and the MUMPS instance (JOB = -2). Safe to call at any phase.
   subroutine mumps_solver_free(self)
      class(mumps_solver_t), intent(inout) :: self
      if (allocated(self%id)) then
         call release_user_arrays(self%id)
         if (self%phase >= phase_initialised) then
            self%id%job = -2
            call serial_dmumps(self%id)
         end if
         deallocate (self%id)
      end if
      self%phase = phase_empty
   end subroutine mumps_solver_free

   !> Name of a MUMPS sequential ordering code ICNTL(7)/INFOG(7).
   pure function mumps_ordering_name(code) result(name)
      !> Ordering code
      integer(ip), intent(in) :: code
      character(len=:), allocatable :: name
      character(len=*), parameter :: names(0:7) = [character(len=15) :: 'AMD', &
         'given (PERM_IN)', 'AMF', 'SCOTCH', 'PORD', 'METIS', 'QAMD', 'automatic']
      name = 'unknown'
      if (code >= 0 .and. code <= 7) name = trim(names(code))
   end function mumps_ordering_name

   ! ---------------------------------------------------------------------------------------------

   !> JOB = 3 on `nrhs` columns packed in `b` (n*nrhs), solution overwriting `b`.
   subroutine solve_columns(self, b, nrhs, error)
      type(mumps_solver_t), intent(inout) :: self
      real(dp), intent(inout) :: b(:)
      integer(ip), intent(in) :: nrhs
      type(error_t), allocatable, intent(out) :: error
      integer :: stat
      real(dp) :: t0
      if (self%phase /= phase_factorised) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'MUMPS solve: no valid factorisation; ' // &
            'call factorise(values, error) first (and check its error)')
         return
      end if
      if (size(b, kind=i8) /= int(self%n, i8) * nrhs) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'MUMPS solve: right-hand side of size ' // &
            to_str(size(b)) // ' for a matrix of order ' // to_str(self%n))
         return
      end if
      associate (id => self%id)
         if (associated(id%rhs)) then
            if (size(id%rhs, kind=i8) /= size(b, kind=i8)) deallocate (id%rhs)
         end if
         ! centralised right-hand sides and solution: on the host only (ICNTL(20) = ICNTL(21) = 0)
         if (.not. associated(id%rhs) .and. self%parallel%is_root()) then
            allocate (id%rhs(size(b)), stat=stat)
            if (stat /= 0) then
               call fatal_error(error, FFRF_NUMERIC_ERROR, 'MUMPS solve: cannot allocate ' // &
                  to_str(size(b)) // ' right-hand side entries')
               return
            end if
         end if
         if (self%parallel%is_root()) id%rhs = b
         id%nrhs = nrhs
         id%lrhs = self%n
         id%job = 3
         t0 = wall_time()
         call serial_dmumps(id)
         self%time_solve = self%time_solve + (wall_time() - t0)
         if (id%infog(1) < 0) then
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'MUMPS solve (n = ' // to_str(self%n) &
               // ', ' // to_str(nrhs) // ' right-hand sides): ' // &
               describe_status(id%infog(1), id%infog(2)))
            return
         end if
         if (self%parallel%is_root()) b = id%rhs
         ! every rank continues with the same solution (the Lanczos state stays identical)
         call self%parallel%broadcast_reals(b)
      end associate
      self%num_solves = self%num_solves + nrhs
   end subroutine solve_columns

   !> Nullify the input pointers of the structure (MUMPS tests `associated` on them).
   subroutine nullify_user_pointers(id)
      type(dmumps_struc), intent(inout) :: id
      nullify (id%a, id%irn, id%jcn, id%colsca, id%rowsca, id%irn_loc, id%jcn_loc, id%a_loc, &
               id%eltptr, id%eltvar, id%a_elt, id%perm_in, id%blkptr, id%blkvar, id%rhs, &
               id%redrhs, id%rhs_sparse, id%sol_loc, id%rhs_loc, id%irhs_sparse, id%irhs_ptr, &
               id%isol_loc, id%irhs_loc, id%schur, id%listvar_schur, id%wk_user)
   end subroutine nullify_user_pointers

   !> The remedies for factors that do not fit, without those already in use.
   function mumps_solver_memory_remedies(self) result(text)
      class(mumps_solver_t), intent(in) :: self
      character(len=:), allocatable :: text
      text = 'more ranks (the MPI build: mpirun -np N)'
      if (.not. self%out_of_core) text = text // ', out-of-core factors (&modes out_of_core ' &
         // '= .true.)'
      text = text // ', or a coarser mesh'
   end function mumps_solver_memory_remedies

   !> 'in-core full-rank', 'out-of-core block low-rank', ...
   function memory_options_text(self) result(text)
      class(mumps_solver_t), intent(in) :: self
      character(len=:), allocatable :: text
      text = merge('out-of-core', 'in-core    ', self%out_of_core)
      text = trim(text) // merge(' block low-rank', ' full-rank     ', &
         self%compression_tolerance > 0.0_dp)
      text = trim(text)
   end function memory_options_text

end module ffrf_la_mumps
