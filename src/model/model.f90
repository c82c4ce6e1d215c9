!> The model of a case: the input as read (case_input_t, strings) resolved once for the
!> applications. One record per body (its &body keys, material and motion together, no parallel
!> arrays), with every choice made here: rigid or flexible, whether it has a mesh, the modes to
!> compute (num_modes decided once, ffrf_model_specs body_modes_spec), and its interfaces
!> resolved (interface_spec_t) in the order that makes an interface's marker handle its index:
!> body_modes_t%interfaces(k), the k-th virtual node of the mode shapes and the flexible body's
!> marker k are the body's k-th interface. Names become indices here (body_index, marker_index),
!> so nothing downstream recounts the case's &interface groups. The mechanism groups (joints,
!> loads, markers, crank, selection, integrator) are resolved into model_t%mechanism
!> (ffrf_model_mechanism) with their bodies as model body indices and markers as handles.
module ffrf_model_model
   use ffrf_core_error, only: error_t, add_context, fatal_error, FFRF_INPUT_ERROR
   use ffrf_mpc_interface, only: interface_spec_t, mpc_name
   use ffrf_modes_input, only: body_spec_t, modes_spec_t
   use ffrf_input_body, only: body_input_t
   use ffrf_input_case, only: case_input_t
   use ffrf_input_mechanism, only: body_motion_input_t, GROUND_NAME, law_function, load_choices, &
      quantity_choices, DRIVER_RATE
   use ffrf_mbs_torsion_spring, only: torsion_spring_t
   use ffrf_mbs_bushing, only: bushing_t
   use ffrf_model_mechanism, only: mechanism_model_t, model_marker_t, model_load_t, &
      joint_kind_of, selection_of, LOAD_PRESSURE
   use ffrf_core_choices, only: choice_kind, choice_words
   use ffrf_model_specs, only: body_modes_spec, body_interface_specs, body_interface_indices
   use ffrf_mbs_sensors, only: sensor_kind_of, sensor_choices
   use ffrf_input_interface, only: weighting_choices
   implicit none
   private
   public :: model_body_t, model_t, build_model, body_spec_of

   !> One body of the case, resolved.
   type :: model_body_t
      !> Body name (&body name)
      character(len=64) :: name = ''
      !> The &body as read (mesh file, material, volumes, geometric_stiffness)
      type(body_input_t) :: body
      !> What the numerics take of it (compute_body_modes): name, volumes, material
      type(body_spec_t) :: spec
      !> Mechanism keys of the &body (mass properties of a rigid body without a mesh, modal
      !> damping, start position, coarse meshes)
      type(body_motion_input_t) :: motion
      !> .true. for a rigid body (&body type = 'rigid'), decided here once
      logical :: rigid = .false.
      !> .true. when the body has a mesh file
      logical :: meshed = .false.
      !> num_modes given on the &body (>= 0); .false.: left open (&modes num_modes, or the
      !> automatic model of an engine run)
      logical :: num_modes_given = .false.
      !> Modes to compute (0 modes for a rigid body)
      type(modes_spec_t) :: modes
      !> The body's interfaces, resolved; interface k is marker handle k
      type(interface_spec_t), allocatable :: interfaces(:)
      !> Index into case%interfaces of interface k
      integer, allocatable :: interface_groups(:)
   contains
      !> Marker handle (interface index) of the interface called name, 0 if none
      procedure :: marker_index => body_marker_index
   end type model_body_t

   !> A case resolved for the applications.
   type :: model_t
      type(model_body_t), allocatable :: bodies(:)
      !> Joints, loads, markers, crank, model selection, integrator (empty for a modal case)
      type(mechanism_model_t) :: mechanism
   contains
      !> Index of the body called name, 0 if none (e.g. the ground)
      procedure :: body_index => model_body_index
      !> The &marker (index in mechanism%markers) that orients interface marker handle `handle`
      !> of flexible model body b, 0 if none
      procedure :: interface_marker => model_interface_marker
      !> MPC of the crank's interfaces ('RBE2', 'RBE3', 'rigid'; '' without crank), a label
      procedure :: crank_mpc => model_crank_mpc
   end type model_t

contains

   !> Resolve `case` into `model` (names to indices, strings to enumerations, choices made).
   subroutine build_model(case, model, error)
      !> The case as read and checked (read_case)
      type(case_input_t), intent(in) :: case
      type(model_t), intent(out) :: model
      type(error_t), allocatable, intent(out) :: error
      integer :: k
      allocate (model%bodies(size(case%bodies)))
      do k = 1, size(case%bodies)
         associate (b => model%bodies(k))
            b%name = case%bodies(k)%name
            b%body = case%bodies(k)
            b%spec = body_spec_of(case%bodies(k))
            b%motion = case%motions(k)
            b%rigid = case%motions(k)%type == 'rigid'
            b%meshed = len_trim(case%bodies(k)%mesh_file) > 0
            b%num_modes_given = case%motions(k)%num_modes >= 0
            call body_modes_spec(case, k, b%modes, error)
            if (.not. allocated(error)) call body_interface_specs(case%interfaces, b%name, &
               b%interfaces, error)
            if (allocated(error)) then
               call add_context(error, '&body "' // trim(b%name) // '"')
               return
            end if
            b%interface_groups = body_interface_indices(case%interfaces, b%name)
         end associate
      end do
      call build_mechanism_model(case, model, error)
   end subroutine build_model

   !> The body to cut from its mesh (compute_body_modes) of a &body as read: name, volumes and
   !> material (the mesh file stays with the application that reads it).
   pure function body_spec_of(body) result(spec)
      type(body_input_t), intent(in) :: body
      type(body_spec_t) :: spec
      spec = body_spec_t(body%name, body%volumes, body%young, body%poisson, body%density)
   end function body_spec_of

   !> Resolve the mechanism groups of `case` into model%mechanism (ffrf_model_mechanism); the
   !> bodies of `model` are resolved already.
   subroutine build_mechanism_model(case, model, error)
      type(case_input_t), intent(in) :: case
      type(model_t), intent(inout) :: model
      type(error_t), allocatable, intent(out) :: error
      integer :: k
      if (.not. case%is_mechanism) then
         allocate (model%mechanism%markers(0), model%mechanism%joints(0), &
            model%mechanism%loads(0), model%mechanism%sensors(0), model%mechanism%springs(0), &
            model%mechanism%torsion_springs(0), model%mechanism%bushings(0), &
            model%mechanism%drivers(0))
         return
      end if
      associate (input => case%mechanism, m => model%mechanism)
         allocate (m%markers(size(input%markers)), m%joints(size(input%joints)), &
            m%loads(size(input%loads)))
         do k = 1, size(input%markers)
            m%markers(k) = model_marker_t(model%body_index(input%markers(k)%body), &
               input%markers(k)%name, input%markers(k)%position, input%markers(k)%orientation, &
               input%markers(k)%oriented, input%markers(k)%node, input%markers(k)%group)
            call choice_kind(weighting_choices, '&marker "' // trim(input%markers(k)%name) // &
               '": weighting', 'known', input%markers(k)%weighting, m%markers(k)%weighting, &
               error)
            if (allocated(error)) return
         end do
         do k = 1, size(input%joints)
            associate (joint => m%joints(k), given => input%joints(k))
               joint%name = given%name
               joint%axis = given%axis
               call joint_kind_of(given%type, joint%kind, error)
               call in_group(error, '&joint "' // trim(given%name) // '"')
               if (.not. allocated(error)) call resolve_ends('joint', given%name, given%body1, &
                  given%marker1, given%body2, given%marker2, joint%body(1), joint%marker(1), &
                  joint%body(2), joint%marker(2), error)
               if (.not. allocated(error)) then
                  call refuse_point_end(joint%body, joint%marker, error)
                  call in_group(error, '&joint "' // trim(given%name) // '"')
               end if
            end associate
            if (allocated(error)) return
         end do
         do k = 1, size(input%loads)
            associate (load => m%loads(k), given => input%loads(k))
               load = model_load_t(name=given%name, direction=given%direction, &
                  value=given%value, stall_torque=given%stall_torque, &
                  free_speed=given%free_speed, switch_off=given%switch_off, &
                  coefficient=given%coefficient, timed=len_trim(given%law%law) > 0)
               if (load%timed) call law_function(given%law, '&load "' // trim(given%name) // &
                  '"', load%law, error)
               if (.not. allocated(error)) call choice_kind(load_choices, 'type', &
                  'a load kind', given%type, load%kind, error)
               if (.not. allocated(error)) call resolve_end(given%body, given%marker, &
                  load%body, load%marker, error)
               if (.not. allocated(error) .and. load%body == 0) call fatal_error(error, &
                  FFRF_INPUT_ERROR, 'body = "' // trim(given%body) // '": a load needs a ' // &
                  'moving body (a &body)')
               call in_group(error, '&load "' // trim(given%name) // '"')
            end associate
            if (allocated(error)) return
         end do
         call resolve_force_elements(error)
         if (.not. allocated(error)) call resolve_drivers(error)
         if (allocated(error)) return
         allocate (m%sensors(count_given(input%sensors)))
         do k = 1, size(m%sensors)
            associate (sensor => m%sensors(k), given => input%sensors(k))
               sensor%name = given%name
               sensor%node = given%node
               sensor%kind = sensor_kind_of(given%type)
               if (sensor%kind == 0) call fatal_error(error, FFRF_INPUT_ERROR, 'type = "' // &
                  trim(given%type) // '" is not a sensor type; use one of ' // &
                  choice_words(sensor_choices))
               if (.not. allocated(error) .and. len_trim(given%marker) > 0) then
                  call resolve_end(given%body, given%marker, sensor%body, sensor%marker, error)
               else if (.not. allocated(error) .and. len_trim(given%body) > 0) then
                  sensor%body = model%body_index(given%body)
                  if (sensor%body == 0) call fatal_error(error, FFRF_INPUT_ERROR, 'body "' // &
                     trim(given%body) // '" is not a &body')
               end if
               if (.not. allocated(error) .and. len_trim(given%spring) > 0) then
                  if (trim(given%type) == 'bushing') then
                     sensor%spring = findloc(m%bushings%name, given%spring, dim=1)
                  else if (trim(given%type) == 'torsion_spring') then
                     sensor%spring = findloc(m%torsion_springs%name, given%spring, dim=1)
                  else
                     sensor%spring = findloc(m%springs%name, given%spring, dim=1)
                  end if
                  if (sensor%spring == 0) call fatal_error(error, FFRF_INPUT_ERROR, 'spring "' &
                     // trim(given%spring) // '" is not a &' // trim(given%type))
               end if
               if (.not. allocated(error) .and. len_trim(given%joint) > 0) then
                  sensor%joint = findloc(input%joints%name, given%joint, dim=1)
                  if (sensor%joint == 0) call fatal_error(error, FFRF_INPUT_ERROR, 'joint "' // &
                     trim(given%joint) // '" is not a &joint')
               end if
               call in_group(error, '&sensor "' // trim(given%name) // '"')
            end associate
            if (allocated(error)) return
         end do
         m%has_pressure = any(m%loads%kind == LOAD_PRESSURE)
         m%crank = 0
         if (len_trim(input%mechanism%crank) > 0) then
            m%crank = model%body_index(input%mechanism%crank)
            if (m%crank == 0) then
               call fatal_error(error, FFRF_INPUT_ERROR, '&mechanism: crank = "' // &
                  trim(input%mechanism%crank) // '" is not a &body')
               return
            end if
         end if
         call selection_of(input%model%selection, m%selection, error)
         if (allocated(error)) return
         m%h_given = input%model%h_given
         m%integrator = input%integrator
         m%max_steps = input%max_steps
         m%energy_watch = input%energy_watch
      end associate

   contains

      !> The &driver groups: joint names to joint numbers, laws to time functions.
      subroutine resolve_drivers(error)
         type(error_t), allocatable, intent(out) :: error
         integer :: d, quantity
         allocate (model%mechanism%drivers(count_given(case%mechanism%drivers)))
         do d = 1, size(model%mechanism%drivers)
            associate (driver => model%mechanism%drivers(d), given => case%mechanism%drivers(d))
               driver%name = given%name
               call choice_kind(quantity_choices, '&driver "' // trim(given%name) // &
                  '": quantity', 'a driver quantity', given%quantity, quantity, error)
               if (allocated(error)) return
               driver%rate = quantity == DRIVER_RATE
               driver%offset = given%offset
               driver%joint = findloc(case%mechanism%joints%name, given%joint, dim=1)
               if (driver%joint == 0) then
                  call fatal_error(error, FFRF_INPUT_ERROR, '&driver "' // trim(given%name) // &
                     '": joint "' // trim(given%joint) // '" is not a &joint')
                  return
               end if
               call law_function(given%law, '&driver "' // trim(given%name) // '"', &
                  driver%law, error)
               if (allocated(error)) return
            end associate
         end do
      end subroutine resolve_drivers

      !> The force elements: &spring and &bushing ends to model body indices and marker handles,
      !> &torsion_spring joint names to joint numbers (in that order of their errors).
      subroutine resolve_force_elements(error)
         type(error_t), allocatable, intent(out) :: error
         integer :: s
         allocate (model%mechanism%springs(count_given(case%mechanism%springs)), &
            model%mechanism%torsion_springs(count_given(case%mechanism%torsion_springs)), &
            model%mechanism%bushings(count_given(case%mechanism%bushings)))
         do s = 1, size(model%mechanism%springs)
            associate (spring => model%mechanism%springs(s), given => case%mechanism%springs(s))
               spring%name = given%name
               spring%stiffness = given%stiffness
               spring%damping = given%damping
               spring%free_length = given%free_length
               call resolve_ends('spring', given%name, given%body1, given%marker1, given%body2, &
                  given%marker2, spring%body(1), spring%marker(1), spring%body(2), &
                  spring%marker(2), error)
            end associate
            if (allocated(error)) return
         end do
         do s = 1, size(model%mechanism%torsion_springs)
            associate (spring => model%mechanism%torsion_springs(s), &
                  given => case%mechanism%torsion_springs(s))
               spring = torsion_spring_t(given%name, findloc(case%mechanism%joints%name, &
                  given%joint, dim=1), stiffness=given%stiffness, damping=given%damping, &
                  free_angle=given%free_angle, free_angle_given=given%free_angle_given)
               if (spring%joint == 0) then
                  call fatal_error(error, FFRF_INPUT_ERROR, '&torsion_spring "' // &
                     trim(given%name) // '": joint "' // trim(given%joint) // &
                     '" is not a &joint')
                  return
               end if
            end associate
         end do
         do s = 1, size(model%mechanism%bushings)
            associate (bushing => model%mechanism%bushings(s), &
                  given => case%mechanism%bushings(s))
               bushing = bushing_t(given%name, stiffness=given%stiffness, &
                  damping=given%damping)
               call resolve_ends('bushing', given%name, given%body1, given%marker1, &
                  given%body2, given%marker2, bushing%body_a, bushing%marker_a, bushing%body_b, &
                  bushing%marker_b, error)
            end associate
            if (allocated(error)) return
         end do
      end subroutine resolve_force_elements

      !> The two ends of group `group` "name" between marker1 of body1 and marker2 of body2
      !> (&joint, &spring, &bushing): model body indices and marker handles (resolve_end).
      subroutine resolve_ends(group, name, body1, marker1, body2, marker2, index1, handle1, &
            index2, handle2, error)
         character(len=*), intent(in) :: group, name, body1, marker1, body2, marker2
         integer, intent(out) :: index1, handle1, index2, handle2
         type(error_t), allocatable, intent(out) :: error
         call resolve_end(body1, marker1, index1, handle1, error)
         if (.not. allocated(error)) call resolve_end(body2, marker2, index2, handle2, error)
         call in_group(error, '&' // group // ' "' // trim(name) // '"')
      end subroutine resolve_ends

      !> Model body index (0: ground) and marker handle of the marker `marker` of body `body`.
      subroutine resolve_end(body, marker, index, handle, error)
         character(len=*), intent(in) :: body, marker
         integer, intent(out) :: index, handle
         type(error_t), allocatable, intent(out) :: error
         integer :: k
         index = model%body_index(body)
         handle = 0
         if (index == 0 .and. body /= GROUND_NAME) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'body "' // trim(body) // '" is neither ' &
               // 'a &body nor the ground ("' // GROUND_NAME // '")')
            return
         end if
         if (index > 0) then
            if (.not. model%bodies(index)%rigid) then
               handle = model%bodies(index)%marker_index(marker)
               if (handle > 0) return
               do k = 1, size(model%mechanism%markers)
                  if (model%mechanism%markers(k)%body == index .and. &
                     model%mechanism%markers(k)%name == marker) then
                     handle = size(model%bodies(index)%interfaces) + k
                     return
                  end if
               end do
               call fatal_error(error, FFRF_INPUT_ERROR, 'marker "' // trim(marker) // &
                  '" is neither an &interface nor a &marker of the flexible body "' // &
                  trim(body) // '"')
               return
            end if
         end if
         do k = 1, size(model%mechanism%markers)
            if (model%mechanism%markers(k)%body == index .and. &
               model%mechanism%markers(k)%name == marker) then
               handle = k
               return
            end if
         end do
         call fatal_error(error, FFRF_INPUT_ERROR, 'marker "' // trim(marker) // '" of body "' &
            // trim(body) // '" is not a &marker group')
      end subroutine resolve_end

      !> A joint end at a flexible body's node or group marker (module ffrf_model_mechanism):
      !> refused, a joint needs an interface.
      subroutine refuse_point_end(bodies, handles, error)
         integer, intent(in) :: bodies(2), handles(2)
         type(error_t), allocatable, intent(out) :: error
         integer :: e
         do e = 1, 2
            if (bodies(e) == 0) cycle
            if (model%bodies(bodies(e))%rigid) cycle
            if (handles(e) <= size(model%bodies(bodies(e))%interfaces)) cycle
            call fatal_error(error, FFRF_INPUT_ERROR, 'marker "' // trim(model%mechanism% &
               markers(handles(e) - size(model%bodies(bodies(e))%interfaces))%name) // &
               '" of the flexible body "' // trim(model%bodies(bodies(e))%name) // '" is a ' // &
               'node or group marker (no interface); declare the group as an &interface ' // &
               'and join there')
            return
         end do
      end subroutine refuse_point_end

   end subroutine build_mechanism_model

   !> MPC of the crank's interfaces, a label for charts and results: 'rigid' for a rigid crank or
   !> one without modes (num_modes = 0 on its &body), else mpc_name of its first interface; ''
   !> without crank or interfaces.
   function model_crank_mpc(self) result(mpc)
      class(model_t), intent(in) :: self
      character(len=:), allocatable :: mpc
      mpc = ''
      if (self%mechanism%crank == 0) return
      associate (crank => self%bodies(self%mechanism%crank))
         if (crank%rigid .or. (crank%num_modes_given .and. crank%modes%num_modes == 0)) then
            mpc = 'rigid'
         else if (size(crank%interfaces) > 0) then
            mpc = trim(mpc_name(crank%interfaces(1)%mpc))
         end if
      end associate
   end function model_crank_mpc

   !> An error in resolving a group (not allocated: none) gets `where`, the group, as context.
   subroutine in_group(error, where)
      type(error_t), allocatable, intent(inout) :: error
      character(len=*), intent(in) :: where
      if (allocated(error)) call add_context(error, where)
   end subroutine in_group

   !> Number of items of a list of the case that may be unallocated (a case built in memory
   !> leaves the groups it has none of unallocated: an absent argument).
   pure integer function count_given(items) result(n)
      class(*), intent(in), optional :: items(:)
      n = 0
      if (present(items)) n = size(items)
   end function count_given

   !> Index of the body called name, 0 if none.
   pure integer function model_body_index(self, name) result(k)
      class(model_t), intent(in) :: self
      !> Body name
      character(len=*), intent(in) :: name
      k = findloc(self%bodies%name, name, dim=1)
   end function model_body_index

   !> The &marker with an orientation that gives flexible model body b's interface `handle` its
   !> frame (docs/mechanisms.md "Joint frames"): its index in mechanism%markers, 0 if none (also
   !> for the ground, a rigid body, or a node or group marker handle).
   pure integer function model_interface_marker(self, b, handle) result(k)
      class(model_t), intent(in) :: self
      !> Model body index (0: the ground) and marker handle
      integer, intent(in) :: b, handle
      integer :: m
      k = 0
      if (b <= 0) return
      if (self%bodies(b)%rigid .or. handle > size(self%bodies(b)%interfaces)) return
      do m = 1, size(self%mechanism%markers)
         associate (marker => self%mechanism%markers(m))
            if (marker%body /= b .or. .not. marker%oriented) cycle
            if (marker%name /= self%bodies(b)%interfaces(handle)%name) cycle
            k = m
            return
         end associate
      end do
   end function model_interface_marker

   !> Marker handle (index among the body's interfaces) of the interface called name, 0 if none.
   pure integer function body_marker_index(self, name) result(k)
      class(model_body_t), intent(in) :: self
      !> Interface (physical surface) name
      character(len=*), intent(in) :: name
      k = findloc(self%interfaces%name, name, dim=1)
   end function body_marker_index

end module ffrf_model_model
