!> Implicit generalized-alpha integrator for index-3 constrained mechanical systems
!> M(q) q'' + Phi_q^T lambda = f(q, q', t), Phi(q, t) = 0 (Arnold & Bruls, Multibody Syst Dyn 18
!> (2007) 185; theory.md section 4), with dense LAPACK linear algebra for the small systems of a
!> mechanism (tens of coordinates) and MUMPS's sparse LU for the iteration matrix of a large one
!> (order >= settings%sparse_threshold: chains of many flexible bodies). Every step runs with
!> the BLAS on one thread (galpha_step; docs/performance_threads.md).
!>
!> - Parameters from the spectral radius at infinity rho_inf (Chung & Hulbert 1993; theory.md 4.1).
!>   rho_inf = 1 (trapezoidal rule, no numerical damping) is REFUSED for a system with
!>   constraints and accepted without them. Index-3 constraints need rho_inf < 1 (Cardona &
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
!>   and the retained multipliers are the unique solution on the independent set (so the reaction of a redundant pair sits entirely on the kept row; for
!>   rigid bodies this is one admissible split among many, not physics).
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
   implicit none
   private
   public :: galpha_settings_t, galpha_stats_t, galpha_integrator_t
   public :: chung_hulbert, check_galpha_settings
   public :: GALPHA_NEWTON_FULL, GALPHA_NEWTON_STEP, GALPHA_NEWTON_ADAPTIVE
   public :: GALPHA_SPARSE_THRESHOLD

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

   !> Layout tag of export_state (first integer), changed with the state's contents
   integer(i8), parameter :: STATE_LAYOUT = 20261125_i8

   !> Settings of a run (the &integrator namelist maps onto these).
   type :: galpha_settings_t
      !> Spectral radius at infinity, in [0, 1]; 1 only for systems without constraints
      real(dp) :: rho_inf = 0.8_dp
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
      !> (then `lu` keeps the assembled matrix, not factors). A pointer: copies of the
      !> integrator (the output's state before the last step) share it and never solve with
      !> it; after import_state it is factorised again from `lu` at the first solve.
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
      real(dp) :: force_scale = 0.0_dp
   end type trial_t

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

   !> Check the settings, find redundant constraint rows, make (q0, v0) consistent (projection
   !> or refusal) and solve for q''_0 and lambda_0 (theory.md 4.3). Calls system%accepted_step
   !> once at t_start.
   !> (init_once with the BLAS on one thread: galpha_step.)
   subroutine galpha_init(self, system, settings, q0, v0, error)
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
      integer :: before
      before = begin_single_blas()
      call init_once(self, system, settings, q0, v0, error)
      call end_single_blas(before)
   end subroutine galpha_init

   !> The work of galpha_init.
   subroutine init_once(self, system, settings, q0, v0, error)
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
      real(dp) :: start
      start = wall_time()
      call check_galpha_settings(settings, error)
      if (allocated(error)) return
      self%settings = settings
      call chung_hulbert(settings%rho_inf, self%alpha_m, self%alpha_f, self%gamma, self%beta)
      self%notes = ''
      self%n = system%num_coordinates()
      self%nc = system%num_constraints()
      if (settings%rho_inf >= 1.0_dp .and. self%nc > 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'generalized-alpha settings: rho_inf = 1 ' &
            // '(no numerical damping) is unstable with index-3 constraints (' // &
            to_str(self%nc) // ' constraint equations here): the multipliers grow without ' // &
            'bound; use rho_inf < 1, typically 0.6 to 0.9')
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
   subroutine detect_redundant(self, system, error)
      type(galpha_integrator_t), intent(inout) :: self
      class(dae_system_t), intent(inout) :: system
      type(error_t), allocatable, intent(out) :: error
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
   end subroutine detect_redundant

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

   !> Advance to settings%t_end.
   subroutine galpha_run(self, system, error)
      !> The integrator (after init)
      class(galpha_integrator_t), intent(inout) :: self
      !> The mechanical system
      class(dae_system_t), intent(inout) :: system
      type(error_t), allocatable, intent(out) :: error
      do while (self%t < self%settings%t_end)
         call self%step(system, error)
         if (allocated(error)) return
      end do
   end subroutine galpha_run

   !> One accepted step (step_once) with the BLAS on one thread, then back to the count it had
   !> (issue 24): the iteration matrix of a mechanism is small (tens to hundreds of unknowns),
   !> and threaded LAPACK on a 100 x 100 matrix runs 30 times slower on a busy 2-core machine
   !> than on one thread. The stages that keep the user's threads (--threads) are the modes
   !> (ARPACK on MUMPS factors); the log's [threads] line says so. A caller stepping in a loop
   !> sets one thread once around the loop (the mechanism session's advance), so that this
   !> switch does nothing: OpenBLAS switched back to its count after every step slowed the
   !> steps by 25 to 70 % on a busy machine (mechanism_session.f90, session_advance).
   subroutine galpha_step(self, system, error)
      !> The integrator (after init)
      class(galpha_integrator_t), intent(inout) :: self
      !> The mechanical system
      class(dae_system_t), intent(inout) :: system
      type(error_t), allocatable, intent(out) :: error
      integer :: before
      before = begin_single_blas()
      call step_once(self, system, error)
      call end_single_blas(before)
   end subroutine galpha_step

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
   subroutine check_alternation(self, h, last, error)
      type(galpha_integrator_t), intent(inout) :: self
      !> The step just accepted (s)
      real(dp), intent(in) :: h
      !> Whether it was the last, shortened step
      logical, intent(in) :: last
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: alternating
      if (self%nc == 0 .or. self%settings%alternation_limit <= 0.0_dp) return
      if (.not. allocated(self%lambda_history)) allocate (self%lambda_history(self%nc, 4))
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
   end subroutine check_alternation

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
      logical :: need_factor, ok
      n = self%n
      nr = size(self%active)
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
      if (.not. allocated(trial%M)) allocate (trial%M(n, n), trial%Phi_q(self%nc, n), &
         trial%r_q(n), trial%phi(self%nc))
      call evaluate(self, system, t_new, trial, error)
      if (allocated(error)) return
      if (.not. finite_trial(trial)) then
         reason = 'NaN or Inf in the residual at the predictor'
         return
      end if
      need_factor = fresh_start .or. self%h_factored < 0.0_dp .or. &
         abs(h - self%h_factored) > 1.0e-10_dp * h .or. &
         self%settings%jacobian /= GALPHA_NEWTON_ADAPTIVE .or. .not. self%reuse_factors
      used_old = .not. need_factor
      age = 0
      previous = huge(1.0_dp)
      previous_residual = huge(1.0_dp)
      allocate (dx(n + nr))
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
         dx(n + 1:) = -self%row_scale * trial%phi(self%active)
         clock = wall_time()
         call solve_iteration(self, dx, error)
         self%stats%solve_seconds = self%stats%solve_seconds + wall_time() - clock
         if (allocated(error)) return
         self%stats%newton_iterations = self%stats%newton_iterations + 1
         if (.not. all_finite(dx)) then
            reason = 'NaN or Inf in the Newton increment'
            return
         end if
         trial%q = trial%q + dx(:n)
         trial%v = trial%v + gamma_p * dx(:n)
         trial%qdd = trial%qdd + beta_p * dx(:n)
         trial%lambda(self%active) = trial%lambda(self%active) + self%row_scale * dx(n + 1:) / bh2
         increment = increment_norm(self, trial, dx, bh2)
         ! Error of the iterate: the increment, or from the contraction rate theta the
         ! estimate theta/(1 - theta) ||dx|| of the remaining ones (Hairer & Wanner, IV.8).
         estimate = increment
         rate = huge(1.0_dp)
         if (iteration >= 2) then
            rate = increment / max(previous, tiny(1.0_dp))
            if (rate < 1.0_dp) estimate = min(increment, rate / (1.0_dp - rate) * increment)
         end if
         if (rate <= skip_rate) then
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
         call evaluate(self, system, t_new, trial, error)
         if (allocated(error)) return
         if (.not. finite_trial(trial)) then
            reason = 'NaN or Inf in the residual (force, mass or constraints)'
            return
         end if
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
   subroutine evaluate(self, system, t, trial, error)
      type(galpha_integrator_t), intent(inout) :: self
      class(dae_system_t), intent(inout) :: system
      real(dp), intent(in) :: t
      type(trial_t), intent(inout) :: trial
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: f(self%n), inertia(self%n), reaction(self%n), clock
      clock = wall_time()
      call system%mass(trial%q, trial%M, error)
      if (allocated(error)) return
      call system%force(trial%q, trial%v, t, f, error)
      if (allocated(error)) return
      call system%constraints_and_jacobian(trial%q, t, trial%phi, trial%Phi_q, error)
      if (allocated(error)) return
      inertia = matmul(trial%M, trial%qdd)
      reaction = matmul(trial%lambda, trial%Phi_q)
      trial%r_q = inertia + reaction - f
      trial%force_scale = max(max_abs(inertia), max_abs(reaction), max_abs(f))
      self%stats%residual_evaluations = self%stats%residual_evaluations + 1
      self%stats%residual_seconds = self%stats%residual_seconds + wall_time() - clock
   end subroutine evaluate

   !> Tangent at the trial state and LU factors of the scaled iteration matrix (theory.md 4.1,
   !> 4.2): D_L S_t D_R = [[M/c + gamma h C_t + beta h^2 K_t, Phi_q^T], [Phi_q, 0]] with
   !> c = (1 - alpha_f)/(1 - alpha_m), K_t = d(M q'')/dq + d(Phi_q^T lambda)/dq - df/dq,
   !> C_t = -df/dq' (kept ones up to settings%tangent_reuse, module header), then the constraint
   !> rows equilibrated (kkt_complete).
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
      integer :: n, nr
      logical :: new_tangent, singular
      n = self%n
      nr = size(self%active)
      ok = .false.
      clock = wall_time()
      c_af = (1.0_dp - self%alpha_f) / (1.0_dp - self%alpha_m)
      new_tangent = fresh_tangent .or. self%tangent_uses >= self%settings%tangent_reuse .or. &
         .not. allocated(self%tangent_K)
      if (new_tangent) then
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
      ! The iteration matrix is assembled in the factor storage, kept between factorisations.
      ! (M is screened with the residual, the tangents when computed; a NaN that got through
      ! shows in the Newton increment.)
      if (allocated(self%lu)) then
         if (size(self%lu, 1) /= n + nr) deallocate (self%lu, self%row_scale)
      end if
      if (.not. allocated(self%lu)) allocate (self%lu(n + nr, n + nr), self%row_scale(nr))
      self%lu(:n, :n) = self%beta * h**2 * self%tangent_K + trial%M / c_af + self%gamma * h * &
         self%tangent_C
      call kkt_complete(self%lu, trial%Phi_q, self%active, self%row_scale)
      self%stats%matrix_order = n + nr
      if (n + nr >= self%settings%sparse_threshold) then
         ! Sparse LU (MUMPS): lu keeps the assembled matrix
         if (.not. associated(self%sparse)) allocate (self%sparse)
         call self%sparse%factor(self%lu, singular, error)
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
         call kkt_factor(self%lu, self%pivots, info)
      end if
      if (info /= 0) then
         self%stats%factor_seconds = self%stats%factor_seconds + wall_time() - clock
         return
      end if
      ! The floors are magnitudes: they are kept with the tangent they were computed from
      if (new_tangent .or. self%h_floor /= h) call noise_floor(self, h, self%tangent_K, trial, &
         error)
      if (allocated(error)) return
      self%stats%factor_seconds = self%stats%factor_seconds + wall_time() - clock
      self%h_factored = h
      ok = .true.
   end subroutine factor

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
   subroutine noise_floor(self, h, tangent, trial, error)
      type(galpha_integrator_t), intent(inout) :: self
      !> Step (s)
      real(dp), intent(in) :: h
      !> Tangent K_t = d(M q'' + Phi_q^T lambda - f)/dq at the trial state, n x n
      real(dp), intent(in) :: tangent(:, :)
      type(trial_t), intent(in) :: trial
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: u(:), noise(:), x(:), terms(:)
      real(dp) :: bh2, signum
      integer :: n, nr, i, pattern
      n = self%n
      nr = size(self%active)
      bh2 = self%beta * h**2
      allocate (u(n), terms(n), noise(n + nr), x(n + nr))
      u = epsilon(1.0_dp) * abs(trial%q)
      terms = matmul(abs(trial%M), abs(trial%qdd)) + matmul(abs(trial%lambda), &
         abs(trial%Phi_q)) + abs(matmul(trial%M, trial%qdd) + matmul(trial%lambda, &
         trial%Phi_q) - trial%r_q)
      self%residual_floor = matmul(abs(tangent), u) + epsilon(1.0_dp) * terms
      self%constraint_floor = matmul(abs(trial%Phi_q(self%active, :)), u)
      noise(:n) = bh2 * self%residual_floor
      if (nr > 0) noise(n + 1:) = self%row_scale * self%constraint_floor
      self%increment_floor = [(0.0_dp, i=1, n + nr)]
      do pattern = 1, 2
         do i = 1, n + nr
            ! pattern 1: alternating signs; pattern 2: signs of sin(i^2) (no period)
            if (pattern == 1) then
               signum = merge(1.0_dp, -1.0_dp, mod(i, 2) == 0)
            else
               signum = merge(1.0_dp, -1.0_dp, sin(real(i, dp)**2) >= 0.0_dp)
            end if
            x(i) = signum * noise(i)
         end do
         call solve_iteration(self, x, error)
         if (allocated(error)) return
         self%increment_floor = max(self%increment_floor, abs(x))
      end do
      if (nr > 0) self%increment_floor(n + 1:) = self%row_scale * &
         self%increment_floor(n + 1:) / bh2
      self%h_floor = h
   end subroutine noise_floor

   !> Solve with the factors of the iteration matrix (factor): LAPACK's dgetrs on the dense LU,
   !> or MUMPS when the order reaches settings%sparse_threshold (factorised again from the
   !> assembled matrix in `lu` when the factors are missing: after import_state).
   subroutine solve_iteration(self, x, error)
      type(galpha_integrator_t), intent(inout) :: self
      !> Right-hand side on entry, solution on exit
      real(dp), intent(inout) :: x(:)
      type(error_t), allocatable, intent(out) :: error
      logical :: singular
      if (size(x) < self%settings%sparse_threshold) then
         call kkt_solve(self%lu, self%pivots, x)
         return
      end if
      if (.not. associated(self%sparse)) allocate (self%sparse)
      if (.not. self%sparse%is_factorised()) then
         call self%sparse%factor(self%lu, singular, error)
         if (.not. allocated(error) .and. singular) call fatal_error(error, &
            FFRF_NUMERIC_ERROR, 'the restored iteration matrix is singular')
         if (allocated(error)) return
      end if
      call self%sparse%solve(x, error)
   end subroutine solve_iteration

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
      norm = 0.0_dp
      if (size(self%active) > 0) norm = maxval(abs(trial%phi(self%active)) / &
         (self%settings%newton_atol + floor_factor * self%constraint_floor))
   end function constraint_norm

   !> Whether the residual of a trial is finite.
   logical function finite_trial(trial)
      type(trial_t), intent(in) :: trial
      ! A NaN or Inf in M, f, Phi_q or lambda reaches r_q (NaN * 0 is NaN), and one in Phi reaches
      ! phi: two reductions screen the whole evaluation
      finite_trial = all_finite(trial%r_q) .and. all_finite(trial%phi)
   end function finite_trial

   !> max |x_i|, 0 for an empty vector.
   pure real(dp) function max_abs(x)
      real(dp), intent(in) :: x(:)
      max_abs = 0.0_dp
      if (size(x) > 0) max_abs = maxval(abs(x))
   end function max_abs

   ! ------------------------------------------------------------------ checkpoint

   !> The whole state of the integrator after a step, everything that influences later steps
   !> (the last converged state, the current step, the kept factors, tangents and round-off
   !> floors, the multiplier history, the counters), as a real and an integer array for a
   !> checkpoint file: import_state on an integrator initialised for the same system continues
   !> bit for bit as this one would. The settings are not part of it (they come from the case).
   subroutine galpha_export_state(self, reals, ints)
      class(galpha_integrator_t), intent(in) :: self
      real(dp), allocatable, intent(out) :: reals(:)
      integer(i8), allocatable, intent(out) :: ints(:)
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

   end subroutine galpha_export_state

   !> Restore a state of export_state into an integrator initialised (init) for the same
   !> system and settings; FFRF_INPUT_ERROR when the arrays do not fit it.
   subroutine galpha_import_state(self, reals, ints, error)
      class(galpha_integrator_t), intent(inout) :: self
      real(dp), intent(in) :: reals(:)
      integer(i8), intent(in) :: ints(:)
      type(error_t), allocatable, intent(out) :: error
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
      ! sparse factors, if any, belong to another matrix: refactorised from lu at the next solve
      if (associated(self%sparse)) call self%sparse%free()
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

   end subroutine galpha_import_state

end module ffrf_mbs_generalized_alpha
