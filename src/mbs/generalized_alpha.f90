!> Implicit generalized-alpha integrator for index-3 constrained mechanical systems
!> M(q) q'' + Phi_q^T lambda = f(q, q', t), Phi(q, t) = 0 (Arnold & Bruls, Multibody Syst Dyn 18
!> (2007) 185; theory.md section 4), with dense LAPACK linear algebra for the small systems of a
!> mechanism (tens of coordinates) and MUMPS's sparse LU for the iteration matrix of a large one
!> (order >= settings%sparse_threshold: chains of many flexible bodies). Every step runs with
!> the BLAS on one thread (galpha_step; docs/performance_threads.md).
!>
!> - Parameters from the spectral radius at infinity rho_inf (Chung & Hulbert 1993; theory.md 4.1).
!>   With the default index-3 constraints (settings%constraints = GALPHA_INDEX3), rho_inf = 1
!>   (trapezoidal rule, no numerical damping) is REFUSED for a system with constraints and
!>   accepted without them; the stabilized index-2 formulation (GALPHA_INDEX2, theory.md 4.6,
!>   generalized_alpha_index2.f90) imposes Phi = 0 and Phi_q q' + Phi_t = 0 with a second
!>   multiplier in the position update and accepts rho_inf = 1 (second order; an iteration
!>   matrix of order n + 2 nr instead of n + nr, and every iteration evaluates the residual).
!>   Index-3 constraints need rho_inf < 1 (Cardona &
!>   Geradin 1989; theory.md 4.3), and the stable range of h shrinks as rho_inf -> 1: measured
!>   on the 1 m Cartesian pendulum (theta0 = 1 rad, h = 1e-2 s) the multiplier grows from 18 N
!>   to 1.5e4 N in 10 s with rho_inf = 0.99 and Newton fails near 8 s with rho_inf = 1, while
!>   0.9 and 0.8 stay bounded over 40 s (0.99 with h = 1e-3 s stays bounded too).
!> - Consistent start (theory.md 4.3): positions and velocities are checked against Phi = 0 and
!>   Phi_q q' + Phi_t = 0 and, when violated, projected by the minimum-norm correction (or
!>   refused, settings%project_initial = .false.); q''_0 and lambda_0 solve the saddle-point
!>   system [[M, Phi_q^T], [Phi_q, 0]] [q''; lambda] = [f; g]; a_0 = q''_0.
!> - Step (theory.md 4.1): predictor q''_{n+1} = q''_n, lambda_{n+1} = lambda_n; Newton on
!>   [r_q; Phi] with the iteration matrix S_t (beta', gamma'), scaled by D_L = diag(beta h^2 I, I),
!>   D_R = diag(I, I/(beta h^2)) (theory.md 4.2) and equilibrated per constraint row, so that its
!>   conditioning does not grow as h**(-4).
!> - Convergence when both the weighted RMS increment (Arnold & Hante, JCND 12 (2017) 021002)
!>   ||dq_i/(atol + rtol|q_i|), dlambda_j/(lambda_atol + rtol|lambda_j|)||_rms <= 1 (or its
!>   estimate theta/(1 - theta) ||dx|| from the contraction rate theta, Hairer & Wanner IV.8)
!>   and the residual test max|r_q| <= rtol max(|M q''|, |f|, |Phi_q^T lambda|) + force_atol,
!>   max|Phi_i| <= atol hold.
!> - Attainable accuracy: each tolerance is raised by 10 times the round-off floor of its
!>   component (noise_floor, at each factorisation): for the residual test, the change of r_q
!>   and Phi under the rounding of q (|K_t| eps |q| and |Phi_q| eps |q|, K_t = d(M q'' +
!>   Phi_q^T lambda - f)/dq) plus eps times the magnitudes of the terms of r_q; for the
!>   increment test, the increment Newton produces from that residual noise (two solves with
!>   the factors). For well-conditioned systems the floors are far below atol/rtol and nothing
!>   changes. They matter for a stiff element between coordinates (k eps |q| in the residual)
!>   and for constraint rows that are redundant for rigid bodies but kept because stiff modal
!>   coordinates make them independent (an over-constrained loop through a flexible body):
!>   their multipliers are statically indeterminate reactions fixed by K_ff, and their
!>   round-off grows with K_ff. Measured on the engine with the RC set 1 rotating link (8 modes,
!>   eigenvalues x s; 7 such rows, smallest singular value 3.4e-4 of the row-normalised Phi_q),
!>   newton_atol 1e-12, rtol 1e-10, h = 1e-4 s: before, Newton (even full Newton with iterative
!>   refinement of the solves) cycled at weighted increments 1e2..7e3, the
!>   multipliers of those rows moving by 0.02 N at |lambda| 6e4 N for s = 100, and the run
!>   failed at t = 1e-4 s for s = 100 (as reported also at 5.3e-4 s for s >= 1e4; 21 rejected
!>   attempts in 3000 steps for s = 1); after, 0 rejected attempts for s = 1 .. 1e8
!>   (test_mbs_flexible_engine). Two masses joined by a spring of k = 1e9 .. 1e15 N/m with both
!>   positions prescribed failed at t = 0.008 s before and run without a rejected attempt
!>   after (test_mbs_stiff).
!>   From the second iteration a step whose increment test passes is accepted without the full
!>   residual evaluation at the new iterate when the iteration contracts clearly (rate theta <=
!>   skip_rate = 0.1) and the residual predicted there, theta times the one at the iterate the
!>   increment started from, passes; only Phi is evaluated there, and must pass (the constraint
!>   statistics stay exact). On the reference engine this took the residual evaluations from
!>   3.4 to 2.7 per step, with the same rotor angle and speed to the 8 digits printed.
!> - Iteration matrix (factor): S = [[M/c + gamma h C_t + beta h^2 K_t, Phi_q^T], [Phi_q, 0]]
!>   from the current M and Phi_q (known from the residual evaluation; they change fastest, with
!>   the bodies' rotation) and tangents K_t, C_t that a factorisation at the predictor of a step
!>   may keep from an earlier one, up to settings%tangent_reuse factorisations (a modified
!>   Newton in the small terms: gyroscopic, load and constraint-force derivatives, beta h^2 and
!>   gamma h times smaller than M). A refactorisation within a step (slow convergence) and the
!>   retry of a failed attempt always compute fresh tangents. Measured on the reference engine
!>   (engine_rc1, 20000 steps of 1e-4 s): tangents in 2503 of 20010 factorisations, the same
!>   rotor angle and speed to the 8 digits printed as with fresh tangents at every one.
!> - Jacobian policies (settings%jacobian): GALPHA_NEWTON_STEP (default) factorises at every
!>   step's predictor and keeps the factors within the step while they converge;
!>   GALPHA_NEWTON_FULL refactorises at every iteration; GALPHA_NEWTON_ADAPTIVE also keeps
!>   them across steps. On the reference engine (before the predicted-residual acceptance
!>   above) STEP needed 2.7 iterations and 3.4 residual evaluations per step against
!>   ADAPTIVE's 4.2 and 4.6 with 0.64 factorisations (the rotating link makes old factors
!>   converge at rates 0.03-0.1): 2.1 s against 2.6 s for the 2 s run.
!>   Within a step (both) and across steps (ADAPTIVE) the factors are refactored at the current
!>   iterate:
!>   * within a step, when the contraction rate theta = ||dx_k||/||dx_{k-1}|| of the current
!>     factors exceeds settings%refactor_rate, or when the iterations it predicts,
!>     log(estimate)/log(1/theta), exceed settings%refactor_iterations or the iterations left
!>     (a stale matrix at theta 0.1-0.2 otherwise ran out of iterations: measured 54 rejected
!>     steps in 3000 on the reference engine at newton_atol 1e-12, rtol 1e-10, now 0);
!>   * within a step, when the residual test fails and the residual contracts by less than
!>     refactor_rate while the increments already pass (at their round-off floor they no
!>     longer measure the progress: s = 1e8 above otherwise had 57 rejected attempts);
!>   * across steps of the same size (ADAPTIVE), only if the factors converged the step within
!>     settings%refactor_iterations iterations (the predictor's multipliers jump from step to
!>     step, and a stale matrix then needs many iterations: 7 per step on the reference engine
!>     before this rule, 3.4 after).
!>   A failed attempt on an old Jacobian is retried once with a fresh one before the step is
!>   cut. stats times the parts of a step (residual, tangent, factorisation, solves).
!> - Step control: on non-convergence, a singular iteration matrix or a NaN the step is cut by
!>   settings%step_cut and retried from the last converged state; after settings%grow_after
!>   accepted steps it grows back by 1/step_cut up to settings%h. Below settings%min_step the
!>   integrator returns FFRF_NUMERIC_ERROR naming the time, the step and the last residual; the
!>   last converged state stays in t, q, v, qdd, a, lambda.
!> - Redundant constraints: at the start (and every settings%rank_check_interval steps if > 0)
!>   the dependent rows of Phi_q are found by QR with column pivoting (find_redundant_rows; ties
!>   go to the earliest row, on every processor) and dropped from the equations; `dropped`
!>   lists them. Chosen split of the reactions: a dropped row's multiplier is reported as zero
!>   and the retained multipliers are the unique solution on the independent set (so the
!>   reaction of a redundant pair sits entirely on the kept row; for
!>   rigid bodies this is one admissible split among many, not physics).
!>
!> Files: this module (types, settings checks); its submodules generalized_alpha_start.f90
!> (init: the consistent start, redundant rows), generalized_alpha_step.f90 (step, run:
!> Newton, factors, step control), generalized_alpha_state.f90 (checkpoint state) and
!> generalized_alpha_index2.f90 (the stabilized index-2 blocks).
module ffrf_mbs_generalized_alpha
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_kinds, only: dp, ip, i8
   use ffrf_core_error, only: error_t, fatal_error, add_context, FFRF_INPUT_ERROR, &
      FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_finite, only: all_finite
   use ffrf_core_log, only: wall_time
   use ffrf_la_lapack, only: dposv
   use ffrf_la_blas_threads, only: begin_single_blas, end_single_blas
   use ffrf_mbs_dae_system, only: dae_system_t
   use ffrf_mbs_galpha_linalg, only: find_redundant_rows, kkt_matrix, kkt_complete, &
      kkt_factor, kkt_solve, kkt_sparse_t
   use ffrf_la_block_sparse, only: block_sparse_t
   implicit none
   private
   public :: galpha_settings_t, galpha_stats_t, galpha_integrator_t
   public :: chung_hulbert, check_galpha_settings
   public :: GALPHA_NEWTON_FULL, GALPHA_NEWTON_STEP, GALPHA_NEWTON_ADAPTIVE
   public :: GALPHA_SPARSE_THRESHOLD
   public :: GALPHA_INDEX3, GALPHA_INDEX2

   !> Safety factor on the round-off floors of the residual and the increment (noise_floor): the
   !> multiplier increments of the round-off cycle measured on the engine of
   !> test_mbs_flexible_engine (eigenvalues x 100, before the floor) were 0.03 to 1.5 times the
   !> estimated floor
   real(dp), parameter :: floor_factor = 10.0_dp

   !> Largest contraction rate of the Newton iteration at which a converged step is accepted on
   !> its predicted residual, without evaluating it (attempt)
   real(dp), parameter :: skip_rate = 0.1_dp

   !> Consecutive steps over settings%alternation_limit that stop a run (check_alternation)
   integer, parameter :: alternation_window = 20

   !> Jacobian policy: full Newton, a new iteration matrix at every iteration
   integer, parameter :: GALPHA_NEWTON_FULL = 1
   !> Jacobian policy: one iteration matrix per step (at the predictor)
   integer, parameter :: GALPHA_NEWTON_STEP = 2
   !> Jacobian policy: keep the factors across iterations and steps of equal size while the
   !> contraction rate stays below refactor_rate (default)
   integer, parameter :: GALPHA_NEWTON_ADAPTIVE = 3

   !> Default order of the iteration matrix (coordinates + kept constraint rows) from which it
   !> is factorised by the sparse LU (MUMPS, kkt_sparse_t) instead of LAPACK's dense dgetrf
   !> (settings%sparse_threshold). Measured on chains of flexible links (benchmark_threads,
   !> docs/performance_threads.md): the two meet at orders of 400 to 450, MUMPS's fixed costs
   !> (about 1 ms per factorisation) lose below, its linear growth wins above (1.6 times faster
   !> per step at order 816); 800 is the conservative end. The reference engines (iteration
   !> matrices of order 56 to 82) stay far below: dense, bitwise as before.
   integer, parameter :: GALPHA_SPARSE_THRESHOLD = 800

   !> Constraint formulation (settings%constraints): index 3, Phi(q, t) = 0 alone (default)
   integer, parameter :: GALPHA_INDEX3 = 1
   !> Constraint formulation: stabilized index 2 (Gear-Gupta-Leimkuhler), Phi = 0 and
   !> Phi_q q' + Phi_t = 0 with a second multiplier nu in the position update (theory.md 4.6;
   !> generalized_alpha_index2.f90)
   integer, parameter :: GALPHA_INDEX2 = 2

   !> Layout tag of export_state (first integer), changed with the state's contents
   integer(i8), parameter :: STATE_LAYOUT = 20261125_i8

   !> Settings of a run (the &integrator namelist maps onto these).
   type :: galpha_settings_t
      !> Spectral radius at infinity, in [0, 1]; 1 only for systems without constraints or
      !> with constraints = GALPHA_INDEX2
      real(dp) :: rho_inf = 0.8_dp
      !> Constraint formulation: GALPHA_INDEX3 (default) or GALPHA_INDEX2 (theory.md 4.6)
      integer :: constraints = GALPHA_INDEX3
      !> Time step (s); the nominal and largest step
      real(dp) :: h = 1.0e-3_dp
      !> Start time (s)
      real(dp) :: t_start = 0.0_dp
      !> End time (s)
      real(dp) :: t_end = 1.0_dp
      !> Absolute tolerance on position increments and on constraint residuals (m or rad)
      real(dp) :: newton_atol = 1.0e-10_dp
      !> Relative tolerance on increments of q and lambda and on the force balance
      real(dp) :: newton_rtol = 1.0e-8_dp
      !> Absolute tolerance on multiplier increments (N or N m per unit of constraint)
      real(dp) :: lambda_atol = 1.0e-8_dp
      !> Absolute floor of the force-balance residual (N)
      real(dp) :: force_atol = 1.0e-10_dp
      !> Newton iterations per attempt
      integer :: max_iterations = 10
      !> GALPHA_NEWTON_FULL, GALPHA_NEWTON_STEP (default) or GALPHA_NEWTON_ADAPTIVE
      integer :: jacobian = GALPHA_NEWTON_STEP
      !> Contraction rate above which an old iteration matrix is refactored, in (0, 1)
      real(dp) :: refactor_rate = 0.2_dp
      !> Predicted further iterations with an old iteration matrix (from its contraction rate)
      !> above which it is refactored
      integer :: refactor_iterations = 3
      !> Factorisations at the predictor of a step that may reuse the tangent matrices K_t, C_t
      !> of an earlier one (the iteration matrix is then rebuilt from the current M and Phi_q,
      !> which change fastest, and the kept tangents); 0: fresh tangents at every factorisation
      integer :: tangent_reuse = 8
      !> Smallest step before giving up (s)
      real(dp) :: min_step = 1.0e-9_dp
      !> Factor applied to the step after a failed attempt, in (0, 1)
      real(dp) :: step_cut = 0.5_dp
      !> Accepted steps at a reduced step before it grows by 1/step_cut
      integer :: grow_after = 4
      !> Relative tolerance of the rank-revealing QR that finds redundant constraint rows
      real(dp) :: rank_rtol = 1.0e-9_dp
      !> Recheck the redundant rows every this many steps (0: at the start only)
      integer :: rank_check_interval = 0
      !> Largest step-to-step alternating part of the multipliers, as a fraction of the largest
      !> |lambda| so far, before the run stops as unstable (0: no check); module header
      real(dp) :: alternation_limit = 0.25_dp
      !> Project inconsistent initial positions/velocities onto the constraints (else refuse)
      logical :: project_initial = .true.
      !> Order of the iteration matrix from which the sparse LU (MUMPS) replaces the dense one
      !> (GALPHA_SPARSE_THRESHOLD); 1: always sparse, huge(1): always dense
      integer :: sparse_threshold = GALPHA_SPARSE_THRESHOLD
      !> Restart checkpoints of a mechanism run (ffrf_app_mechanism_run; they do not change
      !> the integration): every this many seconds of wall time (0: none by time) and every
      !> this many steps (0: none by steps)
      real(dp) :: checkpoint_seconds = 2.0_dp
      integer :: checkpoint_steps = 0
   end type galpha_settings_t

   !> Counters and timings of a run.
   type :: galpha_stats_t
      !> Accepted steps
      integer(i8) :: steps = 0
      !> Rejected attempts (non-convergence, NaN, singular matrix)
      integer(i8) :: rejected_steps = 0
      !> Newton iterations (linear solves), accepted and rejected attempts
      integer(i8) :: newton_iterations = 0
      !> LU factorisations of the iteration matrix
      integer(i8) :: factorizations = 0
      !> Evaluations of the tangent matrices K_t, C_t (at most one per factorisation)
      integer(i8) :: tangents = 0
      !> Evaluations of the residual (mass, force, constraints, Jacobian)
      integer(i8) :: residual_evaluations = 0
      !> Wall time spent in init and step (s)
      real(dp) :: wall_seconds = 0.0_dp
      !> Parts of wall_seconds (s): residual evaluations (mass, force, constraints, Jacobian),
      !> tangent matrices of the system, assembly and LU factorisation of the iteration matrix,
      !> and the triangular solves
      real(dp) :: residual_seconds = 0.0_dp, tangent_seconds = 0.0_dp, factor_seconds = 0.0_dp
      real(dp) :: solve_seconds = 0.0_dp
      !> Smallest accepted step (s)
      real(dp) :: h_min = huge(1.0_dp)
      !> Order of the last iteration matrix, and the sparse LU's analyses (pattern changes)
      !> and factorisations (0 on the dense path)
      integer :: matrix_order = 0
      integer(i8) :: sparse_analyses = 0, sparse_factorizations = 0
      !> Entries of the sparse LU's pattern and of its factors (MUMPS INFOG(29))
      integer(i8) :: sparse_entries = 0, sparse_factor_entries = 0
      !> Seconds in MUMPS's analyses and factorisations (part of factor_seconds)
      real(dp) :: sparse_mumps_seconds = 0.0_dp
      !> Largest |Phi_i| over accepted steps, kept and dropped rows (m or rad)
      real(dp) :: max_constraint_violation = 0.0_dp
   end type galpha_stats_t

   !> The integrator and its state at the last converged time (theory.md 4.1).
   type :: galpha_integrator_t
      !> Settings of the run
      type(galpha_settings_t) :: settings
      !> Chung-Hulbert parameters (theory.md 4.1)
      real(dp) :: alpha_m = 0.0_dp, alpha_f = 0.0_dp, gamma = 0.5_dp, beta = 0.25_dp
      !> Number of coordinates and of constraint equations
      integer :: n = 0, nc = 0
      !> Time of the last converged state (s)
      real(dp) :: t = 0.0_dp
      !> Current step (s); below settings%h after cuts
      real(dp) :: h = 0.0_dp
      !> Generalized coordinates, velocities, accelerations q'' and algorithmic accelerations a
      real(dp), allocatable :: q(:), v(:), qdd(:), a(:)
      !> Lagrange multipliers, nc; zero on dropped rows
      real(dp), allocatable :: lambda(:)
      !> Constraint rows kept in the equations (independent), ascending
      integer, allocatable :: active(:)
      !> Redundant constraint rows dropped from the equations, ascending
      integer, allocatable :: dropped(:)
      !> Counters and timings
      type(galpha_stats_t) :: stats
      !> Notes for the log (dropped rows, projected start), one per line
      character(len=:), allocatable :: notes
      !> Weighted increment and residual norms of the last Newton iteration (<= 1: converged)
      real(dp) :: last_increment = 0.0_dp, last_residual = 0.0_dp
      !> LU factors of the scaled iteration matrix, its pivots and constraint-row scale
      real(dp), allocatable, private :: lu(:, :), row_scale(:)
      !> Round-off floor of the Newton increment at the factored state: |dq_i| (n) and
      !> |dlambda_j| (kept rows) that round-off of the state alone produces (noise_floor)
      real(dp), allocatable, private :: increment_floor(:)
      !> Round-off floors of r_q (n, N) and of Phi on the kept rows (m or rad) (noise_floor)
      real(dp), allocatable, private :: residual_floor(:), constraint_floor(:)
      integer(ip), allocatable, private :: pivots(:)
      !> Kept tangent matrices K_t = d(M q'' + Phi_q^T lambda - f)/dq and C_t = -df/dq' (n x n)
      !> and the factorisations that have used them since they were computed
      real(dp), allocatable, private :: tangent_K(:, :), tangent_C(:, :)
      integer, private :: tangent_uses = huge(1)
      !> The sparse path (order >= settings%sparse_threshold): the kept tangents block-sparse
      !> (system%tangents_sparse), whether they are valid, and the work matrix M/c + gamma h C_t +
      !> beta h^2 K_t; nothing n x n is formed, as
      !> docs/performance_threads.md "The iteration matrix: dense or sparse LU" describes
      type(block_sparse_t), private :: sparse_K, sparse_C, sparse_A
      logical, private :: sparse_tangent = .false.
      !> Step the round-off floors were computed for (s); negative: none
      real(dp), private :: h_floor = -1.0_dp
      !> Multipliers of the last accepted steps of equal size (nc x 4, newest last), how many
      !> are valid, and the largest |lambda_j| of the run (alternation check)
      real(dp), allocatable, private :: lambda_history(:, :)
      integer, private :: history_count = 0
      real(dp), private :: lambda_peak = 0.0_dp
      !> Consecutive steps with the alternation above the limit
      integer, private :: alternation_steps = 0
      !> Step the factors were computed for (s); negative: no valid factors
      real(dp), private :: h_factored = -1.0_dp
      !> Accepted steps since the last cut
      integer, private :: successes = 0
      !> Whether the next step may start on the current factors (GALPHA_NEWTON_ADAPTIVE)
      logical, private :: reuse_factors = .false.
      !> Sparse LU of the iteration matrix when its order reaches settings%sparse_threshold
      !> (then `lu` is not used: the matrix goes to MUMPS as triplets). A pointer: copies of
      !> the integrator (the output's state before the last step) share it and never solve
      !> with it; after import_state the next step factorises anew.
      type(kkt_sparse_t), pointer, private :: sparse => null()
   contains
      !> Check settings, detect redundant rows, make the start consistent
      procedure :: init => galpha_init
      !> Advance one accepted step (cutting and retrying as needed), up to t_end
      procedure :: step => galpha_step
      !> Advance to settings%t_end
      procedure :: run => galpha_run
      !> The whole state that influences later steps, as flat arrays (checkpoint)
      procedure :: export_state => galpha_export_state
      !> Restore a state of export_state (restart)
      procedure :: import_state => galpha_import_state
   end type galpha_integrator_t

   !> Work state of one attempted step
   type :: trial_t
      real(dp), allocatable :: q(:), v(:), qdd(:), lambda(:), a_base(:)
      real(dp), allocatable :: M(:, :), Phi_q(:, :), r_q(:), phi(:)
      !> On the sparse path M and Phi_q block-sparse instead (system%mass_sparse,
      !> system%constraints_and_jacobian_sparse)
      logical :: sparse = .false.
      type(block_sparse_t) :: M_sparse, Phi_sparse
      real(dp) :: force_scale = 0.0_dp
      !> Index 2 only (theory.md 4.6): the velocity constraints g = Phi_q q' + Phi_t (nc), the
      !> direction of the position correction, B = Phi_q^T of the kept rows at the step's
      !> predictor, each column divided by its largest entry (n x nr), and beta h / gamma, the
      !> factor that turns g into a position-sized residual (s)
      real(dp), allocatable :: g(:), B(:, :)
      real(dp) :: velocity_scale = 0.0_dp
      !> Index 2 on the sparse path: B = Phi_q(active, :)^T diag(B_scale), Phi_q at the predictor
      !> block-sparse (all rows), B_scale (nr) the inverse largest entries
      type(block_sparse_t) :: B_sparse
      real(dp), allocatable :: B_scale(:)
   end type trial_t

   interface
      !> Check the settings, find redundant constraint rows, make (q0, v0) consistent (projection
      !> or refusal) and solve for q''_0 and lambda_0 (theory.md 4.3). Calls system%accepted_step
      !> once at t_start.
      !> (init_once with the BLAS on one thread: galpha_step.)
      module subroutine galpha_init(self, system, settings, q0, v0, error)
         !> The integrator
         class(galpha_integrator_t), intent(out) :: self
         !> The mechanical system
         class(dae_system_t), intent(inout) :: system
         !> Settings of the run
         type(galpha_settings_t), intent(in) :: settings
         !> Initial coordinates, n
         real(dp), intent(in) :: q0(:)
         !> Initial velocities, n
         real(dp), intent(in) :: v0(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine galpha_init

      !> One accepted step (step_once) with the BLAS on one thread, then back to the count it had
      !> (issue 24): the iteration matrix of a mechanism is small (tens to hundreds of unknowns),
      !> and threaded LAPACK on a 100 x 100 matrix runs 30 times slower on a busy 2-core machine
      !> than on one thread. The stages that keep the user's threads (--threads) are the modes
      !> (ARPACK on MUMPS factors); the log's [threads] line says so. A caller stepping in a loop
      !> sets one thread once around the loop (the mechanism session's advance), so that this
      !> switch does nothing: OpenBLAS switched back to its count after every step slowed the
      !> steps by 25 to 70 % on a busy machine (mechanism_session.f90, session_advance).
      module subroutine galpha_step(self, system, error)
         !> The integrator (after init)
         class(galpha_integrator_t), intent(inout) :: self
         !> The mechanical system
         class(dae_system_t), intent(inout) :: system
         type(error_t), allocatable, intent(out) :: error
      end subroutine galpha_step

      !> Advance to settings%t_end.
      module subroutine galpha_run(self, system, error)
         class(galpha_integrator_t), intent(inout) :: self
         class(dae_system_t), intent(inout) :: system
         type(error_t), allocatable, intent(out) :: error
      end subroutine galpha_run

      !> The whole state of the integrator after a step, everything that influences later steps
      !> (the last converged state, the current step, the kept factors, tangents and round-off
      !> floors, the multiplier history, the counters), as a real and an integer array for a
      !> checkpoint file: import_state on an integrator initialised for the same system continues
      !> bit for bit as this one would. The settings are not part of it (they come from the case).
      module subroutine galpha_export_state(self, reals, ints)
         class(galpha_integrator_t), intent(in) :: self
         real(dp), allocatable, intent(out) :: reals(:)
         integer(i8), allocatable, intent(out) :: ints(:)
      end subroutine galpha_export_state

      !> Restore a state of export_state into an integrator initialised (init) for the same
      !> system and settings; FFRF_INPUT_ERROR when the arrays do not fit it.
      module subroutine galpha_import_state(self, reals, ints, error)
         class(galpha_integrator_t), intent(inout) :: self
         real(dp), intent(in) :: reals(:)
         integer(i8), intent(in) :: ints(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine galpha_import_state
      !> Find the redundant rows of Phi_q at the current q (generalized_alpha_start.f90).
      module subroutine detect_redundant(self, system, error)
         type(galpha_integrator_t), intent(inout) :: self
         class(dae_system_t), intent(inout) :: system
         type(error_t), allocatable, intent(out) :: error
      end subroutine detect_redundant

      !> Stop on the weak instability of index-3 generalized-alpha near rho_inf = 1: multipliers
      !> alternating from step to step (generalized_alpha_state.f90).
      module subroutine check_alternation(self, h, last, error)
         type(galpha_integrator_t), intent(inout) :: self
         !> The step just accepted (s)
         real(dp), intent(in) :: h
         !> Whether it was the last, shortened step
         logical, intent(in) :: last
         type(error_t), allocatable, intent(out) :: error
      end subroutine check_alternation

      !> Index 2: the position-correction direction B at the predictor and beta h / gamma
      !> (generalized_alpha_index2.f90).
      module subroutine index2_direction(self, h, trial)
         type(galpha_integrator_t), intent(in) :: self
         real(dp), intent(in) :: h
         type(trial_t), intent(inout) :: trial
      end subroutine index2_direction

      !> Index 2: the blocks of nu in the scaled iteration matrix, around the index-3 matrix
      !> already in self%lu(:n + nr, :n + nr).
      module subroutine index2_blocks(self, h, trial)
         type(galpha_integrator_t), intent(inout) :: self
         real(dp), intent(in) :: h
         type(trial_t), intent(in) :: trial
      end subroutine index2_blocks

      !> Index 2: the position increment dq = x + B z of a Newton solution [x; y; z].
      module function index2_increment(self, trial, dx) result(dq)
         type(galpha_integrator_t), intent(in) :: self
         type(trial_t), intent(in) :: trial
         real(dp), intent(in) :: dx(:)
         real(dp) :: dq(self%n)
      end function index2_increment

      !> Index 2 on the sparse path: nu's columns of the scaled iteration matrix as triplets,
      !> beta h^2 K_t B (rows 1..n) and S Phi_q B (the multiplier rows), O(entries) from
      !> B's blocks paired with K_t's and Phi_q's in each column group (product_triplets).
      module subroutine index2_sparse_triplets(self, h, trial, irn, jcn, values)
         type(galpha_integrator_t), intent(in) :: self
         real(dp), intent(in) :: h
         type(trial_t), intent(in) :: trial
         integer(ip), allocatable, intent(out) :: irn(:), jcn(:)
         real(dp), allocatable, intent(out) :: values(:)
      end subroutine index2_sparse_triplets

      !> max |x_i|, 0 for an empty vector.
      pure module function max_abs(x) result(largest)
         real(dp), intent(in) :: x(:)
         real(dp) :: largest
      end function max_abs

      ! the linear algebra of the iteration matrix (generalized_alpha_linear.f90)
      !> The sparse path of factor: A = beta h^2 K_t + M/c + gamma h C_t block-sparse, the
      !> constraint rows scaled as kkt_complete does (to the largest |A_ii|), both constraint
      !> blocks and the zero diagonal of the lower-right block as triplets for MUMPS. O(entries).
      module subroutine sparse_assemble(self, h, c_af, trial, singular, error)
         type(galpha_integrator_t), intent(inout) :: self
         real(dp), intent(in) :: h, c_af
         type(trial_t), intent(in) :: trial
         logical, intent(out) :: singular
         type(error_t), allocatable, intent(out) :: error
      end subroutine sparse_assemble

      !> Round-off floors of the residual and of the Newton increment (attainable accuracy). The
      !> residual cannot be evaluated more accurately than the rounding of the state allows: q is
      !> known to u_i = eps |q_i|, which changes r_q by |K_t| u (K_t = d(M q'' + Phi_q^T lambda -
      !> f)/dq: a stiff element between coordinates of magnitude |q| leaves k eps |q|) and Phi by
      !> |Phi_q| u, and each term of r_q is rounded to eps (|M| |q''| + |Phi_q^T| |lambda| + |f|).
      !> (q'' and q' are stored apart from q and move by sub-ulp amounts of q, so M/c and C_t add
      !> nothing.) Newton maps this residual noise into increments S^-1 [beta h^2 noise_r;
      !> noise_Phi]: for constraint rows whose multipliers are statically indeterminate reactions
      !> fixed by a stiff element (rows independent only through stiff modal coordinates) these
      !> are far above lambda_atol + rtol |lambda|, and the iterations cycle at that level without
      !> converging. The increment floor is estimated by two solves with the noise vector under two
      !> sign patterns (round-off has no preferred sign).
      module subroutine noise_floor(self, h, trial, error)
         type(galpha_integrator_t), intent(inout) :: self
         !> Step (s)
         real(dp), intent(in) :: h
         !> The trial state; the tangent K_t = d(M q'' + Phi_q^T lambda - f)/dq at it is the kept
         !> one (tangent_K, or sparse_K on the sparse path)
         type(trial_t), intent(in) :: trial
         type(error_t), allocatable, intent(out) :: error
      end subroutine noise_floor

      !> Solve with the factors of the iteration matrix (factor): LAPACK's dgetrs on the dense LU,
      !> or MUMPS when the order reaches settings%sparse_threshold (factorised again from the
      !> kept triplets when the factors are missing).
      module subroutine solve_iteration(self, x, error)
         type(galpha_integrator_t), intent(inout) :: self
         !> Right-hand side on entry, solution on exit
         real(dp), intent(inout) :: x(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine solve_iteration

      !> M q'' and Phi_q^T lambda at a trial (absolute: |M| |q''| and |Phi_q|^T |lambda|), from the
      !> dense or the block-sparse matrices.
      module subroutine trial_products(trial, absolute, inertia, reaction)
         type(trial_t), intent(in) :: trial
         logical, intent(in) :: absolute
         real(dp), intent(out) :: inertia(:), reaction(:)
      end subroutine trial_products
   end interface

contains

   !> Chung-Hulbert parameters of theory.md 4.1: alpha_m = (2 rho - 1)/(rho + 1),
   !> alpha_f = rho/(rho + 1), gamma = 1/2 + alpha_f - alpha_m, beta = (gamma + 1/2)**2/4.
   pure subroutine chung_hulbert(rho_inf, alpha_m, alpha_f, gamma, beta)
      !> Spectral radius at infinity, in [0, 1]
      real(dp), intent(in) :: rho_inf
      !> Weights of the algorithmic acceleration (theory.md 4.1)
      real(dp), intent(out) :: alpha_m, alpha_f
      !> Newmark parameters
      real(dp), intent(out) :: gamma, beta
      alpha_m = (2.0_dp * rho_inf - 1.0_dp) / (rho_inf + 1.0_dp)
      alpha_f = rho_inf / (rho_inf + 1.0_dp)
      gamma = 0.5_dp + alpha_f - alpha_m
      beta = 0.25_dp * (gamma + 0.5_dp)**2
   end subroutine chung_hulbert

   !> Range checks of the settings; each message names the key, the value and the allowed range.
   subroutine check_galpha_settings(settings, error)
      !> Settings to check
      type(galpha_settings_t), intent(in) :: settings
      type(error_t), allocatable, intent(out) :: error
      character(len=*), parameter :: where = 'generalized-alpha settings: '
      associate (s => settings)
         if (.not. (s%rho_inf >= 0.0_dp .and. s%rho_inf <= 1.0_dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // 'rho_inf = ' // to_str(s%rho_inf) &
               // ', must lie in [0, 1] (0.6 to 0.9 recommended for index-3 constraints)')
         else if (.not. (s%h > 0.0_dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // 'h = ' // to_str(s%h) // &
               ' s, must be positive')
         else if (.not. (s%t_end > s%t_start)) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // 't_end = ' // to_str(s%t_end) // &
               ' s, must be after t_start = ' // to_str(s%t_start) // ' s')
         else if (.not. (s%newton_atol > 0.0_dp .and. s%newton_rtol > 0.0_dp .and. &
            s%lambda_atol > 0.0_dp .and. s%force_atol >= 0.0_dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // 'newton_atol = ' // &
               to_str(s%newton_atol) // ', newton_rtol = ' // to_str(s%newton_rtol) // &
               ', lambda_atol = ' // to_str(s%lambda_atol) // ', force_atol = ' // &
               to_str(s%force_atol) // ': tolerances must be positive (force_atol >= 0)')
         else if (s%max_iterations < 1) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // 'max_iterations = ' // &
               to_str(s%max_iterations) // ', must be at least 1')
         else if (s%constraints /= GALPHA_INDEX3 .and. s%constraints /= GALPHA_INDEX2) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // 'constraints = ' // &
               to_str(s%constraints) // ', must be 1 (index 3) or 2 (stabilized index 2)')
         else if (s%jacobian < GALPHA_NEWTON_FULL .or. s%jacobian > GALPHA_NEWTON_ADAPTIVE) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // 'jacobian = ' // &
               to_str(s%jacobian) // ', must be 1 (full Newton), 2 (per step) or 3 (adaptive)')
         else if (.not. (s%refactor_rate > 0.0_dp .and. s%refactor_rate < 1.0_dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // 'refactor_rate = ' // &
               to_str(s%refactor_rate) // ', must lie in (0, 1)')
         else if (.not. (s%checkpoint_seconds >= 0.0_dp .and. s%checkpoint_seconds <= &
            1.0e9_dp) .or. s%checkpoint_steps < 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // 'checkpoint_seconds = ' // &
               to_str(s%checkpoint_seconds) // ', checkpoint_steps = ' // &
               to_str(s%checkpoint_steps) // ': must be >= 0 (0: no checkpoints by wall ' // &
               'time, resp. by steps)')
         else if (s%tangent_reuse < 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // 'tangent_reuse = ' // &
               to_str(s%tangent_reuse) // ', must be 0 (fresh tangents) or positive')
         else if (s%refactor_iterations < 1) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // 'refactor_iterations = ' // &
               to_str(s%refactor_iterations) // ', must be at least 1')
         else if (.not. (s%min_step > 0.0_dp .and. s%min_step <= s%h)) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // 'min_step = ' // &
               to_str(s%min_step) // ' s, must lie in (0, h = ' // to_str(s%h) // ' s]')
         else if (.not. (s%step_cut > 0.0_dp .and. s%step_cut < 1.0_dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // 'step_cut = ' // &
               to_str(s%step_cut) // ', must lie in (0, 1)')
         else if (s%grow_after < 1) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // 'grow_after = ' // &
               to_str(s%grow_after) // ', must be at least 1')
         else if (.not. (s%rank_rtol > 0.0_dp .and. s%rank_rtol < 1.0_dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // 'rank_rtol = ' // &
               to_str(s%rank_rtol) // ', must lie in (0, 1)')
         else if (.not. (s%alternation_limit >= 0.0_dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // 'alternation_limit = ' // &
               to_str(s%alternation_limit) // ', must be 0 (no check) or positive')
         else if (s%rank_check_interval < 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // 'rank_check_interval = ' // &
               to_str(s%rank_check_interval) // ', must be 0 (start only) or positive')
         end if
      end associate
   end subroutine check_galpha_settings

end module ffrf_mbs_generalized_alpha
