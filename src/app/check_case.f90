!> `ffrf --check`: everything of a case that can be checked without computing modes or
!> integrating: the case text (ffrf_input_case), every flexible body's mesh and coarse meshes (read,
!> the body's volumes extracted, its interfaces built: nodes, weights, virtual node, reference
!> conditions parsed; its node and group markers placed on it), the meshes of rigid bodies that
!> take their mass from a mesh, and the pressure model or table of an engine, and the stored
!> modes of a body with &body modes_file (read and checked against the body's fingerprint by the
!> run's own check, check_stored_modes). Meant for quick validation, e.g. by a fuzzer: no results
!> file is written and no matrix is assembled. What a mechanism run would refuse only after the
!> modes is refused here too: rho_inf = 1 with the default index-3 constraints (generalized-alpha
!> refuses it with constraints, and every mechanism has its joints and Euler rows:
!> ffrf_mbs_generalized_alpha; constraints = 'index2' accepts it, theory.md 4.6). Gravity is
!> accepted on every body kind (rigid and flexible, docs/theory.md 3.6), so there is nothing
!> about it to refuse.
module ffrf_app_check_case
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, add_context, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_paths, only: folder_of, join_path
   use ffrf_core_log, only: logger_t
   use ffrf_input_case, only: case_input_t
   use ffrf_mesh_mesh, only: mesh_t, extract_body
   use ffrf_mesh_bulk_data, only: read_mesh_file
   use ffrf_mpc_interface, only: interface_t, build_interface
   use ffrf_mpc_mesh_point, only: mesh_point_t, build_mesh_point
   use ffrf_model_model, only: model_t, model_body_t, build_model
   use ffrf_app_run_options, only: run_options_t, set_log_level
   use ffrf_app_output_paths, only: check_output_paths
   use ffrf_input_nml_run, only: log_level_code
   use ffrf_app_engine_pressure, only: pressure_model_t
   use ffrf_app_mechanism_builder, only: make_pressure_model, check_joint_frames
   use ffrf_app_body_modes, only: check_stored_modes
   use ffrf_app_scene_prerun, only: check_scene_targets
   use ffrf_io_modes_file, only: stored_modes_t, read_stored_modes
   use ffrf_mbs_generalized_alpha, only: GALPHA_INDEX3
   implicit none
   private
   public :: check_case

contains

   !> Check `case` (read by read_case) and its meshes; no error: the case can be run.
   subroutine check_case(case, options, log, error)
      !> The case, read and checked
      type(case_input_t), intent(in) :: case
      !> Folders (the mesh folder) and log level
      type(run_options_t), intent(in) :: options
      !> Logger: one line per mesh checked
      type(logger_t), intent(inout) :: log
      type(error_t), allocatable, intent(out) :: error
      type(pressure_model_t) :: pressure
      character(len=:), allocatable :: mesh_dir
      character(len=256), allocatable :: files(:)
      type(model_t) :: model
      type(mesh_t) :: body_mesh
      type(interface_t), allocatable :: interfaces(:)
      logical :: flexible
      integer :: k, f

      call set_log_level(log, options, log_level_code(case%run%log_level))
      ! as the runs: no output on an input or on another output
      call check_output_paths(case, options, error)
      if (allocated(error)) return
      call build_model(case, model, error)
      if (allocated(error)) then
         call add_context(error, case%file_name)
         return
      end if
      ! as galpha_init at the run's start, after the modes: a mechanism always has constraints
      if (case%is_mechanism .and. model%mechanism%integrator%rho_inf >= 1.0_dp .and. &
         model%mechanism%integrator%constraints == GALPHA_INDEX3) then
         call fatal_error(error, FFRF_INPUT_ERROR, case%file_name // ': &integrator rho_inf = ' &
            // to_str(model%mechanism%integrator%rho_inf) // ': generalized-alpha without ' // &
            'numerical damping is unstable with the index-3 constraints of a mechanism (its ' // &
            'joints and Euler rows; the run refuses it after computing the modes); use ' // &
            'rho_inf < 1, typically 0.6 to 0.9, or constraints = ''index2''')
         return
      end if
      ! as build_mechanism: the joint frames of two oriented markers, in the given poses
      if (case%is_mechanism) then
         call check_joint_frames(model, error)
         ! as the automatic model of a scene: its targets (no pre-run, no modes)
         if (.not. allocated(error)) call check_scene_targets(case, model, error)
         if (allocated(error)) then
            call add_context(error, case%file_name)
            return
         end if
      end if
      mesh_dir = options%mesh_dir
      if (len(mesh_dir) == 0) mesh_dir = folder_of(case%file_name)
      do k = 1, size(case%bodies)
         associate (body => case%bodies(k))
            ! As the runs: a rigid body has no modes, and needs a mesh only for its mass
            flexible = .not. model%bodies(k)%rigid
            if (.not. flexible .and. len_trim(body%mesh_file) == 0) cycle
            files = [body%mesh_file]
            if (case%is_mechanism .and. flexible) files = [pack(case%motions(k)%coarse_meshes, &
               len_trim(case%motions(k)%coarse_meshes) > 0), files]
            do f = 1, size(files)
               call check_body_mesh(model%bodies(k), join_path(mesh_dir, trim(files(f))), &
                  flexible, log, body_mesh, interfaces, error)
               if (.not. allocated(error) .and. flexible) call check_mesh_points(k, model, &
                  body_mesh, error)
               if (allocated(error)) exit
            end do
            ! the body's own mesh (the last file) for the modes taken from a file
            if (.not. allocated(error) .and. flexible .and. len_trim(body%modes_file) > 0) &
               call check_modes_file(model%bodies(k), body_mesh, interfaces, log, error)
            if (allocated(error)) then
               call add_context(error, case%file_name // ': &body "' // trim(body%name) // '"')
               return
            end if
         end associate
      end do
      if (model%mechanism%has_pressure) then
         call make_pressure_model(case, pressure, error)
         if (allocated(error)) then
            call add_context(error, case%file_name)
            return
         end if
      end if
      call log%info('check', case%file_name // ': checked, ' // to_str(size(case%bodies)) // &
         ' bodies, ' // to_str(size(case%interfaces)) // ' interfaces: no errors')
   end subroutine check_case

   !> Read one mesh of body k, extract its volumes and (flexible) build its interfaces.
   subroutine check_body_mesh(model_body, mesh_file, flexible, log, body_mesh, interfaces, error)
      !> The body, resolved (volumes, interfaces)
      type(model_body_t), intent(in) :: model_body
      character(len=*), intent(in) :: mesh_file
      logical, intent(in) :: flexible
      type(logger_t), intent(in) :: log
      !> The body cut from the mesh
      type(mesh_t), intent(out) :: body_mesh
      !> Its interfaces, built (flexible; none for a rigid body)
      type(interface_t), allocatable, intent(out) :: interfaces(:)
      type(error_t), allocatable, intent(out) :: error
      type(mesh_t) :: mesh
      integer :: i
      associate (body => model_body%body)
         call read_mesh_file(mesh_file, mesh, error)
         if (allocated(error)) return
         call extract_body(mesh, pack(body%volumes, len_trim(body%volumes) > 0), body_mesh, &
            error)
         if (allocated(error)) then
            call add_context(error, 'mesh "' // mesh_file // '"')
            return
         end if
         allocate (interfaces(merge(size(model_body%interfaces), 0, flexible)))
         if (flexible) then
            do i = 1, size(model_body%interfaces)
               call build_interface(body_mesh, model_body%interfaces(i), interfaces(i), error)
               if (allocated(error)) then
                  call add_context(error, 'mesh "' // mesh_file // '"')
                  return
               end if
            end do
         end if
         call log%info('check', trim(body%name) // ': ' // mesh_file // ', ' // &
            to_str(body_mesh%num_nodes) // ' nodes, ' // to_str(body_mesh%num_tets()) // &
            ' tetrahedra')
      end associate
   end subroutine check_body_mesh

   !> The node and group markers of model body k (&marker node, group) on its mesh, as the run
   !> builds them (ffrf_mpc_mesh_point): an unknown node tag or physical group, or a curve or
   !> point without nodes on the body, fails here.
   subroutine check_mesh_points(k, model, body_mesh, error)
      integer, intent(in) :: k
      type(model_t), intent(in) :: model
      type(mesh_t), intent(in) :: body_mesh
      type(error_t), allocatable, intent(out) :: error
      integer :: m
      type(mesh_point_t) :: point
      do m = 1, size(model%mechanism%markers)
         associate (marker => model%mechanism%markers(m))
            ! a marker named as an interface only orients it (docs/mechanisms.md "Joint frames")
            if (marker%body /= k .or. (marker%node == 0 .and. len_trim(marker%group) == 0)) cycle
            call build_mesh_point(body_mesh, marker%node, marker%group, marker%weighting, &
               point, error)
            if (allocated(error)) then
               call add_context(error, '&marker "' // trim(marker%name) // '"')
               return
            end if
         end associate
      end do
   end subroutine check_mesh_points

   !> &body modes_file: read the body's stored modes and check them as the run does
   !> (check_stored_modes): a missing or unreadable file, no modes of the body, or modes computed
   !> for another mesh, material, interfaces or modes specification fail here as in the run.
   subroutine check_modes_file(model_body, body_mesh, interfaces, log, error)
      !> The body, resolved (modes to compute, num_modes given)
      type(model_body_t), intent(in) :: model_body
      !> The body cut from its mesh file
      type(mesh_t), intent(in) :: body_mesh
      !> Its interfaces, built
      type(interface_t), intent(in) :: interfaces(:)
      type(logger_t), intent(in) :: log
      type(error_t), allocatable, intent(out) :: error
      type(stored_modes_t) :: stored
      associate (body => model_body%body)
         call read_stored_modes(trim(body%modes_file), trim(body%name), 'modes_file', stored, &
            error)
         if (allocated(error)) return
         call check_stored_modes(body, body_mesh, interfaces, model_body%modes, &
            model_body%num_modes_given, stored, error)
         if (allocated(error)) return
         call log%info('check', trim(body%name) // ': ' // to_str(size(stored%frequency_hz)) // &
            ' modes in modes_file "' // trim(body%modes_file) // '", fingerprint ' // &
            stored%fingerprint%total_hash() // ' matches')
      end associate
   end subroutine check_modes_file

end module ffrf_app_check_case
