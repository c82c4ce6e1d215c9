!> The automatic model of a scene without a crank (&model selection = 'auto' with &model targets;
!> docs/mechanisms.md "Targets on sensors"): the error estimates, from the record of a rigid
!> pre-run of the same mechanism (ffrf_app_scene_prerun), that choose each flexible body's modes
!> and the time step. The engine's own estimates are in ffrf_app_engine_model_selection.
!>
!> 1. Loads. The pre-run moves every selected flexible body rigidly (num_modes = 0: its mesh's
!>    inertia) with the case's loads, drivers and springs; at every step it records per body,
!>    in the body axes, the force and moment of each joint at each interface, the acceleration
!>    a0 of the frame origin, the angular velocity w and acceleration alpha, and gravity g.
!>    A mode j (mass-normalised shape Phi_j, virtual-node motion [u_ij; theta_ij]) receives
!>       f_j(t) = sum_i (u_ij . F_i + theta_ij . M_i) + s_j . (g - a0) - sum_ab W_ab S_j,ab,
!>       W = skew(alpha) + w w^T - |w|^2 I,  s_j = int rho Phi_j,  S_j,ab = int rho Phi_j,a x_b
!>    (the exact generalized force on the modal coordinates at zeta = 0: joint forces, gravity
!>    and the inertia of the rigid motion).
!> 2. Response. With the masses jointed at its interfaces (A_j, mu_j = A_j/(1 + A_j) as the
!>    engine's), the mode obeys x'' + 2 zeta w~ x' + w~^2 x = (1 - mu_j) f_j, w~ = w sqrt(1 - mu_j),
!>    solved exactly for f linear between the recorded steps, from rest (the body starts
!>    undeformed): modal superposition in time, which is H(r) applied to the whole spectrum of
!>    the (not periodic) loads without the wrap-around of a discrete transform.
!> 3. Sensors. A node_displacement target of the body gets Psi_n,j x_j(t); a reaction target
!>    gets the change of the force the joint carries, the inertia of the mode's motion:
!>    |b_j| |x_j''(t)|, b_j = s_j + sum_i m_i u~_ij (the mode's momentum with the jointed masses,
!>    u~ relative to the grounded interfaces), or m_i |u~_ij| at the joint's own interface i if
!>    larger. A node target on a body B jointed to body k at interface i: the mode shakes B's
!>    base by u_ij x_j'', a relative change 2 |u_ij x_j''(t)| / max_t |g - a0|_B of B's load
!>    field (the 2 of a suddenly applied load), taken as the relative error of the deflection
!>    (quasi-static in B). Bodies not jointed directly are not estimated. A target on the
!>    motion of body k's interface i (a marker's position, velocity or angular velocity, a
!>    joint's coordinate; TARGET_INTERFACE) gets its elastic motion |u_ij| |x_j|,
!>    |theta_ij| |x_j| (a revolute's angle), |u_ij| |x_j'| or |theta_ij| |x_j'|. The sensor's peak
!>    P_s = max_t r_s(t) = r_s(t_p) (r: |F| in the pre-run; |sum over
!>    the candidates Psi_n x| for a node) moves by a perturbation of magnitude at most d(t) by
!>    at most max(d(t_p), max_t (r_s + d) - P_s): a mode's error e_sj is this over P_s for
!>    d = |c_sj|, the dropped modes' for d = sum of their |c_sj|. Modes are dropped, smallest
!>    max_s e_sj / budget_s first, while every target's error of the dropped set fits its
!>    budget (a third of its tolerance). A mean target's mean M = mean_t r_s(t) moves by at
!>    most mean_t d(t): its error is that over |M|.
!> 4. Step. Per target: the rigid part from generalized-alpha's periodic response of a free mass
!>    to each harmonic of the recorded sensor (linear trend removed), plus each kept mode's
!>    dynamic part (c_sj without the quasi-static x_qs = f_j / w_j^2) times eps_j = |w~_h/w - 1|
!>    + xi~ at w~_j h (ffrf_app_engine_model_selection, 4), plus the peak read from the steps,
!>    (1/2) |r''| (h/2)^2 / P_s. The largest step of the engine's ladder within every budget
!>    and at most t_end / 20 is taken.
module ffrf_app_scene_model
   use ffrf_core_kinds, only: dp, pi
   use ffrf_la_sparse, only: csr_t, csr_matvec
   use ffrf_app_model_estimates, only: galpha_response, galpha_mode, jointed_mass_share, &
      STEP_LADDER
   implicit none
   private
   public :: scene_record_t, scene_body_record_t, scene_selection_t, scene_select_modes, &
      scene_step_errors, scene_select_step, TARGET_REACTION, TARGET_NODE, TARGET_INTERFACE, &
      modal_response

   !> Kinds of targets: a joint's reaction, a mesh node's deflection, the motion of a chosen
   !> body's interface (a marker's position, velocity or angular velocity, a joint's coordinate)
   integer, parameter :: TARGET_REACTION = 1, TARGET_NODE = 2, TARGET_INTERFACE = 3

   !> What the pre-run recorded of one flexible body (body axes), n steps.
   type :: scene_body_record_t
      !> .true. for a body the selection chooses
      logical :: selected = .false.
      !> Force and moment at each interface, (6 num_interfaces, n)
      real(dp), allocatable :: load(:, :)
      !> Frame origin acceleration, angular velocity and acceleration, gravity, (3, n)
      real(dp), allocatable :: acceleration(:, :), omega(:, :), alpha(:, :), gravity(:, :)
   end type scene_body_record_t

   !> The rigid pre-run's record and the targets.
   type :: scene_record_t
      !> Pre-run step (s) and the recorded times (n, from t_start)
      real(dp) :: h = 0.0_dp
      real(dp), allocatable :: time(:)
      !> Per &body (case order)
      type(scene_body_record_t), allocatable :: bodies(:)
      !> Targets: sensor names, tolerances, TARGET_*, model body (node), Gmsh node tag, joint
      character(len=64), allocatable :: names(:)
      real(dp), allocatable :: tolerances(:)
      integer, allocatable :: kinds(:), body(:), node(:), joint(:)
      !> .true.: a target on the sensor's mean over the run, else on its peak
      logical, allocatable :: mean(:)
      !> Interface targets: the motion measured (1 translation, 2 rotation), its order (0 the
      !> value, 1 its rate), and per end (2) the model body and its interface (0: none)
      integer, allocatable :: rows(:), order(:), side_body(:, :), side_interface(:, :)
      !> Reaction and interface targets: the sensor's magnitude in the pre-run (|F| of the
      !> joint on its body 1; |value| of the sensor's first three values), (n, targets)
      real(dp), allocatable :: series(:, :)
      !> Peak (or mean, for a mean target) of each target (node targets: set by the selection
      !> of their body)
      real(dp), allocatable :: peak(:)
      !> |r''| / P at the peak of each target (1/s^2)
      real(dp), allocatable :: curvature(:)
   end type scene_record_t

   !> The choice for one flexible body.
   type :: scene_selection_t
      !> Kept candidates (ascending); empty: rigid
      integer, allocatable :: kept(:)
      !> Frequencies with the jointed masses (Hz), jointed-mass shares
      real(dp), allocatable :: loaded_hz(:), mass_share(:)
      !> Error of dropping each candidate per target (targets, modes), and its dynamic part
      real(dp), allocatable :: error(:, :), dynamic(:, :)
      !> Sum of the dropped errors per target
      real(dp), allocatable :: truncation(:)
      !> Estimated mesh error per target (0: a single mesh, not estimated)
      real(dp), allocatable :: mesh_error(:)
      real(dp) :: damping = 0.0_dp
   end type scene_selection_t

contains

   !> Choose the modes of body k (module header, 1-3). `shape`, `virtual_node_shape`: the
   !> candidates (mass-normalised); `relative`: the virtual-node shape relative to the grounded
   !> interfaces; `node_rows(:, s)`: the mesh node of a node target s of this body (0: none);
   !> `at_interface(s)`: the interface of body k at reaction target s's joint whose other body
   !> is not the ground (0: none). Updates record%peak and record%curvature of node targets.
   subroutine scene_select_modes(record, k, frequency_hz, shape, virtual_node_shape, relative, &
         mass_matrix, xyz, attached, zeta, node_index, at_interface, link_interface, budgets, &
         selection)
      type(scene_record_t), intent(inout) :: record
      integer, intent(in) :: k
      real(dp), intent(in) :: frequency_hz(:), shape(:, :), virtual_node_shape(:, :)
      real(dp), intent(in) :: relative(:, :), xyz(:, :), attached(:), zeta
      type(csr_t), intent(in) :: mass_matrix
      integer, intent(in) :: node_index(:), at_interface(:)
      !> For a node target on another body: the interface of body k jointed to it (0: none)
      integer, intent(in) :: link_interface(:)
      real(dp), intent(in) :: budgets(:)
      type(scene_selection_t), intent(out) :: selection
      real(dp), allocatable :: s(:, :), big_s(:, :, :), force(:, :), x(:, :), v(:, :), a(:, :)
      real(dp), allocatable :: sum_node(:, :), score(:), contribution(:, :, :)
      real(dp), allocatable :: dynamic_part(:, :, :), envelope(:, :), trial(:)
      real(dp) :: w(3, 3), momentum(3), omega, c
      integer :: nm, nt, nr, j, t, m, i, p, e, row
      logical, allocatable :: keep(:)
      nm = size(frequency_hz)
      nt = size(record%time)
      nr = size(record%names)
      selection%damping = zeta
      call shape_integrals(shape, mass_matrix, xyz, s, big_s)
      allocate (force(nt, nm), source=0.0_dp)
      associate (rec => record%bodies(k))
         do t = 1, nt
            w = skew(rec%alpha(:, t)) + spread(rec%omega(:, t), 2, 3) * &
               spread(rec%omega(:, t), 1, 3)
            do i = 1, 3
               w(i, i) = w(i, i) - sum(rec%omega(:, t)**2)
            end do
            do j = 1, nm
               force(t, j) = sum(virtual_node_shape(:, j) * rec%load(:, t)) + &
                  sum(s(:, j) * (rec%gravity(:, t) - rec%acceleration(:, t))) - &
                  sum(w * big_s(:, :, j))
            end do
         end do
      end associate
      selection%mass_share = jointed_mass_share(relative, attached)
      selection%loaded_hz = frequency_hz * sqrt(1.0_dp - selection%mass_share)
      allocate (x(nt, nm), v(nt, nm), a(nt, nm))
      do j = 1, nm
         omega = 2.0_dp * pi * selection%loaded_hz(j)
         call modal_response(record%h, omega, zeta, (1.0_dp - selection%mass_share(j)) * &
            force(:, j), x(:, j), v(:, j), a(:, j))
      end do
      ! each mode's contribution |c_sj(t)| to each target, whole and dynamic part
      allocate (contribution(nt, nm, nr), dynamic_part(nt, nm, nr), source=0.0_dp)
      do p = 1, nr
         if (record%kinds(p) == TARGET_NODE .and. node_index(p) > 0) then
            m = node_index(p)
            sum_node = matmul(shape(3 * m - 2:3 * m, :), transpose(x))
            record%series(:, p) = norm2(sum_node, dim=1)
            record%peak(p) = maxval(record%series(:, p))
            if (record%mean(p)) record%peak(p) = sum(record%series(:, p)) / real(nt, dp)
            i = maxloc(record%series(:, p), dim=1)
            record%curvature(p) = norm2(matmul(shape(3 * m - 2:3 * m, :), a(i, :))) / &
               max(record%peak(p), tiny(1.0_dp))
            if (record%mean(p)) record%curvature(p) = 0.0_dp
            do j = 1, nm
               contribution(:, j, p) = norm2(shape(3 * m - 2:3 * m, j)) * abs(x(:, j))
               dynamic_part(:, j, p) = norm2(shape(3 * m - 2:3 * m, j)) * abs(x(:, j) - &
                  force(:, j) / (2.0_dp * pi * frequency_hz(j))**2)
            end do
         else if (record%kinds(p) == TARGET_NODE .and. link_interface(p) > 0) then
            ! a node of the body jointed at interface i: the mode shakes its base, a relative
            ! change of its load field of |u_ij x_j''| / max |g - a0|, twice for the transient
            i = link_interface(p)
            associate (other => record%bodies(record%body(p)))
               c = maxval(norm2(other%gravity - other%acceleration, dim=1))
            end associate
            do j = 1, nm
               contribution(:, j, p) = 2.0_dp * norm2(relative(6 * i - 5:6 * i - 3, j)) * &
                  abs(a(:, j)) / max(c, tiny(1.0_dp))
               dynamic_part(:, j, p) = contribution(:, j, p)
            end do
         else if (record%kinds(p) == TARGET_INTERFACE) then
            ! the interface's elastic motion u_ij x_j or theta_ij x_j, or its rate
            do e = 1, 2
               if (record%side_body(e, p) /= k) cycle
               row = 6 * record%side_interface(e, p) - 5 + 3 * (record%rows(p) - 1)
               do j = 1, nm
                  c = norm2(virtual_node_shape(row:row + 2, j))
                  if (record%order(p) == 0) then
                     contribution(:, j, p) = contribution(:, j, p) + c * abs(x(:, j))
                     dynamic_part(:, j, p) = dynamic_part(:, j, p) + c * abs(x(:, j) - &
                        force(:, j) / (2.0_dp * pi * frequency_hz(j))**2)
                  else
                     contribution(:, j, p) = contribution(:, j, p) + c * abs(v(:, j))
                     dynamic_part(:, j, p) = dynamic_part(:, j, p) + c * abs(v(:, j))
                  end if
               end do
            end do
         else if (record%kinds(p) == TARGET_REACTION) then
            do j = 1, nm
               momentum = s(:, j)
               do i = 1, size(attached)
                  momentum = momentum + attached(i) * relative(6 * i - 5:6 * i - 3, j)
               end do
               c = norm2(momentum)
               i = at_interface(p)
               if (i > 0) c = max(c, attached(i) * norm2(relative(6 * i - 5:6 * i - 3, j)))
               contribution(:, j, p) = c * abs(a(:, j))
               dynamic_part(:, j, p) = contribution(:, j, p)
            end do
         end if
      end do
      allocate (selection%error(nr, nm), selection%dynamic(nr, nm), source=0.0_dp)
      do p = 1, nr
         do j = 1, nm
            selection%error(p, j) = target_error(p, contribution(:, j, p))
            selection%dynamic(p, j) = target_error(p, dynamic_part(:, j, p))
         end do
      end do
      ! drop the candidates of smallest relative error while every target's budget holds for
      ! the envelope of the dropped contributions
      allocate (score(nm), keep(nm), selection%truncation(nr), envelope(nt, nr), trial(nr))
      keep = .true.
      selection%truncation = 0.0_dp
      envelope = 0.0_dp
      do j = 1, nm
         score(j) = maxval([0.0_dp, selection%error(:, j) / budgets])
      end do
      do i = 1, nm
         j = minloc(score, dim=1, mask=keep .and. score < huge(1.0_dp))
         if (j == 0) exit
         do p = 1, nr
            trial(p) = target_error(p, envelope(:, p) + contribution(:, j, p))
         end do
         if (any(trial > budgets)) then
            score(j) = huge(1.0_dp)
            cycle
         end if
         envelope = envelope + contribution(:, j, :)
         selection%truncation = trial
         keep(j) = .false.
      end do
      selection%kept = pack([(j, j=1, nm)], keep)
   contains
      !> The error of target p for a perturbation d: peak_error, or max d for a node target of
      !> another body (d relative already).
      real(dp) function target_error(p, d)
         integer, intent(in) :: p
         real(dp), intent(in) :: d(:)
         if (record%kinds(p) == TARGET_NODE .and. link_interface(p) > 0) then
            target_error = maxval(d)
            if (record%mean(p)) target_error = sum(d) / real(size(d), dp)
         else
            target_error = peak_error(record, p, d)
         end if
      end function target_error
   end subroutine scene_select_modes

   !> Bound of the change of target p's peak P = max r(t) = r(t_p) by a perturbation of
   !> magnitude at most d(t): max(d(t_p), max_t (r(t) + d(t)) - P) / P (module header, 3); of
   !> a mean target's mean M: mean_t d(t) / |M|.
   pure real(dp) function peak_error(record, p, d)
      type(scene_record_t), intent(in) :: record
      integer, intent(in) :: p
      real(dp), intent(in) :: d(:)
      integer :: peak_index
      if (record%mean(p)) then
         peak_error = sum(d) / real(size(d), dp) / max(abs(record%peak(p)), tiny(1.0_dp))
         return
      end if
      peak_index = maxloc(record%series(:, p), dim=1)
      peak_error = max(d(peak_index), maxval(record%series(:, p) + d) - record%peak(p)) / &
         max(record%peak(p), tiny(1.0_dp))
   end function peak_error

   !> s_j = Phi_j^T M e_a and S_j,ab = Phi_j^T M (x_b e_a) (module header, 1): M the consistent
   !> mass matrix (3 per node, node by node), x the node positions in the body frame.
   subroutine shape_integrals(shape, mass_matrix, xyz, s, big_s)
      real(dp), intent(in) :: shape(:, :), xyz(:, :)
      type(csr_t), intent(in) :: mass_matrix
      real(dp), allocatable, intent(out) :: s(:, :), big_s(:, :, :)
      real(dp) :: field(size(shape, 1)), product_(size(shape, 1))
      integer :: a, b
      allocate (s(3, size(shape, 2)), big_s(3, 3, size(shape, 2)))
      do a = 1, 3
         field = 0.0_dp
         field(a::3) = 1.0_dp
         call csr_matvec(mass_matrix, field, product_)
         s(a, :) = matmul(product_, shape)
         do b = 1, 3
            field = 0.0_dp
            field(a::3) = xyz(b, :)
            call csr_matvec(mass_matrix, field, product_)
            big_s(a, b, :) = matmul(product_, shape)
         end do
      end do
   end subroutine shape_integrals

   pure function skew(u) result(m)
      real(dp), intent(in) :: u(3)
      real(dp) :: m(3, 3)
      m = reshape([0.0_dp, u(3), -u(2), -u(3), 0.0_dp, u(1), u(2), -u(1), 0.0_dp], [3, 3])
   end function skew

   !> x'' + 2 zeta w x' + w^2 x = f(t), f linear between samples h apart, from x = x' = 0 at the
   !> first sample (exact: the particular solution of a linear load plus the free motion), zeta
   !> < 1. Returns x, x' and x'' at the samples.
   pure subroutine modal_response(h, omega, zeta, f, x, v, a)
      real(dp), intent(in) :: h, omega, zeta, f(:)
      real(dp), intent(out) :: x(:), v(:), a(:)
      real(dp) :: sigma, wd, decay, cs, sn, slope, offset, y0, y1, z
      integer :: n
      sigma = zeta * omega
      wd = omega * sqrt(1.0_dp - zeta**2)
      decay = exp(-sigma * h)
      cs = cos(wd * h)
      sn = sin(wd * h)
      x(1) = 0.0_dp
      v(1) = 0.0_dp
      a(1) = f(1)
      do n = 1, size(f) - 1
         ! particular solution offset + slope t of the load f(n) + (f(n+1) - f(n)) t / h
         slope = (f(n + 1) - f(n)) / h / omega**2
         offset = f(n) / omega**2 - 2.0_dp * zeta * slope / omega
         y0 = x(n) - offset
         z = v(n) - slope
         y1 = decay * (y0 * cs + (z + sigma * y0) / wd * sn)
         v(n + 1) = decay * (z * cs - (omega**2 * y0 + sigma * z) / wd * sn) + slope
         x(n + 1) = y1 + offset + slope * h
         a(n + 1) = f(n + 1) - 2.0_dp * sigma * v(n + 1) - omega**2 * x(n + 1)
      end do
   end subroutine modal_response

   !> Step errors per target at step h (module header, 4): the rigid part of the reaction
   !> targets, the kept modes' dynamic parts times eps_j, and the peak read from the steps.
   function scene_step_errors(record, mode_hz, dynamic, h, rho_inf) result(errors)
      type(scene_record_t), intent(in) :: record
      !> Kept modes of every body: frequencies with the jointed masses (Hz) and their dynamic
      !> errors per target (targets, modes)
      real(dp), intent(in) :: mode_hz(:), dynamic(:, :), h, rho_inf
      real(dp) :: errors(size(record%names))
      real(dp) :: ratio, damping, eps, trend(size(record%time)), omega
      complex(dp) :: c
      integer :: p, j, k, n, t
      n = size(record%time)
      errors = 0.0_dp
      do p = 1, size(errors)
         if (record%kinds(p) /= TARGET_NODE .and. n > 2) then
            trend = record%series(:, p) - (record%series(1, p) + (record%series(n, p) - &
               record%series(1, p)) * [(real(t - 1, dp), t=1, n)] / real(n - 1, dp))
            do k = 1, n / 2
               omega = 2.0_dp * pi * real(k, dp) / (record%h * real(n, dp))
               c = 2.0_dp / real(n, dp) * sum(trend * cmplx(cos(omega * record%time), &
                  -sin(omega * record%time), dp))
               errors(p) = errors(p) + abs(c) * abs(galpha_response(0.0_dp, 0.0_dp, omega, h, &
                  rho_inf) - 1.0_dp)
            end do
            errors(p) = errors(p) / max(record%peak(p), tiny(1.0_dp))
         end if
         errors(p) = errors(p) + 0.5_dp * record%curvature(p) * (0.5_dp * h)**2
      end do
      do j = 1, size(mode_hz)
         call galpha_mode(2.0_dp * pi * mode_hz(j) * h, rho_inf, ratio, damping)
         eps = min(abs(ratio - 1.0_dp) + damping, 1.0_dp)
         errors = errors + eps * dynamic(:, j)
      end do
   end function scene_step_errors

   !> The largest step of the ladder, at most t_end / 20, whose step errors fit the budgets
   !> (1e-7 s if none).
   subroutine scene_select_step(record, mode_hz, dynamic, rho_inf, duration, budgets, h, errors)
      type(scene_record_t), intent(in) :: record
      real(dp), intent(in) :: mode_hz(:), dynamic(:, :), rho_inf, duration, budgets(:)
      real(dp), intent(out) :: h
      real(dp), allocatable, intent(out) :: errors(:)
      integer :: decade, m
      do decade = -1, -7, -1
         do m = size(STEP_LADDER), 1, -1
            h = STEP_LADDER(m) * 10.0_dp**decade
            if (h > duration / 20.0_dp) cycle
            errors = scene_step_errors(record, mode_hz, dynamic, h, rho_inf)
            if (all(errors <= budgets)) return
         end do
      end do
   end subroutine scene_select_step

end module ffrf_app_scene_model
