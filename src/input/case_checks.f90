!> The cross-group checks of a case (ffrf_input_case): names that must refer to groups of the
!> case, the output path, the step count, joint axes against marker frames, rigid starts.
submodule (ffrf_input_case) ffrf_input_case_checks
   implicit none

contains

   module procedure check_output_path
      character(len=:), allocatable :: rest, part
      integer :: slash
      if (len_trim(path) == 0) return
      if (path(1:1) == '/') then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': an absolute path; outputs stay ' &
            // 'inside the output folder (--output-dir): give a path relative to it')
         return
      end if
      rest = trim(path)
      do while (len(rest) > 0)
         slash = index(rest, '/')
         if (slash == 0) then
            part = rest
            rest = ''
         else
            part = rest(:slash - 1)
            rest = rest(slash + 1:)
         end if
         if (part == '..') then
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': a ''..'' component leaves ' &
               // 'the output folder (--output-dir); give a path inside it')
            return
         end if
      end do
   end procedure check_output_path

   module procedure check_step_count
      real(dp) :: steps
      associate (s => case%mechanism%integrator, max_steps => case%mechanism%max_steps)
         if (case%mechanism%model%h_given .and. s%h > s%t_end - s%t_start) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('integrator', 1, 'h') // &
               ': longer than the run, t_end - t_start = ' // to_str(s%t_end - s%t_start) // &
               ' s; give h < t_end')
            return
         end if
         steps = (s%t_end - s%t_start) / s%h
         if (steps > real(max_steps, dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('integrator', 1, 't_end') // &
               ': (t_end - t_start)/h = ' // to_str(steps, 4) // ' steps of h = ' // &
               to_str(s%h) // ' s, more than max_steps = ' // to_str(max_steps) // &
               '; shorten the run, enlarge h, or raise &integrator max_steps on purpose')
         end if
      end associate
   end procedure check_step_count

   !> A joint at a &marker with an orientation acts in that frame, marker1's when both have one
   !> (docs/mechanisms.md "Joint frames"): the axis of every kind but spherical and fixed must
   !> be the frame's z axis in the starting pose (global: the body's orientation times the
   !> marker's).
   subroutine check_joint_axis(where, case, joint, error)
      character(len=*), intent(in) :: where
      type(case_input_t), intent(in) :: case
      type(joint_input_t), intent(in) :: joint
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: z(3)
      integer :: m
      character(len=64) :: body, marker
      if (joint%type == 'spherical' .or. joint%type == 'fixed') return
      body = joint%body1
      marker = joint%marker1
      m = oriented_marker(body, marker)
      if (m == 0) then
         body = joint%body2
         marker = joint%marker2
         m = oriented_marker(body, marker)
      end if
      if (m == 0) return
      z = case%mechanism%markers(m)%orientation(:, 3)
      if (body /= GROUND_NAME) z = matmul(case%motions(body_index(case, body))%orientation, z)
      if (abs(dot_product(joint%axis / norm2(joint%axis), z)) < 1.0_dp - 1.0e-9_dp) &
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': axis = (' // &
         vector_text(joint%axis) // ') is not the z axis (' // vector_text(z) // ') of ' // &
         '&marker "' // trim(marker) // '" of body "' // trim(body) // '" (its orientation, ' // &
         'in the starting pose); give axis along it, or leave the marker''s orientation out')
   contains
      !> Index of the &marker (body, name) when it has an orientation, else 0.
      integer function oriented_marker(b, name)
         character(len=*), intent(in) :: b, name
         oriented_marker = findloc(case%mechanism%markers%body == b .and. &
            case%mechanism%markers%name == name, .true., dim=1)
         if (oriented_marker > 0) then
            if (.not. case%mechanism%markers(oriented_marker)%oriented) oriented_marker = 0
         end if
      end function oriented_marker
   end subroutine check_joint_axis

   module procedure check_mechanism_names
      integer :: k
      associate (mech => case%mechanism)
         do k = 1, size(case%interfaces)
            if (case%motions(body_index(case, case%interfaces(k)%body))%type == 'rigid') then
               call fatal_error(error, FFRF_INPUT_ERROR, src%at('interface', k, 'body') // &
                  ': &interface "' // &
                  trim(case%interfaces(k)%name) // '": body "' // &
                  trim(case%interfaces(k)%body) // '" is rigid (no mesh); give its joint ' // &
                  'points as &marker groups')
               return
            end if
         end do
         do k = 1, size(mech%markers)
            associate (m => mech%markers(k))
               if (m%body == GROUND_NAME .and. m%node == 0 .and. len_trim(m%group) == 0) cycle
               if (m%body == GROUND_NAME) then
                  call fatal_error(error, FFRF_INPUT_ERROR, src%at('marker', k, 'body') // &
                     ': &marker "' // trim(m%name) // '": the ground has no mesh; node and ' // &
                     'group place a marker on a flexible body''s mesh: give a position instead')
                  return
               end if
               if (body_index(case, m%body) == 0) then
                  call fatal_error(error, FFRF_INPUT_ERROR, src%at('marker', k, 'body') // &
                     ': &marker "' // trim(m%name) // &
                     '": body "' // trim(m%body) // '" is not a &body of this case (nor ' // &
                     '"ground")')
               else if (case%motions(body_index(case, m%body))%type /= 'rigid') then
                  call check_point_marker(k, m, error)
               else if (m%node > 0 .or. len_trim(m%group) > 0) then
                  call fatal_error(error, FFRF_INPUT_ERROR, src%at('marker', k, 'body') // &
                     ': &marker "' // trim(m%name) // '": body "' // trim(m%body) // &
                     '" is rigid; node and group place a marker on a flexible body''s ' // &
                     'mesh: give a position instead')
               end if
               if (allocated(error)) return
            end associate
         end do
         do k = 1, size(mech%joints)
            associate (j => mech%joints(k))
               call check_marker(case, src%at('joint', k, 'body1') // ': &joint "' // &
                  trim(j%name) // '"', j%body1, j%marker1, error, joint_end=.true.)
               if (.not. allocated(error)) call check_marker(case, src%at('joint', k, 'body2') &
                  // ': &joint "' // trim(j%name) // '"', j%body2, j%marker2, error, &
                  joint_end=.true.)
               if (.not. allocated(error)) call check_joint_axis(src%at('joint', k, 'axis') // &
                  ': &joint "' // trim(j%name) // '"', case, j, error)
               if (allocated(error)) return
            end associate
         end do
         do k = 1, size(mech%loads)
            associate (l => mech%loads(k))
               call check_marker(case, src%at('load', k, 'body') // ': &load "' // &
                  trim(l%name) // '"', l%body, l%marker, error)
               if (allocated(error)) return
               if (l%body == GROUND_NAME) then
                  call fatal_error(error, FFRF_INPUT_ERROR, src%at('load', k, 'body') // &
                     ': &load "' // trim(l%name) // '": a load on the ground does nothing; ' // &
                     'name a moving body')
                  return
               end if
               if (any(l%type == [character(len=16) :: 'pressure', 'starter', 'drag']) .and. &
                  len_trim(mech%mechanism%crank) == 0) then
                  call fatal_error(error, FFRF_INPUT_ERROR, src%at('load', k, 'type') // &
                     ': &load "' // trim(l%name) // '" (' // trim(l%type) // ') depends on ' // &
                     'the crank angle or speed: name the crank body in &mechanism crank = ...')
                  return
               end if
            end associate
         end do
         do k = 1, spring_count(mech)
            associate (x => mech%springs(k))
               call check_marker(case, src%at('spring', k, 'body1') // ': &spring "' // &
                  trim(x%name) // '"', x%body1, x%marker1, error)
               if (.not. allocated(error)) call check_marker(case, src%at('spring', k, 'body2') &
                  // ': &spring "' // trim(x%name) // '"', x%body2, x%marker2, error)
               if (.not. allocated(error) .and. x%free_length < 0.0_dp) then
                  if (rigid_start_distance(case, x%body1, x%marker1, x%body2, x%marker2) == &
                     0.0_dp) call fatal_error(error, FFRF_INPUT_ERROR, src%at('spring', k, &
                     'body2') // ': &spring "' // trim(x%name) // '": its markers coincide ' &
                     // 'at the start (length 0) and free_length is not given; give ' // &
                     'free_length (m)')
               end if
               if (allocated(error)) return
            end associate
         end do
         do k = 1, driver_count(mech)
            associate (x => mech%drivers(k))
               call check_element_joint('driver', 'driver', k, x%name, x%joint, 'revolute', &
                  'prismatic', error)
               if (allocated(error)) return
               if (count(mech%drivers(:k)%joint == x%joint) > 1) then
                  call fatal_error(error, FFRF_INPUT_ERROR, src%at('driver', k, 'joint') // &
                     ': &driver "' // trim(x%name) // '": joint "' // trim(x%joint) // &
                     '" has a driver already; one driver per joint')
                  return
               end if
            end associate
         end do
         do k = 1, size(element_names(mech, 'torsion_spring'))
            associate (x => mech%torsion_springs(k))
               call check_element_joint('torsion_spring', 'torsion spring', k, x%name, &
                  x%joint, 'revolute', 'cylindrical', error)
               if (allocated(error)) return
            end associate
         end do
         do k = 1, size(element_names(mech, 'bushing'))
            associate (x => mech%bushings(k))
               call check_marker(case, src%at('bushing', k, 'body1') // ': &bushing "' // &
                  trim(x%name) // '"', x%body1, x%marker1, error)
               if (.not. allocated(error)) call check_marker(case, src%at('bushing', k, &
                  'body2') // ': &bushing "' // trim(x%name) // '"', x%body2, x%marker2, error)
               if (allocated(error)) return
            end associate
         end do
         call check_sensor_names(src, case, error)
         if (allocated(error)) return
         if (len_trim(mech%mechanism%crank) > 0) then
            if (body_index(case, mech%mechanism%crank) == 0) then
               call fatal_error(error, FFRF_INPUT_ERROR, src%at('mechanism', 1, 'crank') // &
                  ': &mechanism: crank = "' // &
                  trim(mech%mechanism%crank) // '" is not a &body of this case')
               return
            end if
         end if
      end associate

   contains

      !> The joint of &group k "name" is a &joint of the case of type type_a or type_b (a `what`
      !> needs one of them).
      subroutine check_element_joint(group, what, k, name, joint, type_a, type_b, error)
         character(len=*), intent(in) :: group, what
         integer, intent(in) :: k
         character(len=*), intent(in) :: name, joint, type_a, type_b
         type(error_t), allocatable, intent(out) :: error
         integer :: j
         associate (joints => case%mechanism%joints)
            j = findloc(joints%name, joint, dim=1)
            if (j == 0) then
               call fatal_error(error, FFRF_INPUT_ERROR, src%at(group, k, 'joint') // ': &' // &
                  group // ' "' // trim(name) // '": joint "' // trim(joint) // &
                  '" is not a &joint of this case (joints: ' // join_words(joints%name, ', ') // &
                  ')')
            else if (joints(j)%type /= type_a .and. joints(j)%type /= type_b) then
               call fatal_error(error, FFRF_INPUT_ERROR, src%at(group, k, 'joint') // ': &' // &
                  group // ' "' // trim(name) // '": joint "' // trim(joint) // '" is ' // &
                  trim(joints(j)%type) // '; a ' // what // ' needs a ' // type_a // ' or ' // &
                  type_b // ' joint')
            end if
         end associate
      end subroutine check_element_joint

      !> A &marker on a flexible body places itself on its mesh: node or group (not both: the
      !> reader), named apart from the body's interfaces.
      subroutine check_point_marker(k, m, error)
         integer, intent(in) :: k
         type(marker_input_t), intent(in) :: m
         type(error_t), allocatable, intent(out) :: error
         logical :: is_interface
         is_interface = any(case%interfaces%body == m%body .and. case%interfaces%name == m%name)
         if (is_interface .and. m%node == 0 .and. len_trim(m%group) == 0) then
            ! the interface's own marker frame (docs/mechanisms.md "Joint frames")
            if (any(m%position /= 0.0_dp)) then
               call fatal_error(error, FFRF_INPUT_ERROR, src%at('marker', k, 'position') // &
                  ': &marker "' // trim(m%name) // '": the &interface of that name on body "' &
                  // trim(m%body) // '" is placed by its virtual node; drop the position ' // &
                  '(the marker gives the interface its orientation only)')
            else if (.not. m%oriented) then
               call fatal_error(error, FFRF_INPUT_ERROR, src%at('marker', k, 'name') // &
                  ': &marker "' // trim(m%name) // '": body "' // trim(m%body) // '" has ' // &
                  'an &interface of that name, which the marker can only orient; give its ' // &
                  'orientation, or drop the &marker')
            end if
         else if (m%node == 0 .and. len_trim(m%group) == 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%at('marker', k, 'body') // &
               ': &marker "' // trim(m%name) // '": body "' // trim(m%body) // '" has a ' // &
               'mesh; place the marker by node = <a node tag> or group = ''<a physical ' // &
               'surface>'' (its joint points are its &interface groups, which a &marker ' // &
               'of the same name may orient)')
         else if (is_interface) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%at('marker', k, 'name') // &
               ': &marker "' // trim(m%name) // '": body "' // trim(m%body) // '" has an ' // &
               '&interface of that name; name the marker apart')
         else if (m%node > 0 .and. any(len_trim(case%motions(body_index(case, m%body))% &
            coarse_meshes) > 0)) then
            ! the automatic model may take a coarse mesh, whose node tags are other points
            call fatal_error(error, FFRF_INPUT_ERROR, src%at('marker', k, 'node') // &
               ': &marker "' // trim(m%name) // '": body "' // trim(m%body) // '" has ' // &
               'coarse_meshes, whose node tags are other points; place the marker by ' // &
               'group = ''<a physical surface>'' or drop coarse_meshes')
         end if
      end subroutine check_point_marker
   end procedure check_mechanism_names

   !> Distance at the start between two markers of rigid bodies or the ground (&body position +
   !> A &marker position, A the &body orientation); -1 when an end is a
   !> flexible body's interface (known only from its mesh: the run checks it).
   pure real(dp) function rigid_start_distance(case, body1, marker1, body2, marker2) &
      result(distance)
      type(case_input_t), intent(in) :: case
      character(len=*), intent(in) :: body1, marker1, body2, marker2
      real(dp) :: point1(3), point2(3)
      logical :: known1, known2
      call start_point(body1, marker1, point1, known1)
      call start_point(body2, marker2, point2, known2)
      distance = -1.0_dp
      if (known1 .and. known2) distance = norm2(point2 - point1)
   contains
      pure subroutine start_point(body, marker, point, known)
         character(len=*), intent(in) :: body, marker
         real(dp), intent(out) :: point(3)
         logical, intent(out) :: known
         integer :: b, m
         point = 0.0_dp
         b = body_index(case, body)
         known = body == GROUND_NAME
         if (b > 0) then
            known = case%motions(b)%type == 'rigid'
            point = case%motions(b)%position
         end if
         if (.not. known) return
         m = findloc(case%mechanism%markers%body == body .and. &
            case%mechanism%markers%name == marker, .true., dim=1)
         known = m > 0
         if (.not. known) return
         if (b > 0) then
            point = point + matmul(case%motions(b)%orientation, case%mechanism%markers(m)%position)
         else
            point = point + case%mechanism%markers(m)%position
         end if
      end subroutine start_point
   end function rigid_start_distance

   module procedure driver_count
      driver_count = 0
      if (allocated(mech%drivers)) driver_count = size(mech%drivers)
   end procedure driver_count

   module procedure spring_count
      spring_count = 0
      if (allocated(mech%springs)) spring_count = size(mech%springs)
   end procedure spring_count

   module procedure sensor_count
      sensor_count = 0
      if (allocated(mech%sensors)) sensor_count = size(mech%sensors)
   end procedure sensor_count

   !> The body, marker and joint a &sensor names exist (the marker as check_marker asks).
   subroutine check_sensor_names(src, case, error)
      type(nml_source_t), intent(in) :: src
      type(case_input_t), intent(in) :: case
      type(error_t), allocatable, intent(out) :: error
      logical :: missing
      character(len=:), allocatable :: group
      integer :: k
      associate (mech => case%mechanism)
         if (.not. allocated(mech%sensors)) return
         do k = 1, size(mech%sensors)
            associate (x => mech%sensors(k))
               if (len_trim(x%marker) > 0) then
                  call check_marker(case, src%at('sensor', k, 'marker') // ': &sensor "' // &
                     trim(x%name) // '"', x%body, x%marker, error)
               else if (len_trim(x%body) > 0) then
                  if (body_index(case, x%body) == 0) then
                     call fatal_error(error, FFRF_INPUT_ERROR, src%at('sensor', k, 'body') // &
                        ': &sensor "' // trim(x%name) // '": body "' // trim(x%body) // &
                        '" is not a &body of this case (bodies: ' // &
                        join_words(case%bodies%name, ', ') // ')')
                  else if (x%node > 0 .and. &
                     len_trim(case%bodies(body_index(case, x%body))%mesh_file) == 0) then
                     call fatal_error(error, FFRF_INPUT_ERROR, src%at('sensor', k, 'node') // &
                        ': &sensor "' // trim(x%name) // '": body "' // trim(x%body) // &
                        '" has no mesh, so no node ' // to_str(x%node) // '; measure a ' // &
                        'body with a mesh_file')
                  end if
               end if
               if (.not. allocated(error) .and. len_trim(mech%mechanism%crank) > 0 .and. &
                  (x%name == 'crank_angle' .or. x%name == 'crank_speed')) call fatal_error( &
                  error, FFRF_INPUT_ERROR, src%at('sensor', k, 'name') // ': &sensor "' // &
                  trim(x%name) // '": the name belongs to the engine''s own sensor (a case ' // &
                  'with &mechanism crank has crank_angle and crank_speed); name it otherwise')
               if (.not. allocated(error) .and. len_trim(x%joint) > 0) then
                  if (.not. any(mech%joints%name == x%joint)) call fatal_error(error, &
                     FFRF_INPUT_ERROR, src%at('sensor', k, 'joint') // ': &sensor "' // &
                     trim(x%name) // '": joint "' // trim(x%joint) // '" is not a &joint ' // &
                     'of this case (joints: ' // join_words(mech%joints%name, ', ') // ')')
               end if
               if (.not. allocated(error) .and. trim(x%type) == 'driver') then
                  missing = driver_count(mech) == 0
                  if (.not. missing) missing = .not. any(mech%drivers%joint == x%joint)
                  if (missing) call fatal_error(error, FFRF_INPUT_ERROR, src%at('sensor', k, &
                     'joint') // ': &sensor "' // trim(x%name) // '": joint "' // &
                     trim(x%joint) // '" has no &driver; add &driver name = ..., joint = ''' // &
                     trim(x%joint) // ''' /')
               end if
               if (.not. allocated(error) .and. len_trim(x%spring) > 0) then
                  ! spring names a &spring, or the &torsion_spring or &bushing of those types
                  group = 'spring'
                  if (trim(x%type) == 'torsion_spring' .or. trim(x%type) == 'bushing') &
                     group = trim(x%type)
                  call check_spring_name(src%at('sensor', k, 'spring') // ': &sensor "' // &
                     trim(x%name) // '"', group, x%spring, element_names(mech, group), error)
               end if
               if (allocated(error)) return
            end associate
         end do
      end associate
   end subroutine check_sensor_names

   !> `name` (of a &sensor at `where`) is one of `names`, the &`group` names of the case.
   subroutine check_spring_name(where, group, name, names, error)
      character(len=*), intent(in) :: where, group, name
      character(len=64), intent(in) :: names(:)
      type(error_t), allocatable, intent(out) :: error
      if (size(names) == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': spring "' // trim(name) // &
            '" is not a &' // group // ' of this case (it has none)')
      else if (.not. any(names == name)) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': spring "' // trim(name) // &
            '" is not a &' // group // ' of this case (' // group // 's: ' // &
            join_words(names, ', ') // ')')
      end if
   end subroutine check_spring_name

   module procedure element_names
      allocate (names(0))
      select case (group)
      case ('spring')
         if (allocated(mech%springs)) names = mech%springs%name
      case ('torsion_spring')
         if (allocated(mech%torsion_springs)) names = mech%torsion_springs%name
      case ('bushing')
         if (allocated(mech%bushings)) names = mech%bushings%name
      end select
   end procedure element_names

   !> body is 'ground' or a &body, and marker one of its markers (module header).
   subroutine check_marker(case, where, body, marker, error, joint_end)
      type(case_input_t), intent(in) :: case
      character(len=*), intent(in) :: where, body, marker
      type(error_t), allocatable, intent(out) :: error
      !> A joint's end: a flexible body's node or group marker is refused (no interface)
      logical, intent(in), optional :: joint_end
      integer :: b
      logical :: point
      b = body_index(case, body)
      point = .false.
      ! a &marker named as an interface only orients it (check_point_marker): no point
      if (b > 0) point = case%motions(b)%type /= 'rigid' .and. &
         any(case%mechanism%markers%body == body .and. case%mechanism%markers%name == marker) &
         .and. .not. any(case%interfaces%body == body .and. case%interfaces%name == marker)
      if (point) then
         if (present(joint_end)) then
            if (joint_end) call fatal_error(error, FFRF_INPUT_ERROR, where // ': marker "' // &
               trim(marker) // '" of the flexible body "' // trim(body) // '" is a node or ' // &
               'group marker (a load and output point, no interface); a joint needs an ' // &
               'interface: declare the group as an &interface and join there')
         end if
         return
      end if
      if (body /= GROUND_NAME .and. b == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': body "' // trim(body) // &
            '" is not a &body of this case (bodies: ' // join_words(case%bodies%name, ', ') // &
            ', ground)')
      else if (body == GROUND_NAME .or. case%motions(max(b, 1))%type == 'rigid') then
         if (.not. any(case%mechanism%markers%body == body .and. &
            case%mechanism%markers%name == marker)) call fatal_error(error, FFRF_INPUT_ERROR, &
            where // ': marker "' // trim(marker) // '" of body "' // trim(body) // &
            '" is not defined; add &marker body = ''' // trim(body) // ''', name = ''' // &
            trim(marker) // ''', position = x, y, z /')
      else if (.not. any(case%interfaces%body == body .and. case%interfaces%name == marker)) &
         then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': body "' // trim(body) // &
            '" has no interface "' // trim(marker) // '" (the markers of a meshed body are ' // &
            'its &interface groups: ' // interface_list(case, body) // ', and its &marker ' // &
            'groups with node or group)')
      end if
   end subroutine check_marker

   module procedure body_index
      do k = 1, size(case%bodies)
         if (case%bodies(k)%name == name) return
      end do
      k = 0
   end procedure body_index

   function interface_list(case, body) result(text)
      type(case_input_t), intent(in) :: case
      character(len=*), intent(in) :: body
      character(len=:), allocatable :: text
      integer :: k
      text = ''
      do k = 1, size(case%interfaces)
         if (case%interfaces(k)%body /= body) cycle
         if (len(text) > 0) text = text // ', '
         text = text // trim(case%interfaces(k)%name)
      end do
      if (len(text) == 0) text = 'none'
   end function interface_list

   module procedure msh_name
      name = nml_string(file_name)
      if (len(name) == 0) name = 'none'
   end procedure msh_name

   module procedure case_name_of
      integer :: slash, dot
      if (file_name == '-') then
         name = 'stdin'
         return
      end if
      slash = index(file_name, '/', back=.true.)
      name = file_name(slash + 1:)
      dot = index(name, '.', back=.true.)
      if (dot > 1) name = name(:dot - 1)
   end procedure case_name_of

   module procedure mechanism_case_input_t_max_steps
      type(mechanism_case_input_t) :: defaults
      n = defaults%max_steps
   end procedure mechanism_case_input_t_max_steps

end submodule ffrf_input_case_checks
