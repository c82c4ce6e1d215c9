!> The automatic model of a mechanism case (&model selection = 'auto'; the rules and error
!> estimates are in ffrf_app_engine_model_selection): which case qualifies, the mesh and modes of
!> each flexible body whose num_modes the input leaves open, the time step when &integrator gives
!> none, and the report of the choice (log and results file, /model_selection).
!>
!> The selection runs on an engine case: a crank, a pressure load on a rigid body with a mass
!> (the piston) and a drag load (the regime speed). Anything else keeps the manual defaults
!> (&modes num_modes, h = 1e-3 s), with a note that says why.
module ffrf_app_engine_auto_model
   use ffrf_core_kinds, only: dp, pi
   use ffrf_core_error, only: error_t, add_context
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: logger_t, stage_times_t, LOG_QUIET
   use ffrf_la_sparse, only: csr_t
   use ffrf_input_case, only: case_input_t, vector_text
   use ffrf_app_engine_results, only: engine_results_t
   use ffrf_modes_input, only: modes_spec_t
   use ffrf_input_body, only: body_input_t
   use ffrf_mpc_interface, only: interface_spec_t
   use ffrf_modes_modal_analysis, only: body_modes_t
   use ffrf_modes_fingerprint, only: set_kept_modes
   use ffrf_app_body_modes, only: compute_body_modes_from_file
   use ffrf_app_joint_free_modes, only: joint_locks_t, joint_free_modes, locked_components
   use ffrf_model_model, only: model_t
   use ffrf_model_mechanism, only: LOAD_PRESSURE, LOAD_DRAG, SELECTION_AUTO
   use ffrf_app_engine_pressure, only: pressure_model_t
   use ffrf_app_engine_model_selection, only: excitation_t, engine_excitation, body_selection_t, &
      mode_effect_t, select_modes, mesh_frequency_error, select_time_step, step_errors
   use ffrf_app_scene_model, only: scene_record_t, scene_selection_t
   implicit none
   private
   public :: model_choice_t, start_model_selection, selects_body, select_body_model, &
      select_step, write_model_choice
   ! for the scenes without a crank (ffrf_app_scene_choice)
   public :: body_choice_t, grounded_interfaces, relative_shape, attached_masses, keep_modes, &
      log_locks, mesh_frequency_delta

   !> The choice for one flexible body.
   type :: body_choice_t
      character(len=64) :: name = ''
      !> Mesh file taken and the candidate meshes tried (coarse to fine)
      character(len=256) :: mesh_file = ''
      character(len=256), allocatable :: meshes_tried(:)
      !> Estimated mesh force error of each mesh tried (-1: not estimated, a single mesh)
      real(dp), allocatable :: mesh_errors(:)
      !> Candidate frequencies (Hz, free of jointed masses: the modes the joints leave free,
      !> ffrf_app_joint_free_modes) and the selection on the mesh taken
      real(dp), allocatable :: candidate_hz(:)
      !> What the joints locked of the computed modes on the mesh taken
      type(joint_locks_t) :: locks
      type(body_selection_t) :: selection
      !> Mesh error of the mesh taken (force -1: not estimated)
      type(mode_effect_t) :: mesh_error = mode_effect_t(-1.0_dp, 0.0_dp)
   end type body_choice_t

   !> The whole choice and its predicted errors.
   type :: model_choice_t
      !> .true. when the selection runs; otherwise `reason` says why not
      logical :: active = .false.
      character(len=:), allocatable :: reason
      type(excitation_t) :: excitation
      !> Budgets of the force and speed errors of each of truncation, mesh and step: a third
      !> of the targets
      real(dp) :: force_budget = 0.0_dp, speed_budget = 0.0_dp
      !> Chosen step (s; 0: not chosen) and its predicted errors
      real(dp) :: h = 0.0_dp
      type(mode_effect_t) :: step_error
      type(body_choice_t), allocatable :: bodies(:)
      !> Mass of each &body's coarsest mesh once known (kg; -1: not yet), so that a jointed
      !> body's mesh mass is computed once (attached_masses)
      real(dp), allocatable :: mesh_mass(:)
      !> A scene without a crank (ffrf_app_scene_choice): the rigid pre-run's record and
      !> targets, each body's choice (parallel to bodies), the step's errors per target
      logical :: scene = .false.
      type(scene_record_t) :: record
      type(scene_selection_t), allocatable :: scene_bodies(:)
      real(dp), allocatable :: scene_step_error(:)
   end type model_choice_t

contains

   !> Decide whether the selection runs; if so, the excitation at the regime speed.
   subroutine start_model_selection(case, model, pressure, has_pressure, log, choice, record)
      type(case_input_t), intent(in) :: case
      !> The case resolved (selection, loads, rigid flags)
      type(model_t), intent(in) :: model
      type(pressure_model_t), intent(in) :: pressure
      logical, intent(in) :: has_pressure
      type(logger_t), intent(in) :: log
      type(model_choice_t), intent(out) :: choice
      !> A scene without a crank: the rigid pre-run's record (ffrf_app_scene_prerun)
      type(scene_record_t), intent(in), optional :: record
      integer :: l, piston
      real(dp) :: drag, piston_mass
      allocate (choice%bodies(0))
      allocate (choice%mesh_mass(size(case%bodies)), source=-1.0_dp)
      choice%reason = ''
      if (model%mechanism%selection /= SELECTION_AUTO) then
         choice%reason = '&model selection = ''manual'''
         return
      end if
      drag = 0.0_dp
      piston_mass = 0.0_dp
      do l = 1, size(model%mechanism%loads)
         associate (load => model%mechanism%loads(l))
            if (load%kind == LOAD_DRAG) drag = load%coefficient
            if (load%kind == LOAD_PRESSURE) then
               piston = load%body
               if (model%bodies(piston)%rigid) piston_mass = model%bodies(piston)%motion%mass
            end if
         end associate
      end do
      if (model%mechanism%crank == 0 .and. present(record)) then
         ! a scene without an engine (ffrf_app_scene_choice): its log names no engine part
         choice%active = .true.
         choice%scene = .true.
         choice%record = record
         allocate (choice%scene_bodies(0))
         allocate (choice%scene_step_error(size(record%names)), source=0.0_dp)
         return
      else if (model%mechanism%crank == 0) then
         ! a scene without an engine: its log and results name no engine part
         choice%reason = 'a scene without an engine needs &model targets on its sensors ' // &
            'and a flexible body without num_modes (docs/mechanisms.md "Targets on sensors")'
      else if (.not. has_pressure) then
         choice%reason = 'not an engine (no pressure load)'
      else if (.not. (drag > 0.0_dp)) then
         choice%reason = 'no drag load to set the regime speed'
      else if (.not. (piston_mass > 0.0_dp)) then
         choice%reason = 'the pressure load''s body is not rigid with a mass (the piston)'
      else if (.not. (pressure%mean_indicated_torque() > 0.0_dp)) then
         choice%reason = 'the cycle does no positive work (no regime speed)'
      end if
      if (len(choice%reason) > 0) then
         call log%note('model', 'automatic model selection off: ' // choice%reason // &
            '; open choices take the defaults (&modes num_modes, h = 1e-3 s)')
         return
      end if
      choice%active = .true.
      choice%force_budget = case%mechanism%model%force_tolerance / 3.0_dp
      choice%speed_budget = case%mechanism%model%speed_tolerance / 3.0_dp
      call engine_excitation(pressure, piston_mass, drag, choice%excitation)
      choice%excitation%resonance_floor = case%mechanism%model%resonance_floor
      associate (x => choice%excitation)
         call log%info('model', 'automatic model: targets regime speed ' // &
            to_str(case%mechanism%model%speed_tolerance, 3) // ', joint forces ' // &
            to_str(case%mechanism%model%force_tolerance, 3) // ' (relative); a third of each ' // &
            'for mode truncation, mesh and time step')
         call log%info('model', 'excitation: regime speed ' // to_str(x%regime_speed, 5) // &
            ' rad/s (mean indicated torque ' // to_str(x%mean_torque, 5) // &
            ' N m = drag c omega^2), cycle ' // to_str(x%cycle_hz, 5) // ' Hz, peak conrod ' // &
            'force ' // to_str(x%peak_force, 5) // ' N')
      end associate
   end subroutine start_model_selection

   !> .true. when the selection chooses body k's mesh and modes (flexible, num_modes not given,
   !> no modes_file: modes taken from a file fix the body's mesh and modes).
   pure function selects_body(model, choice, k) result(selects)
      !> The case resolved (rigid flags, num_modes given, meshes)
      type(model_t), intent(in) :: model
      type(model_choice_t), intent(in) :: choice
      integer, intent(in) :: k
      logical :: selects
      selects = choice%active .and. .not. model%bodies(k)%rigid .and. &
         .not. model%bodies(k)%num_modes_given .and. model%bodies(k)%meshed .and. &
         len_trim(model%bodies(k)%body%modes_file) == 0
   end function selects_body

   !> Modes of body k on its candidate meshes, coarse to fine, until one meets the mesh budget
   !> (ffrf_app_engine_model_selection, 3); the kept modes of that mesh in `modes`, its mass matrix.
   subroutine select_body_model(case, model, k, mesh_dir, log, times, choice, modes, &
         mass_matrix, error)
      type(case_input_t), intent(in) :: case
      !> The case resolved (joints with model body indices and marker handles)
      type(model_t), intent(in) :: model
      integer, intent(in) :: k
      character(len=*), intent(in) :: mesh_dir
      type(logger_t), intent(in) :: log
      type(stage_times_t), intent(inout) :: times
      type(model_choice_t), intent(inout) :: choice
      type(body_modes_t), intent(out) :: modes
      type(csr_t), intent(out) :: mass_matrix
      type(error_t), allocatable, intent(out) :: error
      type(body_choice_t) :: body
      type(body_modes_t) :: previous, current
      type(csr_t) :: previous_mass, current_mass
      type(body_selection_t) :: previous_selection, current_selection
      type(joint_locks_t) :: previous_locks, current_locks
      type(mode_effect_t) :: coarse_effect, fine_effect
      type(body_input_t) :: input
      type(modes_spec_t) :: spec
      type(interface_spec_t), allocatable :: interfaces(:)
      character(len=256), allocatable :: meshes(:)
      real(dp), allocatable :: attached(:), fine_delta(:), coarse_delta(:)
      logical, allocatable :: grounded(:)
      real(dp) :: ratio, zeta
      integer :: i, n

      input = case%bodies(k)
      zeta = case%motions(k)%modal_damping
      meshes = [pack(case%motions(k)%coarse_meshes, len_trim(case%motions(k)%coarse_meshes) &
         > 0), input%mesh_file]
      body%name = input%name
      ! the model's modes and interfaces of the body, with the count of this use
      spec = model%bodies(k)%modes
      interfaces = model%bodies(k)%interfaces
      spec%num_modes = case%mechanism%model%candidate_modes
      allocate (body%meshes_tried(0), body%mesh_errors(0))
      do i = 1, size(meshes)
         input%mesh_file = meshes(i)
         call compute_body_modes_from_file(input, interfaces, spec, mesh_dir, log, times, &
            current, error, mass_matrix=current_mass)
         if (.not. allocated(error)) call joint_free_modes(model, k, current, current_locks, &
            error)
         if (allocated(error)) then
            call add_context(error, 'automatic model, candidate mesh "' // trim(meshes(i)) // '"')
            return
         end if
         call log_locks(log, input%name, meshes(i), current_locks, current%frequency_hz)
         if (i == 1) then
            choice%mesh_mass(k) = current%mass
            grounded = grounded_interfaces(model, k, current)
            call attached_masses(case, model, k, current, mesh_dir, log, choice, attached, error)
            if (allocated(error)) return
            where (grounded) attached = 0.0_dp
         end if
         call select_modes(choice%excitation, current%frequency_hz, &
            relative_shape(current%virtual_node_shape, grounded), attached, zeta, &
            choice%force_budget, choice%speed_budget, current_selection)
         body%meshes_tried = [body%meshes_tried, meshes(i)]
         body%mesh_errors = [body%mesh_errors, -1.0_dp]
         if (i > 1) then
            call mesh_frequency_delta(previous, current, ratio, fine_delta, coarse_delta)
            coarse_effect = mesh_frequency_error(choice%excitation, previous_selection, &
               coarse_delta)
            fine_effect = mesh_frequency_error(choice%excitation, current_selection, fine_delta)
            body%mesh_errors(i - 1) = coarse_effect%force
            body%mesh_errors(i) = fine_effect%force
            call log%info('model', trim(body%name) // ': mesh ' // trim(meshes(i - 1)) // &
               ': estimated mesh error, force ' // to_str(coarse_effect%force, 3) // &
               ', speed ' // to_str(coarse_effect%speed, 3) // ' (largest frequency error ' // &
               'of its kept modes ' // to_str(maxval([0.0_dp, &
               coarse_delta(previous_selection%kept)]), 3) &
               // ', against ' // trim(meshes(i)) // &
               ', size ratio ' // to_str(ratio, 3) // ')')
            if (coarse_effect%force <= choice%force_budget .and. coarse_effect%speed <= &
               choice%speed_budget) then
               body%mesh_error = coarse_effect
               call take(previous, previous_mass, previous_selection, previous_locks, &
                  meshes(i - 1))
               return
            end if
            body%mesh_error = fine_effect
         end if
         previous = current
         previous_mass = current_mass
         previous_selection = current_selection
         previous_locks = current_locks
      end do
      ! the finest mesh
      n = size(meshes)
      call take(previous, previous_mass, previous_selection, previous_locks, meshes(n))
      if (body%mesh_error%force > choice%force_budget .or. body%mesh_error%speed > &
         choice%speed_budget) call log%note('model', trim(body%name) // ': even the finest ' // &
         'mesh (' // trim(meshes(n)) // ') has an estimated mesh error above its budget: give ' &
         // 'finer meshes to meet the targets')

   contains

      !> Keep the selected modes of a mesh and record the choice.
      subroutine take(chosen, chosen_mass, selection, locks, mesh_file)
         type(body_modes_t), intent(inout) :: chosen
         type(csr_t), intent(inout) :: chosen_mass
         type(body_selection_t), intent(in) :: selection
         type(joint_locks_t), intent(in) :: locks
         character(len=*), intent(in) :: mesh_file
         body%mesh_file = mesh_file
         body%locks = locks
         body%candidate_hz = chosen%frequency_hz
         body%selection = selection
         call keep_modes(chosen, selection%kept)
         modes = chosen
         mass_matrix = chosen_mass
         choice%bodies = [choice%bodies, body]
         call log_body(log, body)
      end subroutine take

   end subroutine select_body_model

   !> The relative frequency errors of the candidates of two meshes of a body, coarse then
   !> fine: first-order Richardson on the mode frequencies (paired_modes), element size
   !> ~ nodes^(-1/3) and `ratio` the size ratio; `coarse_delta` 0 for a coarse mode no fine one
   !> pairs with.
   subroutine mesh_frequency_delta(previous, current, ratio, fine_delta, coarse_delta)
      type(body_modes_t), intent(in) :: previous, current
      real(dp), intent(out) :: ratio
      real(dp), allocatable, intent(out) :: fine_delta(:), coarse_delta(:)
      integer, allocatable :: pair(:)
      ratio = max((real(size(current%mesh%xyz, 2), dp) / &
         real(size(previous%mesh%xyz, 2), dp))**(1.0_dp / 3.0_dp), 1.0_dp + 1.0e-6_dp)
      pair = paired_modes(previous, current)
      fine_delta = abs(previous%frequency_hz(pair) - current%frequency_hz) / &
         (ratio - 1.0_dp) / current%frequency_hz
      coarse_delta = spread(0.0_dp, 1, size(previous%frequency_hz))
      coarse_delta(pair) = ratio * fine_delta
   end subroutine mesh_frequency_delta

   !> For each mode of the finer mesh, the mode of the coarser one it is: the largest modal
   !> assurance criterion of the virtual-node motions (the same points on both meshes) among the
   !> modes within 30 % in frequency, or the nearest frequency for modes that hardly move the
   !> virtual nodes or match none.
   pure function paired_modes(coarse, fine) result(pair)
      type(body_modes_t), intent(in) :: coarse, fine
      integer :: pair(size(fine%frequency_hz))
      real(dp) :: mac(size(coarse%frequency_hz)), norm_fine, scale
      integer :: i, j
      scale = maxval(abs(fine%virtual_node_shape))
      do j = 1, size(pair)
         norm_fine = norm2(fine%virtual_node_shape(:, j))
         if (norm_fine > 1.0e-6_dp * scale) then
            do i = 1, size(mac)
               mac(i) = dot_product(coarse%virtual_node_shape(:, i), &
                  fine%virtual_node_shape(:, j))**2 / max(norm2(coarse%virtual_node_shape(:, &
                  i))**2 * norm_fine**2, tiny(1.0_dp))
               ! a mesh changes a frequency by a few per cent, not by 30 %
               if (abs(coarse%frequency_hz(i) / fine%frequency_hz(j) - 1.0_dp) > 0.3_dp) &
                  mac(i) = 0.0_dp
            end do
            pair(j) = maxloc(mac, dim=1)
            if (mac(pair(j)) > 0.8_dp) cycle
         end if
         pair(j) = minloc(abs(coarse%frequency_hz - fine%frequency_hz(j)), dim=1)
      end do
   end function paired_modes

   !> .true. for each interface of body k held to the ground by a joint that fixes its
   !> translations (locked_components: revolute, spherical, universal, fixed; not prismatic or
   !> cylindrical).
   pure function grounded_interfaces(model, k, modes) result(grounded)
      !> The case resolved (joints with model body indices and marker handles)
      type(model_t), intent(in) :: model
      integer, intent(in) :: k
      type(body_modes_t), intent(in) :: modes
      logical :: grounded(size(modes%interfaces))
      integer :: i, j
      logical :: locked(6)
      grounded = .false.
      do i = 1, size(modes%interfaces)
         ! the body's interface i is its marker handle i (ffrf_model_model)
         do j = 1, size(model%mechanism%joints)
            associate (joint => model%mechanism%joints(j))
               locked = locked_components(joint%kind)
               if (.not. all(locked(1:3))) cycle
               if (all(joint%body == [0, k]) .and. joint%marker(2) == i .or. &
                  all(joint%body == [k, 0]) .and. joint%marker(1) == i) grounded(i) = .true.
            end associate
         end do
      end do
   end function grounded_interfaces

   !> The virtual-node motions the jointed bodies feel in the assembly: the bearings hold the
   !> grounded interfaces, so the floating frame follows them and the other interfaces move by
   !> u_i - mean(u_grounded) (translations; rotations as given); the grounded ones by nothing.
   !> Without grounded interfaces, u as it is.
   pure function relative_shape(shape, grounded) result(relative)
      real(dp), intent(in) :: shape(:, :)
      logical, intent(in) :: grounded(:)
      real(dp) :: relative(size(shape, 1), size(shape, 2))
      real(dp) :: mean(3, size(shape, 2))
      integer :: i
      relative = shape
      if (.not. any(grounded)) return
      mean = 0.0_dp
      do i = 1, size(grounded)
         if (grounded(i)) mean = mean + shape(6 * i - 5:6 * i - 3, :)
      end do
      mean = mean / real(count(grounded), dp)
      do i = 1, size(grounded)
         relative(6 * i - 5:6 * i - 3, :) = shape(6 * i - 5:6 * i - 3, :) - mean
         if (grounded(i)) relative(6 * i - 5:6 * i - 3, :) = 0.0_dp
      end do
   end function relative_shape

   !> Mass jointed at each interface of body k (kg): the mass of the body at the other end of
   !> each joint on that interface (a rigid &body's mass key, or the mass of a meshed body's
   !> coarsest mesh); the ground adds nothing (its joints act where the reference conditions
   !> already hold the virtual node, or they stiffen the mode: leaving them out overestimates).
   subroutine attached_masses(case, model, k, modes, mesh_dir, log, choice, mass, error)
      type(case_input_t), intent(in) :: case
      !> The case resolved (joints with model body indices and marker handles)
      type(model_t), intent(in) :: model
      integer, intent(in) :: k
      type(body_modes_t), intent(in) :: modes
      character(len=*), intent(in) :: mesh_dir
      type(logger_t), intent(in) :: log
      !> Its mesh_mass cache is read and filled
      type(model_choice_t), intent(inout) :: choice
      real(dp), allocatable, intent(out) :: mass(:)
      type(error_t), allocatable, intent(out) :: error
      integer :: i, j, other
      character(len=64) :: name
      real(dp) :: other_mass
      allocate (mass(size(modes%interfaces)), source=0.0_dp)
      name = model%bodies(k)%name
      do i = 1, size(modes%interfaces)
         do j = 1, size(model%mechanism%joints)
            associate (joint => model%mechanism%joints(j))
               other = 0
               if (joint%body(1) == k .and. joint%marker(1) == i) other = joint%body(2)
               if (joint%body(2) == k .and. joint%marker(2) == i) other = joint%body(1)
               if (other <= 0) cycle
               if (model%bodies(other)%meshed) then
                  if (choice%mesh_mass(other) < 0.0_dp) then
                     call mesh_mass(case, model, other, mesh_dir, log, &
                        choice%mesh_mass(other), error)
                     if (allocated(error)) return
                  end if
                  other_mass = choice%mesh_mass(other)
               else
                  other_mass = model%bodies(other)%motion%mass
               end if
               mass(i) = mass(i) + other_mass
            end associate
         end do
      end do
      call log%info('model', trim(name) // ': masses jointed at the interfaces ' // &
         vector_text(mass, 4) // ' kg')
   end subroutine attached_masses

   !> Mass of body k's coarsest mesh (kg), from its consistent mass matrix.
   subroutine mesh_mass(case, model, k, mesh_dir, log, mass, error)
      type(case_input_t), intent(in) :: case
      !> The case resolved (modes and interfaces of body k)
      type(model_t), intent(in) :: model
      integer, intent(in) :: k
      character(len=*), intent(in) :: mesh_dir
      type(logger_t), intent(in) :: log
      real(dp), intent(out) :: mass
      type(error_t), allocatable, intent(out) :: error
      type(body_input_t) :: input
      type(modes_spec_t) :: spec
      type(interface_spec_t), allocatable :: interfaces(:)
      type(body_modes_t) :: modes
      type(stage_times_t) :: times
      type(logger_t) :: quiet
      input = case%bodies(k)
      if (len_trim(case%motions(k)%coarse_meshes(1)) > 0) input%mesh_file = &
         case%motions(k)%coarse_meshes(1)
      ! the model's modes and interfaces of the body, with the count of this use
      spec = model%bodies(k)%modes
      interfaces = model%bodies(k)%interfaces
      spec%num_modes = 0
      quiet = log
      quiet%level = LOG_QUIET
      call compute_body_modes_from_file(input, interfaces, spec, mesh_dir, quiet, times, modes, &
         error)
      mass = modes%mass
   end subroutine mesh_mass

   !> Keep the modes `kept` (ascending) of a modal result.
   subroutine keep_modes(modes, kept)
      type(body_modes_t), intent(inout) :: modes
      integer, intent(in) :: kept(:)
      call set_kept_modes(modes%fingerprint, kept, size(modes%frequency_hz))
      modes%frequency_hz = modes%frequency_hz(kept)
      modes%shape = modes%shape(:, kept)
      modes%virtual_node_shape = modes%virtual_node_shape(:, kept)
      if (allocated(modes%residual)) modes%residual = modes%residual(kept)
   end subroutine keep_modes

   !> The step from the harmonics and the kept modes of every selected body
   !> (ffrf_app_engine_model_selection, 4); h = 0 when &integrator gives it.
   subroutine select_step(model, log, choice)
      !> The case resolved (h given, integrator settings)
      type(model_t), intent(in) :: model
      type(logger_t), intent(in) :: log
      type(model_choice_t), intent(inout) :: choice
      real(dp), allocatable :: mode_hz(:)
      type(mode_effect_t), allocatable :: effect(:)
      type(mode_effect_t) :: total
      integer :: b
      if (.not. choice%active) return
      allocate (mode_hz(0), effect(0))
      do b = 1, size(choice%bodies)
         associate (s => choice%bodies(b)%selection)
            mode_hz = [mode_hz, s%loaded_hz(s%kept)]
            effect = [effect, s%effect(s%kept)]
         end associate
      end do
      if (model%mechanism%h_given) then
         call log%info('model', 'time step h = ' // to_str(model%mechanism%integrator%h, 3) // &
            ' s given by &integrator')
         return
      end if
      call log_step_ladder()
      call select_time_step(choice%excitation, mode_hz, effect, &
         model%mechanism%integrator%rho_inf, choice%force_budget, choice%speed_budget, choice%h, &
         choice%step_error)
      call log%info('model', 'time step h = ' // to_str(choice%h, 3) // ' s (' // &
         to_str(choice%excitation%regime_speed * choice%h * 180.0_dp / pi, 3) // &
         ' deg of crank per step at the regime speed): estimated step error, force ' // &
         to_str(choice%step_error%force, 3) // ', speed ' // to_str(choice%step_error%speed, 3))
      total = predicted_error(choice)
      call log%info('model', 'predicted relative error (truncation + mesh + step): joint ' // &
         'forces ' // to_str(total%force, 3) // ', regime speed ' // to_str(total%speed, 3))
   contains
      !> Debug: the step errors over a coarse ladder.
      subroutine log_step_ladder()
         real(dp), parameter :: steps(6) = [2.5e-5_dp, 5.0e-5_dp, 1.0e-4_dp, 2.0e-4_dp, &
            4.0e-4_dp, 8.0e-4_dp]
         type(mode_effect_t) :: step_effect
         integer :: i
         do i = 1, size(steps)
            step_effect = step_errors(choice%excitation, mode_hz, effect, steps(i), &
               model%mechanism%integrator%rho_inf)
            call log%debug('model', 'step ' // to_str(steps(i), 3) // ' s: force ' // &
               to_str(step_effect%force, 3) // ', speed ' // to_str(step_effect%speed, 3))
         end do
      end subroutine log_step_ladder
   end subroutine select_step

   !> Truncation + mesh (a mesh not estimated counts 0) + step errors over the selected bodies.
   pure function predicted_error(choice) result(total)
      type(model_choice_t), intent(in) :: choice
      type(mode_effect_t) :: total
      integer :: b
      total = choice%step_error
      do b = 1, size(choice%bodies)
         associate (body => choice%bodies(b))
            total%force = total%force + body%selection%truncation%force + &
               max(body%mesh_error%force, 0.0_dp)
            total%speed = total%speed + body%selection%truncation%speed + &
               max(body%mesh_error%speed, 0.0_dp)
         end associate
      end do
   end function predicted_error

   !> Which computed modes the joints lock and the free modes left (ffrf_app_joint_free_modes).
   subroutine log_locks(log, name, mesh_file, locks, free_hz)
      type(logger_t), intent(in) :: log
      character(len=*), intent(in) :: name, mesh_file
      type(joint_locks_t), intent(in) :: locks
      !> Frequencies of the free modes (Hz)
      real(dp), intent(in) :: free_hz(:)
      character(len=:), allocatable :: held
      integer :: j
      if (locks%num_locked == 0) then
         call log%info('model', trim(name) // ': mesh ' // trim(mesh_file) // ': the joints ' &
            // 'lock none of the ' // to_str(locks%num_candidates) // ' candidate modes')
         return
      end if
      held = ''
      do j = 1, locks%num_candidates
         if (locks%free_share(j) < 0.5_dp) held = held // ' ' // to_str(j) // ' (' // &
            to_str(locks%candidate_hz(j), 5) // ' Hz, ' // to_str(100.0_dp * (1.0_dp - &
            locks%free_share(j)), 3) // ' % locked)'
      end do
      if (len(held) == 0) held = ' none more than half'
      call log%info('model', trim(name) // ': mesh ' // trim(mesh_file) // ': the joints lock ' &
         // to_str(locks%num_locked) // ' combination(s) of the ' // &
         to_str(locks%num_candidates) // ' candidate modes, motions the rest of the ' // &
         'assembly cannot follow (the joint components the candidates move: ' // locks%locks // &
         '); candidates mostly locked:' // held)
      call log%info('model', trim(name) // ': ' // to_str(size(free_hz)) // ' modes the ' // &
         'joints leave free (Rayleigh-Ritz in the candidates), ' // to_str(minval([huge(1.0_dp), &
         free_hz]), 5) // ' .. ' // to_str(maxval([0.0_dp, free_hz]), 5) // ' Hz: the ' // &
         'candidates of the selection')
   end subroutine log_locks

   subroutine log_body(log, body)
      type(logger_t), intent(in) :: log
      type(body_choice_t), intent(in) :: body
      character(len=:), allocatable :: kept
      integer :: i, j
      associate (s => body%selection)
         kept = ''
         do i = 1, size(s%kept)
            j = s%kept(i)
            kept = kept // ' ' // to_str(j) // ' (' // to_str(body%candidate_hz(j), 5) // &
               ' Hz, ' // to_str(s%loaded_hz(j), 5) // ' Hz jointed, force ' // &
               to_str(s%effect(j)%force, 2) // ')'
         end do
         if (size(s%kept) == 0) kept = ' none: rigid meets the targets (every mode''s ' // &
            'estimated errors fit the budgets), the body moves rigidly'
         call log%info('model', trim(body%name) // ': mesh ' // trim(body%mesh_file) // &
            ', keeps ' // to_str(size(s%kept)) // ' of ' // to_str(size(s%effect)) // &
            ' candidate modes:' // kept)
         call log%info('model', trim(body%name) // ': dropped modes, force ' // &
            to_str(s%truncation%force, 3) // ', speed ' // to_str(s%truncation%speed, 3) // &
            '; one mode above the candidates (mu = 1), force ' // to_str(s%tail%force, 3) // &
            '; mesh ' // trim(merge('force ' // to_str(body%mesh_error%force, 3) // ', speed ' &
            // to_str(body%mesh_error%speed, 3), 'not estimated (no coarse_meshes)' // &
            repeat(' ', 32), body%mesh_error%force >= 0.0_dp)))
      end associate
   end subroutine log_body

   !> /model_selection of the results file: targets, excitation, per body the mesh, candidates and
   !> kept modes, the step and the predicted errors.
   subroutine write_model_choice(results, case, choice, error)
      type(engine_results_t), intent(inout) :: results
      type(case_input_t), intent(in) :: case
      type(model_choice_t), intent(in) :: choice
      type(error_t), allocatable, intent(out) :: error
      character(len=*), parameter :: root = '/model_selection'
      type(mode_effect_t) :: total
      integer :: b
      call results%write_real(root // '/active', [merge(1.0_dp, 0.0_dp, choice%active)], '1', &
         error)
      ! a scene without an engine: ffrf_app_scene_choice writes the rest
      if (allocated(error) .or. .not. choice%active .or. choice%scene) return
      call results%write_real(root // '/targets', [case%mechanism%model%speed_tolerance, &
         case%mechanism%model%force_tolerance], '1', error)
      if (.not. allocated(error)) call results%write_real(root // '/regime_speed_estimate', &
         [choice%excitation%regime_speed], 'rad/s', error)
      total = predicted_error(choice)
      if (.not. allocated(error)) call results%write_real(root // '/harmonic_weights', &
         abs(choice%excitation%force) / choice%excitation%peak_force, '1', error)
      if (.not. allocated(error)) call results%write_real(root // '/time_step', [choice%h], 's', &
         error)
      ! [force, speed] in total and of the step
      if (.not. allocated(error)) call results%write_real(root // '/predicted_error', &
         [total%force, total%speed, choice%step_error%force, choice%step_error%speed], '1', &
         error)
      do b = 1, size(choice%bodies)
         if (allocated(error)) return
         associate (body => choice%bodies(b), path => root // '/' // trim(choice%bodies(b)%name))
            call results%write_real(path // '/candidate_hz', body%candidate_hz, 'Hz', error)
            if (.not. allocated(error)) call results%write_real(path // '/computed_hz', &
               body%locks%candidate_hz, 'Hz', error)
            if (.not. allocated(error)) call results%write_real(path // '/free_share', &
               body%locks%free_share, '1', error)
            if (.not. allocated(error)) call results%write_real(path // '/force_error', &
               body%selection%effect%force, '1', error)
            if (.not. allocated(error)) call results%write_real(path // '/speed_error', &
               body%selection%effect%speed, '1', error)
            if (.not. allocated(error)) call results%write_int(path // '/kept_modes', &
               body%selection%kept, error)
            if (.not. allocated(error)) call results%write_real(path // '/errors', &
               [body%selection%truncation%force, body%selection%truncation%speed, &
               body%mesh_error%force, body%mesh_error%speed], '1', error)
            if (.not. allocated(error)) call results%write_real(path // '/mesh_errors', &
               body%mesh_errors, '1', error)
            if (.not. allocated(error)) call results%write_strings(path // '/meshes_tried', &
               body%meshes_tried, error)
            if (.not. allocated(error)) call results%write_strings(path // '/mesh_file', &
               [body%mesh_file], error)
         end associate
      end do
   end subroutine write_model_choice

end module ffrf_app_engine_auto_model
