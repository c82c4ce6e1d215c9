!> The C API of include/ffrf.h: bind(C) entry points over ffrf_case_t (ffrf_capi_case). A
!> handle `ffrf_case *` is the C address of a capi_handle_t (the case object and the message of
!> its last call, NUL-terminated). Every entry point checks its pointers (c_associated before
!> c_f_pointer), shifts 0-based C indices to the 1-based Fortran ones, returns the status
!> (FFRF_OK = 0, else error%code) and keeps the message in the handle; nothing stops, prints
!> or touches global state, so distinct handles may be used from distinct threads (docs/api.md
!> names the third-party solvers that are not reentrant).
!>
!> This module holds the handle type and the interfaces of the shared prologue and of the entry
!> points without a case yet; their bodies are in the submodule capi_handle.f90 (the entry
!> prologue, status, copies; open, new, run, last error, close). The entry points on a case
!> (body data, mechanism, a case from arrays) are the module ffrf_capi_entries
!> (capi_entries.f90), over this one.
module ffrf_capi
   use, intrinsic :: iso_c_binding, only: c_int, c_double, c_char, c_ptr, c_size_t
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t
   use ffrf_capi_case, only: ffrf_case_t
   implicit none
   private
   public :: ffrf_version, ffrf_case_open, ffrf_case_new, ffrf_case_run, ffrf_last_error, &
      ffrf_case_close
   ! the prologue and copies the entry points of ffrf_capi_entries share
   public :: capi_handle_t, from_c, status_of, bad_call, ready, put_int, put_reals, got_handle, &
      copy_out, count_entry, name_entry, BODY_NODES, BODY_MODE_SHAPES, BODY_VIRTUAL_NODE_SHAPES

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

   end interface

end module ffrf_capi
