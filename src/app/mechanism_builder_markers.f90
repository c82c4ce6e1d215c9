!> The markers of a mechanism being built (ffrf_app_mechanism_builder, header "Markers and joint
!> frames"): joint, load, sensor and force-element ends resolved to body markers and frames.
submodule (ffrf_app_mechanism_builder) ffrf_app_mechanism_builder_markers
   use ffrf_mpc_mesh_point, only: mesh_point_t, build_mesh_point
   use ffrf_mbs_rotation, only: cross3, axial3
   implicit none

contains

   module procedure resolve_markers
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
            if (.not. is_oriented(resolved, joint%body(e), joint%marker(e))) cycle
            given = .true.
            frame = given_frame(resolved, joint%body(e), joint%marker(e))
            return
         end do
      end subroutine joint_frame

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
      !> &marker orientation replaces either (also one named as a flexible body's interface).
      !> A flexible body's interface marker (the node frame) serves when `node_frame` and the
      !> interface has no orientation, else a framed marker at its virtual node.
      subroutine marker_of(b, handle, frame, joint_end, marker, node_frame)
         integer, intent(in) :: b, handle
         real(dp), intent(in) :: frame(3, 3)
         logical, intent(in) :: joint_end, node_frame
         integer, intent(out) :: marker
         integer :: k, node, n_if
         real(dp) :: local(3, 3)
         local = frame
         if (joint_end .and. b > 0) then
            if (rotated(resolved%bodies(b)%motion%orientation)) local = &
               matmul(transpose(resolved%bodies(b)%motion%orientation), frame)
         end if
         if (b > 0) then
            if (.not. resolved%bodies(b)%rigid) then
               n_if = size(resolved%bodies(b)%interfaces)
               node = handle
               if (handle > n_if) then
                  ! a node or group marker (&marker handle - n_if): the virtual node after the
                  ! interfaces' of its point, the body axes or its &marker orientation
                  node = findloc(lists(b)%points, handle - n_if, dim=1)
                  if (node == 0) then
                     lists(b)%points = [lists(b)%points, handle - n_if]
                     node = size(lists(b)%points)
                  end if
                  node = n_if + node
                  associate (point => resolved%mechanism%markers(handle - n_if))
                     if (point%oriented) local = point%orientation
                  end associate
               else
                  ! an interface: its node frame, or a framed marker at its virtual node in the
                  ! joint's frame or its own &marker orientation (as a rigid marker's)
                  marker = handle
                  k = resolved%interface_marker(b, handle)
                  if (k > 0) then
                     local = resolved%mechanism%markers(k)%orientation
                  else if (node_frame) then
                     return
                  end if
               end if
               do k = 1, size(lists(b)%nodes)
                  if (lists(b)%nodes(k) == node .and. maxval(abs(lists(b)%frames(:, :, k) - &
                     local)) < 1.0e-12_dp) then
                     marker = n_if + k
                     return
                  end if
               end do
               lists(b)%nodes = [lists(b)%nodes, node]
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

   end procedure resolve_markers

   module procedure check_joint_frames
      real(dp), parameter :: tolerance = 1.0e-6_dp
      real(dp) :: f1(3, 3), f2(3, 3), r(3, 3), angle
      character(len=:), allocatable :: what
      integer :: j
      do j = 1, size(resolved%mechanism%joints)
         associate (joint => resolved%mechanism%joints(j))
            if (.not. (is_oriented(resolved, joint%body(1), joint%marker(1)) .and. &
               is_oriented(resolved, joint%body(2), joint%marker(2)))) cycle
            f1 = given_frame(resolved, joint%body(1), joint%marker(1))
            f2 = given_frame(resolved, joint%body(2), joint%marker(2))
            select case (joint%kind)
            case (JOINT_REVOLUTE, JOINT_CYLINDRICAL)
               what = 'z axes'
               angle = atan2(norm2(cross3(f1(:, 3), f2(:, 3))), dot_product(f1(:, 3), f2(:, 3)))
            case (JOINT_PRISMATIC, JOINT_FIXED)
               ! the angle of the relative rotation R = F1^T F2
               what = 'frames'
               r = matmul(transpose(f1), f2)
               angle = atan2(norm2(axial3(r)), 0.5_dp * (r(1, 1) + r(2, 2) + r(3, 3) - 1.0_dp))
            case (JOINT_UNIVERSAL)
               ! the cross's arms x1 and y2 perpendicular
               what = 'cross arms x1, y2 (off perpendicular)'
               angle = asin(min(1.0_dp, abs(dot_product(f1(:, 1), f2(:, 2)))))
            case default
               cycle
            end select
            if (angle <= tolerance) cycle
            call fatal_error(error, FFRF_INPUT_ERROR, '&joint "' // trim(joint%name) // '" (' // &
               joint_kind_name(joint%kind) // '): the frames of its markers ' // &
               end_name(joint%body(1), joint%marker(1)) // ' and ' // &
               end_name(joint%body(2), joint%marker(2)) // ' disagree in the starting pose: ' // &
               'their ' // what // ' are ' // to_str(angle, 3) // ' rad apart (more than ' // &
               to_str(tolerance) // ' rad); give the two &marker orientations (turned by ' // &
               'their &body orientations) frames that agree, or an orientation to one marker only')
            return
         end associate
      end do

   contains

      !> '"marker" (body "name")' of marker handle `handle` on model body b (0: the ground).
      function end_name(b, handle) result(text)
         integer, intent(in) :: b, handle
         character(len=:), allocatable :: text
         integer :: k
         if (b > 0) then
            k = resolved%interface_marker(b, handle)
            if (k == 0) k = handle
            text = '"' // trim(resolved%mechanism%markers(k)%name) // '" (body "' // &
               trim(resolved%bodies(b)%name) // '")'
         else
            text = '"' // trim(resolved%mechanism%markers(handle)%name) // '" (body "' // &
               GROUND_NAME // '")'
         end if
      end function end_name

   end procedure check_joint_frames

   !> Marker handle `handle` of model body b (0: ground) is a &marker point with an orientation,
   !> or a flexible body's interface that a &marker of its name orients.
   logical function is_oriented(resolved, b, handle)
      type(model_t), intent(in) :: resolved
      integer, intent(in) :: b, handle
      is_oriented = .false.
      if (b > 0) then
         if (.not. resolved%bodies(b)%rigid) then
            is_oriented = resolved%interface_marker(b, handle) > 0
            return
         end if
      end if
      is_oriented = resolved%mechanism%markers(handle)%oriented
   end function is_oriented

   !> The global frame in the given starting pose of an oriented marker (is_oriented): its
   !> &marker orientation C turned by its body's &body orientation A (A C; the ground: C; a
   !> flexible body's interface: its undeformed virtual node frame is the body axes).
   function given_frame(resolved, b, handle) result(frame)
      type(model_t), intent(in) :: resolved
      integer, intent(in) :: b, handle
      real(dp) :: frame(3, 3)
      integer :: k
      k = handle
      if (b > 0) then
         if (.not. resolved%bodies(b)%rigid) k = resolved%interface_marker(b, handle)
      end if
      frame = resolved%mechanism%markers(k)%orientation
      if (b > 0) frame = matmul(resolved%bodies(b)%motion%orientation, frame)
   end function given_frame

   module procedure add_framed_markers
      type(mesh_point_t) :: point
      real(dp), allocatable :: rows(:, :)
      integer :: i, marker, node, c, m
      m = flexible%num_modes
      do i = 1, size(list%points)
         associate (given => markers(list%points(i)))
            call build_mesh_point(modes%mesh, given%node, given%group, given%weighting, point, &
               error)
            if (allocated(error)) then
               call add_context(error, '&marker "' // trim(given%name) // '"')
               return
            end if
         end associate
         ! [Psi_Pt; Psi_Pr] = G Psi_B
         allocate (rows(6, m), source=0.0_dp)
         do c = 1, size(point%nodes)
            rows = rows + matmul(point%G(:, 3 * c - 2:3 * c), &
               modes%shape(3 * point%nodes(c) - 2:3 * point%nodes(c), 1:m))
         end do
         call flexible%add_point(rows, point%xyz, node, error)
         deallocate (rows)
         if (allocated(error)) return
         if (node /= num_interfaces + i) then
            call fatal_error(error, FFRF_INPUT_ERROR, '&marker "' // &
               trim(markers(list%points(i))%name) // '" became virtual node ' // to_str(node) // &
               ', expected ' // to_str(num_interfaces + i) // ' (the modes have ' // &
               to_str(node - i) // ' interfaces, the case ' // to_str(num_interfaces) // ')')
            return
         end if
      end do
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
   end procedure add_framed_markers

   module procedure virtual_positions
      integer :: i
      do i = 1, size(modes%interfaces)
         xyz(:, i) = modes%interfaces(i)%virtual_xyz
      end do
   end procedure virtual_positions

   module procedure make_sensors
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
   end procedure make_sensors

   !> A node sensor's node (a Gmsh node tag of the body's mesh): its position in the body frame
   !> and its rows of the kept mode shapes (none for a rigid body).
   subroutine node_rows(body, node, sensor, error)
      type(built_body_t), intent(in) :: body
      integer, intent(in) :: node
      type(sensor_t), intent(inout) :: sensor
      type(error_t), allocatable, intent(out) :: error
      type(mesh_point_t) :: point
      integer :: i
      if (.not. body%meshed .or. .not. allocated(body%modes%mesh%xyz)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'node = ' // to_str(node) // ': the body ' // &
            'has no mesh; measure a body with a mesh_file')
         return
      end if
      call build_mesh_point(body%modes%mesh, node, '', 0, point, error)
      if (allocated(error)) return
      i = point%nodes(1)
      sensor%node = node
      sensor%node_xyz = body%modes%mesh%xyz(:, i)
      allocate (sensor%node_shape(3, 0))
      if (body%num_modes > 0 .and. allocated(body%modes%shape)) &
         sensor%node_shape = body%modes%shape(3 * i - 2:3 * i, 1:body%num_modes)
   end subroutine node_rows

end submodule ffrf_app_mechanism_builder_markers
