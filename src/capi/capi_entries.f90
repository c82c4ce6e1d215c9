!> The entry points of the C API on a case (a submodule of ffrf_capi): body data (names,
!> frequencies, sizes, nodes, mode shapes, virtual-node rows, mass properties, invariants), the
!> mechanism (advance, time, crank, body and marker state, joints, sensors, the host's marker
!> loads) and a case from arrays (bodies, surfaces, interfaces, modes, communicator). Each is
!> the prologue of ffrf_capi_handle, one call of ffrf_case_t, and the copies out.
submodule (ffrf_capi) ffrf_capi_entries
   use, intrinsic :: iso_c_binding, only: c_associated, c_f_pointer
   use ffrf_core_strings, only: to_str
   implicit none

contains

   module procedure ffrf_body_count
      stat = count_entry(c, 'ffrf_body_count', n)
   end procedure ffrf_body_count

   module procedure ffrf_body_name
      stat = name_entry(c, 'ffrf_body_name', body, buf, length)
   end procedure ffrf_body_name

   module procedure ffrf_body_frequencies
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      real(dp), allocatable :: values(:)
      integer(c_int), pointer :: out
      integer(c_size_t) :: n
      if (.not. ready(c, h, stat, [c_associated(count)], 'ffrf_body_frequencies: count is NULL')) &
         return
      if (capacity < 0) then
         stat = bad_call(h, 'ffrf_body_frequencies: capacity ' // to_str(int(capacity)) // &
            ' is negative')
         return
      end if
      call c_f_pointer(count, out)
      out = 0
      call h%case%frequencies(int(body) + 1, values, error)
      stat = status_of(h, error)
      if (stat /= 0) return
      stat = copy_out(h, 'ffrf_body_frequencies', values, hz, int(capacity, c_size_t), n)
      out = int(n, c_int)
   end procedure ffrf_body_frequencies

   module procedure ffrf_body_sizes
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      integer :: sizes(3)
      if (.not. got_handle(c, h, stat)) return
      call h%case%body_sizes(int(body) + 1, sizes(1), sizes(2), sizes(3), error)
      call put_int(num_nodes, sizes(1))
      call put_int(num_modes, sizes(2))
      call put_int(num_interfaces, sizes(3))
      stat = status_of(h, error)
   end procedure ffrf_body_sizes

   !> Common part of the array queries of a body: `kind` (BODY_NODES, BODY_MODE_SHAPES or
   !> BODY_VIRTUAL_NODE_SHAPES) selects the array, `which` names the entry point in messages.
   integer(c_int) function body_array(c, body, kind, which, array, capacity, count) &
         result(stat)
      type(c_ptr), intent(in) :: c, array, count
      integer, intent(in) :: kind
      integer(c_int), intent(in) :: body
      character(len=*), intent(in) :: which
      integer(c_size_t), intent(in) :: capacity
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      real(dp), allocatable :: values(:, :)
      integer(c_size_t), pointer :: out
      integer(c_size_t) :: n
      if (.not. ready(c, h, stat, [c_associated(count)], which // ': count is NULL')) return
      call c_f_pointer(count, out)
      out = 0
      select case (kind)
      case (BODY_NODES)
         call h%case%nodes(int(body) + 1, values, error)
      case (BODY_MODE_SHAPES)
         call h%case%mode_shapes(int(body) + 1, values, error)
      case default
         call h%case%virtual_node_shapes(int(body) + 1, values, error)
      end select
      stat = status_of(h, error)
      if (stat /= 0) return
      stat = copy_out(h, which, reshape(values, [size(values)]), array, capacity, n)
      out = n
   end function body_array

   module procedure ffrf_body_nodes
      stat = body_array(c, body, BODY_NODES, 'ffrf_body_nodes', xyz, capacity, count)
   end procedure ffrf_body_nodes

   module procedure ffrf_body_mode_shapes
      stat = body_array(c, body, BODY_MODE_SHAPES, 'ffrf_body_mode_shapes', shape, capacity, count)
   end procedure ffrf_body_mode_shapes

   module procedure ffrf_body_virtual_node_shapes
      stat = body_array(c, body, BODY_VIRTUAL_NODE_SHAPES, &
         'ffrf_body_virtual_node_shapes', rows, capacity, count)
   end procedure ffrf_body_virtual_node_shapes

   module procedure ffrf_body_mass_properties
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      real(dp) :: m, com(3), inertia_tensor(3, 3)
      if (.not. ready(c, h, stat, [c_associated(mass), c_associated(center), &
         c_associated(inertia)], 'ffrf_body_mass_properties: mass, center or inertia is NULL')) &
         return
      call h%case%mass_properties(int(body) + 1, m, com, inertia_tensor, error)
      stat = status_of(h, error)
      if (stat /= 0) return
      call put_reals(mass, [m])
      call put_reals(center, com)
      call put_reals(inertia, reshape(inertia_tensor, [9]))
   end procedure ffrf_body_mass_properties

   module procedure ffrf_body_invariant
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      real(dp), allocatable :: array(:)
      integer(c_size_t), pointer :: out
      integer(c_size_t) :: n
      if (.not. ready(c, h, stat, [c_associated(name), c_associated(count)], &
         'ffrf_body_invariant: name or count is NULL')) return
      call c_f_pointer(count, out)
      out = 0
      call h%case%invariant(int(body) + 1, from_c(name), array, error)
      stat = status_of(h, error)
      if (stat /= 0) return
      stat = copy_out(h, 'ffrf_body_invariant', array, values, capacity, n)
      out = n
   end procedure ffrf_body_invariant

   module procedure ffrf_mechanism_advance
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      if (.not. got_handle(c, h, stat)) return
      call h%case%advance(real(t, dp), error)
      stat = status_of(h, error)
   end procedure ffrf_mechanism_advance

   module procedure ffrf_crank_state
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      real(dp) :: a, s
      if (.not. ready(c, h, stat, [c_associated(angle), c_associated(speed)], &
         'ffrf_crank_state: angle_rad or speed_rad_s is NULL')) return
      call h%case%crank_state(a, s, error)
      call put_reals(angle, [a])
      call put_reals(speed, [s])
      stat = status_of(h, error)
   end procedure ffrf_crank_state

   module procedure ffrf_mechanism_time
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      real(dp) :: now, last
      if (.not. got_handle(c, h, stat)) return
      call h%case%time(now, last, error)
      stat = status_of(h, error)
      if (stat /= 0) return
      call put_reals(t, [now])
      call put_reals(t_end, [last])
   end procedure ffrf_mechanism_time

   module procedure ffrf_body_state
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      real(dp), allocatable :: qb(:), vb(:)
      integer(c_int), pointer :: out
      integer(c_size_t) :: n
      if (.not. ready(c, h, stat, [c_associated(count), capacity >= 0], &
         'ffrf_body_state: count is NULL or capacity negative')) return
      call c_f_pointer(count, out)
      out = 0
      call h%case%body_state(int(body) + 1, qb, vb, error)
      stat = status_of(h, error)
      if (stat /= 0) return
      out = int(size(qb), c_int)
      if (c_associated(q)) stat = copy_out(h, 'ffrf_body_state', qb, q, int(capacity, &
         c_size_t), n)
      if (stat == 0 .and. c_associated(v)) stat = copy_out(h, 'ffrf_body_state', vb, v, &
         int(capacity, c_size_t), n)
   end procedure ffrf_body_state

   module procedure ffrf_marker_count
      stat = count_entry(c, 'ffrf_marker_count', n, body)
   end procedure ffrf_marker_count

   module procedure ffrf_marker_state
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      real(dp) :: values(3, 3)
      if (.not. got_handle(c, h, stat)) return
      call h%case%marker_state(int(body) + 1, int(marker) + 1, values(:, 1), values(:, 2), &
         values(:, 3), error)
      stat = status_of(h, error)
      if (stat /= 0) return
      call put_reals(position, values(:, 1))
      call put_reals(velocity, values(:, 2))
      call put_reals(angular_velocity, values(:, 3))
   end procedure ffrf_marker_state

   module procedure ffrf_joint_count
      stat = count_entry(c, 'ffrf_joint_count', n)
   end procedure ffrf_joint_count

   module procedure ffrf_joint_name
      stat = name_entry(c, 'ffrf_joint_name', joint, buf, length)
   end procedure ffrf_joint_name

   module procedure ffrf_joint_reaction
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      real(dp) :: f(3, 2), m(3, 2)
      if (.not. ready(c, h, stat, [c_associated(force), c_associated(moment)], &
         'ffrf_joint_reaction: force or moment is NULL')) return
      call h%case%joint_reaction(int(joint) + 1, f, m, error)
      stat = status_of(h, error)
      if (stat /= 0) return
      call put_reals(force, reshape(f, [6]))
      call put_reals(moment, reshape(m, [6]))
   end procedure ffrf_joint_reaction

   module procedure ffrf_driver_state
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      real(dp) :: state(3)
      if (.not. ready(c, h, stat, [c_associated(values)], &
         'ffrf_driver_state: values is NULL')) return
      call h%case%driver_state(int(joint) + 1, state, error)
      stat = status_of(h, error)
      if (stat == 0) call put_reals(values, state)
   end procedure ffrf_driver_state

   module procedure ffrf_sensor_count
      stat = count_entry(c, 'ffrf_sensor_count', n)
   end procedure ffrf_sensor_count

   module procedure ffrf_sensor_name
      stat = name_entry(c, 'ffrf_sensor_name', sensor, buf, length)
   end procedure ffrf_sensor_name

   module procedure ffrf_sensor_values
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      real(dp), allocatable :: x(:)
      integer(c_int), pointer :: out
      integer(c_size_t) :: n
      if (.not. ready(c, h, stat, [c_associated(count), capacity >= 0], &
         'ffrf_sensor_values: count is NULL or capacity negative')) return
      call c_f_pointer(count, out)
      out = 0
      call h%case%sensor_values(int(sensor) + 1, x, error)
      stat = status_of(h, error)
      if (stat /= 0) return
      out = int(size(x), c_int)
      if (c_associated(values)) stat = copy_out(h, 'ffrf_sensor_values', x, values, &
         int(capacity, c_size_t), n)
   end procedure ffrf_sensor_values

   module procedure ffrf_marker_set_load
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      real(c_double), pointer :: p(:)
      real(dp) :: f(3), m(3)
      if (.not. got_handle(c, h, stat)) return
      f = 0.0_dp
      m = 0.0_dp
      if (c_associated(force)) then
         call c_f_pointer(force, p, [3])
         f = p
      end if
      if (c_associated(moment)) then
         call c_f_pointer(moment, p, [3])
         m = p
      end if
      call h%case%set_marker_load(int(body) + 1, int(marker) + 1, f, m, error)
      stat = status_of(h, error)
   end procedure ffrf_marker_set_load

   module procedure ffrf_case_add_body
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      real(c_double), pointer :: x(:, :)
      integer(c_int), pointer :: t(:, :)
      if (.not. ready(c, h, stat, [c_associated(name), c_associated(xyz), c_associated(tets)], &
         'ffrf_case_add_body: name, xyz or tets is NULL')) return
      if (num_nodes < 4 .or. num_tets < 1 .or. (nodes_per_tet /= 4 .and. &
         nodes_per_tet /= 10)) then
         stat = bad_call(h, 'ffrf_case_add_body: ' // to_str(int(num_nodes)) // ' nodes, ' // &
            to_str(int(num_tets)) // ' tetrahedra of ' // to_str(int(nodes_per_tet)) // &
            ' nodes; give at least 4 nodes, 1 tetrahedron, 4 or 10 nodes per tetrahedron')
         return
      end if
      call c_f_pointer(xyz, x, [3, int(num_nodes)])
      call c_f_pointer(tets, t, [int(nodes_per_tet), int(num_tets)])
      call h%case%add_body(from_c(name), real(x, dp), int(t) + 1, real(young, dp), &
         real(poisson, dp), real(density, dp), error)
      stat = status_of(h, error)
   end procedure ffrf_case_add_body

   module procedure ffrf_case_add_surface
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      integer(c_int), pointer :: t(:, :)
      if (.not. ready(c, h, stat, [c_associated(name), c_associated(triangles)], &
         'ffrf_case_add_surface: name or triangles is NULL')) return
      if (num_triangles < 1 .or. (nodes_per_triangle /= 3 .and. nodes_per_triangle /= 6)) then
         stat = bad_call(h, 'ffrf_case_add_surface: ' // to_str(int(num_triangles)) // &
            ' triangles of ' // to_str(int(nodes_per_triangle)) // ' nodes; give at least ' // &
            'one triangle of 3 or 6 nodes')
         return
      end if
      call c_f_pointer(triangles, t, [int(nodes_per_triangle), int(num_triangles)])
      call h%case%add_surface(int(body) + 1, from_c(name), int(t) + 1, error)
      stat = status_of(h, error)
   end procedure ffrf_case_add_surface

   module procedure ffrf_case_add_interface
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      real(c_double), pointer :: position(:)
      logical :: forbidden(6)
      if (.not. ready(c, h, stat, [c_associated(surface)], &
         'ffrf_case_add_interface: surface is NULL')) return
      forbidden = forbidden_of(rc)
      if (c_associated(virtual_node)) then
         call c_f_pointer(virtual_node, position, [3])
         call h%case%add_interface(int(body) + 1, from_c(surface), int(mpc), forbidden, error, &
            position=real(position, dp))
      else
         call h%case%add_interface(int(body) + 1, from_c(surface), int(mpc), forbidden, error)
      end if
      stat = status_of(h, error)
   end procedure ffrf_case_add_interface

   module procedure ffrf_case_add_interface_nodes
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      integer(c_int), pointer :: node_list(:)
      real(c_double), pointer :: w(:), position(:)
      logical :: forbidden(6)
      if (.not. ready(c, h, stat, [c_associated(name), c_associated(nodes)], &
         'ffrf_case_add_interface_nodes: name or nodes is NULL')) return
      if (num_nodes < 1) then
         stat = bad_call(h, 'ffrf_case_add_interface_nodes: num_nodes = ' // &
            to_str(int(num_nodes)) // '; give at least one node')
         return
      end if
      call c_f_pointer(nodes, node_list, [num_nodes])
      forbidden = forbidden_of(rc)
      ! a disassociated pointer is an absent optional argument (Fortran 2008)
      nullify (w, position)
      if (c_associated(weights)) call c_f_pointer(weights, w, [num_nodes])
      if (c_associated(virtual_node)) call c_f_pointer(virtual_node, position, [3])
      call h%case%add_interface_nodes(int(body) + 1, from_c(name), int(mpc), &
         int(node_list) + 1, forbidden, error, weights=w, position=position)
      stat = status_of(h, error)
   end procedure ffrf_case_add_interface_nodes

   module procedure ffrf_case_set_num_modes
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      if (.not. got_handle(c, h, stat)) return
      call h%case%set_num_modes(int(num_modes), error)
      stat = status_of(h, error)
   end procedure ffrf_case_set_num_modes

   module procedure ffrf_case_set_communicator
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      if (.not. got_handle(c, h, stat)) return
      call h%case%set_communicator(int(fortran_comm), error)
      stat = status_of(h, error)
   end procedure ffrf_case_set_communicator

   !> The reference conditions of an interface from the C array rc[6] (nonzero: forbidden); none
   !> when rc is NULL.
   function forbidden_of(rc) result(forbidden)
      type(c_ptr), intent(in) :: rc
      logical :: forbidden(6)
      integer(c_int), pointer :: flags(:)
      forbidden = .false.
      if (.not. c_associated(rc)) return
      call c_f_pointer(rc, flags, [6])
      forbidden = flags /= 0
   end function forbidden_of

end submodule ffrf_capi_entries
