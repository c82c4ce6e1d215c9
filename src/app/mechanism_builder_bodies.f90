!> The bodies of a mechanism being built (ffrf_app_mechanism_builder): a flexible body's modes
!> computed (or reused) and its geometric stiffness, or a rigid body, added to the mechanism.
submodule (ffrf_app_mechanism_builder) ffrf_app_mechanism_builder_bodies
   use ffrf_core_log, only: LOG_QUIET
   use ffrf_input_body, only: body_input_t
   use ffrf_modes_input, only: modes_spec_t
   implicit none

contains

   module procedure add_body
      type(csr_t) :: mass_matrix, stiffness_matrix
      type(flexible_body_t) :: flexible
      type(rigid_body_t) :: rigid
      type(stage_timer_t) :: timer
      real(dp) :: mass, com(3), inertia(3, 3)
      character(len=:), allocatable :: name
      logical :: exporting

      name = trim(resolved%name)
      ! &run export asks for the body's FE matrices (the Exudyn body file): K is kept too
      exporting = .false.
      if (present(results_file)) exporting = len(results_file) > 0 .and. &
         exports_matrices(case%run%export)
      associate (motion => resolved%motion)
         if (built%meshed) then
            if (len_trim(resolved%body%modes_file) > 0) then
               ! modes from an earlier run's results file, checked (K only for the geometric
               ! stiffness or an export: assembled again, no eigen solve)
               if (resolved%body%geometric_stiffness .or. (exporting .and. .not. &
                  resolved%rigid)) then
                  call reuse_body_modes(resolved%body, resolved%interfaces, resolved%modes, &
                     resolved%num_modes_given, mesh_dir, log, times, built%modes, error, &
                     mass_matrix=mass_matrix, stiffness_matrix=stiffness_matrix)
               else
                  call reuse_body_modes(resolved%body, resolved%interfaces, resolved%modes, &
                     resolved%num_modes_given, mesh_dir, log, times, built%modes, error, &
                     mass_matrix=mass_matrix)
               end if
            else if (selects_body(case_model, model, k)) then
               if (resolved%body%geometric_stiffness) then
                  call fatal_error(error, FFRF_INPUT_ERROR, 'geometric_stiffness needs ' // &
                     'num_modes on the &body (the automatic model does not estimate stress ' // &
                     'stiffening)')
                  return
               end if
               if (model%scene) then
                  call scene_body_model(case, case_model, k, mesh_dir, log, times, model, &
                     built%modes, mass_matrix, error)
               else
                  call select_body_model(case, case_model, k, mesh_dir, log, times, model, &
                     built%modes, mass_matrix, error)
               end if
               ! the export: K of the mesh the model chose, assembled again (no eigen solve)
               if (.not. allocated(error) .and. exporting .and. .not. resolved%rigid) &
                  call chosen_mesh_stiffness(resolved, trim(model%bodies(size(model%bodies))% &
                  mesh_file), mesh_dir, log, times, stiffness_matrix, error)
            else if (resolved%body%geometric_stiffness .or. (exporting .and. .not. &
               resolved%rigid)) then
               ! K too, for the static solutions of the geometric stiffness (no reassembly) or
               ! the export
               call compute_body_modes_from_file(resolved%body, resolved%interfaces, &
                  resolved%modes, mesh_dir, log, times, built%modes, error, &
                  mass_matrix=mass_matrix, stiffness_matrix=stiffness_matrix)
            else
               call compute_body_modes_from_file(resolved%body, resolved%interfaces, &
                  resolved%modes, mesh_dir, log, times, built%modes, error, &
                  mass_matrix=mass_matrix)
            end if
            if (allocated(error)) return
            built%num_modes = size(built%modes%frequency_hz)
         end if
         if (resolved%rigid) then
            if (built%meshed) then
               mass = built%modes%mass
               com = built%modes%center_of_mass
               inertia = built%modes%inertia
            else
               mass = motion%mass
               com = motion%center_of_mass
               inertia = inertia_tensor(motion%inertia)
            end if
            built%num_modes = 0
            call rigid%init(mass, com, inertia, list%xyz, list%frames, error)
            if (.not. allocated(error)) call mech%add_body(rigid, name, built%index, error)
            if (.not. allocated(error)) call log%info('mechanism', name // ': rigid, mass ' // &
               to_str(mass, 6) // ' kg, ' // to_str(size(list%names)) // ' marker(s)')
            return
         end if
         call timer%begin()
         call flexible%init(mass_matrix, built%modes%mesh%xyz, built%modes%shape, &
            (2.0_dp * pi * built%modes%frequency_hz)**2, built%modes%virtual_node_shape, &
            virtual_positions(built%modes), error)
         call times%add(name // ': inertia invariants', timer%seconds())
         if (.not. allocated(error)) call add_framed_markers(list, size(resolved%interfaces), &
            flexible, error, case_model%mechanism%markers, built%modes)
         if (.not. allocated(error) .and. motion%modal_damping > 0.0_dp .and. &
            built%num_modes > 0) call flexible%set_modal_damping([motion%modal_damping], error)
         if (.not. allocated(error) .and. resolved%body%geometric_stiffness) then
            if (built%num_modes > 0) then
               call add_geometric_stiffness(resolved%spec, built%modes, stiffness_matrix, &
                  mass_matrix, log, times, flexible, error)
            else
               call log%note('mechanism', name // ': geometric_stiffness ignored: no modes ' // &
                  '(the body moves rigidly)')
            end if
         end if
         if (.not. allocated(error)) call mech%add_body(flexible, name, built%index, error)
         if (allocated(error)) return
         if (exporting) then
            call export_flexible(case, results_file, built%modes, mass_matrix, &
               stiffness_matrix, log, error)
            if (allocated(error)) return
         end if
         call log%info('mechanism', name // ': flexible (FFRF), ' // to_str(built%num_modes) // &
            ' modes, mass ' // to_str(flexible%mass, 6) // ' kg, ' // &
            to_str(flexible%num_markers - size(list%points)) // ' interface marker(s)' // &
            trim(merge(', geometric stiffness', '                     ', &
            allocated(flexible%geometric_stiffness))) // mesh_point_count(size(list%points)))
      end associate
   end procedure add_body

   !> The exports of &run export of a flexible body of the mechanism (export_body, the file a
   !> modal run of the body writes), from the process that writes the results.
   subroutine export_flexible(case, results_file, modes, M, K, log, error)
      type(case_input_t), intent(in) :: case
      character(len=*), intent(in) :: results_file
      !> The body's mesh, interfaces and the modes the mechanism uses
      type(body_modes_t), intent(in) :: modes
      !> Its FE mass and stiffness matrices
      type(csr_t), intent(in) :: M, K
      type(logger_t), intent(in) :: log
      type(error_t), allocatable, intent(out) :: error
      type(parallel_t) :: ranks
      ranks = current_ranks()
      if (.not. ranks%is_root()) return
      call export_body(trim(case%run%export), results_file, modes, M, K, log, error)
   end subroutine export_flexible

   !> The stiffness matrix of a body of the automatic model on the mesh it chose (mesh_file),
   !> for the export: the mesh read and the matrices assembled as for its modes, no eigen
   !> solve, quietly (the model's own log lines said what was computed).
   subroutine chosen_mesh_stiffness(resolved, mesh_file, mesh_dir, log, times, K, error)
      type(model_body_t), intent(in) :: resolved
      character(len=*), intent(in) :: mesh_file, mesh_dir
      type(logger_t), intent(in) :: log
      type(stage_times_t), intent(inout) :: times
      type(csr_t), intent(out) :: K
      type(error_t), allocatable, intent(out) :: error
      type(body_input_t) :: input
      type(modes_spec_t) :: geometry_only
      type(body_modes_t) :: unused
      type(logger_t) :: quiet
      input = resolved%body
      input%mesh_file = mesh_file
      geometry_only = resolved%modes
      geometry_only%num_modes = 0
      quiet = log
      quiet%level = LOG_QUIET
      call compute_body_modes_from_file(input, resolved%interfaces, geometry_only, mesh_dir, &
         quiet, times, unused, error, stiffness_matrix=K)
   end subroutine chosen_mesh_stiffness

   !> ', n at mesh points' for the log when a flexible body has n > 0 node or group markers (the
   !> interface markers are counted without them, issue 24).
   pure function mesh_point_count(n) result(text)
      integer, intent(in) :: n
      character(len=:), allocatable :: text
      text = ''
      if (n > 0) text = ', ' // to_str(n) // ' at mesh points'
   end function mesh_point_count

   !> The modal geometric stiffness of the centrifugal load cases for a flexible body.
   subroutine add_geometric_stiffness(input, modes, K, M, log, times, flexible, error)
      !> The body (material)
      type(body_spec_t), intent(in) :: input
      !> Its mesh, interfaces, RC set and modes
      type(body_modes_t), intent(in) :: modes
      !> Its FE stiffness and consistent mass matrices (compute_body_modes)
      type(csr_t), intent(in) :: K, M
      type(logger_t), intent(in) :: log
      type(stage_times_t), intent(inout) :: times
      !> The flexible body, initialised with the same modes
      type(flexible_body_t), intent(inout) :: flexible
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: geometric_stiffness(:, :, :)
      call compute_modal_geometric_stiffness(input, modes, log, times, geometric_stiffness, &
         error, stiffness_matrix=K, mass_matrix=M)
      if (.not. allocated(error)) call flexible%set_geometric_stiffness(geometric_stiffness, &
         error)
   end subroutine add_geometric_stiffness

end submodule ffrf_app_mechanism_builder_bodies
