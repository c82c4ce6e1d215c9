!> The C API of include/ffrf.h: bind(C) entry points over ffrf_case_t (ffrf_capi_case). A
!> handle `ffrf_case *` is the C address of a capi_handle_t (the case object and the message of
!> its last call, NUL-terminated). Every entry point checks its pointers (c_associated before
!> c_f_pointer), shifts 0-based C indices to the 1-based Fortran ones, returns the status
!> (FFRF_OK = 0, else error%code) and keeps the message in the handle; nothing stops, prints
!> or touches global state, so distinct handles may be used from distinct threads (docs/api.md
!> names the third-party solvers that are not reentrant).
module ffrf_capi
   use, intrinsic :: iso_c_binding, only: c_int, c_double, c_char, c_ptr, c_size_t, &
      c_null_char, c_null_ptr, c_associated, c_f_pointer, c_loc
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error
   use ffrf_core_strings, only: to_str
   use ffrf_core_build_info, only: FFRF_VERSION_MAJOR, FFRF_VERSION_MINOR, FFRF_VERSION_PATCH
   use ffrf_capi_case, only: ffrf_case_t, FFRF_BAD_CALL
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

   !> ffrf_last_error(NULL): a fixed, read-only text
   character(kind=c_char), target, save :: null_handle_message(33) = [character(kind=c_char) &
      :: 'f', 'f', 'r', 'f', ':', ' ', 'N', 'U', 'L', 'L', ' ', 'c', 'a', 's', 'e', ' ', 'h', &
      'a', 'n', 'd', 'l', 'e', ' ', '(', 'n', 'o', ' ', 'c', 'a', 's', 'e', ')', c_null_char]

contains

   ! ------------------------------------------------------------------ helpers

   !> The Fortran string of a NUL-terminated C string.
   function from_c(text) result(string)
      type(c_ptr), intent(in) :: text
      character(len=:), allocatable :: string
      character(kind=c_char), pointer :: chars(:)
      integer :: n
      interface
         pure function c_strlen(s) result(length) bind(c, name='strlen')
            import :: c_ptr, c_size_t
            implicit none
            type(c_ptr), value, intent(in) :: s
            integer(c_size_t) :: length
         end function c_strlen
      end interface
      n = int(c_strlen(text))
      call c_f_pointer(text, chars, [n])
      allocate (character(len=n) :: string)
      string = transfer(chars(:n), string)
      if (n == 0) string = ''
   end function from_c

   !> Keep `error` (or "" when not allocated) as the handle's message; the status.
   integer(c_int) function status_of(h, error) result(stat)
      type(capi_handle_t), intent(inout) :: h
      type(error_t), allocatable, intent(in) :: error
      integer :: n, i
      if (.not. allocated(error)) then
         h%message = [c_null_char]
         stat = 0
         return
      end if
      n = 0
      if (allocated(error%message)) n = len(error%message)
      if (allocated(h%message)) deallocate (h%message)
      allocate (h%message(n + 1))
      do i = 1, n
         h%message(i) = error%message(i:i)
      end do
      h%message(n + 1) = c_null_char
      stat = int(error%code, c_int)
      if (stat == 0) stat = int(FFRF_BAD_CALL, c_int)
   end function status_of

   !> A bad call: keep the message, give FFRF_BAD_CALL.
   integer(c_int) function bad_call(h, message) result(stat)
      type(capi_handle_t), intent(inout) :: h
      character(len=*), intent(in) :: message
      type(error_t), allocatable :: error
      call fatal_error(error, FFRF_BAD_CALL, message)
      stat = status_of(h, error)
   end function bad_call

   !> The handle behind `c`, or null.
   function handle_of(c) result(h)
      type(c_ptr), intent(in) :: c
      type(capi_handle_t), pointer :: h
      h => null()
      if (c_associated(c)) call c_f_pointer(c, h)
   end function handle_of

   !> The entry prologue of every call on a handle: h from c; false with stat = FFRF_BAD_CALL
   !> for a NULL handle (no handle to keep a message in).
   logical function got_handle(c, h, stat)
      type(c_ptr), intent(in) :: c
      type(capi_handle_t), pointer, intent(out) :: h
      integer(c_int), intent(out) :: stat
      h => handle_of(c)
      got_handle = associated(h)
      stat = merge(0_c_int, int(FFRF_BAD_CALL, c_int), got_handle)
   end function got_handle

   !> The end of every *_count call: FFRF_BAD_CALL when the output n is NULL, else *n = count
   !> and the status of the query's error.
   integer(c_int) function put_count(h, what, count, error, n) result(stat)
      type(capi_handle_t), intent(inout) :: h
      character(len=*), intent(in) :: what
      integer, intent(in) :: count
      type(error_t), allocatable, intent(in) :: error
      type(c_ptr), intent(in) :: n
      integer(c_int), pointer :: out
      if (.not. c_associated(n)) then
         stat = bad_call(h, what // ': n is NULL')
         return
      end if
      call c_f_pointer(n, out)
      out = int(count, c_int)
      stat = status_of(h, error)
   end function put_count

   !> Copy `values` into a C array of `capacity` doubles; count = size(values). FFRF_BAD_CALL
   !> when the array is smaller (its first capacity values written); a NULL array with
   !> capacity 0 only reports the count.
   integer(c_int) function copy_out(h, what, values, array, capacity, count) result(stat)
      type(capi_handle_t), intent(inout) :: h
      character(len=*), intent(in) :: what
      real(dp), intent(in) :: values(:)
      type(c_ptr), intent(in) :: array
      integer(c_size_t), intent(in) :: capacity
      integer(c_size_t), intent(out) :: count
      real(c_double), pointer :: out(:)
      integer(c_size_t) :: n
      count = size(values, kind=c_size_t)
      if (.not. c_associated(array)) then
         if (capacity == 0) then
            h%message = [c_null_char]
            stat = 0
         else
            stat = bad_call(h, what // ': the array is NULL but its capacity is ' // &
               to_str(int(capacity)))
         end if
         return
      end if
      n = min(capacity, count)
      call c_f_pointer(array, out, [max(n, 1_c_size_t)])
      out(:n) = values(:n)
      if (capacity < count) then
         stat = bad_call(h, what // ': the array holds ' // to_str(int(capacity)) // &
            ' values, ' // to_str(int(count)) // ' are needed')
      else
         h%message = [c_null_char]
         stat = 0
      end if
   end function copy_out

   !> Copy a name into a C buffer of len bytes (with its NUL); FFRF_BAD_CALL when too small.
   integer(c_int) function copy_name(h, what, name, buf, length) result(stat)
      type(capi_handle_t), intent(inout) :: h
      character(len=*), intent(in) :: what, name
      type(c_ptr), intent(in) :: buf
      integer(c_size_t), intent(in) :: length
      character(kind=c_char), pointer :: out(:)
      integer :: i, n
      if (.not. c_associated(buf)) then
         stat = bad_call(h, what // ': the buffer is NULL')
         return
      end if
      if (length < 1) then
         stat = bad_call(h, what // ': the buffer has length 0; "' // name // '" needs ' // &
            to_str(len(name) + 1) // ' bytes with its NUL')
         return
      end if
      call c_f_pointer(buf, out, [length])
      n = int(min(int(len(name), c_size_t), length - 1))
      do i = 1, n
         out(i) = name(i:i)
      end do
      out(n + 1) = c_null_char
      if (n < len(name)) then
         stat = bad_call(h, what // ': the buffer has ' // to_str(int(length)) // &
            ' bytes; "' // name // '" needs ' // to_str(len(name) + 1) // ' with its NUL')
      else
         h%message = [c_null_char]
         stat = 0
      end if
   end function copy_name

   ! ------------------------------------------------------------------ case

   !> void ffrf_version(int *major, int *minor, int *patch)
   subroutine ffrf_version(major, minor, patch) bind(c, name='ffrf_version')
      type(c_ptr), value :: major, minor, patch
      integer(c_int), pointer :: p
      if (c_associated(major)) then
         call c_f_pointer(major, p)
         p = FFRF_VERSION_MAJOR
      end if
      if (c_associated(minor)) then
         call c_f_pointer(minor, p)
         p = FFRF_VERSION_MINOR
      end if
      if (c_associated(patch)) then
         call c_f_pointer(patch, p)
         p = FFRF_VERSION_PATCH
      end if
   end subroutine ffrf_version

   !> int ffrf_case_open(const char *case_file, const char *mesh_dir, const char *output_dir,
   !> ffrf_case **c)
   integer(c_int) function ffrf_case_open(case_file, mesh_dir, output_dir, c) result(stat) &
         bind(c, name='ffrf_case_open')
      type(c_ptr), value :: case_file, mesh_dir, output_dir, c
      type(c_ptr), pointer :: out
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      if (.not. c_associated(c)) then
         stat = FFRF_BAD_CALL
         return
      end if
      call c_f_pointer(c, out)
      allocate (h)
      out = c_loc(h)
      if (.not. c_associated(case_file)) then
         stat = bad_call(h, 'ffrf_case_open: case_file is NULL')
         return
      end if
      if (c_associated(mesh_dir) .and. c_associated(output_dir)) then
         call h%case%open(from_c(case_file), error, mesh_dir=from_c(mesh_dir), &
            output_dir=from_c(output_dir))
      else if (c_associated(mesh_dir)) then
         call h%case%open(from_c(case_file), error, mesh_dir=from_c(mesh_dir))
      else if (c_associated(output_dir)) then
         call h%case%open(from_c(case_file), error, output_dir=from_c(output_dir))
      else
         call h%case%open(from_c(case_file), error)
      end if
      stat = status_of(h, error)
   end function ffrf_case_open

   !> int ffrf_case_run(ffrf_case *c)
   integer(c_int) function ffrf_case_run(c) result(stat) bind(c, name='ffrf_case_run')
      type(c_ptr), value :: c
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      if (.not. got_handle(c, h, stat)) return
      call h%case%run(error)
      stat = status_of(h, error)
   end function ffrf_case_run

   !> int ffrf_body_count(const ffrf_case *c, int *n)
   integer(c_int) function ffrf_body_count(c, n) result(stat) bind(c, name='ffrf_body_count')
      type(c_ptr), value :: c, n
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      integer :: count
      if (.not. got_handle(c, h, stat)) return
      call h%case%body_count(count, error)
      stat = put_count(h, 'ffrf_body_count', count, error, n)
   end function ffrf_body_count

   !> int ffrf_body_name(const ffrf_case *c, int body, char *buf, size_t len)
   integer(c_int) function ffrf_body_name(c, body, buf, length) result(stat) &
         bind(c, name='ffrf_body_name')
      type(c_ptr), value :: c, buf
      integer(c_int), value :: body
      integer(c_size_t), value :: length
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      character(len=:), allocatable :: name
      if (.not. got_handle(c, h, stat)) return
      call h%case%body_name(int(body) + 1, name, error)
      stat = status_of(h, error)
      if (stat == 0) stat = copy_name(h, 'ffrf_body_name', name, buf, length)
   end function ffrf_body_name

   !> int ffrf_body_frequencies(const ffrf_case *c, int body, double *hz, int capacity,
   !> int *count)
   integer(c_int) function ffrf_body_frequencies(c, body, hz, capacity, count) result(stat) &
         bind(c, name='ffrf_body_frequencies')
      type(c_ptr), value :: c, hz, count
      integer(c_int), value :: body, capacity
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      real(dp), allocatable :: values(:)
      integer(c_int), pointer :: out
      integer(c_size_t) :: n
      if (.not. got_handle(c, h, stat)) return
      if (.not. c_associated(count)) then
         stat = bad_call(h, 'ffrf_body_frequencies: count is NULL')
         return
      end if
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
      real(c_double), pointer :: p
      real(dp) :: a, s
      if (.not. got_handle(c, h, stat)) return
      if (.not. (c_associated(angle) .and. c_associated(speed))) then
         stat = bad_call(h, 'ffrf_crank_state: angle_rad or speed_rad_s is NULL')
         return
      end if
      call h%case%crank_state(a, s, error)
      call c_f_pointer(angle, p)
      p = a
      call c_f_pointer(speed, p)
      p = s
      stat = status_of(h, error)
   end function ffrf_crank_state

   !> const char *ffrf_last_error(const ffrf_case *c)
   function ffrf_last_error(c) result(message) bind(c, name='ffrf_last_error')
      type(c_ptr), value :: c
      type(c_ptr) :: message
      type(capi_handle_t), pointer :: h
      h => handle_of(c)
      if (.not. associated(h)) then
         message = c_loc(null_handle_message)
         return
      end if
      if (.not. allocated(h%message)) h%message = [c_null_char]
      message = c_loc(h%message)
   end function ffrf_last_error

   !> void ffrf_case_close(ffrf_case *c)
   subroutine ffrf_case_close(c) bind(c, name='ffrf_case_close')
      type(c_ptr), value :: c
      type(capi_handle_t), pointer :: h
      h => handle_of(c)
      if (.not. associated(h)) return
      call h%case%close()
      deallocate (h)
   end subroutine ffrf_case_close

   ! ------------------------------------------------------------------ body data

   !> int ffrf_body_sizes(const ffrf_case *c, int body, int *num_nodes, int *num_modes,
   !> int *num_interfaces)
   integer(c_int) function ffrf_body_sizes(c, body, num_nodes, num_modes, num_interfaces) &
         result(stat) bind(c, name='ffrf_body_sizes')
      type(c_ptr), value :: c, num_nodes, num_modes, num_interfaces
      integer(c_int), value :: body
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      integer(c_int), pointer :: p
      integer :: sizes(3)
      if (.not. got_handle(c, h, stat)) return
      call h%case%body_sizes(int(body) + 1, sizes(1), sizes(2), sizes(3), error)
      if (c_associated(num_nodes)) then
         call c_f_pointer(num_nodes, p)
         p = int(sizes(1), c_int)
      end if
      if (c_associated(num_modes)) then
         call c_f_pointer(num_modes, p)
         p = int(sizes(2), c_int)
      end if
      if (c_associated(num_interfaces)) then
         call c_f_pointer(num_interfaces, p)
         p = int(sizes(3), c_int)
      end if
      stat = status_of(h, error)
   end function ffrf_body_sizes

   !> Common part of the array queries of a body: `kind` (BODY_NODES, BODY_MODE_SHAPES or
   !> BODY_VIRTUAL_NODE_SHAPES) selects the array, `which` names the entry point in messages.
   integer(c_int) function body_array(c, body, kind, which, array, capacity, count) result(stat)
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
      if (.not. got_handle(c, h, stat)) return
      if (.not. c_associated(count)) then
         stat = bad_call(h, which // ': count is NULL')
         return
      end if
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
      real(c_double), pointer :: p, p3(:), p9(:)
      real(dp) :: m, com(3), inertia_tensor(3, 3)
      if (.not. got_handle(c, h, stat)) return
      if (.not. (c_associated(mass) .and. c_associated(center) .and. &
         c_associated(inertia))) then
         stat = bad_call(h, 'ffrf_body_mass_properties: mass, center or inertia is NULL')
         return
      end if
      call h%case%mass_properties(int(body) + 1, m, com, inertia_tensor, error)
      stat = status_of(h, error)
      if (stat /= 0) return
      call c_f_pointer(mass, p)
      p = m
      call c_f_pointer(center, p3, [3])
      p3 = com
      call c_f_pointer(inertia, p9, [9])
      p9 = reshape(inertia_tensor, [9])
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
      if (.not. got_handle(c, h, stat)) return
      if (.not. (c_associated(name) .and. c_associated(count))) then
         stat = bad_call(h, 'ffrf_body_invariant: name or count is NULL')
         return
      end if
      call c_f_pointer(count, out)
      out = 0
      call h%case%invariant(int(body) + 1, from_c(name), array, error)
      stat = status_of(h, error)
      if (stat /= 0) return
      stat = copy_out(h, 'ffrf_body_invariant', array, values, capacity, n)
      out = n
   end function ffrf_body_invariant

   ! ------------------------------------------------------------------ mechanism state

   !> int ffrf_mechanism_time(const ffrf_case *c, double *t, double *t_end)
   integer(c_int) function ffrf_mechanism_time(c, t, t_end) result(stat) &
         bind(c, name='ffrf_mechanism_time')
      type(c_ptr), value :: c, t, t_end
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      real(c_double), pointer :: p
      real(dp) :: now, last
      if (.not. got_handle(c, h, stat)) return
      call h%case%time(now, last, error)
      stat = status_of(h, error)
      if (stat /= 0) return
      if (c_associated(t)) then
         call c_f_pointer(t, p)
         p = now
      end if
      if (c_associated(t_end)) then
         call c_f_pointer(t_end, p)
         p = last
      end if
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
      if (.not. got_handle(c, h, stat)) return
      if (.not. c_associated(count) .or. capacity < 0) then
         stat = bad_call(h, 'ffrf_body_state: count is NULL or capacity negative')
         return
      end if
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
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      integer :: count
      if (.not. got_handle(c, h, stat)) return
      call h%case%marker_count(int(body) + 1, count, error)
      stat = put_count(h, 'ffrf_marker_count', count, error, n)
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
      call put3(position, values(:, 1))
      call put3(velocity, values(:, 2))
      call put3(angular_velocity, values(:, 3))
   end function ffrf_marker_state

   !> int ffrf_driver_state(const ffrf_case *c, int joint, double values[3])
   integer(c_int) function ffrf_driver_state(c, joint, values) result(stat) &
         bind(c, name='ffrf_driver_state')
      type(c_ptr), value :: c, values
      integer(c_int), value :: joint
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      real(dp) :: state(3)
      if (.not. got_handle(c, h, stat)) return
      if (.not. c_associated(values)) then
         stat = bad_call(h, 'ffrf_driver_state: values is NULL')
         return
      end if
      call h%case%driver_state(int(joint) + 1, state, error)
      stat = status_of(h, error)
      if (stat == 0) call put3(values, state)
   end function ffrf_driver_state

   !> Write 3 values to a C array when it is not NULL.
   subroutine put3(array, values)
      type(c_ptr), intent(in) :: array
      real(dp), intent(in) :: values(3)
      real(c_double), pointer :: p(:)
      if (.not. c_associated(array)) return
      call c_f_pointer(array, p, [3])
      p = values
   end subroutine put3

   !> int ffrf_joint_count(const ffrf_case *c, int *n)
   integer(c_int) function ffrf_joint_count(c, n) result(stat) bind(c, name='ffrf_joint_count')
      type(c_ptr), value :: c, n
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      integer :: count
      if (.not. got_handle(c, h, stat)) return
      call h%case%joint_count(count, error)
      stat = put_count(h, 'ffrf_joint_count', count, error, n)
   end function ffrf_joint_count

   !> int ffrf_joint_name(const ffrf_case *c, int joint, char *buf, size_t len)
   integer(c_int) function ffrf_joint_name(c, joint, buf, length) result(stat) &
         bind(c, name='ffrf_joint_name')
      type(c_ptr), value :: c, buf
      integer(c_int), value :: joint
      integer(c_size_t), value :: length
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      character(len=:), allocatable :: name
      if (.not. got_handle(c, h, stat)) return
      call h%case%joint_name(int(joint) + 1, name, error)
      stat = status_of(h, error)
      if (stat == 0) stat = copy_name(h, 'ffrf_joint_name', name, buf, length)
   end function ffrf_joint_name

   !> int ffrf_joint_reaction(const ffrf_case *c, int joint, double force[6], double moment[6])
   integer(c_int) function ffrf_joint_reaction(c, joint, force, moment) result(stat) &
         bind(c, name='ffrf_joint_reaction')
      type(c_ptr), value :: c, force, moment
      integer(c_int), value :: joint
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      real(dp) :: f(3, 2), m(3, 2)
      real(c_double), pointer :: p(:)
      if (.not. got_handle(c, h, stat)) return
      if (.not. (c_associated(force) .and. c_associated(moment))) then
         stat = bad_call(h, 'ffrf_joint_reaction: force or moment is NULL')
         return
      end if
      call h%case%joint_reaction(int(joint) + 1, f, m, error)
      stat = status_of(h, error)
      if (stat /= 0) return
      call c_f_pointer(force, p, [6])
      p = reshape(f, [6])
      call c_f_pointer(moment, p, [6])
      p = reshape(m, [6])
   end function ffrf_joint_reaction

   !> int ffrf_sensor_count(const ffrf_case *c, int *n)
   integer(c_int) function ffrf_sensor_count(c, n) result(stat) bind(c, name='ffrf_sensor_count')
      type(c_ptr), value :: c, n
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      integer :: count
      if (.not. got_handle(c, h, stat)) return
      call h%case%sensor_count(count, error)
      stat = put_count(h, 'ffrf_sensor_count', count, error, n)
   end function ffrf_sensor_count

   !> int ffrf_sensor_name(const ffrf_case *c, int sensor, char *buf, size_t len)
   integer(c_int) function ffrf_sensor_name(c, sensor, buf, length) result(stat) &
         bind(c, name='ffrf_sensor_name')
      type(c_ptr), value :: c, buf
      integer(c_int), value :: sensor
      integer(c_size_t), value :: length
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      character(len=:), allocatable :: name
      if (.not. got_handle(c, h, stat)) return
      call h%case%sensor_name(int(sensor) + 1, name, error)
      stat = status_of(h, error)
      if (stat == 0) stat = copy_name(h, 'ffrf_sensor_name', name, buf, length)
   end function ffrf_sensor_name

   !> int ffrf_sensor_values(const ffrf_case *c, int sensor, double *values, int capacity,
   !> int *count)
   integer(c_int) function ffrf_sensor_values(c, sensor, values, capacity, count) result(stat) &
         bind(c, name='ffrf_sensor_values')
      type(c_ptr), value :: c, values, count
      integer(c_int), value :: sensor, capacity
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      real(dp), allocatable :: x(:)
      integer(c_int), pointer :: out
      integer(c_size_t) :: n
      if (.not. got_handle(c, h, stat)) return
      if (.not. c_associated(count) .or. capacity < 0) then
         stat = bad_call(h, 'ffrf_sensor_values: count is NULL or capacity negative')
         return
      end if
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
   integer(c_int) function ffrf_marker_set_load(c, body, marker, force, moment) result(stat) &
         bind(c, name='ffrf_marker_set_load')
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

   ! ------------------------------------------------------------------ a case from arrays

   !> int ffrf_case_new(ffrf_case **c)
   integer(c_int) function ffrf_case_new(c) result(stat) bind(c, name='ffrf_case_new')
      type(c_ptr), value :: c
      type(c_ptr), pointer :: out
      type(capi_handle_t), pointer :: h
      if (.not. c_associated(c)) then
         stat = FFRF_BAD_CALL
         return
      end if
      call c_f_pointer(c, out)
      allocate (h)
      out = c_loc(h)
      call h%case%new()
      h%message = [c_null_char]
      stat = 0
   end function ffrf_case_new

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
      if (.not. got_handle(c, h, stat)) return
      if (.not. (c_associated(name) .and. c_associated(xyz) .and. c_associated(tets))) then
         stat = bad_call(h, 'ffrf_case_add_body: name, xyz or tets is NULL')
         return
      end if
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
      if (.not. got_handle(c, h, stat)) return
      if (.not. (c_associated(name) .and. c_associated(triangles))) then
         stat = bad_call(h, 'ffrf_case_add_surface: name or triangles is NULL')
         return
      end if
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
   integer(c_int) function ffrf_case_add_interface(c, body, surface, mpc, virtual_node, rc) &
         result(stat) bind(c, name='ffrf_case_add_interface')
      type(c_ptr), value :: c, surface, virtual_node, rc
      integer(c_int), value :: body, mpc
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      real(c_double), pointer :: position(:)
      integer(c_int), pointer :: flags(:)
      logical :: forbidden(6)
      if (.not. got_handle(c, h, stat)) return
      if (.not. c_associated(surface)) then
         stat = bad_call(h, 'ffrf_case_add_interface: surface is NULL')
         return
      end if
      forbidden = .false.
      if (c_associated(rc)) then
         call c_f_pointer(rc, flags, [6])
         forbidden = flags /= 0
      end if
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
   integer(c_int) function ffrf_case_add_interface_nodes(c, body, name, mpc, num_nodes, nodes, &
         weights, virtual_node, rc) result(stat) bind(c, name='ffrf_case_add_interface_nodes')
      type(c_ptr), value :: c, name, nodes, weights, virtual_node, rc
      integer(c_int), value :: body, mpc, num_nodes
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      integer(c_int), pointer :: node_list(:), flags(:)
      real(c_double), pointer :: w(:), position(:)
      logical :: forbidden(6)
      if (.not. got_handle(c, h, stat)) return
      if (.not. (c_associated(name) .and. c_associated(nodes))) then
         stat = bad_call(h, 'ffrf_case_add_interface_nodes: name or nodes is NULL')
         return
      end if
      if (num_nodes < 1) then
         stat = bad_call(h, 'ffrf_case_add_interface_nodes: num_nodes = ' // &
            to_str(int(num_nodes)) // '; give at least one node')
         return
      end if
      call c_f_pointer(nodes, node_list, [num_nodes])
      forbidden = .false.
      if (c_associated(rc)) then
         call c_f_pointer(rc, flags, [6])
         forbidden = flags /= 0
      end if
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

end module ffrf_capi
