!> Reported multipliers of near-redundant constraint rows (issue 30, part 4; theory.md 4.3).
!>
!> Exactly dependent rows of Phi_q are dropped at the start (find_redundant_rows). Rows that are
!> dependent for rigid bodies but kept because a flexible body's modal coordinates make them
!> independent form self-stress states of the rigid mechanism: multiplier combinations w with
!> Phi_r^T w = 0 on the rigid-body coordinates (R, theta) that load only the modal coordinates,
!> Phi_q^T w = [0; Phi_zeta^T w]. Their amplitude c is fixed by the modal equations alone:
!> p c = (modal force), p = |Jn_zeta^T w| the modes' participation. With two in-plane conrod modes
!> closing the engine's out-of-plane loop, p fell to 1e-7 .. 7e-3 (of the rigid block's |R_11|)
!> and the pin-axis reactions reached 1.7e10 N against in-plane forces of 2.7e4 N.
!>
!> Threshold (sigma_rtol = TOLERANCE_FACTOR x &model force_tolerance, 0.1 by default): the model
!> is built to give joint forces to force_tolerance (1e-2) of the peak force F, so the modal
!> force is known to about force_tolerance F and c to force_tolerance F / p; a self-stress is
!> reported as the dynamics give it only where that is below a tenth of F, p > 10 force_tolerance.
!> Measured (participation, smallest over the run): the hand-set engine (10 modes per body)
!> 0.50; the automatic model before its joint-free candidates (issue 30, part 1; engine_rc1,
!> rc2, rc3, rigid) 2e-7 .. 7.4e-3 for their first direction, 0.29 .. 0.88 for the others
!> except rc1's second (6e-3 .. 0.54, which crossed the threshold during the run: its flags
!> switch with it); with the joint-free candidates the engine inputs have none below it.
!>
!> Rule (min_norm_multipliers): with the row scale m_i = max_j |Phi_q(i, j)| and the scaled
!> multipliers mu = m lambda (Phi_q^T lambda = Jn^T mu, Jn the row-normalised kept rows), the
!> self-stress space W of the rigid block (null space by QR with column pivoting, RIGID_NULL_RTOL)
!> and the SVD of Jn^T W give the directions d_j = W y_j with singular value s_j <= sigma_rtol
!> |R_11|; the reported multipliers are mu - sum_j d_j (d_j^T mu), divided by m: the
!> minimum-norm multipliers on those directions, which is the rigid mechanism's minimum-norm
!> split of the reaction (what a rigid model would report if it kept the rows) plus the
!> self-stress the modes do resolve. The integration is not touched (only the reported split
!> changes); the removed generalized force, sum_j s_j (d_j^T mu) on the modal coordinates, is the
!> part the modes resolve too poorly. Directions inside W leave the rows the rigid mechanism
!> determines alone (the in-plane pin forces of the engine stay bit for bit); an SVD of the
!> whole Jn^T, tried first, mixed them in at s_min / s_next (1e-2) and moved them by 2e4 N. A
!> kept row is marked min-norm when the rule moved its scaled multiplier by more than
!> CHANGE_RTOL of the largest reported one: every unmarked row is within that of its raw
!> multiplier (the in-plane pin forces of the variant moved by at most 6.1e-5 of the peak force,
!> regression_reactions_variant_check). (A first version
!> marked only rows whose share sum_j d_j(i)**2 of the directions exceeded 1e-2; on issue 30's
!> variant the rule moved unmarked rows too, the cylinder's moment from 1914 to 2e-4 N m: a small
!> share of a removed component of 3e4 N.)
!>
!> The caller checks every check_interval accepted steps while no direction is near-redundant
!> and at every step while one is (reaction_split_t), so healthy runs pay one check per
!> check_interval steps (a Jacobian, a QR of the rigid block: about 30 x 35) and report their
!> multipliers bit for bit; runs with a near-redundant direction pay it every step (engine_rc1,
!> 2 s: 21 s against 15 s of wall time on the loaded 2-core machine, first version with an SVD
!> of the rigid block; the QR took the 0.5 s run from 4.9 to 4.2 s, 3.7 s without the check).
module ffrf_mbs_reaction_split
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_kinds, only: dp, ip
   use ffrf_core_error, only: error_t, fatal_error, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_la_dense, only: singular_values
   use ffrf_mbs_galpha_linalg, only: dgeqp3
   implicit none
   private
   public :: min_norm_multipliers, reaction_split_t, DEFAULT_SIGMA_RTOL, TOLERANCE_FACTOR

   !> Default threshold on the participation s_j / |R_11| (module header and
   !> reaction_split_t%sigma_rtol): TOLERANCE_FACTOR x the default force_tolerance 1e-2
   real(dp), parameter :: DEFAULT_SIGMA_RTOL = 0.1_dp

   !> The threshold on the participation is this factor times the joint-force tolerance of the
   !> model (&model force_tolerance, default 1e-2): module header
   real(dp), parameter :: TOLERANCE_FACTOR = 10.0_dp

   !> Diagonal entries |R_kk| of the rigid block's pivoted QR up to this fraction of |R_11| end
   !> its rank: the columns past it span the rigid mechanism's self-stress space. Exact
   !> self-stress gives 1e-16; the flexible bodies' deformation moves the markers and lifts it
   !> (measured over 0.3 s: 3e-16 engine_rc1 and engine_rigid, 1.4e-14 the titanium conrod at
   !> 80 bar, 5.8e-6 engine_rc1_manual with 10 modes per body), while the independent columns
   !> stay above 2.1e-2 (engine_rc1_manual; 9.1e-2 engine_rc1): 1e-3 is 170 times above the one
   !> and 21 times below the other
   real(dp), parameter :: RIGID_NULL_RTOL = 1.0e-3_dp

   !> A kept row is marked min-norm when the rule moved its scaled multiplier by more than this
   !> fraction of the largest reported scaled multiplier (the joint-force scale)
   real(dp), parameter :: CHANGE_RTOL = 1.0e-3_dp

   !> Tracks the conditioning of the kept constraint rows over a run and gives the reported
   !> multipliers of each step (module header).
   type :: reaction_split_t
      !> Threshold on the participation s_j / |R_11| at or below which a self-stress direction
      !> is near-redundant (module header)
      real(dp) :: sigma_rtol = DEFAULT_SIGMA_RTOL
      !> Accepted steps between two checks while no direction is near-redundant (the caller
      !> checks at step numbers divisible by it, so a restarted run checks the same steps)
      integer :: check_interval = 50
      !> Whether the last check found a near-redundant direction (then every step is checked)
      logical :: near = .false.
      !> Smallest participation s_j / |R_11| at the last check and over the run (1: none)
      real(dp) :: sigma_ratio = 1.0_dp, smallest_ratio = 1.0_dp
      !> Checks made
      integer :: checks = 0
      !> Rows (nc) reported by minimum norm at the last update, at any update, and the first
      !> time each was (s; huge when never)
      logical, allocatable :: min_norm(:), ever(:)
      real(dp), allocatable :: first_time(:)
   contains
      !> The reported multipliers of the current state
      procedure :: update => reaction_split_update
   end type reaction_split_t

contains

   !> A check of the state (t, Phi_q, lambda): the reported multipliers by the minimum-norm rule
   !> of the module header when a direction is near-redundant, else lambda itself. The caller
   !> calls it every check_interval steps and at every step while `near`, and reports lambda
   !> unchanged at the other steps. `newly` is true when a row is marked for the first time
   !> (the caller logs it).
   subroutine reaction_split_update(self, t, Phi_q, active, lambda, modal, reported, newly, &
         error)
      class(reaction_split_t), intent(inout) :: self
      !> Time of the state (s)
      real(dp), intent(in) :: t
      !> Constraint Jacobian, all rows (nc x n)
      real(dp), intent(in) :: Phi_q(:, :)
      !> Kept rows, ascending
      integer, intent(in) :: active(:)
      !> Multipliers of the integrator (nc, zero on dropped rows)
      real(dp), intent(in) :: lambda(:)
      !> Whether each coordinate is modal (n)
      logical, intent(in) :: modal(:)
      !> Reported multipliers (nc)
      real(dp), intent(out) :: reported(:)
      !> A row was marked min-norm for the first time
      logical, intent(out) :: newly
      type(error_t), allocatable, intent(out) :: error
      integer :: nc
      nc = size(lambda)
      newly = .false.
      if (.not. allocated(self%min_norm)) then
         allocate (self%min_norm(nc), self%ever(nc), self%first_time(nc))
         self%min_norm = .false.
         self%ever = .false.
         self%first_time = huge(1.0_dp)
      end if
      self%checks = self%checks + 1
      call min_norm_multipliers(Phi_q, active, lambda, modal, self%sigma_rtol, reported, &
         self%min_norm, self%sigma_ratio, error)
      if (allocated(error)) return
      self%smallest_ratio = min(self%smallest_ratio, self%sigma_ratio)
      self%near = any(self%min_norm)
      newly = any(self%min_norm .and. .not. self%ever)
      where (self%min_norm .and. .not. self%ever) self%first_time = t
      self%ever = self%ever .or. self%min_norm
   end subroutine reaction_split_update

   !> Minimum-norm multipliers on the near-redundant directions of the kept rows (module
   !> header): reported = lambda except along the near-redundant directions, where the scaled
   !> multipliers are projected out. The directions come from the row-normalised Jn^T (columns:
   !> kept rows): (1) the null space W of its rigid-body block (the coordinates that are not
   !> modal), the self-stress space of the rigid mechanism (null_space, RIGID_NULL_RTOL); (2)
   !> the SVD of the whole Jn^T W, whose right singular vectors y_j with s_j <= sigma_rtol
   !> |R_11| (|R_11| the largest column norm of the rigid block) give the near-redundant
   !> directions W y_j. Dropped rows keep their zero multipliers.
   subroutine min_norm_multipliers(Phi_q, active, lambda, modal, sigma_rtol, reported, &
         min_norm, sigma_ratio, error)
      !> Constraint Jacobian, all rows (nc x n)
      real(dp), intent(in) :: Phi_q(:, :)
      !> Kept rows, ascending
      integer, intent(in) :: active(:)
      !> Multipliers (nc)
      real(dp), intent(in) :: lambda(:)
      !> Whether each coordinate is modal (n); the others are rigid-body coordinates
      logical, intent(in) :: modal(:)
      !> Threshold on the participation s_j / |R_11|, in (0, 1)
      real(dp), intent(in) :: sigma_rtol
      !> Reported multipliers (nc)
      real(dp), intent(out) :: reported(:)
      !> Rows whose reported multiplier is set by the minimum-norm rule (nc)
      logical, intent(out) :: min_norm(:)
      !> Smallest participation s_j / |R_11| (1 when the rigid mechanism has no self-stress)
      real(dp), intent(out) :: sigma_ratio
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: a(:, :), ar(:, :), w(:, :), b(:, :), sb(:), y(:, :), &
         row_max(:), mu(:), mu_raw(:), share(:), direction(:)
      real(dp) :: s1
      integer :: n, nr, nrig, d, i, k
      reported = lambda
      min_norm = .false.
      sigma_ratio = 1.0_dp
      n = size(Phi_q, 2)
      nr = size(active)
      nrig = count(.not. modal)
      if (nr == 0 .or. n == 0 .or. nrig == 0) return
      allocate (a(n, nr), row_max(nr), mu(nr), share(nr))
      do i = 1, nr
         row_max(i) = maxval(abs(Phi_q(active(i), :)))
         if (.not. row_max(i) > 0.0_dp) row_max(i) = 1.0_dp
         a(:, i) = Phi_q(active(i), :) / row_max(i)
      end do
      if (.not. (all(ieee_is_finite(a)) .and. all(ieee_is_finite(lambda)))) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'reaction split: the constraint ' // &
            'Jacobian or the multipliers hold a NaN or infinite entry')
         return
      end if
      ! (1) self-stress space of the rigid block
      ar = a(pack([(i, i=1, n)], .not. modal), :)
      call null_space(ar, RIGID_NULL_RTOL, w, s1, error)
      if (allocated(error)) return
      d = size(w, 2)
      if (d == 0 .or. .not. s1 > 0.0_dp) return
      ! (2) the whole Jacobian on that space
      b = matmul(a, w)
      call singular_values(b, sb, error, v=y)
      if (allocated(error)) return
      sigma_ratio = 0.0_dp
      if (size(sb) == d) sigma_ratio = sb(d) / s1
      mu = row_max * lambda(active)
      mu_raw = mu
      share = 0.0_dp
      do k = 1, d
         if (k <= size(sb)) then
            if (sb(k) > sigma_rtol * s1) cycle
         end if
         direction = matmul(w, y(:, k))
         mu = mu - dot_product(direction, mu) * direction
         share = share + direction**2
      end do
      if (.not. any(share > 0.0_dp)) return
      reported(active) = mu / row_max
      do i = 1, nr
         min_norm(active(i)) = abs(mu(i) - mu_raw(i)) > CHANGE_RTOL * maxval(abs(mu))
      end do
   end subroutine min_norm_multipliers

   !> Orthonormal basis w (columns) of the null space of a (m x n), by QR with column
   !> pivoting (dgeqp3; A P = Q R): the columns past the last |R_kk| > rtol |R_11| are
   !> dependent, each gives P [-R11^-1 R12(:, j); e_j]; then modified Gram-Schmidt, twice. The
   !> subspace does not depend on the pivot order (only its basis does). `scale` = |R_11|, the
   !> largest column norm of a. a is overwritten.
   subroutine null_space(a, rtol, w, scale, error)
      real(dp), intent(inout) :: a(:, :)
      real(dp), intent(in) :: rtol
      real(dp), allocatable, intent(out) :: w(:, :)
      real(dp), intent(out) :: scale
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: tau(:), work(:), x(:)
      real(dp) :: query(1)
      integer(ip), allocatable :: jpvt(:)
      integer(ip) :: m, n, info
      integer :: r, d, i, j, k, pass
      m = int(size(a, 1), ip)
      n = int(size(a, 2), ip)
      scale = 0.0_dp
      allocate (jpvt(n), tau(max(1_ip, min(m, n))), x(n))
      jpvt = 0_ip
      call dgeqp3(m, n, a, max(1_ip, m), jpvt, tau, query, -1_ip, info)
      allocate (work(max(1_ip, int(query(1), ip))))
      call dgeqp3(m, n, a, max(1_ip, m), jpvt, tau, work, int(size(work), ip), info)
      if (info /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'reaction split: QR of a ' // &
            to_str(int(m)) // ' x ' // to_str(int(n)) // ' block of the constraint ' // &
            'Jacobian failed (dgeqp3 info = ' // to_str(int(info)) // ')')
         return
      end if
      r = 0
      if (min(m, n) > 0) scale = abs(a(1, 1))
      do k = 1, int(min(m, n))
         if (.not. abs(a(k, k)) > rtol * scale) exit
         r = k
      end do
      d = int(n) - r
      allocate (w(n, d))
      do j = 1, d
         x = 0.0_dp
         x(r + j) = 1.0_dp
         do i = r, 1, -1
            x(i) = -(dot_product(a(i, i + 1:r), x(i + 1:r)) + a(i, r + j)) / a(i, i)
         end do
         w(jpvt, j) = x
      end do
      do pass = 1, 2
         do j = 1, d
            do k = 1, j - 1
               w(:, j) = w(:, j) - dot_product(w(:, k), w(:, j)) * w(:, k)
            end do
            w(:, j) = w(:, j) / norm2(w(:, j))
         end do
      end do
   end subroutine null_space

end module ffrf_mbs_reaction_split
