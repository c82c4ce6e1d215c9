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
!> serves as before. A &marker orientation (rigid bodies and the ground) gives a joint its frame
!> instead of the axis (resolve_markers).
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
   use ffrf_modes_modal_geometric_stiffness, only: compute_modal_geometric_stiffness
   use ffrf_input_mechanism, only: GROUND_NAME
   use ffrf_model_mechanism, only: model_joint_t, model_load_t, LOAD_PRESSURE, LOAD_STARTER, &
      LOAD_DRAG, LOAD_CONSTANT_FORCE, LOAD_CONSTANT_TORQUE
   use ffrf_mbs_joints, only: JOINT_SPHERICAL
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
   implicit none
   private
   public :: built_body_t, build_mechanism, frame_from_axis, make_pressure_model

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
   end type built_body_t

   !> Marker requests of one rigid body or the ground: position (body frame) and frame; of one
   !> flexible body: the markers after its interfaces', each an interface (nodes) and a frame C.
   type :: marker_list_t
      character(len=64), allocatable :: names(:)
      real(dp), allocatable :: xyz(:, :)
      real(dp), allocatable :: frames(:, :, :)
      integer, allocatable :: nodes(:)
   end type marker_list_t

contains

   !> Compute the modes of the meshed bodies, build the mechanism and its starting state q, v
   !> (assembled at the &mechanism crank angle and speed). `pressure` is the cylinder pressure
   !> model when a &load of type pressure exists (has_pressure).
   subroutine build_mechanism(case, resolved, mesh_dir, log, times, mech, bodies, q, v, &
         pressure, has_pressure, error, choice, sensors)
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
            lists(k)%nodes(0))
      end do
      has_pressure = resolved%mechanism%has_pressure
      if (has_pressure) then
         call make_pressure_model(case, pressure, error)
         if (allocated(error)) return
      end if
      call start_model_selection(case, resolved, pressure, has_pressure, log, model)

      do k = 1, nb
         bodies(k)%meshed = resolved%bodies(k)%meshed
      end do
      ! Markers of the joint ends and loads
      call resolve_markers(resolved, lists, ends, sensor_markers, spring_ends, bushing_ends)
      call ground%init(lists(0)%xyz, lists(0)%frames, error)
      if (.not. allocated(error)) call mech%add_body(ground, GROUND_NAME, ground_index, error)
      if (allocated(error)) return
      do k = 1, nb
         call add_body(case, resolved, k, resolved%bodies(k), mesh_dir, log, times, lists(k), &
            model, mech, bodies(k), error)
         if (allocated(error)) then
            call add_context(error, '&body "' // trim(case%bodies(k)%name) // '"')
            return
         end if
      end do
      call select_step(resolved, log, model)
      if (present(choice)) choice = model
      call add_joints(resolved, bodies, ground_index, ends, mech, error)
      if (.not. allocated(error)) call add_loads(resolved, bodies, ends, mech, pressure, error)
      if (.not. allocated(error)) call add_springs(resolved, bodies, ground_index, spring_ends, &
         mech, error)
      if (.not. allocated(error)) call add_drivers(resolved, mech, error)
      if (.not. allocated(error)) call add_force_elements(resolved, bodies, ground_index, &
         bushing_ends, mech, error)
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

   !> The sensors of the case resolved to mechanism indices; an engine case (a crank) gets the
   !> engine's crank sensors after them.
   subroutine make_sensors(case, resolved, bodies, ground_index, sensor_markers, sensors, error)
      type(case_input_t), intent(in) :: case
      type(model_t), intent(in) :: resolved
      type(built_body_t), intent(in) :: bodies(:)
      integer, intent(in) :: ground_index
      !> Marker of each sensor on its body (resolve_markers; 0: none)
      integer, intent(in) :: sensor_markers(:)
      type(sensor_t), allocatable, intent(out) :: sensors(:)
      type(error_t), allocatable, intent(out) :: error
      integer :: k
      associate (given => resolved%mechanism%sensors)
         allocate (sensors(size(given)))
         do k = 1, size(given)
            sensors(k)%name = given(k)%name
            sensors(k)%kind = given(k)%kind
            sensors(k)%marker = sensor_markers(k)
            if (sensors(k)%marker > 0) sensors(k)%marker_name = case%mechanism%sensors(k)%marker
            sensors(k)%joint = given(k)%joint
            sensors(k)%spring = given(k)%spring
            sensors(k)%body = mechanism_index(bodies, ground_index, given(k)%body)
            if (given(k)%node > 0) then
               call node_rows(bodies(given(k)%body), given(k)%node, sensors(k), error)
               if (allocated(error)) then
                  call add_context(error, '&sensor "' // trim(given(k)%name) // '"')
                  return
               end if
            end if
         end do
      end associate
      if (resolved%mechanism%crank > 0) call add_crank_sensors(sensors, error)
   end subroutine make_sensors

   !> A node sensor's node (a Gmsh node tag of the body's mesh): its position in the body frame
   !> and its rows of the kept mode shapes (none for a rigid body).
   subroutine node_rows(body, node, sensor, error)
      type(built_body_t), intent(in) :: body
      integer, intent(in) :: node
      type(sensor_t), intent(inout) :: sensor
      type(error_t), allocatable, intent(out) :: error
      integer :: i
      if (.not. body%meshed .or. .not. allocated(body%modes%mesh%xyz)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'node = ' // to_str(node) // ': the body ' // &
            'has no mesh; measure a body with a mesh_file')
         return
      end if
      i = node
      if (allocated(body%modes%mesh%node_tags)) i = findloc(body%modes%mesh%node_tags, &
         int(node, i8), dim=1)
      if (i < 1 .or. i > size(body%modes%mesh%xyz, 2)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'node = ' // to_str(node) // ' is not a ' // &
            'node of the body''s mesh (' // to_str(size(body%modes%mesh%xyz, 2)) // ' nodes)')
         return
      end if
      sensor%node = node
      sensor%node_xyz = body%modes%mesh%xyz(:, i)
      allocate (sensor%node_shape(3, 0))
      if (body%num_modes > 0 .and. allocated(body%modes%shape)) &
         sensor%node_shape = body%modes%shape(3 * i - 2:3 * i, 1:body%num_modes)
   end subroutine node_rows

   !> Marker number on its body of every joint end and load: ends(1:2, j) for joint j (body 1
   !> and body 2), ends(3, l) for load l. Flexible bodies: the interface's marker handle in the
   !> model, or a framed marker after the interfaces' (module header). Rigid bodies and the
   !> ground: a new marker per distinct (&marker point, frame) in `lists`. A joint's frame in
   !> the starting pose (global) is its marker1's &marker orientation when given, else its
   !> marker2's, else frame_from_axis(axis) (the input checked that axis is then the frame's
   !> z axis: ffrf_input_case).
   subroutine resolve_markers(resolved, lists, ends, sensor_markers, spring_ends, bushing_ends)
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
      real(dp) :: frame(3, 3)
      logical :: given
      integer :: j, l, e
      associate (joints => resolved%mechanism%joints, loads => resolved%mechanism%loads)
         allocate (ends(3, max(size(joints), size(loads))), source=0)
         do j = 1, size(joints)
            call joint_frame(joints(j), frame, given)
            do e = 1, 2
               call marker_of(joints(j)%body(e), joints(j)%marker(e), frame, .true., &
                  ends(e, j), joints(j)%kind == JOINT_SPHERICAL .or. (.not. given .and. &
                  along_body_z(joints(j)%body(e), joints(j)%axis)))
            end do
         end do
         do l = 1, size(loads)
            call marker_of(loads(l)%body, loads(l)%marker, identity3(), .false., ends(3, l), &
               .true.)
         end do
      end associate
      associate (sensors => resolved%mechanism%sensors)
         allocate (sensor_markers(size(sensors)), source=0)
         do l = 1, size(sensors)
            if (sensors(l)%marker > 0) call marker_of(sensors(l)%body, sensors(l)%marker, &
               identity3(), .false., sensor_markers(l), .true.)
         end do
      end associate
      associate (springs => resolved%mechanism%springs)
         allocate (spring_ends(2, size(springs)), source=0)
         do l = 1, size(springs)
            do e = 1, 2
               call marker_of(springs(l)%body(e), springs(l)%marker(e), identity3(), .false., &
                  spring_ends(e, l), .true.)
            end do
         end do
      end associate
      associate (bushings => resolved%mechanism%bushings)
         allocate (bushing_ends(2, size(bushings)), source=0)
         do l = 1, size(bushings)
            call marker_of(bushings(l)%body_a, bushings(l)%marker_a, identity3(), .false., &
               bushing_ends(1, l), .true.)
            call marker_of(bushings(l)%body_b, bushings(l)%marker_b, identity3(), .false., &
               bushing_ends(2, l), .true.)
         end do
      end associate

   contains

      !> The joint's frame in the starting pose (global) and whether a &marker orientation gave
      !> it.
      subroutine joint_frame(joint, frame, given)
         type(model_joint_t), intent(in) :: joint
         real(dp), intent(out) :: frame(3, 3)
         logical, intent(out) :: given
         integer :: e
         given = .false.
         frame = frame_from_axis(joint%axis)
         do e = 1, 2
            if (.not. is_oriented(joint%body(e), joint%marker(e))) cycle
            given = .true.
            frame = resolved%mechanism%markers(joint%marker(e))%orientation
            if (joint%body(e) > 0) frame = matmul(resolved%bodies(joint%body(e))%motion% &
               orientation, frame)
            return
         end do
      end subroutine joint_frame

      !> Marker handle `handle` of model body b (0: ground) is a &marker point with an orientation.
      logical function is_oriented(b, handle)
         integer, intent(in) :: b, handle
         is_oriented = .false.
         if (b > 0) then
            if (.not. resolved%bodies(b)%rigid) return
         end if
         is_oriented = resolved%mechanism%markers(handle)%oriented
      end function is_oriented

      !> The (unit) joint axis is along model body b's z axis in the starting pose (b > 0).
      logical function along_body_z(b, axis)
         integer, intent(in) :: b
         real(dp), intent(in) :: axis(3)
         along_body_z = .false.
         if (b > 0) along_body_z = abs(dot_product(axis, &
            resolved%bodies(b)%motion%orientation(:, 3))) >= 1.0_dp - 1.0e-12_dp
      end function along_body_z

      !> Marker on model body b (0: ground) of the marker handle `handle` (module
      !> ffrf_model_mechanism). A joint end's `frame` is global in the starting pose (stored in
      !> the body axes of a rotated body); a load's, sensor's or spring's is the body axes; a
      !> &marker orientation replaces either. A flexible body's interface marker (the node
      !> frame) serves when `node_frame`, else a framed marker at its virtual node.
      subroutine marker_of(b, handle, frame, joint_end, marker, node_frame)
         integer, intent(in) :: b, handle
         real(dp), intent(in) :: frame(3, 3)
         logical, intent(in) :: joint_end, node_frame
         integer, intent(out) :: marker
         integer :: k
         real(dp) :: local(3, 3)
         local = frame
         if (joint_end .and. b > 0) then
            if (rotated(resolved%bodies(b)%motion%orientation)) local = &
               matmul(transpose(resolved%bodies(b)%motion%orientation), frame)
         end if
         if (b > 0) then
            if (.not. resolved%bodies(b)%rigid) then
               marker = handle
               if (node_frame) return
               do k = 1, size(lists(b)%nodes)
                  if (lists(b)%nodes(k) == handle .and. maxval(abs(lists(b)%frames(:, :, k) - &
                     local)) < 1.0e-12_dp) then
                     marker = size(resolved%bodies(b)%interfaces) + k
                     return
                  end if
               end do
               lists(b)%nodes = [lists(b)%nodes, handle]
               lists(b)%frames = reshape([lists(b)%frames, local], [3, 3, size(lists(b)%nodes)])
               marker = size(resolved%bodies(b)%interfaces) + size(lists(b)%nodes)
               return
            end if
         end if
         associate (point => resolved%mechanism%markers(handle))
            if (point%oriented) local = point%orientation
            do k = 1, size(lists(b)%names)
               if (lists(b)%names(k) == point%name .and. maxval(abs(lists(b)%frames(:, :, k) - &
                  local)) < 1.0e-12_dp) then
                  marker = k
                  return
               end if
            end do
            lists(b)%names = [character(len=64) :: lists(b)%names, point%name]
            lists(b)%xyz = reshape([lists(b)%xyz, point%position], [3, size(lists(b)%names)])
         end associate
         lists(b)%frames = reshape([lists(b)%frames, local], [3, 3, size(lists(b)%names)])
         marker = size(lists(b)%names)
      end subroutine marker_of

   end subroutine resolve_markers

   !> Compute the body's modes if it has a mesh, make it and add it to the mechanism.
   subroutine add_body(case, case_model, k, resolved, mesh_dir, log, times, list, model, mech, &
         built, error)
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
      type(csr_t) :: mass_matrix, stiffness_matrix
      type(flexible_body_t) :: flexible
      type(rigid_body_t) :: rigid
      type(stage_timer_t) :: timer
      real(dp) :: mass, com(3), inertia(3, 3)
      character(len=:), allocatable :: name

      name = trim(resolved%name)
      associate (motion => resolved%motion)
         if (built%meshed) then
            if (len_trim(resolved%body%modes_file) > 0) then
               ! modes from an earlier run's results file, checked (K only for the geometric
               ! stiffness)
               if (resolved%body%geometric_stiffness) then
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
               call select_body_model(case, case_model, k, mesh_dir, log, times, model, &
                  built%modes, mass_matrix, error)
            else if (resolved%body%geometric_stiffness) then
               ! K too, for the static solutions of the geometric stiffness (no reassembly)
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
            flexible, error)
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
         call log%info('mechanism', name // ': flexible (FFRF), ' // to_str(built%num_modes) // &
            ' modes, mass ' // to_str(flexible%mass, 6) // ' kg, ' // &
            to_str(flexible%num_markers) // ' interface marker(s)' // &
            trim(merge(', geometric stiffness', '                     ', &
            allocated(flexible%geometric_stiffness))))
      end associate
   end subroutine add_body

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

   function virtual_positions(modes) result(xyz)
      type(body_modes_t), intent(in) :: modes
      real(dp) :: xyz(3, size(modes%interfaces))
      integer :: i
      do i = 1, size(modes%interfaces)
         xyz(:, i) = modes%interfaces(i)%virtual_xyz
      end do
   end function virtual_positions

   !> The framed markers of a flexible body (resolve_markers), after its interfaces' markers.
   subroutine add_framed_markers(list, num_interfaces, flexible, error)
      type(marker_list_t), intent(in) :: list
      !> Number of the body's interfaces (markers 1..num_interfaces)
      integer, intent(in) :: num_interfaces
      type(flexible_body_t), intent(inout) :: flexible
      type(error_t), allocatable, intent(out) :: error
      integer :: i, marker
      do i = 1, size(list%nodes)
         call flexible%add_marker(list%nodes(i), list%frames(:, :, i), marker, error)
         if (allocated(error)) return
         if (marker /= num_interfaces + i) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'joint frame marker ' // to_str(i) // &
               ' became marker ' // to_str(marker) // ', expected ' // &
               to_str(num_interfaces + i) // ' (the modes have ' // &
               to_str(flexible%num_markers - i) // ' interfaces, the case ' // &
               to_str(num_interfaces) // ')')
            return
         end if
      end do
   end subroutine add_framed_markers

   subroutine add_joints(resolved, bodies, ground_index, ends, mech, error)
      !> The case resolved (joints: kinds and model body indices)
      type(model_t), intent(in) :: resolved
      type(built_body_t), intent(in) :: bodies(:)
      integer, intent(in) :: ground_index
      integer, intent(in) :: ends(:, :)
      type(mechanism_t), intent(inout) :: mech
      type(error_t), allocatable, intent(out) :: error
      integer :: j
      associate (joints => resolved%mechanism%joints)
         do j = 1, size(joints)
            call mech%add_joint(joints(j)%kind, trim(joints(j)%name), &
               mechanism_index(bodies, ground_index, joints(j)%body(1)), ends(1, j), &
               mechanism_index(bodies, ground_index, joints(j)%body(2)), ends(2, j), error)
            if (allocated(error)) then
               call add_context(error, '&joint "' // trim(joints(j)%name) // '"')
               return
            end if
         end do
      end associate
   end subroutine add_joints

   !> Mechanism index of model body k (0: the ground, at ground_index).
   pure integer function mechanism_index(bodies, ground_index, k)
      type(built_body_t), intent(in) :: bodies(:)
      integer, intent(in) :: ground_index, k
      mechanism_index = ground_index
      if (k > 0) mechanism_index = bodies(k)%index
   end function mechanism_index

   !> The &spring groups as spring-dampers of the mechanism (ffrf_mbs_spring_damper); a free
   !> length not given is set from the starting pose by build_mechanism.
   subroutine add_springs(resolved, bodies, ground_index, spring_ends, mech, error)
      !> The case resolved (springs: model body indices, constants)
      type(model_t), intent(in) :: resolved
      type(built_body_t), intent(in) :: bodies(:)
      integer, intent(in) :: ground_index
      !> Markers of the springs' ends (resolve_markers)
      integer, intent(in) :: spring_ends(:, :)
      type(mechanism_t), intent(inout) :: mech
      type(error_t), allocatable, intent(out) :: error
      type(spring_damper_t) :: spring
      integer :: s
      associate (springs => resolved%mechanism%springs)
         do s = 1, size(springs)
            spring%name = springs(s)%name
            spring%body_a = mechanism_index(bodies, ground_index, springs(s)%body(1))
            spring%marker_a = spring_ends(1, s)
            spring%body_b = mechanism_index(bodies, ground_index, springs(s)%body(2))
            spring%marker_b = spring_ends(2, s)
            spring%stiffness = springs(s)%stiffness
            spring%damping = springs(s)%damping
            spring%free_length = springs(s)%free_length
            call mech%add_spring(spring, error)
            if (allocated(error)) then
               call add_context(error, '&spring "' // trim(springs(s)%name) // '"')
               return
            end if
         end do
      end associate
   end subroutine add_springs

   !> The &driver groups as drivers of the mechanism's joints (ffrf_mbs_joint_driver; the
   !> mechanism's joints are the &joint groups in order).
   subroutine add_drivers(resolved, mech, error)
      type(model_t), intent(in) :: resolved
      type(mechanism_t), intent(inout) :: mech
      type(error_t), allocatable, intent(out) :: error
      type(joint_driver_t) :: driver
      integer :: d
      do d = 1, size(resolved%mechanism%drivers)
         associate (given => resolved%mechanism%drivers(d))
            driver%name = given%name
            driver%joint = given%joint
            driver%rate = given%rate
            driver%offset = given%offset
            driver%law = given%law
            call mech%add_driver(driver, error)
            if (allocated(error)) then
               call add_context(error, '&driver "' // trim(given%name) // '"')
               return
            end if
         end associate
      end do
   end subroutine add_drivers

   !> The &bushing and &torsion_spring groups as force elements of the mechanism
   !> (ffrf_mbs_bushing: model body indices and marker handles become mechanism bodies and the
   !> ends' markers; ffrf_mbs_torsion_spring: the mechanism's joints are the &joint groups in
   !> order).
   subroutine add_force_elements(resolved, bodies, ground_index, bushing_ends, mech, error)
      type(model_t), intent(in) :: resolved
      type(built_body_t), intent(in) :: bodies(:)
      integer, intent(in) :: ground_index
      !> Markers of the bushings' ends (resolve_markers)
      integer, intent(in) :: bushing_ends(:, :)
      type(mechanism_t), intent(inout) :: mech
      type(error_t), allocatable, intent(out) :: error
      type(bushing_t) :: bushing
      integer :: s
      do s = 1, size(resolved%mechanism%bushings)
         bushing = resolved%mechanism%bushings(s)
         bushing%body_a = mechanism_index(bodies, ground_index, bushing%body_a)
         bushing%body_b = mechanism_index(bodies, ground_index, bushing%body_b)
         bushing%marker_a = bushing_ends(1, s)
         bushing%marker_b = bushing_ends(2, s)
         call mech%add_bushing(bushing, error)
         if (allocated(error)) then
            call add_context(error, '&bushing "' // trim(bushing%name) // '"')
            return
         end if
      end do
      do s = 1, size(resolved%mechanism%torsion_springs)
         call mech%add_torsion_spring(resolved%mechanism%torsion_springs(s), error)
         if (allocated(error)) then
            call add_context(error, '&torsion_spring "' // &
               trim(resolved%mechanism%torsion_springs(s)%name) // '"')
            return
         end if
      end do
   end subroutine add_force_elements

   subroutine add_loads(resolved, bodies, ends, mech, pressure, error)
      !> The case resolved (loads: kinds, parameters, model body indices)
      type(model_t), intent(in) :: resolved
      type(built_body_t), intent(in) :: bodies(:)
      integer, intent(in) :: ends(:, :)
      type(mechanism_t), intent(inout) :: mech
      !> The cylinder pressure model (made by build_mechanism when a pressure load exists)
      type(pressure_model_t), intent(in) :: pressure
      type(error_t), allocatable, intent(out) :: error
      type(pressure_force_t) :: gas
      type(starter_torque_t) :: starter
      type(drag_torque_t) :: drag
      type(constant_load_t) :: constant
      type(timed_load_t) :: timed
      integer :: l
      do l = 1, size(resolved%mechanism%loads)
         associate (input => resolved%mechanism%loads(l))
            select case (input%kind)
            case (LOAD_PRESSURE)
               gas%model = pressure
               call fill(gas, input, LOAD_FORCE, ends(3, l))
               call mech%add_load(gas, error)
            case (LOAD_STARTER)
               starter%stall_torque = input%stall_torque
               starter%free_speed = input%free_speed
               starter%switch_off = input%switch_off
               call fill(starter, input, LOAD_TORQUE, ends(3, l))
               call mech%add_load(starter, error)
            case (LOAD_DRAG)
               drag%coefficient = input%coefficient
               call fill(drag, input, LOAD_TORQUE, ends(3, l))
               call mech%add_load(drag, error)
            case (LOAD_CONSTANT_FORCE, LOAD_CONSTANT_TORQUE)
               if (input%timed) then
                  timed%value = input%value
                  timed%law = input%law
                  call fill(timed, input, merge(LOAD_FORCE, LOAD_TORQUE, &
                     input%kind == LOAD_CONSTANT_FORCE), ends(3, l))
                  call mech%add_load(timed, error)
               else
                  constant%value = input%value
                  call fill(constant, input, merge(LOAD_FORCE, LOAD_TORQUE, &
                     input%kind == LOAD_CONSTANT_FORCE), ends(3, l))
                  call mech%add_load(constant, error)
               end if
            end select
            if (allocated(error)) then
               call add_context(error, '&load "' // trim(input%name) // '"')
               return
            end if
         end associate
      end do

   contains

      !> The load_t part of a load from its resolved &load group.
      subroutine fill(load, input, kind, marker)
         class(load_t), intent(inout) :: load
         type(model_load_t), intent(in) :: input
         integer, intent(in) :: kind, marker
         load%kind = kind
         load%body = bodies(input%body)%index
         load%marker = marker
         load%direction = input%direction
         load%name = input%name(:len(load%name))
      end subroutine fill

   end subroutine add_loads

   !> The single-zone model of &pressure, or the user's table (angle in deg, absolute pressure
   !> in Pa, one pair per line, '#' comments). The table must be a regular file of at most
   !> MAX_TABLE_BYTES (a FIFO or device would never end); its rows are counted before the
   !> arrays are allocated, and every number must be finite.
   subroutine make_pressure_model(case, pressure, error)
      type(case_input_t), intent(in) :: case
      type(pressure_model_t), intent(out) :: pressure
      type(error_t), allocatable, intent(out) :: error
      !> Largest pressure table read (bytes): 16 MiB, ~500 000 rows (0.1 deg needs 7200)
      integer(i8), parameter :: MAX_TABLE_BYTES = 16_i8 * 1024_i8**2
      real(dp), allocatable :: angles(:), values(:)
      real(dp) :: pair(2)
      character(len=512) :: line, msg
      character(len=:), allocatable :: file_name, where
      integer :: unit, stat, line_number, rows, pass, n
      if (len_trim(case%mechanism%pressure_table) == 0) then
         call pressure%init(case%mechanism%pressure, error)
         if (allocated(error)) call add_context(error, '&pressure')
         return
      end if
      file_name = trim(case%mechanism%pressure_table)
      where = '&pressure table_file "' // file_name // '"'
      call check_input_file(file_name, '&pressure table_file', MAX_TABLE_BYTES, error)
      if (allocated(error)) return
      ! one unit per file in the process (Fortran 2008, 9.5.4): threads reading it take turns
      call enter_serial_section(SECTION_FILES)
      open (newunit=unit, file=file_name, status='old', action='read', iostat=stat, iomsg=msg)
      if (stat /= 0) then
         call leave_serial_section(SECTION_FILES)
         call fatal_error(error, FFRF_IO_ERROR, where // ': ' // trim(msg))
         return
      end if
      ! pass 1 counts the rows and checks them, pass 2 stores them
      rows = 0
      do pass = 1, 2
         if (pass == 2) allocate (angles(rows), values(rows))
         rewind (unit)
         line_number = 0
         rows = 0
         do
            read (unit, '(a)', advance='no', iostat=stat, size=n) line
            if (is_iostat_end(stat)) exit
            line_number = line_number + 1
            if (stat == 0) then
               call fatal_error(error, FFRF_INPUT_ERROR, where // ', line ' // &
                  to_str(line_number) // ': longer than ' // to_str(len(line)) // &
                  ' characters; one angle and one pressure per line')
               exit
            else if (.not. is_iostat_eor(stat)) then
               call fatal_error(error, FFRF_IO_ERROR, where // ', line ' // &
                  to_str(line_number) // ': cannot read it')
               exit
            end if
            line = adjustl(line(:n))
            if (len_trim(line) == 0 .or. line(1:1) == '#') cycle
            read (line, *, iostat=stat) pair
            if (stat /= 0 .or. .not. all(abs(pair) <= huge(1.0_dp))) then
               call fatal_error(error, FFRF_INPUT_ERROR, where // ', line ' // &
                  to_str(line_number) // ': expected two numbers, angle (deg) ' // &
                  'and absolute pressure (Pa), both finite')
               exit
            end if
            rows = rows + 1
            if (pass == 2) then
               angles(rows) = pair(1)
               values(rows) = pair(2)
            end if
         end do
         if (allocated(error)) exit
      end do
      close (unit)
      call leave_serial_section(SECTION_FILES)
      if (allocated(error)) return
      call pressure%init_from_table(case%mechanism%pressure, angles, values, error)
      if (allocated(error)) call add_context(error, where)
   end subroutine make_pressure_model

   !> Starting pose: every body at its &body position and orientation (Euler parameters by
   !> Shepperd's method) with zero modal coordinates, then assembled (minimum-norm Gauss-Newton)
   !> at the &mechanism crank angle; velocities at its crank speed, projected from the &body
   !> velocity and angular_velocity when a body gives one. The log says for each body how far
   !> the assembly moved it.
   subroutine starting_state(case, resolved, bodies, mech, log, q, v, error)
      type(case_input_t), intent(in) :: case
      !> The case resolved (start positions)
      type(model_t), intent(in) :: resolved
      type(built_body_t), intent(in) :: bodies(:)
      type(mechanism_t), intent(inout) :: mech
      type(logger_t), intent(in) :: log
      real(dp), allocatable, intent(out) :: q(:), v(:)
      type(error_t), allocatable, intent(out) :: error
      integer :: k, offset
      real(dp) :: angle, tolerance
      real(dp), allocatable :: q_given(:), v_given(:)
      logical :: moving
      allocate (q(mech%num_coordinates()), v(mech%num_coordinates()), source=0.0_dp)
      do k = 1, size(bodies)
         offset = mech%bodies(bodies(k)%index)%offset
         associate (motion => resolved%bodies(k)%motion)
            q(offset + 1:offset + 3) = motion%position
            if (rotated(motion%orientation)) then
               q(offset + 4:offset + 7) = euler_from_rotation(motion%orientation)
            else
               q(offset + 4) = 1.0_dp
            end if
         end associate
      end do
      moving = any([(any(resolved%bodies(k)%motion%velocity /= 0.0_dp) .or. &
         any(resolved%bodies(k)%motion%angular_velocity /= 0.0_dp), k = 1, size(bodies))])
      q_given = q
      angle = case%mechanism%mechanism%crank_angle_deg * pi / 180.0_dp
      ! The joints close to the integrator's constraint tolerance: a mesh's virtual nodes are
      ! off their ideal places by round-off of the mesh (~1e-8 m on the crank), which a few
      ! modes cannot always absorb exactly (a 1e-11 m misfit was seen on the reference engine).
      tolerance = resolved%mechanism%integrator%newton_atol
      if (mech%rotor > 0) then
         call mech%assemble(q, 0.0_dp, error, rotor_angle=angle, tolerance=tolerance)
      else
         call mech%assemble(q, 0.0_dp, error, tolerance=tolerance)
      end if
      v_given = given_velocities(resolved, bodies, mech, q)
      if (allocated(error)) then
         ! (reported below)
      else if (mech%rotor > 0 .and. moving) then
         call mech%initial_velocities(q, 0.0_dp, v, error, &
            rotor_speed=case%mechanism%mechanism%crank_speed, guess=v_given)
      else if (mech%rotor > 0) then
         call mech%initial_velocities(q, 0.0_dp, v, error, &
            rotor_speed=case%mechanism%mechanism%crank_speed)
      else if (moving) then
         call mech%initial_velocities(q, 0.0_dp, v, error, guess=v_given)
      else
         call mech%initial_velocities(q, 0.0_dp, v, error)
      end if
      if (allocated(error)) then
         call add_context(error, 'assembling the starting pose (check the &body positions, ' // &
            'orientations and &marker points: the joints must nearly close)')
         return
      end if
      do k = 1, size(bodies)
         call log_assembly(trim(resolved%bodies(k)%name), &
            mech%bodies(bodies(k)%index)%offset, q_given, v_given, q, v, log)
         call check_assembly_deformation(trim(resolved%bodies(k)%name), bodies(k), &
            q(mech%bodies(bodies(k)%index)%offset + 8:), log, error)
         if (allocated(error)) return
      end do
   end subroutine starting_state

   !> The assembly may move a flexible body's modal coordinates (from zero) to close its joints
   !> on the round-off of the mesh's virtual nodes (~1e-8 m on the reference crank); it must
   !> not close a gap of the given geometry by deforming the body (a 0.3 m link stretched to
   !> a ground point 5 m away, issue 24). Refused when an interface's elastic displacement
   !> Psi_v zeta exceeds 1e-3 of the body's size (its mesh's bounding-box diagonal), a strain
   !> no linear FFRF body should start with; the log states the largest one otherwise.
   subroutine check_assembly_deformation(name, body, zeta, log, error)
      character(len=*), intent(in) :: name
      type(built_body_t), intent(in) :: body
      !> The body's modal coordinates after the assembly (and what follows them, unused)
      real(dp), intent(in) :: zeta(:)
      type(logger_t), intent(in) :: log
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: limit = 1.0e-3_dp
      real(dp) :: size_m, largest, u
      integer :: i, worst
      if (body%num_modes == 0 .or. .not. allocated(body%modes%mesh%xyz) .or. &
         .not. allocated(body%modes%virtual_node_shape)) return
      associate (shape => body%modes%virtual_node_shape, xyz => body%modes%mesh%xyz)
         if (size(shape, 2) /= body%num_modes) return
         size_m = norm2(maxval(xyz, dim=2) - minval(xyz, dim=2))
         largest = 0.0_dp
         worst = 1
         do i = 1, size(shape, 1) / 6
            u = norm2(matmul(shape(6 * i - 5:6 * i - 3, :), zeta(:body%num_modes)))
            if (u > largest) then
               largest = u
               worst = i
            end if
         end do
      end associate
      call log%info('assembly', 'body "' // name // '": largest elastic displacement of an ' &
         // 'interface ' // to_str(largest, 3) // ' m (' // to_str(largest / size_m, 3) // &
         ' of its size ' // to_str(size_m, 4) // ' m)')
      if (largest > limit * size_m) call fatal_error(error, FFRF_INPUT_ERROR, &
         'assembling the starting pose: the joints close only by deforming body "' // name // &
         '": its interface "' // body%modes%interfaces(worst)%name // '" moves ' // &
         to_str(largest, 3) // ' m elastically, more than ' // to_str(limit) // ' of the ' // &
         'body''s size (' // to_str(size_m, 4) // ' m); check the &marker points and &body ' // &
         'positions: the joints must close with the bodies undeformed')
   end subroutine check_assembly_deformation

   !> The starting velocities of the &body keys at the assembled pose q: the frame origin's
   !> velocity and the Euler-parameter rates theta_dot = G(theta)^T omega / 4 of the global
   !> angular velocity (G G^T = 4 I, G theta = 0); modal rates zero.
   function given_velocities(resolved, bodies, mech, q) result(v)
      type(model_t), intent(in) :: resolved
      type(built_body_t), intent(in) :: bodies(:)
      type(mechanism_t), intent(in) :: mech
      real(dp), intent(in) :: q(:)
      real(dp) :: v(size(q))
      integer :: k, offset
      v = 0.0_dp
      do k = 1, size(bodies)
         offset = mech%bodies(bodies(k)%index)%offset
         associate (motion => resolved%bodies(k)%motion)
            v(offset + 1:offset + 3) = motion%velocity
            v(offset + 4:offset + 7) = 0.25_dp * matmul(transpose(euler_g(q(offset + 4:offset &
               + 7))), motion%angular_velocity)
         end associate
      end do
   end function given_velocities

   !> One log line: how far the assembly moved a body (its frame origin, m) and changed its
   !> velocity (of the frame origin, m/s) from the &body keys.
   subroutine log_assembly(name, offset, q_given, v_given, q, v, log)
      character(len=*), intent(in) :: name
      !> The body's coordinates are q(offset + 1:)
      integer, intent(in) :: offset
      real(dp), intent(in) :: q_given(:), v_given(:), q(:), v(:)
      type(logger_t), intent(in) :: log
      real(dp) :: rates(3)
      rates = matmul(euler_g(q(offset + 4:offset + 7)), v(offset + 4:offset + 7) - &
         v_given(offset + 4:offset + 7))
      call log%info('assembly', 'body "' // name // '": moved ' // &
         to_str(norm2(q(offset + 1:offset + 3) - q_given(offset + 1:offset + 3)), 3) // &
         ' m, velocity changed ' // to_str(norm2(v(offset + 1:offset + 3) - &
         v_given(offset + 1:offset + 3)), 3) // ' m/s, angular velocity changed ' // &
         to_str(norm2(rates), 3) // ' rad/s')
   end subroutine log_assembly

   !> The orientation differs from the identity (a rotated starting pose).
   pure logical function rotated(orientation)
      real(dp), intent(in) :: orientation(3, 3)
      rotated = any(orientation /= identity3())
   end function rotated

end module ffrf_app_mechanism_builder
