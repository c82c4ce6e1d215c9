!> The automatic model's choices for a scene without a crank (&model targets; the estimates are
!> in ffrf_app_scene_model, the loads from ffrf_app_scene_prerun): each chosen flexible body's
!> modes on its mesh_file, among the modes its joints leave free (ffrf_app_joint_free_modes),
!> the time step, the log and /model_selection of the results file.
module ffrf_app_scene_choice
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, add_context
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: logger_t, stage_times_t
   use ffrf_la_sparse, only: csr_t
   use ffrf_input_case, only: case_input_t
   use ffrf_input_body, only: body_input_t
   use ffrf_modes_input, only: modes_spec_t
   use ffrf_mpc_interface, only: interface_spec_t
   use ffrf_mpc_mesh_point, only: mesh_point_t, build_mesh_point
   use ffrf_modes_modal_analysis, only: body_modes_t
   use ffrf_model_model, only: model_t
   use ffrf_app_body_modes, only: compute_body_modes_from_file
   use ffrf_app_joint_free_modes, only: joint_locks_t, joint_free_modes
   use ffrf_app_engine_results, only: engine_results_t
   use ffrf_app_engine_auto_model, only: model_choice_t, body_choice_t, grounded_interfaces, &
      relative_shape, attached_masses, keep_modes, log_locks, mesh_frequency_delta
   use ffrf_app_scene_model, only: scene_record_t, scene_selection_t, scene_select_modes, &
      scene_select_step, TARGET_NODE, TARGET_REACTION
   implicit none
   private
   public :: scene_body_model, scene_step, write_scene_choice

contains

   !> Modes of body k on its candidate meshes (&body coarse_meshes, then mesh_file), coarse to
   !> fine: on each the candidates the joints leave free and the kept ones by the targets'
   !> budgets (a third of each tolerance); the coarsest mesh whose kept modes' frequency errors
   !> (Richardson against the next mesh, ffrf_app_engine_auto_model mesh_frequency_delta) fit
   !> the mesh budgets (a third of each tolerance) is taken; `modes` keeps its kept modes.
   subroutine scene_body_model(case, model, k, mesh_dir, log, times, choice, modes, &
         mass_matrix, error)
      type(case_input_t), intent(in) :: case
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
      type(scene_selection_t) :: selection, previous_selection
      type(joint_locks_t) :: locks, previous_locks
      type(body_modes_t) :: previous
      type(csr_t) :: previous_mass
      type(scene_record_t) :: start_record, record, previous_record
      character(len=256), allocatable :: meshes(:)
      real(dp), allocatable :: attached(:), fine_delta(:), coarse_delta(:), mesh_error(:)
      logical, allocatable :: grounded(:)
      real(dp) :: ratio
      integer :: i, p, j
      character(len=:), allocatable :: kept

      meshes = [pack(case%motions(k)%coarse_meshes, len_trim(case%motions(k)%coarse_meshes) &
         > 0), case%bodies(k)%mesh_file]
      body%name = case%bodies(k)%name
      allocate (body%meshes_tried(0), body%mesh_errors(0))
      start_record = choice%record
      do i = 1, size(meshes)
         record = start_record
         call mesh_candidates(meshes(i), i == 1, modes, mass_matrix, locks, record, selection)
         if (allocated(error)) return
         body%meshes_tried = [body%meshes_tried, meshes(i)]
         body%mesh_errors = [body%mesh_errors, -1.0_dp]
         allocate (selection%mesh_error(size(record%names)), source=0.0_dp)
         if (i > 1) then
            call mesh_frequency_delta(previous, modes, ratio, fine_delta, coarse_delta)
            mesh_error = frequency_error(previous_selection, coarse_delta)
            body%mesh_errors(i - 1) = maxval([0.0_dp, mesh_error / record%tolerances])
            selection%mesh_error = frequency_error(selection, fine_delta)
            body%mesh_errors(i) = maxval([0.0_dp, selection%mesh_error / record%tolerances])
            call log%info('model', trim(body%name) // ': mesh ' // trim(meshes(i - 1)) // &
               ': estimated mesh error per target:' // target_list(choice, mesh_error) // &
               ' (largest frequency error of its kept modes ' // to_str(maxval([0.0_dp, &
               coarse_delta(previous_selection%kept)]), 3) // ', against ' // &
               trim(meshes(i)) // ', size ratio ' // to_str(ratio, 3) // ')')
            if (all(mesh_error <= record%tolerances / 3.0_dp)) then
               previous_selection%mesh_error = mesh_error
               call take(previous, previous_mass, previous_selection, previous_locks, &
                  previous_record, meshes(i - 1))
               return
            end if
         end if
         if (i == size(meshes)) exit
         previous = modes
         previous_mass = mass_matrix
         previous_selection = selection
         previous_locks = locks
         previous_record = record
      end do
      call take(modes, mass_matrix, selection, locks, record, meshes(size(meshes)))
      if (any(selection%mesh_error > record%tolerances / 3.0_dp)) call log%note('model', &
         trim(body%name) // ': even the finest mesh (' // trim(meshes(size(meshes))) // &
         ') has an estimated mesh error above its budget: give finer meshes to meet the targets')

   contains

      !> The candidates of one mesh and their selection (the jointed masses from the first).
      subroutine mesh_candidates(mesh_file, first, modes, mass_matrix, locks, record, selection)
         character(len=*), intent(in) :: mesh_file
         logical, intent(in) :: first
         type(body_modes_t), intent(out) :: modes
         type(csr_t), intent(out) :: mass_matrix
         type(joint_locks_t), intent(out) :: locks
         type(scene_record_t), intent(inout) :: record
         type(scene_selection_t), intent(out) :: selection
         type(body_input_t) :: input
         type(modes_spec_t) :: spec
         type(interface_spec_t), allocatable :: interfaces(:)
         type(mesh_point_t) :: point
         real(dp), allocatable :: relative(:, :)
         integer, allocatable :: node_index(:), at_interface(:), link_interface(:)
         integer :: p, j, other
         input = case%bodies(k)
         input%mesh_file = mesh_file
         spec = model%bodies(k)%modes
         interfaces = model%bodies(k)%interfaces
         spec%num_modes = case%mechanism%model%candidate_modes
         call compute_body_modes_from_file(input, interfaces, spec, mesh_dir, log, times, &
            modes, error, mass_matrix=mass_matrix)
         if (.not. allocated(error)) call joint_free_modes(model, k, modes, locks, error)
         if (.not. allocated(error)) call log_locks(log, input%name, mesh_file, locks, &
            modes%frequency_hz)
         if (.not. allocated(error) .and. first) then
            choice%mesh_mass(k) = modes%mass
            grounded = grounded_interfaces(model, k, modes)
            call attached_masses(case, model, k, modes, mesh_dir, log, choice, attached, error)
            if (.not. allocated(error)) where (grounded) attached = 0.0_dp
         end if
         if (allocated(error)) then
            call add_context(error, 'automatic model, body "' // trim(input%name) // &
               '", mesh "' // trim(mesh_file) // '"')
            return
         end if
         relative = relative_shape(modes%virtual_node_shape, grounded)
         allocate (node_index(size(record%names)), at_interface(size(record%names)), &
            link_interface(size(record%names)), source=0)
         do p = 1, size(record%names)
            if (record%kinds(p) == TARGET_NODE .and. record%body(p) == k) then
               call build_mesh_point(modes%mesh, record%node(p), '', 0, point, error)
               if (allocated(error)) then
                  call add_context(error, '&model targets: &sensor "' // &
                     trim(record%names(p)) // '", mesh "' // trim(mesh_file) // '"')
                  return
               end if
               node_index(p) = point%nodes(1)
            else if (record%kinds(p) == TARGET_NODE) then
               do j = 1, size(model%mechanism%joints)
                  associate (joint => model%mechanism%joints(j))
                     if (joint%body(1) == k .and. joint%body(2) == record%body(p)) &
                        link_interface(p) = joint%marker(1)
                     if (joint%body(2) == k .and. joint%body(1) == record%body(p)) &
                        link_interface(p) = joint%marker(2)
                  end associate
               end do
            else if (record%kinds(p) == TARGET_REACTION) then
               associate (joint => model%mechanism%joints(record%joint(p)))
                  do j = 1, 2
                     other = joint%body(3 - j)
                     if (joint%body(j) == k .and. other > 0) at_interface(p) = joint%marker(j)
                  end do
               end associate
            end if
         end do
         call scene_select_modes(record, k, modes%frequency_hz, modes%shape, &
            modes%virtual_node_shape, relative, mass_matrix, modes%mesh%xyz, attached, &
            case%motions(k)%modal_damping, node_index, at_interface, link_interface, &
            record%tolerances / 3.0_dp, selection)
      end subroutine mesh_candidates

      !> Keep the selected modes of the mesh taken, record and log the choice.
      subroutine take(chosen, chosen_mass, chosen_selection, chosen_locks, chosen_record, &
            mesh_file)
         !> The mesh taken, its record, candidates, mass matrix, selection and locks
         character(len=*), intent(in) :: mesh_file
         type(scene_record_t), intent(in) :: chosen_record
         type(body_modes_t), intent(inout) :: chosen
         type(csr_t), intent(inout) :: chosen_mass
         type(scene_selection_t), intent(in) :: chosen_selection
         type(joint_locks_t), intent(in) :: chosen_locks
         choice%record = chosen_record
         body%mesh_file = mesh_file
         body%candidate_hz = chosen%frequency_hz
         body%locks = chosen_locks
         mass_matrix = chosen_mass
         call keep_modes(chosen, chosen_selection%kept)
         modes = chosen
         choice%bodies = [choice%bodies, body]
         choice%scene_bodies = [choice%scene_bodies, chosen_selection]
         kept = ''
         do p = 1, size(chosen_selection%kept)
            j = chosen_selection%kept(p)
            kept = kept // ' ' // to_str(j) // ' (' // to_str(body%candidate_hz(j), 5) // &
               ' Hz, ' // to_str(chosen_selection%loaded_hz(j), 5) // ' Hz jointed, ' // &
               'largest relative error if dropped ' // to_str(maxval([0.0_dp, &
               chosen_selection%error(:, j) / choice%record%tolerances]), 2) // &
               ' of a tolerance)'
         end do
         if (size(chosen_selection%kept) == 0) kept = ' none: rigid meets the targets ' // &
            '(every mode''s estimated errors fit the budgets), the body moves rigidly'
         call log%info('model', trim(body%name) // ': mesh ' // trim(body%mesh_file) // &
            ', keeps ' // to_str(size(chosen_selection%kept)) // ' of ' // &
            to_str(size(body%candidate_hz)) // ' candidate modes:' // kept)
         call log%info('model', trim(body%name) // ': dropped modes, estimated error per ' // &
            'target:' // target_list(choice, chosen_selection%truncation))
      end subroutine take

   end subroutine scene_body_model

   !> Error per target of relative frequency errors delta of the candidates of a selection: a
   !> kept mode's response changes by 2 delta_j of its quasi-static part (x ~ 1/w^2) and by
   !> delta_j of its dynamic part (as the step's period error), bounded by
   !> sum over the kept j of delta_j (2 e_pj + d_pj), e and d its error and dynamic part.
   pure function frequency_error(selection, delta) result(total)
      type(scene_selection_t), intent(in) :: selection
      real(dp), intent(in) :: delta(:)
      real(dp) :: total(size(selection%error, 1))
      integer :: j
      total = 0.0_dp
      do j = 1, size(selection%kept)
         associate (m => selection%kept(j))
            total = total + delta(m) * (2.0_dp * selection%error(:, m) + &
               selection%dynamic(:, m))
         end associate
      end do
   end function frequency_error

   !> " name value" for each target (" name mean value" for a mean target).
   function target_list(choice, values) result(text)
      type(model_choice_t), intent(in) :: choice
      real(dp), intent(in) :: values(:)
      character(len=:), allocatable :: text
      integer :: p
      text = ''
      do p = 1, size(values)
         text = text // ' ' // trim(choice%record%names(p)) // trim(merge(' mean', '     ', &
            choice%record%mean(p))) // ' ' // to_str(values(p), 3)
      end do
   end function target_list

   !> The step from the kept modes and the loads' spectrum (ffrf_app_scene_model, 4); h = 0
   !> when &integrator gives it.
   subroutine scene_step(case, model, log, choice)
      type(case_input_t), intent(in) :: case
      type(model_t), intent(in) :: model
      type(logger_t), intent(in) :: log
      type(model_choice_t), intent(inout) :: choice
      real(dp), allocatable :: mode_hz(:), dynamic(:, :)
      integer :: b
      associate (record => choice%record)
         allocate (mode_hz(0), dynamic(size(record%names), 0))
         do b = 1, size(choice%scene_bodies)
            associate (s => choice%scene_bodies(b))
               mode_hz = [mode_hz, s%loaded_hz(s%kept)]
               dynamic = reshape([dynamic, s%dynamic(:, s%kept)], [size(record%names), &
                  size(mode_hz)])
            end associate
         end do
         call log%info('model', 'automatic model: targets (relative error of the peak, or ' // &
            'of the mean over the run)' // target_list(choice, record%tolerances) // &
            '; a third of each for mode truncation, mesh and time step')
         if (model%mechanism%h_given) then
            call log%info('model', 'time step h = ' // to_str(model%mechanism%integrator%h, &
               3) // ' s given by &integrator')
         else
            call scene_select_step(record, mode_hz, dynamic, model%mechanism%integrator%rho_inf, &
               case%mechanism%integrator%t_end - case%mechanism%integrator%t_start, &
               record%tolerances / 3.0_dp, choice%h, choice%scene_step_error)
            call log%info('model', 'time step h = ' // to_str(choice%h, 3) // ' s (' // &
               to_str(size(mode_hz)) // ' kept mode(s), up to ' // to_str(maxval([0.0_dp, &
               mode_hz]), 5) // ' Hz jointed): estimated step error per target:' // &
               target_list(choice, choice%scene_step_error))
         end if
         call log%info('model', 'predicted relative error (truncation + mesh + step) per ' // &
            'target:' &
            // target_list(choice, predicted(choice)))
      end associate
   end subroutine scene_step

   !> Truncation of every body + step, per target.
   pure function predicted(choice) result(total)
      type(model_choice_t), intent(in) :: choice
      real(dp) :: total(size(choice%record%names))
      integer :: b
      total = choice%scene_step_error
      do b = 1, size(choice%scene_bodies)
         total = total + choice%scene_bodies(b)%truncation + choice%scene_bodies(b)%mesh_error
      end do
   end function predicted

   !> /model_selection of a scene: targets, step, predicted errors, per body its candidates,
   !> kept modes and each candidate's error per target.
   subroutine write_scene_choice(results, choice, error)
      type(engine_results_t), intent(inout) :: results
      type(model_choice_t), intent(in) :: choice
      type(error_t), allocatable, intent(out) :: error
      character(len=*), parameter :: root = '/model_selection'
      integer :: b
      call results%write_strings(root // '/target_names', choice%record%names, error)
      if (.not. allocated(error)) call results%write_strings(root // '/target_statistics', &
         [character(len=4) :: (merge('mean', 'peak', choice%record%mean(b)), &
         b=1, size(choice%record%mean))], error)
      if (.not. allocated(error)) call results%write_real(root // '/target_tolerances', &
         choice%record%tolerances, '1', error)
      if (.not. allocated(error)) call results%write_real(root // '/target_peaks', &
         choice%record%peak, '1', error)
      if (.not. allocated(error)) call results%write_real(root // '/time_step', [choice%h], &
         's', error)
      if (.not. allocated(error)) call results%write_real(root // '/predicted_error', &
         predicted(choice), '1', error)
      if (.not. allocated(error)) call results%write_real(root // '/step_error', &
         choice%scene_step_error, '1', error)
      do b = 1, size(choice%scene_bodies)
         if (allocated(error)) return
         associate (body => choice%bodies(b), s => choice%scene_bodies(b), &
               path => root // '/' // trim(choice%bodies(b)%name))
            call results%write_real(path // '/candidate_hz', body%candidate_hz, 'Hz', error)
            if (.not. allocated(error)) call results%write_real(path // '/loaded_hz', &
               s%loaded_hz, 'Hz', error)
            if (.not. allocated(error)) call results%write_real(path // '/computed_hz', &
               body%locks%candidate_hz, 'Hz', error)
            if (.not. allocated(error)) call results%write_real(path // '/free_share', &
               body%locks%free_share, '1', error)
            if (.not. allocated(error)) call results%write_int(path // '/kept_modes', s%kept, &
               error)
            if (.not. allocated(error)) call results%write_matrix(path // '/target_errors', &
               s%error, '1', error)
            if (.not. allocated(error)) call results%write_real(path // '/truncation_error', &
               s%truncation, '1', error)
            if (.not. allocated(error)) call results%write_real(path // '/mesh_error', &
               s%mesh_error, '1', error)
            if (.not. allocated(error)) call results%write_strings(path // '/meshes_tried', &
               body%meshes_tried, error)
            if (.not. allocated(error)) call results%write_real(path // '/mesh_errors', &
               body%mesh_errors, '1', error)
            if (.not. allocated(error)) call results%write_strings(path // '/mesh_file', &
               [body%mesh_file], error)
         end associate
      end do
   end subroutine write_scene_choice

end module ffrf_app_scene_choice
