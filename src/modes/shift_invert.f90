!> Constrained generalized symmetric eigenproblem by shift-invert Lanczos (ARPACK mode 3) on one
!> MUMPS factorisation (theory.md 5.1-5.3):
!>
!>     K x = lambda M x   subject to   C x = 0,
!>
!> K, M symmetric n x n (both triangles stored), M positive definite on null(C), C a
!> num_constraints x n matrix of full row rank (it may have no rows). The operator is
!> y = OP x = (K - sigma M)^-1 M x restricted to null(C), applied by solving the KKT system
!>
!>     [ K - sigma M   C^T ] [ y  ]   [ M x ]
!>     [ C             0   ] [ mu ] = [ 0   ]                                          (5.2b)
!>
!> y lies in null(C) and OP is M-self-adjoint there, so dsaupd runs in R^n with B = M
!> (bmat = 'G', which = 'LM'); lambda = sigma + 1/nu. The constraint rows are scaled to the
!> magnitude of diag(K) (toolchain.md, pitfall 7). The inertia of the KKT matrix gives the
!> Sturm count: eigenvalues below sigma = negative pivots - num_constraints (theory.md 5.3).
!> The returned eigenvalues are Rayleigh quotients of the M-normalised Ritz vectors, each pair
!> with its residual, and the block with its M-orthonormality error.
!>
!> Spectra you can trust (theory.md 5.6-5.8): known null vectors (the rigid-body modes of a free
!> body, `rigid`) are deflated exactly, never searched for: every operator application is
!> followed by the M-orthogonal projection P y = y - X (M X)^T y. After convergence the inertia
!> of the KKT matrix at a shift s just above the highest returned eigenvalue proves that no
!> eigenvalue is missing below it (Sturm check); a short count triggers a recovery. With an
!> upper bound `max_eigenvalue` every eigenvalue below it is computed by shift windows
!> (spectrum slicing), each window proven by the counts at its ends.
!>
!> The implementation is split in two families of submodules: ffrf_modes_shift_invert_lanczos
!> (ARPACK and block eigen loops on one factorisation) with its children _factorise (KKT
!> matrix, factorisations) and _pairs (the checks of the eigenpairs), and
!> ffrf_modes_shift_invert_spectrum (deflation, Sturm counts) with its child _windows (the
!> driver: windows, recoveries).
module ffrf_modes_shift_invert
   use ffrf_core_kinds, only: dp, ip, i8
   use ffrf_core_error, only: error_t
   use ffrf_core_log, only: logger_t
   use ffrf_core_interrupt, only: interrupt_t
   use ffrf_la_sparse, only: csr_t
   use ffrf_la_mumps, only: mumps_solver_t
   use ffrf_core_parallel, only: parallel_t
   implicit none
   private
   public :: eigen_options_t, eigen_result_t, solve_shift_invert, project_null_space
   public :: AUTO_BLOCK_MIN_DOFS, DEFAULT_WINDOW_SIZE, MULTIPLET_RTOL

   !> Most eigenpairs computed in one shift window (docs/method.md "Modes: spectra you can trust"):
   !> above it the spectrum is sliced; the eigensolver's basis is that of one window
   integer(ip), parameter :: DEFAULT_WINDOW_SIZE = 50
   !> Eigenvalues that agree to this relative difference form one multiplet: num_modes never
   !> cuts through one (its other members are returned too), a window boundary never falls
   !> inside one
   real(dp), parameter :: MULTIPLET_RTOL = 1.0e-6_dp

   !> Smallest constrained dimension n - num_constraints for which eigensolver = 'auto' picks
   !> the block method (docs/performance.md "Large meshes": measured break-even far below; the
   !> bodies of the test suite and the engine's reference meshes stay on ARPACK, bit for bit as
   !> before)
   integer(ip), parameter :: AUTO_BLOCK_MIN_DOFS = 200000

   !> Settings of the shift-invert Lanczos solver.
   type :: eigen_options_t
      !> Number of eigenpairs wanted (those nearest sigma)
      integer(ip) :: num_modes = 10
      !> Shift sigma, in the units of lambda ((rad/s)^2 for K, M in SI). Below the lowest wanted
      !> eigenvalue, e.g. -(2 pi f_low)^2; never 0 for a free-free body (toolchain.md pitfall 8)
      real(dp) :: sigma = 0.0_dp
      !> Lanczos basis size; 0 = max(2 num_modes + 1, 20), capped by n - num_constraints
      integer(ip) :: ncv = 0
      !> ARPACK relative accuracy of the Ritz values; <= 0 means machine epsilon
      real(dp) :: tolerance = 0.0_dp
      !> Maximum number of implicit restarts (ARPACK iparam(3))
      integer(ip) :: max_iterations = 300
      !> If sigma sits (numerically) on an eigenvalue, move it once and refactorise
      logical :: retry_shift = .true.
      !> Null-pivot threshold relative to the norm of the scaled KKT matrix (MUMPS CNTL(3));
      !> a pivot below it means sigma is an eigenvalue or the constraints are dependent
      real(dp) :: null_pivot_threshold = 1.0e-12_dp
      !> The ranks MUMPS factorises and solves on (MPI build; default one process). Every rank
      !> calls with the same K, M, C and gets the same result.
      type(parallel_t) :: parallel
      !> Out-of-core MUMPS factorisation (factors in files in ooc_directory)
      logical :: out_of_core = .false.
      !> Folder of the out-of-core files; blank: TMPDIR, else the current folder
      character(len=256) :: ooc_directory = ''
      !> Memory limit of the process in MB: -1 automatic (MemAvailable), 0 none (the default
      !> here: library callers opt in; the case input defaults to -1)
      integer(i8) :: memory_limit_mb = 0
      !> Block low-rank dropping tolerance of the factors (MUMPS CNTL(7)); 0 = full rank
      real(dp) :: compression_tolerance = 0.0_dp
      !> 'arpack' (ARPACK, one right-hand side per solve), 'block' (block Lanczos with thick
      !> restarts, num_modes + 4 right-hand sides per solve: ffrf_modes_block_krylov) or 'auto':
      !> 'block' when n - num_constraints >= AUTO_BLOCK_MIN_DOFS, where the factor is large
      !> and reading it once per vector dominates the eigen loop, else 'arpack'
      character(len=16) :: eigensolver = 'auto'
      !> Stop at the next check when a signal (SIGTERM, SIGINT, SIGHUP, SIGUSR1, SIGXCPU: the
      !> run is being ended) is pending on any rank: after the factorisation and before every
      !> solve of the eigen loop, with an FFRF_INTERRUPTED error. MUMPS's analysis and
      !> factorisation cannot be interrupted. Default .false.: the solve runs to its end.
      logical :: stop_on_signal = .false.
      !> Sturm check (theory.md 5.7): after convergence, one more factorisation at a shift s just
      !> above the highest returned eigenvalue; its inertia must count exactly the returned ones
      !> (and the deflated null vectors) between the shift and s, else a recovery runs. With
      !> max_eigenvalue the counts are part of the method and always made.
      logical :: sturm_check = .true.
      !> Upper bound of the wanted eigenvalues ((rad/s)^2): > 0 asks for every eigenvalue from
      !> sigma up to it (at most num_modes, the smaller set wins), by as many shift windows as
      !> needed (theory.md 5.8); <= 0 (default): the num_modes nearest sigma
      real(dp) :: max_eigenvalue = 0.0_dp
      !> Most eigenpairs per shift window: more wanted modes are computed window by window
      integer(ip) :: window_size = DEFAULT_WINDOW_SIZE
   end type eigen_options_t

   !> Eigenpairs and statistics of one `solve_shift_invert` call.
   type :: eigen_result_t
      !> Problem size n and number of constraint rows
      integer(ip) :: n = 0
      integer(ip) :: num_constraints = 0
      !> Number of eigenpairs returned
      integer(ip) :: num_modes = 0
      !> Eigenvalues lambda, ascending ((rad/s)^2 for SI K, M): Rayleigh quotients x^T K x
      real(dp), allocatable :: eigenvalues(:)
      !> Eigenvectors as columns (n x num_modes), x^T M x = 1, C x = 0
      real(dp), allocatable :: vectors(:, :)
      !> Relative residual of each pair, ||P (K x - lambda M x)|| / max(||P K x||,
      !> |sigma| ||M x||), P the orthogonal projector onto null(C) (P = I without constraints);
      !> the |sigma| term keeps it meaningful for rigid modes (lambda ~ 0, K x ~ 0)
      real(dp), allocatable :: residuals(:)
      !> max |X^T M X - I|
      real(dp) :: orthonormality_error = 0.0_dp
      !> Shift actually used (differs from the requested one after a retry)
      real(dp) :: shift = 0.0_dp
      !> Sturm count: eigenvalues of the constrained problem below `shift`, from the inertia of
      !> the KKT matrix (negative pivots - num_constraints)
      integer(ip) :: num_below_shift = 0
      !> Returned eigenvalues below `shift` (at most num_below_shift)
      integer(ip) :: num_found_below_shift = 0
      !> Applications of OP (one KKT solve each)
      integer(i8) :: num_solves = 0
      !> ARPACK implicit restarts (iparam(3) on exit)
      integer(ip) :: num_iterations = 0
      !> Lanczos basis size used
      integer(ip) :: ncv = 0
      !> Eigensolver used: 'arpack' or 'block'; for 'block', right-hand sides per solve and
      !> block solves
      character(len=16) :: eigensolver = ''
      integer(ip) :: block_size = 0
      integer(ip) :: num_block_solves = 0
      !> Numerical factorisations done (1, more after an SPD fallback or a shift retry)
      integer(ip) :: num_factorisations = 0
      !> MUMPS SYM of the final factorisation (1 SPD, 2 indefinite)
      integer(ip) :: sym = 0
      !> Entries in the factors (MUMPS INFOG(29))
      integer(i8) :: factor_entries = 0
      !> Negative pivots of the KKT matrix (MUMPS INFOG(12))
      integer(ip) :: num_negative_pivots = 0
      !> MB used by MUMPS during factorisation (INFOG(21))
      integer(ip) :: factor_memory_mb = 0
      !> Wall seconds: METIS ordering, MUMPS analysis, last factorisation, Lanczos loop (solves
      !> included), of which MUMPS solves, post-processing (normalisation, residuals), whole call
      real(dp) :: time_ordering = 0.0_dp
      real(dp) :: time_analysis = 0.0_dp
      real(dp) :: time_factorisation = 0.0_dp
      real(dp) :: time_lanczos = 0.0_dp
      real(dp) :: time_solves = 0.0_dp
      real(dp) :: time_check = 0.0_dp
      real(dp) :: time_total = 0.0_dp
      !> Wall seconds of the static solves asked with constraint_targets
      real(dp) :: time_constraint_solves = 0.0_dp
      !> MUMPS analysis estimates (ffrf_la_mumps): factor entries INFOG(20), flops RINFOG(1),
      !> MB in-core INFOG(16)/(17), out-of-core INFOG(26)/(27), low-rank in-core INFOG(36),
      !> the one for the options used (predicted) and the limit checked (0: none)
      integer(i8) :: estimated_factor_entries = 0
      real(dp) :: estimated_flops = 0.0_dp
      integer(i8) :: estimated_memory_incore_mb = 0, estimated_memory_incore_total_mb = 0, &
                     estimated_memory_ooc_mb = 0, estimated_memory_ooc_total_mb = 0, &
                     estimated_memory_blr_mb = 0, predicted_memory_mb = 0, memory_limit_mb = 0
      !> Factor entries after block low-rank compression, INFOG(35) (= factor_entries without)
      integer(i8) :: compressed_factor_entries = 0
      !> Options used: out-of-core, compression tolerance (0: full rank)
      logical :: out_of_core = .false.
      real(dp) :: compression_tolerance = 0.0_dp
      !> Null vectors deflated (`rigid`): their number and Rayleigh quotients x^T K x after
      !> M-orthonormalisation (round-off of 0); they are not among the returned eigenpairs
      integer(ip) :: num_rigid = 0
      real(dp), allocatable :: rigid_eigenvalues(:)
      !> Sturm check made (theory.md 5.7): at sturm_shift ((rad/s)^2) the inertia counts
      !> sturm_count eigenvalues below it (negative pivots - constraint rows, the deflated null
      !> vectors included), equal to the returned ones below it plus num_rigid
      logical :: sturm_checked = .false.
      real(dp) :: sturm_shift = 0.0_dp
      integer(ip) :: sturm_count = 0
      !> Lower end of the proven interval: sigma and num_below_shift, or a shift below the
      !> lowest returned eigenvalue when some lie below sigma (a positive sigma). Every
      !> eigenvalue in [sturm_shift_low, sturm_shift) is returned: sturm_count -
      !> sturm_count_low = returned ones in it + the null vectors in it
      real(dp) :: sturm_shift_low = 0.0_dp
      integer(ip) :: sturm_count_low = 0
      !> Shift windows (1 without slicing), recoveries after a short count (more vectors, another
      !> shift, the other eigensolver), factorisations made for counts and window shifts and the
      !> wall seconds of them (their analyses included)
      integer(ip) :: num_windows = 0
      integer(ip) :: num_recoveries = 0
      integer(ip) :: num_count_factorisations = 0
      real(dp) :: time_sturm = 0.0_dp
      !> Modes returned beyond num_modes to keep a multiplet whole (num_modes cut through it)
      integer(ip) :: num_multiplet_extra = 0
   end type eigen_result_t

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

   !> A deflated subspace: X (n x d), M-orthonormal, in null(C), and M X. Every operator
   !> application is followed by P y = y - X (M X)^T y (theory.md 5.6).
   type :: deflation_t
      real(dp), allocatable :: X(:, :), MX(:, :)
   end type deflation_t

   interface
      !> Eigenpairs of K x = lambda M x, C x = 0 nearest options%sigma (shift-invert Lanczos).
      !> With sigma = 0 the factorised KKT matrix is also that of the static problem
      !> [[K, C^T], [C, 0]] [x; mu] = [0; t]: give `constraint_targets` (columns t) and get the
      !> `constraint_solutions` x (Craig-Bampton static modes) from the same factorisation.
      module subroutine solve_shift_invert(K, M, C, options, result, log, error, &
            constraint_targets, constraint_solutions, rigid)
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
         !> Known null vectors of K on null(C) (n x r, e.g. the rigid-body modes of a free
         !> body, in null(C)): deflated exactly, not among the returned pairs (theory.md 5.6)
         real(dp), intent(in), optional :: rigid(:, :)
      end subroutine solve_shift_invert

      !> Columns of r replaced by their orthogonal projection P r = r - C^T (C C^T)^-1 C r onto
      !> null(C) (C with a handful of rows, e.g. reference conditions).
      module subroutine project_null_space(C, r, error)
         !> Constraint rows, full row rank
         type(csr_t), intent(in) :: C
         !> Vectors as columns (C%num_cols rows), projected in place
         real(dp), intent(inout) :: r(:, :)
         type(error_t), allocatable, intent(out) :: error
      end subroutine project_null_space

      ! --- between the submodules (not public) --------------------------------------------

      !> Sizes and settings checked; n, nc and the wanted count (num_modes capped for slicing).
      module subroutine check_input(K, M, C, options, num_rigid, n, nc, error)
         type(csr_t), intent(in) :: K, M, C
         type(eigen_options_t), intent(in) :: options
         integer(ip), intent(in) :: num_rigid
         integer(ip), intent(out) :: n, nc
         type(error_t), allocatable, intent(out) :: error
      end subroutine check_input

      !> Pattern and constraint block of the KKT matrix (values of K - sigma M set later).
      module subroutine build_kkt(K, M, C, kkt, error)
         type(csr_t), intent(in) :: K, M, C
         type(kkt_t), intent(out) :: kkt
         type(error_t), allocatable, intent(out) :: error
      end subroutine build_kkt

      !> Analyse and factorise at the eigen shift sigma (SPD when possible, one move off an
      !> eigenvalue); result%num_below_shift from the inertia.
      module subroutine factorise_shifted(K, M, options, kkt, sigma, solver, result, log, error)
         type(csr_t), intent(in) :: K, M
         type(eigen_options_t), intent(in) :: options
         type(kkt_t), intent(inout) :: kkt
         real(dp), intent(inout) :: sigma
         type(mumps_solver_t), intent(inout) :: solver
         type(eigen_result_t), intent(inout) :: result
         type(logger_t), intent(in) :: log
         type(error_t), allocatable, intent(out) :: error
      end subroutine factorise_shifted

      !> Symmetric indefinite factorisation at s for its inertia: count = eigenvalues below s.
      !> A null pivot (s numerically an eigenvalue) moves s inside (low, high), at most three
      !> times. A solver holding an SPD analysis is restarted as SYM = 2.
      module subroutine factorise_count(K, M, options, kkt, s, low, high, solver, result, log, &
            error, count, record_analysis)
         type(csr_t), intent(in) :: K, M
         type(eigen_options_t), intent(in) :: options
         type(kkt_t), intent(inout) :: kkt
         real(dp), intent(inout) :: s
         real(dp), intent(in) :: low, high
         type(mumps_solver_t), intent(inout) :: solver
         type(eigen_result_t), intent(inout) :: result
         type(logger_t), intent(in) :: log
         type(error_t), allocatable, intent(out) :: error
         integer(ip), intent(out) :: count
         !> A new analysis records its estimates in result (default: not, they stay those of
         !> the eigen shift's)
         logical, intent(in), optional :: record_analysis
      end subroutine factorise_count

      !> x of [[K, C^T], [C, 0]] [x; mu] = [0; t] for each column t of `targets` (sigma = 0).
      module subroutine constraint_solve(solver, kkt, sigma, targets, solutions, error)
         type(mumps_solver_t), intent(inout) :: solver
         type(kkt_t), intent(in) :: kkt
         real(dp), intent(in) :: sigma
         real(dp), intent(in) :: targets(:, :)
         real(dp), allocatable, intent(out) :: solutions(:, :)
         type(error_t), allocatable, intent(out) :: error
      end subroutine constraint_solve

      !> One eigen solve on the current factors: the nev eigenpairs nearest sigma in the
      !> complement of the deflated subspace, by ARPACK or the block method; z the Ritz vectors
      !> as the eigensolver returns them, lambda their Rayleigh quotients, both ascending in
      !> lambda. Statistics are added to result.
      module subroutine eigen_window(K, M, options, eigensolver, nev, nc, sigma, solver, &
            interrupt, deflation, z, lambda, result, log, error)
         type(csr_t), intent(in) :: K, M
         type(eigen_options_t), intent(in) :: options
         !> 'arpack', 'block' or 'block if possible' (ARPACK when the block sizes do not fit)
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
      end subroutine eigen_window

      !> Normalise, Rayleigh quotients, sort, residuals, M-orthonormality into result.
      module subroutine finish_pairs(K, M, C, z, result, error)
         type(csr_t), intent(in) :: K, M, C
         real(dp), intent(inout) :: z(:, :)
         type(eigen_result_t), intent(inout) :: result
         type(error_t), allocatable, intent(out) :: error
      end subroutine finish_pairs

      !> y = y - X (M X)^T y for the columns of y (twice: classical Gram-Schmidt with one
      !> re-orthogonalisation).
      module subroutine project_deflation(deflation, y)
         type(deflation_t), intent(in) :: deflation
         real(dp), intent(inout) :: y(:, :)
      end subroutine project_deflation

      !> ARPACK's ncv for nev wanted pairs: options%ncv when it exceeds nev (or is given for
      !> nev = num_modes), else max(2 nev + 1, 20), capped by the constrained dimension.
      pure integer(ip) module function arpack_basis_size(options, nev, dimension) result(ncv)
         type(eigen_options_t), intent(in) :: options
         integer(ip), intent(in) :: nev, dimension
      end function arpack_basis_size

      !> The permutation that sorts `values` ascending, equal values in their given order
      !> (Rayleigh quotients; the known pairs by their distance from the shift).
      pure module function ascending_order(values) result(order)
         real(dp), intent(in) :: values(:)
         integer(ip), allocatable :: order(:)
      end function ascending_order

      !> 'block' or 'arpack' for this problem (options%eigensolver, 'auto' by size).
      pure module function eigensolver_of(options, n, nc) result(name)
         type(eigen_options_t), intent(in) :: options
         integer(ip), intent(in) :: n, nc
         character(len=:), allocatable :: name
      end function eigensolver_of
   end interface

end module ffrf_modes_shift_invert
