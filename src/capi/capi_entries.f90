!> The entry points of the C API on a case: body data (names, frequencies, sizes, nodes, mode
!> shapes, virtual-node rows, mass properties, invariants), the mechanism (advance, time, crank,
!> body and marker state, joints, sensors, the host's marker loads) and a case from arrays
!> (bodies, surfaces, interfaces, modes, communicator). Each is the prologue of ffrf_capi
!> (capi_handle.f90), one call of ffrf_case_t, and the copies out; each is declared once, here
!> (bind(C) with the signature of include/ffrf.h, its C prototype above it).
module ffrf_capi_entries
   use, intrinsic :: iso_c_binding, only: c_int, c_double, c_ptr, c_size_t, c_associated, &
      c_f_pointer
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t
   use ffrf_core_strings, only: to_str
   use ffrf_capi, only: capi_handle_t, from_c, status_of, bad_call, ready, put_int, put_reals, &
      got_handle, copy_out, count_entry, name_entry, BODY_NODES, BODY_MODE_SHAPES, &
      BODY_VIRTUAL_NODE_SHAPES
   implicit none
   private
   public :: ffrf_body_count, ffrf_body_name, ffrf_body_frequencies, ffrf_body_sizes, &
      ffrf_body_nodes, ffrf_body_mode_shapes, ffrf_body_virtual_node_shapes, &
      ffrf_body_mass_properties, ffrf_body_invariant
   public :: ffrf_mechanism_advance, ffrf_crank_state, ffrf_mechanism_time, ffrf_body_state, &
      ffrf_marker_count, ffrf_marker_state, ffrf_joint_count, ffrf_joint_name, &
      ffrf_joint_reaction, ffrf_driver_state, ffrf_sensor_count, ffrf_sensor_name, &
      ffrf_sensor_values, ffrf_marker_set_load, ffrf_body_set_pose, ffrf_case_set_export
   public :: ffrf_case_add_body, ffrf_case_add_surface, ffrf_case_add_interface, &
      ffrf_case_add_interface_nodes, ffrf_case_set_num_modes, ffrf_case_set_communicator

contains

   !> int ffrf_body_count(const ffrf_case *c, int *n)
   integer(c_int) function ffrf_body_count(c, n) result(stat) bind(c, &
         name='ffrf_body_count')
      type(c_ptr), value :: c, n
      stat = count_entry(c, 'ffrf_body_count', n)
   end function ffrf_body_count

   !> int ffrf_body_name(const ffrf_case *c, int body, char *buf, size_t len)
   integer(c_int) function ffrf_body_name(c, body, buf, length) result(stat) &
         bind(c, name='ffrf_body_name')
      type(c_ptr), value :: c, buf
      integer(c_int), value :: body
      integer(c_size_t), value :: length
      stat = name_entry(c, 'ffrf_body_name', body, buf, length)
   end function ffrf_body_name

   !> int ffrf_body_frequencies(const ffrf_case *c, int body, double *hz, int capacity,
   !> int *count)
   integer(c_int) function ffrf_body_frequencies(c, body, hz, capacity, count) &
         result(stat) bind(c, name='ffrf_body_frequencies')
      type(c_ptr), value :: c, hz, count
      integer(c_int), value :: body, capacity
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
   end function ffrf_body_frequencies

   !> int ffrf_body_sizes(const ffrf_case *c, int body, int *num_nodes, int *num_modes,
   !> int *num_interfaces)
   integer(c_int) function ffrf_body_sizes(c, body, num_nodes, num_modes, &
         num_interfaces) &
         result(stat) bind(c, name='ffrf_body_sizes')
      type(c_ptr), value :: c, num_nodes, num_modes, num_interfaces
      integer(c_int), value :: body
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      integer :: sizes(3)
      if (.not. got_handle(c, h, stat)) return
      call h%case%body_sizes(int(body) + 1, sizes(1), sizes(2), sizes(3), error)
      call put_int(num_nodes, sizes(1))
      call put_int(num_modes, sizes(2))
      call put_int(num_interfaces, sizes(3))
      stat = status_of(h, error)
   end function ffrf_body_sizes

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

   !> int ffrf_body_nodes(const ffrf_case *c, int body, double *xyz, size_t capacity,
   !> size_t *count)
   integer(c_int) function ffrf_body_nodes(c, body, xyz, capacity, count) result(stat) &
         bind(c, name='ffrf_body_nodes')
      type(c_ptr), value :: c, xyz, count
      integer(c_int), value :: body
      integer(c_size_t), value :: capacity
      stat = body_array(c, body, BODY_NODES, 'ffrf_body_nodes', xyz, capacity, count)
   end function ffrf_body_nodes

   !> int ffrf_body_mode_shapes(const ffrf_case *c, int body, double *shape, size_t capacity,
   !> size_t *count)
   integer(c_int) function ffrf_body_mode_shapes(c, body, shape, capacity, count) &
         result(stat) bind(c, name='ffrf_body_mode_shapes')
      type(c_ptr), value :: c, shape, count
      integer(c_int), value :: body
      integer(c_size_t), value :: capacity
      stat = body_array(c, body, BODY_MODE_SHAPES, 'ffrf_body_mode_shapes', shape, capacity, count)
   end function ffrf_body_mode_shapes

   !> int ffrf_body_virtual_node_shapes(const ffrf_case *c, int body, double *rows,
   !> size_t capacity, size_t *count)
   integer(c_int) function ffrf_body_virtual_node_shapes(c, body, rows, capacity, count) &
         result(stat) bind(c, name='ffrf_body_virtual_node_shapes')
      type(c_ptr), value :: c, rows, count
      integer(c_int), value :: body
      integer(c_size_t), value :: capacity
      stat = body_array(c, body, BODY_VIRTUAL_NODE_SHAPES, &
         'ffrf_body_virtual_node_shapes', rows, capacity, count)
   end function ffrf_body_virtual_node_shapes

   !> int ffrf_body_mass_properties(const ffrf_case *c, int body, double *mass,
   !> double center[3], double inertia[9])
   integer(c_int) function ffrf_body_mass_properties(c, body, mass, center, inertia) &
         result(stat) bind(c, name='ffrf_body_mass_properties')
      type(c_ptr), value :: c, mass, center, inertia
      integer(c_int), value :: body
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
   end function ffrf_body_mass_properties

   !> int ffrf_body_invariant(ffrf_case *c, int body, const char *name, double *values,
   !> size_t capacity, size_t *count)
   integer(c_int) function ffrf_body_invariant(c, body, name, values, capacity, count) &
         result(stat) bind(c, name='ffrf_body_invariant')
      type(c_ptr), value :: c, name, values, count
      integer(c_int), value :: body
      integer(c_size_t), value :: capacity
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
   end function ffrf_body_invariant

   !> int ffrf_mechanism_advance(ffrf_case *c, double t)
   integer(c_int) function ffrf_mechanism_advance(c, t) result(stat) &
         bind(c, name='ffrf_mechanism_advance')
      type(c_ptr), value :: c
      real(c_double), value :: t
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      if (.not. got_handle(c, h, stat)) return
      call h%case%advance(real(t, dp), error)
      stat = status_of(h, error)
   end function ffrf_mechanism_advance

   !> int ffrf_crank_state(const ffrf_case *c, double *angle_rad, double *speed_rad_s)
   integer(c_int) function ffrf_crank_state(c, angle, speed) result(stat) &
         bind(c, name='ffrf_crank_state')
      type(c_ptr), value :: c, angle, speed
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      real(dp) :: a, s
      if (.not. ready(c, h, stat, [c_associated(angle), c_associated(speed)], &
         'ffrf_crank_state: angle_rad or speed_rad_s is NULL')) return
      call h%case%crank_state(a, s, error)
      call put_reals(angle, [a])
      call put_reals(speed, [s])
      stat = status_of(h, error)
   end function ffrf_crank_state

   !> int ffrf_mechanism_time(const ffrf_case *c, double *t, double *t_end)
   integer(c_int) function ffrf_mechanism_time(c, t, t_end) result(stat) &
         bind(c, name='ffrf_mechanism_time')
      type(c_ptr), value :: c, t, t_end
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      real(dp) :: now, last
      if (.not. got_handle(c, h, stat)) return
      call h%case%time(now, last, error)
      stat = status_of(h, error)
      if (stat /= 0) return
      call put_reals(t, [now])
      call put_reals(t_end, [last])
   end function ffrf_mechanism_time

   !> int ffrf_body_state(const ffrf_case *c, int body, double *q, double *v, int capacity,
   !> int *count)
   integer(c_int) function ffrf_body_state(c, body, q, v, capacity, count) result(stat) &
         bind(c, name='ffrf_body_state')
      type(c_ptr), value :: c, q, v, count
      integer(c_int), value :: body, capacity
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
   end function ffrf_body_state

   !> int ffrf_marker_count(const ffrf_case *c, int body, int *n)
   integer(c_int) function ffrf_marker_count(c, body, n) result(stat) &
         bind(c, name='ffrf_marker_count')
      type(c_ptr), value :: c, n
      integer(c_int), value :: body
      stat = count_entry(c, 'ffrf_marker_count', n, body)
   end function ffrf_marker_count

   !> int ffrf_marker_state(const ffrf_case *c, int body, int marker, double position[3],
   !> double velocity[3], double angular_velocity[3])
   integer(c_int) function ffrf_marker_state(c, body, marker, position, velocity, &
         angular_velocity) result(stat) bind(c, name='ffrf_marker_state')
      type(c_ptr), value :: c, position, velocity, angular_velocity
      integer(c_int), value :: body, marker
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
   end function ffrf_marker_state

   !> int ffrf_joint_count(const ffrf_case *c, int *n)
   integer(c_int) function ffrf_joint_count(c, n) result(stat) bind(c, &
         name='ffrf_joint_count')
      type(c_ptr), value :: c, n
      stat = count_entry(c, 'ffrf_joint_count', n)
   end function ffrf_joint_count

   !> int ffrf_joint_name(const ffrf_case *c, int joint, char *buf, size_t len)
   integer(c_int) function ffrf_joint_name(c, joint, buf, length) result(stat) &
         bind(c, name='ffrf_joint_name')
      type(c_ptr), value :: c, buf
      integer(c_int), value :: joint
      integer(c_size_t), value :: length
      stat = name_entry(c, 'ffrf_joint_name', joint, buf, length)
   end function ffrf_joint_name

   !> int ffrf_joint_reaction(const ffrf_case *c, int joint, double force[6], double moment[6])
   integer(c_int) function ffrf_joint_reaction(c, joint, force, moment) result(stat) &
         bind(c, name='ffrf_joint_reaction')
      type(c_ptr), value :: c, force, moment
      integer(c_int), value :: joint
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
   end function ffrf_joint_reaction

   !> int ffrf_driver_state(const ffrf_case *c, int joint, double values[3])
   integer(c_int) function ffrf_driver_state(c, joint, values) result(stat) &
         bind(c, name='ffrf_driver_state')
      type(c_ptr), value :: c, values
      integer(c_int), value :: joint
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      real(dp) :: state(3)
      if (.not. ready(c, h, stat, [c_associated(values)], &
         'ffrf_driver_state: values is NULL')) return
      call h%case%driver_state(int(joint) + 1, state, error)
      stat = status_of(h, error)
      if (stat == 0) call put_reals(values, state)
   end function ffrf_driver_state

   !> int ffrf_sensor_count(const ffrf_case *c, int *n)
   integer(c_int) function ffrf_sensor_count(c, n) result(stat) bind(c, &
         name='ffrf_sensor_count')
      type(c_ptr), value :: c, n
      stat = count_entry(c, 'ffrf_sensor_count', n)
   end function ffrf_sensor_count

   !> int ffrf_sensor_name(const ffrf_case *c, int sensor, char *buf, size_t len)
   integer(c_int) function ffrf_sensor_name(c, sensor, buf, length) result(stat) &
         bind(c, name='ffrf_sensor_name')
      type(c_ptr), value :: c, buf
      integer(c_int), value :: sensor
      integer(c_size_t), value :: length
      stat = name_entry(c, 'ffrf_sensor_name', sensor, buf, length)
   end function ffrf_sensor_name

   !> int ffrf_sensor_values(const ffrf_case *c, int sensor, double *values, int capacity,
   !> int *count)
   integer(c_int) function ffrf_sensor_values(c, sensor, values, capacity, count) &
         result(stat) bind(c, name='ffrf_sensor_values')
      type(c_ptr), value :: c, values, count
      integer(c_int), value :: sensor, capacity
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
   end function ffrf_sensor_values

   !> int ffrf_marker_set_load(ffrf_case *c, int body, int marker, const double force[3],
   !> const double moment[3])
   integer(c_int) function ffrf_marker_set_load(c, body, marker, force, moment) &
         result(stat) bind(c, name='ffrf_marker_set_load')
      type(c_ptr), value :: c, force, moment
      integer(c_int), value :: body, marker
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
   end function ffrf_marker_set_load

   !> int ffrf_body_set_pose(ffrf_case *c, int body, const double position[3],
   !> const double orientation[9], const double velocity[3], const double angular_velocity[3])
   !> (orientation by rows, as &body orientation; NULL keeps the case's value)
   integer(c_int) function ffrf_body_set_pose(c, body, position, orientation, velocity, &
         angular_velocity) result(stat) bind(c, name='ffrf_body_set_pose')
      type(c_ptr), value :: c, position, orientation, velocity, angular_velocity
      integer(c_int), value :: body
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      real(c_double), pointer :: r(:), a(:), u(:), w(:)
      if (.not. got_handle(c, h, stat)) return
      r => vector(position, 3)
      a => vector(orientation, 9)
      u => vector(velocity, 3)
      w => vector(angular_velocity, 3)
      ! absent optional arguments where the pointers are null
      if (associated(a)) then
         call h%case%set_pose(int(body) + 1, error, r, transpose(reshape(a, [3, 3])), u, w)
      else
         call h%case%set_pose(int(body) + 1, error, r, velocity=u, angular_velocity=w)
      end if
      stat = status_of(h, error)
   contains
      !> The n doubles at p, or a null pointer for NULL.
      function vector(p, n) result(values)
         type(c_ptr), intent(in) :: p
         integer, intent(in) :: n
         real(c_double), pointer :: values(:)
         values => null()
         if (c_associated(p)) call c_f_pointer(p, values, [n])
      end function vector
   end function ffrf_body_set_pose

   !> int ffrf_case_set_export(ffrf_case *c, const char *formats)
   integer(c_int) function ffrf_case_set_export(c, formats) result(stat) &
         bind(c, name='ffrf_case_set_export')
      type(c_ptr), value :: c, formats
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      if (.not. ready(c, h, stat, [c_associated(formats)], &
         'ffrf_case_set_export: formats is NULL')) return
      call h%case%set_export(from_c(formats), error)
      stat = status_of(h, error)
   end function ffrf_case_set_export

   !> int ffrf_case_add_body(ffrf_case *c, const char *name, int num_nodes, const double *xyz,
   !> int nodes_per_tet, int num_tets, const int *tets, double young, double poisson,
   !> double density)
   integer(c_int) function ffrf_case_add_body(c, name, num_nodes, xyz, nodes_per_tet, &
         num_tets, tets, young, poisson, density) result(stat) bind(c, name='ffrf_case_add_body')
      type(c_ptr), value :: c, name, xyz, tets
      integer(c_int), value :: num_nodes, nodes_per_tet, num_tets
      real(c_double), value :: young, poisson, density
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
   end function ffrf_case_add_body

   !> int ffrf_case_add_surface(ffrf_case *c, int body, const char *name,
   !> int nodes_per_triangle, int num_triangles, const int *triangles)
   integer(c_int) function ffrf_case_add_surface(c, body, name, nodes_per_triangle, &
         num_triangles, triangles) result(stat) bind(c, name='ffrf_case_add_surface')
      type(c_ptr), value :: c, name, triangles
      integer(c_int), value :: body, nodes_per_triangle, num_triangles
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
   end function ffrf_case_add_surface

   !> int ffrf_case_add_interface(ffrf_case *c, int body, const char *surface, int mpc,
   !> const double *virtual_node, const int rc[6])
   integer(c_int) function ffrf_case_add_interface(c, body, surface, mpc, &
         virtual_node, rc) &
         result(stat) bind(c, name='ffrf_case_add_interface')
      type(c_ptr), value :: c, surface, virtual_node, rc
      integer(c_int), value :: body, mpc
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
   end function ffrf_case_add_interface

   !> int ffrf_case_add_interface_nodes(ffrf_case *c, int body, const char *name, int mpc,
   !> int num_nodes, const int *nodes, const double *weights, const double *virtual_node,
   !> const int rc[6])
   integer(c_int) function ffrf_case_add_interface_nodes(c, body, name, mpc, &
         num_nodes, nodes, &
         weights, virtual_node, rc) result(stat) bind(c, name='ffrf_case_add_interface_nodes')
      type(c_ptr), value :: c, name, nodes, weights, virtual_node, rc
      integer(c_int), value :: body, mpc, num_nodes
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
   end function ffrf_case_add_interface_nodes

   !> int ffrf_case_set_num_modes(ffrf_case *c, int num_modes)
   integer(c_int) function ffrf_case_set_num_modes(c, num_modes) result(stat) &
         bind(c, name='ffrf_case_set_num_modes')
      type(c_ptr), value :: c
      integer(c_int), value :: num_modes
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      if (.not. got_handle(c, h, stat)) return
      call h%case%set_num_modes(int(num_modes), error)
      stat = status_of(h, error)
   end function ffrf_case_set_num_modes

   !> int ffrf_case_set_communicator(ffrf_case *c, int fortran_comm)
   integer(c_int) function ffrf_case_set_communicator(c, fortran_comm) result(stat) &
         bind(c, name='ffrf_case_set_communicator')
      type(c_ptr), value :: c
      integer(c_int), value :: fortran_comm
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      if (.not. got_handle(c, h, stat)) return
      call h%case%set_communicator(int(fortran_comm), error)
      stat = status_of(h, error)
   end function ffrf_case_set_communicator

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

end module ffrf_capi_entries
