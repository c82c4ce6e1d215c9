!> A mechanism_t from a case file's input (namelists of ffrf_input_case) and the modal results of
!> its meshed bodies: bodies, markers, joints, loads, crank, and the consistent starting pose.
!>
!> Bodies. Mechanism body 1 is the ground; then every &body in input order. A flexible body is
!> the reduced FFRF body of its modes (flexible_body_t); with
!> num_modes = 0 it moves rigidly with its mesh's exact inertia. A rigid body is a rigid_body_t
!> with the &body mass keys, or with its mesh's mass properties (mass, centre of mass, inertia
!> about it, from the consistent mass matrix) when it has a mesh_file.
!> Every body starts with its frame origin at `position`, its axes given by `orientation`
!> (default: parallel to the global axes) and its frame moving with `velocity` and
!> `angular_velocity` (default: at rest; modal coordinates and their rates start at zero).
!> A flexible body with `geometric_stiffness` gets the modal geometric stiffness of its six
!> centrifugal load cases (ffrf_modes_modal_geometric_stiffness; stress stiffening of a spinning
!> body, off by default).
!>
!> Markers and joint frames. A flexible body's markers are its interfaces' virtual nodes, with
!> the (deformed) node frame as marker axes (theory.md 3.5). A rigid body's or the ground's
!> markers are made from its &marker points, one per joint end (and per load) that uses them,
!> with the joint's frame: z along the joint axis, x = the unit projection of e_x (e_y if the
!> axis is near e_x) normal to it, y = z × x (global, in the starting pose), stored in the body
!> axes of the &body orientation A (A^T frame); so axis = e_z of an unrotated body gives the body
!> axes. Both ends of a joint get the same frame in the starting pose (the joints of
!> ffrf_mbs_joints expect coinciding frames). A non-spherical joint at a flexible body's
!> interface whose axis is not along the body's z axis (A e_z) gets a marker of its own at the
!> interface's virtual node with the constant orientation C = A^T frame (flexible_body_t
!> add_marker: frame A(theta) exp(phi~) C), so a joint at a flexible interface takes any axis;
!> with the axis along A e_z (or a spherical joint) the interface's marker, the node frame,
!> serves as before. A &marker orientation (rigid bodies, the ground, and a flexible body's
!> interface by its name) gives a joint its frame instead of the axis (resolve_markers); when both ends have one, each keeps its own and
!> check_joint_frames refuses frames that disagree in what the joint locks. A flexible body's
!> &marker with node or group (a mesh point that is no interface) is a further virtual node
!> (flexible_body_t add_point, rows G Psi_B of ffrf_mpc_mesh_point) with a marker of the body's
!> axes, or of its orientation: loads, springs, bushings and sensors take it, joints do not
!> (ffrf_model_model refuses them).
module ffrf_app_mechanism_builder
   use ffrf_core_serial_section, only: enter_serial_section, leave_serial_section, SECTION_FILES
   use ffrf_core_kinds, only: dp, i8, pi
   use ffrf_core_error, only: error_t, fatal_error, add_context, FFRF_INPUT_ERROR, FFRF_IO_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_posix, only: check_input_file
   use ffrf_core_log, only: logger_t, stage_times_t, stage_timer_t
   use ffrf_la_sparse, only: csr_t
   use ffrf_input_case, only: case_input_t
   use ffrf_input_nml_body, only: inertia_tensor
   use ffrf_modes_input, only: body_spec_t
   use ffrf_model_model, only: model_t, model_body_t
   use ffrf_modes_modal_analysis, only: body_modes_t
   use ffrf_app_body_modes, only: compute_body_modes_from_file, reuse_body_modes
   use ffrf_app_body_export, only: export_body, exports_matrices
   use ffrf_core_parallel, only: parallel_t, current_ranks
   use ffrf_modes_modal_geometric_stiffness, only: compute_modal_geometric_stiffness
   use ffrf_input_mechanism, only: GROUND_NAME
   use ffrf_model_mechanism, only: model_joint_t, model_load_t, model_marker_t, LOAD_PRESSURE, &
      LOAD_STARTER, LOAD_DRAG, LOAD_CONSTANT_FORCE, LOAD_CONSTANT_TORQUE
   use ffrf_mbs_joints, only: JOINT_SPHERICAL, JOINT_REVOLUTE, JOINT_UNIVERSAL, JOINT_PRISMATIC, &
      JOINT_FIXED, JOINT_CYLINDRICAL, joint_kind_name
   use ffrf_mbs_rotation, only: identity3, frame_from_axis, euler_from_rotation, euler_g
   use ffrf_mbs_flexible_body, only: flexible_body_t
   use ffrf_mbs_rigid_body, only: rigid_body_t, ground_t
   use ffrf_mbs_mechanism, only: mechanism_t
   use ffrf_mbs_spring_damper, only: spring_damper_t
   use ffrf_mbs_bushing, only: bushing_t
   use ffrf_mbs_joint_driver, only: joint_driver_t
   use ffrf_mbs_mechanism_loads, only: load_t, drag_torque_t, constant_load_t, timed_load_t, &
      LOAD_FORCE, &
      LOAD_TORQUE
   use ffrf_app_engine_starter_load, only: starter_torque_t
   use ffrf_app_engine_crank_sensors, only: add_crank_sensors
   use ffrf_mbs_sensors, only: sensor_t
   use ffrf_app_engine_pressure_load, only: pressure_force_t
   use ffrf_app_engine_pressure, only: pressure_model_t
   use ffrf_app_engine_auto_model, only: model_choice_t, start_model_selection, selects_body, &
      select_body_model, select_step
   use ffrf_app_scene_model, only: scene_record_t
   use ffrf_app_scene_choice, only: scene_body_model, scene_step
   implicit none
   private
   public :: built_body_t, build_mechanism, frame_from_axis, make_pressure_model
   public :: check_joint_frames

   !> What the run keeps of each &body.
   type :: built_body_t
      !> Mechanism index (add_body)
      integer :: index = 0
      !> Kept modes (0 for rigid bodies)
      integer :: num_modes = 0
      !> .true. when it has a mesh (flexible, or rigid with the mesh's inertia)
      logical :: meshed = .false.
      !> Its modal results (meshed bodies): mesh, interfaces, modes
      type(body_modes_t) :: modes
      !> .true. once add_body has made it (its modes computed or reused)
      logical :: made = .false.
   end type built_body_t

   !> Marker requests of one rigid body or the ground: position (body frame) and frame; of one
   !> flexible body: the markers after its interfaces', each a virtual node (nodes) and a frame
   !> C, and its node and group markers (points: model marker indices), virtual nodes after the
   !> interfaces' in this order.
   type :: marker_list_t
      character(len=64), allocatable :: names(:)
      real(dp), allocatable :: xyz(:, :)
      real(dp), allocatable :: frames(:, :, :)
      integer, allocatable :: nodes(:)
      integer, allocatable :: points(:)
   end type marker_list_t

   interface
      !> The sensors of the case resolved to mechanism indices; an engine case (a crank) gets the
      !> engine's crank sensors after them.
      module subroutine make_sensors(case, resolved, bodies, ground_index, sensor_markers, &
            sensors, error)
         type(case_input_t), intent(in) :: case
         type(model_t), intent(in) :: resolved
         type(built_body_t), intent(in) :: bodies(:)
         integer, intent(in) :: ground_index
         !> Marker of each sensor on its body (resolve_markers; 0: none)
         integer, intent(in) :: sensor_markers(:)
         type(sensor_t), allocatable, intent(out) :: sensors(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine make_sensors

      !> Marker number on its body of every joint end and load: ends(1:2, j) for joint j (body 1
      !> and body 2), ends(3, l) for load l. Flexible bodies: the interface's marker handle in the
      !> model, or a framed marker after the interfaces' (module header). Rigid bodies and the
      !> ground: a new marker per distinct (&marker point, frame) in `lists`. A joint's frame in
      !> the starting pose (global) is its marker1's &marker orientation when given, else its
      !> marker2's, else frame_from_axis(axis) (the input checked that axis is then the frame's
      !> z axis: ffrf_input_case).
      module subroutine resolve_markers(resolved, lists, ends, sensor_markers, spring_ends, &
            bushing_ends)
         !> The case resolved (bodies, joints and loads with their marker handles)
         type(model_t), intent(in) :: resolved
         type(marker_list_t), intent(inout) :: lists(0:)
         integer, allocatable, intent(out) :: ends(:, :)
         !> Marker of each &sensor with a marker (0: none); a rigid body's or the ground's sensor
         !> point gets a marker of its own, with the body's axes, after those of joints and loads
         integer, allocatable, intent(out) :: sensor_markers(:)
         !> Markers of the two ends of each &spring (a rigid body's or the ground's point with the
         !> body's axes)
         integer, allocatable, intent(out) :: spring_ends(:, :)
         !> Markers of the two ends of each &bushing (as spring_ends; a &marker orientation gives
         !> the frame)
         integer, allocatable, intent(out) :: bushing_ends(:, :)
      end subroutine resolve_markers

      !> Refuses a joint both of whose markers carry a &marker orientation (rigid bodies and the
      !> ground) when the two frames, turned by their &body orientations, disagree in the given
      !> starting pose in what the joint locks by more than 1e-6 rad: revolute and cylindrical
      !> the z axes, prismatic and fixed the whole frames, universal the twist x1.y2; spherical
      !> nothing (docs/mechanisms.md "Joint frames"). From the given poses, so --check refuses
      !> the same.
      module subroutine check_joint_frames(resolved, error)
         !> The case resolved (bodies with their poses, joints, markers)
         type(model_t), intent(in) :: resolved
         type(error_t), allocatable, intent(out) :: error
      end subroutine check_joint_frames

      !> Compute the body's modes if it has a mesh, make it and add it to the mechanism.
      module subroutine add_body(case, case_model, k, resolved, mesh_dir, log, times, list, &
            model, mech, built, error, results_file)
         type(case_input_t), intent(in) :: case
         !> The case resolved (for the automatic model)
         type(model_t), intent(in) :: case_model
         integer, intent(in) :: k
         !> Body k resolved: rigid flag, modes to compute, interfaces
         type(model_body_t), intent(in) :: resolved
         character(len=*), intent(in) :: mesh_dir
         type(logger_t), intent(in) :: log
         type(stage_times_t), intent(inout) :: times
         type(marker_list_t), intent(in) :: list
         !> The automatic model: chooses the mesh and modes of a flexible body without num_modes
         type(model_choice_t), intent(inout) :: model
         type(mechanism_t), intent(inout) :: mech
         type(built_body_t), intent(inout) :: built
         type(error_t), allocatable, intent(out) :: error
         !> The run's results file: the body's exports of &run export are written beside it
         !> (export_body); absent, none are
         character(len=*), intent(in), optional :: results_file
      end subroutine add_body

      module function virtual_positions(modes) result(xyz)
         type(body_modes_t), intent(in) :: modes
         real(dp) :: xyz(3, size(modes%interfaces))
      end function virtual_positions

      !> The framed markers of a flexible body (resolve_markers), after its interfaces' markers;
      !> first the virtual nodes of its node and group markers (list%points).
      module subroutine add_framed_markers(list, num_interfaces, flexible, error, markers, modes)
         type(marker_list_t), intent(in) :: list
         !> Number of the body's interfaces (markers 1..num_interfaces)
         integer, intent(in) :: num_interfaces
         type(flexible_body_t), intent(inout) :: flexible
         type(error_t), allocatable, intent(out) :: error
         !> The case's &marker groups, resolved (node, group, weighting of list%points)
         type(model_marker_t), intent(in) :: markers(:)
         !> The body's modal results: mesh and mode shapes
         type(body_modes_t), intent(in) :: modes
      end subroutine add_framed_markers

      module subroutine add_joints(resolved, bodies, ground_index, ends, mech, error)
         !> The case resolved (joints: kinds and model body indices)
         type(model_t), intent(in) :: resolved
         type(built_body_t), intent(in) :: bodies(:)
         integer, intent(in) :: ground_index
         integer, intent(in) :: ends(:, :)
         type(mechanism_t), intent(inout) :: mech
         type(error_t), allocatable, intent(out) :: error
      end subroutine add_joints

      !> An error of a mechanism element named by its group and name: '&joint "crank_pin"'
      !> (nothing when error is not allocated).
      module subroutine group_context(error, group, name)
         type(error_t), allocatable, intent(inout) :: error
         !> The namelist group without its '&'
         character(len=*), intent(in) :: group
         character(len=*), intent(in) :: name
      end subroutine group_context

      !> Mechanism index of model body k (0: the ground, at ground_index).
      pure integer module function mechanism_index(bodies, ground_index, k)
         type(built_body_t), intent(in) :: bodies(:)
         integer, intent(in) :: ground_index, k
      end function mechanism_index

      !> The &driver groups as drivers of the mechanism's joints (ffrf_mbs_joint_driver; the
      !> mechanism's joints are the &joint groups in order).
      module subroutine add_drivers(resolved, mech, error)
         type(model_t), intent(in) :: resolved
         type(mechanism_t), intent(inout) :: mech
         type(error_t), allocatable, intent(out) :: error
      end subroutine add_drivers

      !> The &spring, &bushing and &torsion_spring groups as force elements of the mechanism:
      !> spring-dampers (ffrf_mbs_spring_damper; a free length not given is set from the starting
      !> pose by build_mechanism) and bushings (ffrf_mbs_bushing), their model body indices and
      !> marker handles made mechanism bodies and the ends' markers; torsion springs
      !> (ffrf_mbs_torsion_spring: the mechanism's joints are the &joint groups in order).
      module subroutine add_force_elements(resolved, bodies, ground_index, spring_ends, &
            bushing_ends, mech, error)
         !> The case resolved (model body indices, constants)
         type(model_t), intent(in) :: resolved
         type(built_body_t), intent(in) :: bodies(:)
         integer, intent(in) :: ground_index
         !> Markers of the springs' and the bushings' ends (resolve_markers)
         integer, intent(in) :: spring_ends(:, :), bushing_ends(:, :)
         type(mechanism_t), intent(inout) :: mech
         type(error_t), allocatable, intent(out) :: error
      end subroutine add_force_elements

      module subroutine add_loads(resolved, bodies, ends, mech, pressure, error)
         !> The case resolved (loads: kinds, parameters, model body indices)
         type(model_t), intent(in) :: resolved
         type(built_body_t), intent(in) :: bodies(:)
         integer, intent(in) :: ends(:, :)
         type(mechanism_t), intent(inout) :: mech
         !> The cylinder pressure model (made by build_mechanism when a pressure load exists)
         type(pressure_model_t), intent(in) :: pressure
         type(error_t), allocatable, intent(out) :: error
      end subroutine add_loads

      !> The single-zone model of &pressure, or the user's table (angle in deg, absolute pressure
      !> in Pa, one pair per line, '#' comments). The table must be a regular file of at most
      !> MAX_TABLE_BYTES (a FIFO or device would never end); its rows are counted before the
      !> arrays are allocated, and every number must be finite.
      module subroutine make_pressure_model(case, pressure, error)
         type(case_input_t), intent(in) :: case
         type(pressure_model_t), intent(out) :: pressure
         type(error_t), allocatable, intent(out) :: error
      end subroutine make_pressure_model

      !> Starting pose: every body at its &body position and orientation (Euler parameters by
      !> Shepperd's method) with zero modal coordinates, then assembled (minimum-norm Gauss-Newton)
      !> at the &mechanism crank angle; velocities at its crank speed, projected from the &body
      !> velocity and angular_velocity when a body gives one. The log says for each body how far
      !> the assembly moved it.
      module subroutine starting_state(case, resolved, bodies, mech, log, q, v, error)
         type(case_input_t), intent(in) :: case
         !> The case resolved (start positions)
         type(model_t), intent(in) :: resolved
         type(built_body_t), intent(in) :: bodies(:)
         type(mechanism_t), intent(inout) :: mech
         type(logger_t), intent(in) :: log
         real(dp), allocatable, intent(out) :: q(:), v(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine starting_state

      !> The orientation differs from the identity (a rotated starting pose).
      pure logical module function rotated(orientation)
         real(dp), intent(in) :: orientation(3, 3)
      end function rotated
   end interface

contains

   !> Compute the modes of the meshed bodies, build the mechanism and its starting state q, v
   !> (assembled at the &mechanism crank angle and speed). `pressure` is the cylinder pressure
   !> model when a &load of type pressure exists (has_pressure).
   subroutine build_mechanism(case, resolved, mesh_dir, log, times, mech, bodies, q, v, &
         pressure, has_pressure, error, choice, sensors, record, results_file)
      type(case_input_t), intent(in) :: case
      !> The case resolved once (build_model): bodies, interfaces as marker handles, modes,
      !> joints, loads
      type(model_t), intent(in) :: resolved
      !> Folder of relative mesh files
      character(len=*), intent(in) :: mesh_dir
      type(logger_t), intent(in) :: log
      type(stage_times_t), intent(inout) :: times
      type(mechanism_t), intent(out) :: mech
      type(built_body_t), allocatable, intent(out) :: bodies(:)
      real(dp), allocatable, intent(out) :: q(:), v(:)
      type(pressure_model_t), intent(out) :: pressure
      logical, intent(out) :: has_pressure
      type(error_t), allocatable, intent(out) :: error
      !> The automatic model (&model selection; ffrf_app_engine_auto_model): what it chose, with the
      !> time step when &integrator gives none (choice%h > 0)
      type(model_choice_t), intent(out), optional :: choice
      !> The sensors of the case (&sensor, input order), then an engine case's crank sensors
      !> (ffrf_app_engine_crank_sensors)
      type(sensor_t), allocatable, intent(out), optional :: sensors(:)
      !> A scene without a crank: the automatic model's rigid pre-run (ffrf_app_scene_prerun)
      type(scene_record_t), intent(in), optional :: record
      !> The run's results file: each body's exports of &run export (the Exudyn body file) are
      !> written beside it as the body is built; absent (a session that records nothing), none
      character(len=*), intent(in), optional :: results_file
      type(model_choice_t) :: model
      integer, allocatable :: sensor_markers(:)
      type(marker_list_t), allocatable :: lists(:)
      type(ground_t) :: ground
      integer, allocatable :: ends(:, :), spring_ends(:, :), bushing_ends(:, :)
      integer :: nb, k, ground_index

      nb = size(case%bodies)
      allocate (bodies(nb), lists(0:nb))
      do k = 0, nb
         allocate (lists(k)%names(0), lists(k)%xyz(3, 0), lists(k)%frames(3, 3, 0), &
            lists(k)%nodes(0), lists(k)%points(0))
      end do
      has_pressure = resolved%mechanism%has_pressure
      if (has_pressure) then
         call make_pressure_model(case, pressure, error)
         if (allocated(error)) return
      end if
      call start_model_selection(case, resolved, pressure, has_pressure, log, model, record)

      do k = 1, nb
         bodies(k)%meshed = resolved%bodies(k)%meshed
      end do
      ! Markers of the joint ends and loads
      call check_joint_frames(resolved, error)
      if (allocated(error)) return
      call resolve_markers(resolved, lists, ends, sensor_markers, spring_ends, bushing_ends)
      call ground%init(lists(0)%xyz, lists(0)%frames, error)
      if (.not. allocated(error)) call mech%add_body(ground, GROUND_NAME, ground_index, error)
      if (allocated(error)) return
      do k = 1, nb
         call add_body(case, resolved, k, resolved%bodies(k), mesh_dir, log, times, lists(k), &
            model, mech, bodies(k), error, results_file)
         bodies(k)%made = .not. allocated(error)
         call group_context(error, 'body', case%bodies(k)%name)
         if (allocated(error)) return
      end do
      if (present(results_file)) then
         if (len(results_file) > 0 .and. exports_matrices(case%run%export) .and. &
            any(resolved%bodies%rigid)) call log%info('output', 'export: rigid bodies ' // &
            'skipped (no mesh dofs): ' // rigid_names(case, resolved))
      end if
      if (model%scene) then
         call scene_step(case, resolved, log, model)
      else
         call select_step(resolved, log, model)
      end if
      if (present(choice)) choice = model
      call add_joints(resolved, bodies, ground_index, ends, mech, error)
      if (.not. allocated(error)) call add_loads(resolved, bodies, ends, mech, pressure, error)
      if (.not. allocated(error)) call add_force_elements(resolved, bodies, ground_index, &
         spring_ends, bushing_ends, mech, error)
      if (.not. allocated(error)) call add_drivers(resolved, mech, error)
      if (allocated(error)) return
      mech%gravity = case%mechanism%mechanism%gravity
      if (resolved%mechanism%crank > 0) then
         call mech%set_rotor(bodies(resolved%mechanism%crank)%index, error)
         if (allocated(error)) return
      end if
      if (present(sensors)) then
         call make_sensors(case, resolved, bodies, ground_index, sensor_markers, sensors, error)
         if (allocated(error)) return
      end if
      call starting_state(case, resolved, bodies, mech, log, q, v, error)
      if (.not. allocated(error)) call mech%set_spring_free_lengths(q, error)
      if (.not. allocated(error)) call mech%set_torsion_start(q)
   end subroutine build_mechanism

   !> The names of the rigid bodies, comma separated (the export's log line).
   function rigid_names(case, resolved) result(names)
      type(case_input_t), intent(in) :: case
      type(model_t), intent(in) :: resolved
      character(len=:), allocatable :: names
      integer :: k
      names = ''
      do k = 1, size(case%bodies)
         if (.not. resolved%bodies(k)%rigid) cycle
         if (len(names) > 0) names = names // ', '
         names = names // trim(case%bodies(k)%name)
      end do
   end function rigid_names

end module ffrf_app_mechanism_builder
