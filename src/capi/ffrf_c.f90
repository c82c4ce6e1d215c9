!> `use ffrf_c`: the C API of include/ffrf.h for Fortran callers that prefer it to the typed
!> module `ffrf` (older codes, codes that also pass the handle to C): bind(C) interfaces of
!> every function of the header, one to one, and its status constants. Handles are
!> type(c_ptr); strings go in NUL-terminated (`'case.nml' // c_null_char`); indices are
!> 0-based as in C. ffrf_c_string turns ffrf_last_error's result into a Fortran string.
module ffrf_c
   use, intrinsic :: iso_c_binding, only: c_int, c_double, c_char, c_ptr, c_size_t, &
      c_null_char, c_associated, c_f_pointer
   implicit none
   private
   public :: FFRF_OK, FFRF_BAD_CALL, FFRF_INPUT_ERROR, FFRF_FILE_ERROR, FFRF_NUMERIC_ERROR, &
      FFRF_INTERRUPTED
   public :: ffrf_version, ffrf_case_open, ffrf_case_run, ffrf_body_count, ffrf_body_name, &
      ffrf_body_frequencies, ffrf_mechanism_advance, ffrf_crank_state, ffrf_last_error, &
      ffrf_case_close, ffrf_body_sizes, ffrf_body_nodes, ffrf_body_mode_shapes, &
      ffrf_body_virtual_node_shapes, ffrf_body_mass_properties, ffrf_mechanism_time, &
      ffrf_body_state, ffrf_marker_count, ffrf_marker_state, ffrf_joint_count, &
      ffrf_joint_name, ffrf_joint_reaction, ffrf_marker_set_load, ffrf_body_set_pose, ffrf_sensor_count, &
      ffrf_case_set_export, &
      ffrf_sensor_name, ffrf_sensor_values
   public :: ffrf_driver_state
   public :: ffrf_body_invariant
   public :: ffrf_case_new, ffrf_case_add_body, ffrf_case_add_surface, ffrf_case_add_interface, &
      ffrf_case_set_num_modes, FFRF_RBE2, FFRF_RBE3, FFRF_RBE3_AREA
   public :: ffrf_case_add_interface_nodes, FFRF_RBE3_AREA_CONSISTENT
   public :: ffrf_c_string

   !> MPC kinds of ffrf_case_add_interface
   integer(c_int), parameter :: FFRF_RBE2 = 1, FFRF_RBE3 = 2, FFRF_RBE3_AREA = 3, &
      FFRF_RBE3_AREA_CONSISTENT = 4

   !> Status codes of include/ffrf.h
   integer(c_int), parameter :: FFRF_OK = 0, FFRF_BAD_CALL = 1, FFRF_INPUT_ERROR = 2, &
      FFRF_FILE_ERROR = 3, FFRF_NUMERIC_ERROR = 4, FFRF_INTERRUPTED = 5

   interface
      subroutine ffrf_version(major, minor, patch) bind(c, name='ffrf_version')
         import :: c_int
         implicit none
         integer(c_int), intent(out) :: major, minor, patch
      end subroutine ffrf_version

      integer(c_int) function ffrf_case_open(case_file, mesh_dir, output_dir, c) &
            bind(c, name='ffrf_case_open')
         import :: c_int, c_ptr
         implicit none
         !> c_loc of NUL-terminated strings, or c_null_ptr (mesh_dir, output_dir)
         type(c_ptr), value :: case_file, mesh_dir, output_dir
         !> The new handle (close it also after a failure)
         type(c_ptr), intent(out) :: c
      end function ffrf_case_open

      integer(c_int) function ffrf_case_run(c) bind(c, name='ffrf_case_run')
         import :: c_int, c_ptr
         implicit none
         type(c_ptr), value :: c
      end function ffrf_case_run

      integer(c_int) function ffrf_body_count(c, n) bind(c, name='ffrf_body_count')
         import :: c_int, c_ptr
         implicit none
         type(c_ptr), value :: c
         integer(c_int), intent(out) :: n
      end function ffrf_body_count

      integer(c_int) function ffrf_body_name(c, body, buf, length) &
            bind(c, name='ffrf_body_name')
         import :: c_int, c_ptr, c_char, c_size_t
         implicit none
         type(c_ptr), value :: c
         integer(c_int), value :: body
         character(kind=c_char), intent(out) :: buf(*)
         integer(c_size_t), value :: length
      end function ffrf_body_name

      integer(c_int) function ffrf_body_frequencies(c, body, hz, capacity, count) &
            bind(c, name='ffrf_body_frequencies')
         import :: c_int, c_ptr, c_double
         implicit none
         type(c_ptr), value :: c
         integer(c_int), value :: body
         real(c_double), intent(out) :: hz(*)
         integer(c_int), value :: capacity
         integer(c_int), intent(out) :: count
      end function ffrf_body_frequencies

      integer(c_int) function ffrf_mechanism_advance(c, t) &
            bind(c, name='ffrf_mechanism_advance')
         import :: c_int, c_ptr, c_double
         implicit none
         type(c_ptr), value :: c
         real(c_double), value :: t
      end function ffrf_mechanism_advance

      integer(c_int) function ffrf_crank_state(c, angle_rad, speed_rad_s) &
            bind(c, name='ffrf_crank_state')
         import :: c_int, c_ptr, c_double
         implicit none
         type(c_ptr), value :: c
         real(c_double), intent(out) :: angle_rad, speed_rad_s
      end function ffrf_crank_state

      type(c_ptr) function ffrf_last_error(c) bind(c, name='ffrf_last_error')
         import :: c_ptr
         implicit none
         type(c_ptr), value :: c
      end function ffrf_last_error

      subroutine ffrf_case_close(c) bind(c, name='ffrf_case_close')
         import :: c_ptr
         implicit none
         type(c_ptr), value :: c
      end subroutine ffrf_case_close

      integer(c_int) function ffrf_body_sizes(c, body, num_nodes, num_modes, &
            num_interfaces) bind(c, name='ffrf_body_sizes')
         import :: c_int, c_ptr
         implicit none
         type(c_ptr), value :: c
         integer(c_int), value :: body
         integer(c_int), intent(out) :: num_nodes, num_modes, num_interfaces
      end function ffrf_body_sizes

      integer(c_int) function ffrf_body_nodes(c, body, xyz, capacity, count) &
            bind(c, name='ffrf_body_nodes')
         import :: c_int, c_ptr, c_double, c_size_t
         implicit none
         type(c_ptr), value :: c
         integer(c_int), value :: body
         real(c_double), intent(out) :: xyz(*)
         integer(c_size_t), value :: capacity
         integer(c_size_t), intent(out) :: count
      end function ffrf_body_nodes

      integer(c_int) function ffrf_body_mode_shapes(c, body, shape, capacity, count) &
            bind(c, name='ffrf_body_mode_shapes')
         import :: c_int, c_ptr, c_double, c_size_t
         implicit none
         type(c_ptr), value :: c
         integer(c_int), value :: body
         real(c_double), intent(out) :: shape(*)
         integer(c_size_t), value :: capacity
         integer(c_size_t), intent(out) :: count
      end function ffrf_body_mode_shapes

      integer(c_int) function ffrf_body_virtual_node_shapes(c, body, rows, capacity, count) &
            bind(c, name='ffrf_body_virtual_node_shapes')
         import :: c_int, c_ptr, c_double, c_size_t
         implicit none
         type(c_ptr), value :: c
         integer(c_int), value :: body
         real(c_double), intent(out) :: rows(*)
         integer(c_size_t), value :: capacity
         integer(c_size_t), intent(out) :: count
      end function ffrf_body_virtual_node_shapes

      integer(c_int) function ffrf_body_mass_properties(c, body, mass, center, inertia) &
            bind(c, name='ffrf_body_mass_properties')
         import :: c_int, c_ptr, c_double
         implicit none
         type(c_ptr), value :: c
         integer(c_int), value :: body
         real(c_double), intent(out) :: mass, center(3), inertia(9)
      end function ffrf_body_mass_properties

      integer(c_int) function ffrf_mechanism_time(c, t, t_end) &
            bind(c, name='ffrf_mechanism_time')
         import :: c_int, c_ptr, c_double
         implicit none
         type(c_ptr), value :: c
         real(c_double), intent(out) :: t, t_end
      end function ffrf_mechanism_time

      integer(c_int) function ffrf_body_state(c, body, q, v, capacity, count) &
            bind(c, name='ffrf_body_state')
         import :: c_int, c_ptr, c_double
         implicit none
         type(c_ptr), value :: c
         integer(c_int), value :: body
         real(c_double), intent(out) :: q(*), v(*)
         integer(c_int), value :: capacity
         integer(c_int), intent(out) :: count
      end function ffrf_body_state

      integer(c_int) function ffrf_marker_count(c, body, n) bind(c, name='ffrf_marker_count')
         import :: c_int, c_ptr
         implicit none
         type(c_ptr), value :: c
         integer(c_int), value :: body
         integer(c_int), intent(out) :: n
      end function ffrf_marker_count

      integer(c_int) function ffrf_marker_state(c, body, marker, position, velocity, &
            angular_velocity) bind(c, name='ffrf_marker_state')
         import :: c_int, c_ptr, c_double
         implicit none
         type(c_ptr), value :: c
         integer(c_int), value :: body, marker
         real(c_double), intent(out) :: position(3), velocity(3), angular_velocity(3)
      end function ffrf_marker_state

      integer(c_int) function ffrf_joint_count(c, n) bind(c, name='ffrf_joint_count')
         import :: c_int, c_ptr
         implicit none
         type(c_ptr), value :: c
         integer(c_int), intent(out) :: n
      end function ffrf_joint_count

      integer(c_int) function ffrf_joint_name(c, joint, buf, length) &
            bind(c, name='ffrf_joint_name')
         import :: c_int, c_ptr, c_char, c_size_t
         implicit none
         type(c_ptr), value :: c
         integer(c_int), value :: joint
         character(kind=c_char), intent(out) :: buf(*)
         integer(c_size_t), value :: length
      end function ffrf_joint_name

      integer(c_int) function ffrf_joint_reaction(c, joint, force, moment) &
            bind(c, name='ffrf_joint_reaction')
         import :: c_int, c_ptr, c_double
         implicit none
         type(c_ptr), value :: c
         integer(c_int), value :: joint
         real(c_double), intent(out) :: force(6), moment(6)
      end function ffrf_joint_reaction

      integer(c_int) function ffrf_driver_state(c, joint, values) &
            bind(c, name='ffrf_driver_state')
         import :: c_int, c_ptr, c_double
         implicit none
         type(c_ptr), value :: c
         integer(c_int), value :: joint
         real(c_double), intent(out) :: values(3)
      end function ffrf_driver_state

      integer(c_int) function ffrf_sensor_count(c, n) bind(c, name='ffrf_sensor_count')
         import :: c_int, c_ptr
         implicit none
         type(c_ptr), value :: c
         integer(c_int), intent(out) :: n
      end function ffrf_sensor_count

      integer(c_int) function ffrf_sensor_name(c, sensor, buf, length) &
            bind(c, name='ffrf_sensor_name')
         import :: c_int, c_ptr, c_char, c_size_t
         implicit none
         type(c_ptr), value :: c
         integer(c_int), value :: sensor
         character(kind=c_char), intent(out) :: buf(*)
         integer(c_size_t), value :: length
      end function ffrf_sensor_name

      integer(c_int) function ffrf_sensor_values(c, sensor, values, capacity, count) &
            bind(c, name='ffrf_sensor_values')
         import :: c_int, c_ptr, c_double
         implicit none
         type(c_ptr), value :: c
         integer(c_int), value :: sensor, capacity
         real(c_double), intent(out) :: values(*)
         integer(c_int), intent(out) :: count
      end function ffrf_sensor_values

      integer(c_int) function ffrf_marker_set_load(c, body, marker, force, moment) &
            bind(c, name='ffrf_marker_set_load')
         import :: c_int, c_ptr, c_double
         implicit none
         type(c_ptr), value :: c
         integer(c_int), value :: body, marker
         real(c_double), intent(in) :: force(3), moment(3)
      end function ffrf_marker_set_load

      !> orientation by rows (as &body orientation); pass c_null_ptr to keep a value
      integer(c_int) function ffrf_body_set_pose(c, body, position, orientation, velocity, &
            angular_velocity) bind(c, name='ffrf_body_set_pose')
         import :: c_int, c_ptr
         implicit none
         type(c_ptr), value :: c, position, orientation, velocity, angular_velocity
         integer(c_int), value :: body
      end function ffrf_body_set_pose

      !> formats: a NUL-terminated list of export words ("xdmf"), before the run
      integer(c_int) function ffrf_case_set_export(c, formats) bind(c, name='ffrf_case_set_export')
         import :: c_int, c_ptr, c_char
         implicit none
         type(c_ptr), value :: c
         character(kind=c_char), intent(in) :: formats(*)
      end function ffrf_case_set_export

      integer(c_int) function ffrf_body_invariant(c, body, name, values, capacity, count) &
            bind(c, name='ffrf_body_invariant')
         import :: c_int, c_ptr, c_char, c_double, c_size_t
         implicit none
         type(c_ptr), value :: c
         integer(c_int), value :: body
         character(kind=c_char), intent(in) :: name(*)
         real(c_double), intent(out) :: values(*)
         integer(c_size_t), value :: capacity
         integer(c_size_t), intent(out) :: count
      end function ffrf_body_invariant

      integer(c_int) function ffrf_case_new(c) bind(c, name='ffrf_case_new')
         import :: c_int, c_ptr
         implicit none
         type(c_ptr), intent(out) :: c
      end function ffrf_case_new

      integer(c_int) function ffrf_case_add_body(c, name, num_nodes, xyz, nodes_per_tet, &
            num_tets, tets, young, poisson, density) bind(c, name='ffrf_case_add_body')
         import :: c_int, c_ptr, c_char, c_double
         implicit none
         type(c_ptr), value :: c
         character(kind=c_char), intent(in) :: name(*)
         integer(c_int), value :: num_nodes, nodes_per_tet, num_tets
         real(c_double), intent(in) :: xyz(3, *)
         integer(c_int), intent(in) :: tets(nodes_per_tet, *)
         real(c_double), value :: young, poisson, density
      end function ffrf_case_add_body

      integer(c_int) function ffrf_case_add_surface(c, body, name, nodes_per_triangle, &
            num_triangles, triangles) bind(c, name='ffrf_case_add_surface')
         import :: c_int, c_ptr, c_char
         implicit none
         type(c_ptr), value :: c
         integer(c_int), value :: body
         character(kind=c_char), intent(in) :: name(*)
         integer(c_int), value :: nodes_per_triangle, num_triangles
         integer(c_int), intent(in) :: triangles(nodes_per_triangle, *)
      end function ffrf_case_add_surface

      integer(c_int) function ffrf_case_add_interface(c, body, surface, mpc, virtual_node, &
            rc) bind(c, name='ffrf_case_add_interface')
         import :: c_int, c_ptr, c_char
         implicit none
         type(c_ptr), value :: c
         integer(c_int), value :: body
         character(kind=c_char), intent(in) :: surface(*)
         integer(c_int), value :: mpc
         !> c_loc of 3 doubles, or c_null_ptr (centroid); c_loc of 6 ints, or c_null_ptr
         type(c_ptr), value :: virtual_node, rc
      end function ffrf_case_add_interface

      integer(c_int) function ffrf_case_add_interface_nodes(c, body, name, mpc, num_nodes, &
            nodes, weights, virtual_node, rc) bind(c, name='ffrf_case_add_interface_nodes')
         import :: c_int, c_ptr, c_char
         implicit none
         type(c_ptr), value :: c
         integer(c_int), value :: body
         character(kind=c_char), intent(in) :: name(*)
         integer(c_int), value :: mpc, num_nodes
         integer(c_int), intent(in) :: nodes(*)
         !> c_loc of num_nodes doubles, or c_null_ptr (uniform); c_loc of 3 doubles, or
         !> c_null_ptr (weighted centroid); c_loc of 6 ints, or c_null_ptr
         type(c_ptr), value :: weights, virtual_node, rc
      end function ffrf_case_add_interface_nodes

      integer(c_int) function ffrf_case_set_num_modes(c, num_modes) &
            bind(c, name='ffrf_case_set_num_modes')
         import :: c_int, c_ptr
         implicit none
         type(c_ptr), value :: c
         integer(c_int), value :: num_modes
      end function ffrf_case_set_num_modes
   end interface

contains

   !> The Fortran string of a NUL-terminated C string (ffrf_last_error's result).
   function ffrf_c_string(text) result(string)
      type(c_ptr), intent(in) :: text
      character(len=:), allocatable :: string
      character(kind=c_char), pointer :: chars(:)
      integer :: n
      string = ''
      if (.not. c_associated(text)) return
      call c_f_pointer(text, chars, [huge(0)])
      n = 0
      do while (chars(n + 1) /= c_null_char)
         n = n + 1
      end do
      deallocate (string)
      allocate (character(len=n) :: string)
      do n = 1, len(string)
         string(n:n) = chars(n)
      end do
   end function ffrf_c_string

end module ffrf_c
