!> The C API of include/ffrf.h: bind(C) entry points over ffrf_case_t (ffrf_capi_case). A
!> handle `ffrf_case *` is the C address of a capi_handle_t (the case object and the message of
!> its last call, NUL-terminated). Every entry point checks its pointers (c_associated before
!> c_f_pointer), shifts 0-based C indices to the 1-based Fortran ones, returns the status
!> (FFRF_OK = 0, else error%code) and keeps the message in the handle; nothing stops, prints
!> or touches global state, so distinct handles may be used from distinct threads (docs/api.md
!> names the third-party solvers that are not reentrant).
!>
!> This module holds the handle type and the interfaces; the bodies are in the submodules
!> capi_handle.f90 (the entry prologue, status, copies; open, new, run, last error, close) and
!> capi_entries.f90 (the entry points on a case: body data, mechanism, a case from arrays).
module ffrf_capi
   use, intrinsic :: iso_c_binding, only: c_int, c_double, c_char, c_ptr, c_size_t
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t
   use ffrf_capi_case, only: ffrf_case_t
   implicit none
   private
   public :: ffrf_version, ffrf_case_open, ffrf_case_run, ffrf_body_count, ffrf_body_name, &
      ffrf_body_frequencies, ffrf_mechanism_advance, ffrf_crank_state, ffrf_last_error, &
      ffrf_case_close, ffrf_body_sizes, ffrf_body_nodes, ffrf_body_mode_shapes, &
      ffrf_body_virtual_node_shapes, ffrf_body_mass_properties, ffrf_mechanism_time, &
      ffrf_body_state, ffrf_marker_count, ffrf_marker_state, ffrf_joint_count, &
      ffrf_joint_name, ffrf_joint_reaction, ffrf_marker_set_load, ffrf_sensor_count, &
      ffrf_sensor_name, ffrf_sensor_values
   public :: ffrf_driver_state
   public :: ffrf_body_invariant
   public :: ffrf_case_new, ffrf_case_add_body, ffrf_case_add_surface, ffrf_case_add_interface, &
      ffrf_case_set_num_modes
   public :: ffrf_case_add_interface_nodes, ffrf_case_set_communicator

   !> The arrays of a body (body_array)
   integer, parameter :: BODY_NODES = 1, BODY_MODE_SHAPES = 2, BODY_VIRTUAL_NODE_SHAPES = 3

   !> What a `ffrf_case *` points to.
   type :: capi_handle_t
      !> The case
      type(ffrf_case_t) :: case
      !> Message of the last call, NUL-terminated ("" after a success)
      character(kind=c_char), allocatable :: message(:)
   end type capi_handle_t

   interface

      ! --- ffrf_capi_handle (capi_handle.f90) ----------------------------------------------------

      !> The Fortran string of a NUL-terminated C string.
      module function from_c(text) result(string)
         type(c_ptr), intent(in) :: text
         character(len=:), allocatable :: string
      end function from_c

      !> Keep `error` (or "" when not allocated) as the handle's message; the status.
      module integer(c_int) function status_of(h, error) result(stat)
         type(capi_handle_t), intent(inout) :: h
         type(error_t), allocatable, intent(in) :: error
      end function status_of

      !> A bad call: keep the message, give FFRF_BAD_CALL.
      module integer(c_int) function bad_call(h, message) result(stat)
         type(capi_handle_t), intent(inout) :: h
         character(len=*), intent(in) :: message
      end function bad_call

      !> got_handle, then the entry's required pointers: false with stat = FFRF_BAD_CALL and
      !> `message` kept unless every element of `required` (c_associated of each) holds.
      module logical function ready(c, h, stat, required, message)
         type(c_ptr), intent(in) :: c
         type(capi_handle_t), pointer, intent(out) :: h
         integer(c_int), intent(out) :: stat
         logical, intent(in) :: required(:)
         character(len=*), intent(in) :: message
      end function ready

      !> *pointer = value when pointer is not NULL.
      module subroutine put_int(pointer, value)
         type(c_ptr), intent(in) :: pointer
         integer, intent(in) :: value
      end subroutine put_int

      !> Copy `values` to the C array `array` (size(values) doubles) when it is not NULL.
      module subroutine put_reals(array, values)
         type(c_ptr), intent(in) :: array
         real(dp), intent(in) :: values(:)
      end subroutine put_reals

      !> The entry prologue of every call on a handle: h from c; false with stat = FFRF_BAD_CALL
      !> for a NULL handle (no handle to keep a message in).
      module logical function got_handle(c, h, stat)
         type(c_ptr), intent(in) :: c
         type(capi_handle_t), pointer, intent(out) :: h
         integer(c_int), intent(out) :: stat
      end function got_handle

      !> Copy `values` into a C array of `capacity` doubles; count = size(values). FFRF_BAD_CALL
      !> when the array is smaller (its first capacity values written); a NULL array with
      !> capacity 0 only reports the count.
      module integer(c_int) function copy_out(h, what, values, array, capacity, count) result(stat)
         type(capi_handle_t), intent(inout) :: h
         character(len=*), intent(in) :: what
         real(dp), intent(in) :: values(:)
         type(c_ptr), intent(in) :: array
         integer(c_size_t), intent(in) :: capacity
         integer(c_size_t), intent(out) :: count
      end function copy_out

      !> The body of ffrf_body_count, ffrf_marker_count, ffrf_joint_count and ffrf_sensor_count
      !> (`which`, the entry point's name, selects the list): the prologue, *n, the status.
      module integer(c_int) function count_entry(c, which, n, index) result(stat)
         type(c_ptr), intent(in) :: c, n
         character(len=*), intent(in) :: which
         !> The body of ffrf_marker_count (0-based)
         integer(c_int), intent(in), optional :: index
      end function count_entry

      !> The body of ffrf_body_name, ffrf_joint_name and ffrf_sensor_name (`which`, the entry
      !> point's name, selects the list): name `index` (0-based) copied into buf of length bytes.
      module integer(c_int) function name_entry(c, which, index, buf, length) result(stat)
         type(c_ptr), intent(in) :: c, buf
         character(len=*), intent(in) :: which
         integer(c_int), intent(in) :: index
         integer(c_size_t), intent(in) :: length
      end function name_entry

      !> void ffrf_version(int *major, int *minor, int *patch)
      module subroutine ffrf_version(major, minor, patch) bind(c, name='ffrf_version')
         type(c_ptr), value :: major, minor, patch
      end subroutine ffrf_version

      !> int ffrf_case_open(const char *case_file, const char *mesh_dir, const char *output_dir,
      !> ffrf_case **c)
      module integer(c_int) function ffrf_case_open(case_file, mesh_dir, output_dir, c) &
            result(stat) bind(c, name='ffrf_case_open')
         type(c_ptr), value :: case_file, mesh_dir, output_dir, c
      end function ffrf_case_open

      !> int ffrf_case_new(ffrf_case **c)
      module integer(c_int) function ffrf_case_new(c) result(stat) bind(c, name='ffrf_case_new')
         type(c_ptr), value :: c
      end function ffrf_case_new

      !> int ffrf_case_run(ffrf_case *c)
      module integer(c_int) function ffrf_case_run(c) result(stat) bind(c, name='ffrf_case_run')
         type(c_ptr), value :: c
      end function ffrf_case_run

      !> const char *ffrf_last_error(const ffrf_case *c)
      module function ffrf_last_error(c) result(message) bind(c, name='ffrf_last_error')
         type(c_ptr), value :: c
         type(c_ptr) :: message
      end function ffrf_last_error

      !> void ffrf_case_close(ffrf_case *c)
      module subroutine ffrf_case_close(c) bind(c, name='ffrf_case_close')
         type(c_ptr), value :: c
      end subroutine ffrf_case_close

      ! --- ffrf_capi_entries (capi_entries.f90): body data ---------------------------------------

      !> int ffrf_body_count(const ffrf_case *c, int *n)
      module integer(c_int) function ffrf_body_count(c, n) result(stat) bind(c, &
            name='ffrf_body_count')
         type(c_ptr), value :: c, n
      end function ffrf_body_count

      !> int ffrf_body_name(const ffrf_case *c, int body, char *buf, size_t len)
      module integer(c_int) function ffrf_body_name(c, body, buf, length) result(stat) &
            bind(c, name='ffrf_body_name')
         type(c_ptr), value :: c, buf
         integer(c_int), value :: body
         integer(c_size_t), value :: length
      end function ffrf_body_name

      !> int ffrf_body_frequencies(const ffrf_case *c, int body, double *hz, int capacity,
      !> int *count)
      module integer(c_int) function ffrf_body_frequencies(c, body, hz, capacity, count) &
            result(stat) bind(c, name='ffrf_body_frequencies')
         type(c_ptr), value :: c, hz, count
         integer(c_int), value :: body, capacity
      end function ffrf_body_frequencies

      !> int ffrf_body_sizes(const ffrf_case *c, int body, int *num_nodes, int *num_modes,
      !> int *num_interfaces)
      module integer(c_int) function ffrf_body_sizes(c, body, num_nodes, num_modes, &
            num_interfaces) &
            result(stat) bind(c, name='ffrf_body_sizes')
         type(c_ptr), value :: c, num_nodes, num_modes, num_interfaces
         integer(c_int), value :: body
      end function ffrf_body_sizes

      !> int ffrf_body_nodes(const ffrf_case *c, int body, double *xyz, size_t capacity,
      !> size_t *count)
      module integer(c_int) function ffrf_body_nodes(c, body, xyz, capacity, count) result(stat) &
            bind(c, name='ffrf_body_nodes')
         type(c_ptr), value :: c, xyz, count
         integer(c_int), value :: body
         integer(c_size_t), value :: capacity
      end function ffrf_body_nodes

      !> int ffrf_body_mode_shapes(const ffrf_case *c, int body, double *shape, size_t capacity,
      !> size_t *count)
      module integer(c_int) function ffrf_body_mode_shapes(c, body, shape, capacity, count) &
            result(stat) bind(c, name='ffrf_body_mode_shapes')
         type(c_ptr), value :: c, shape, count
         integer(c_int), value :: body
         integer(c_size_t), value :: capacity
      end function ffrf_body_mode_shapes

      !> int ffrf_body_virtual_node_shapes(const ffrf_case *c, int body, double *rows,
      !> size_t capacity, size_t *count)
      module integer(c_int) function ffrf_body_virtual_node_shapes(c, body, rows, capacity, count) &
            result(stat) bind(c, name='ffrf_body_virtual_node_shapes')
         type(c_ptr), value :: c, rows, count
         integer(c_int), value :: body
         integer(c_size_t), value :: capacity
      end function ffrf_body_virtual_node_shapes

      !> int ffrf_body_mass_properties(const ffrf_case *c, int body, double *mass,
      !> double center[3], double inertia[9])
      module integer(c_int) function ffrf_body_mass_properties(c, body, mass, center, inertia) &
            result(stat) bind(c, name='ffrf_body_mass_properties')
         type(c_ptr), value :: c, mass, center, inertia
         integer(c_int), value :: body
      end function ffrf_body_mass_properties

      !> int ffrf_body_invariant(ffrf_case *c, int body, const char *name, double *values,
      !> size_t capacity, size_t *count)
      module integer(c_int) function ffrf_body_invariant(c, body, name, values, capacity, count) &
            result(stat) bind(c, name='ffrf_body_invariant')
         type(c_ptr), value :: c, name, values, count
         integer(c_int), value :: body
         integer(c_size_t), value :: capacity
      end function ffrf_body_invariant

      ! --- ffrf_capi_entries (capi_entries.f90): mechanism ---------------------------------------

      !> int ffrf_mechanism_advance(ffrf_case *c, double t)
      module integer(c_int) function ffrf_mechanism_advance(c, t) result(stat) &
            bind(c, name='ffrf_mechanism_advance')
         type(c_ptr), value :: c
         real(c_double), value :: t
      end function ffrf_mechanism_advance

      !> int ffrf_crank_state(const ffrf_case *c, double *angle_rad, double *speed_rad_s)
      module integer(c_int) function ffrf_crank_state(c, angle, speed) result(stat) &
            bind(c, name='ffrf_crank_state')
         type(c_ptr), value :: c, angle, speed
      end function ffrf_crank_state

      !> int ffrf_mechanism_time(const ffrf_case *c, double *t, double *t_end)
      module integer(c_int) function ffrf_mechanism_time(c, t, t_end) result(stat) &
            bind(c, name='ffrf_mechanism_time')
         type(c_ptr), value :: c, t, t_end
      end function ffrf_mechanism_time

      !> int ffrf_body_state(const ffrf_case *c, int body, double *q, double *v, int capacity,
      !> int *count)
      module integer(c_int) function ffrf_body_state(c, body, q, v, capacity, count) result(stat) &
            bind(c, name='ffrf_body_state')
         type(c_ptr), value :: c, q, v, count
         integer(c_int), value :: body, capacity
      end function ffrf_body_state

      !> int ffrf_marker_count(const ffrf_case *c, int body, int *n)
      module integer(c_int) function ffrf_marker_count(c, body, n) result(stat) &
            bind(c, name='ffrf_marker_count')
         type(c_ptr), value :: c, n
         integer(c_int), value :: body
      end function ffrf_marker_count

      !> int ffrf_marker_state(const ffrf_case *c, int body, int marker, double position[3],
      !> double velocity[3], double angular_velocity[3])
      module integer(c_int) function ffrf_marker_state(c, body, marker, position, velocity, &
            angular_velocity) result(stat) bind(c, name='ffrf_marker_state')
         type(c_ptr), value :: c, position, velocity, angular_velocity
         integer(c_int), value :: body, marker
      end function ffrf_marker_state

      !> int ffrf_joint_count(const ffrf_case *c, int *n)
      module integer(c_int) function ffrf_joint_count(c, n) result(stat) bind(c, &
            name='ffrf_joint_count')
         type(c_ptr), value :: c, n
      end function ffrf_joint_count

      !> int ffrf_joint_name(const ffrf_case *c, int joint, char *buf, size_t len)
      module integer(c_int) function ffrf_joint_name(c, joint, buf, length) result(stat) &
            bind(c, name='ffrf_joint_name')
         type(c_ptr), value :: c, buf
         integer(c_int), value :: joint
         integer(c_size_t), value :: length
      end function ffrf_joint_name

      !> int ffrf_joint_reaction(const ffrf_case *c, int joint, double force[6], double moment[6])
      module integer(c_int) function ffrf_joint_reaction(c, joint, force, moment) result(stat) &
            bind(c, name='ffrf_joint_reaction')
         type(c_ptr), value :: c, force, moment
         integer(c_int), value :: joint
      end function ffrf_joint_reaction

      !> int ffrf_driver_state(const ffrf_case *c, int joint, double values[3])
      module integer(c_int) function ffrf_driver_state(c, joint, values) result(stat) &
            bind(c, name='ffrf_driver_state')
         type(c_ptr), value :: c, values
         integer(c_int), value :: joint
      end function ffrf_driver_state

      !> int ffrf_sensor_count(const ffrf_case *c, int *n)
      module integer(c_int) function ffrf_sensor_count(c, n) result(stat) bind(c, &
            name='ffrf_sensor_count')
         type(c_ptr), value :: c, n
      end function ffrf_sensor_count

      !> int ffrf_sensor_name(const ffrf_case *c, int sensor, char *buf, size_t len)
      module integer(c_int) function ffrf_sensor_name(c, sensor, buf, length) result(stat) &
            bind(c, name='ffrf_sensor_name')
         type(c_ptr), value :: c, buf
         integer(c_int), value :: sensor
         integer(c_size_t), value :: length
      end function ffrf_sensor_name

      !> int ffrf_sensor_values(const ffrf_case *c, int sensor, double *values, int capacity,
      !> int *count)
      module integer(c_int) function ffrf_sensor_values(c, sensor, values, capacity, count) &
            result(stat) bind(c, name='ffrf_sensor_values')
         type(c_ptr), value :: c, values, count
         integer(c_int), value :: sensor, capacity
      end function ffrf_sensor_values

      !> int ffrf_marker_set_load(ffrf_case *c, int body, int marker, const double force[3],
      !> const double moment[3])
      module integer(c_int) function ffrf_marker_set_load(c, body, marker, force, moment) &
            result(stat) bind(c, name='ffrf_marker_set_load')
         type(c_ptr), value :: c, force, moment
         integer(c_int), value :: body, marker
      end function ffrf_marker_set_load

      ! --- ffrf_capi_entries (capi_entries.f90): a case from arrays ------------------------------

      !> int ffrf_case_add_body(ffrf_case *c, const char *name, int num_nodes, const double *xyz,
      !> int nodes_per_tet, int num_tets, const int *tets, double young, double poisson,
      !> double density)
      module integer(c_int) function ffrf_case_add_body(c, name, num_nodes, xyz, nodes_per_tet, &
            num_tets, tets, young, poisson, density) result(stat) bind(c, name='ffrf_case_add_body')
         type(c_ptr), value :: c, name, xyz, tets
         integer(c_int), value :: num_nodes, nodes_per_tet, num_tets
         real(c_double), value :: young, poisson, density
      end function ffrf_case_add_body

      !> int ffrf_case_add_surface(ffrf_case *c, int body, const char *name,
      !> int nodes_per_triangle, int num_triangles, const int *triangles)
      module integer(c_int) function ffrf_case_add_surface(c, body, name, nodes_per_triangle, &
            num_triangles, triangles) result(stat) bind(c, name='ffrf_case_add_surface')
         type(c_ptr), value :: c, name, triangles
         integer(c_int), value :: body, nodes_per_triangle, num_triangles
      end function ffrf_case_add_surface

      !> int ffrf_case_add_interface(ffrf_case *c, int body, const char *surface, int mpc,
      !> const double *virtual_node, const int rc[6])
      module integer(c_int) function ffrf_case_add_interface(c, body, surface, mpc, &
            virtual_node, rc) &
            result(stat) bind(c, name='ffrf_case_add_interface')
         type(c_ptr), value :: c, surface, virtual_node, rc
         integer(c_int), value :: body, mpc
      end function ffrf_case_add_interface

      !> int ffrf_case_add_interface_nodes(ffrf_case *c, int body, const char *name, int mpc,
      !> int num_nodes, const int *nodes, const double *weights, const double *virtual_node,
      !> const int rc[6])
      module integer(c_int) function ffrf_case_add_interface_nodes(c, body, name, mpc, &
            num_nodes, nodes, &
            weights, virtual_node, rc) result(stat) bind(c, name='ffrf_case_add_interface_nodes')
         type(c_ptr), value :: c, name, nodes, weights, virtual_node, rc
         integer(c_int), value :: body, mpc, num_nodes
      end function ffrf_case_add_interface_nodes

      !> int ffrf_case_set_num_modes(ffrf_case *c, int num_modes)
      module integer(c_int) function ffrf_case_set_num_modes(c, num_modes) result(stat) &
            bind(c, name='ffrf_case_set_num_modes')
         type(c_ptr), value :: c
         integer(c_int), value :: num_modes
      end function ffrf_case_set_num_modes

      !> int ffrf_case_set_communicator(ffrf_case *c, int fortran_comm)
      module integer(c_int) function ffrf_case_set_communicator(c, fortran_comm) result(stat) &
            bind(c, name='ffrf_case_set_communicator')
         type(c_ptr), value :: c
         integer(c_int), value :: fortran_comm
      end function ffrf_case_set_communicator
   end interface

end module ffrf_capi
