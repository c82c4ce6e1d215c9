!> The handle of the C API (a submodule of ffrf_capi): the entry prologue, the status and
!> message of a call, copies into C arrays and buffers; open, new, run, last error, close.
submodule (ffrf_capi) ffrf_capi_handle
   use, intrinsic :: iso_c_binding, only: c_null_char, c_associated, c_f_pointer, c_loc
   use ffrf_core_error, only: fatal_error
   use ffrf_core_strings, only: to_str
   use ffrf_core_build_info, only: FFRF_VERSION_MAJOR, FFRF_VERSION_MINOR, FFRF_VERSION_PATCH
   use ffrf_capi_case, only: FFRF_BAD_CALL
   use ffrf_core_serial_section, only: enter_serial_section, leave_serial_section, SECTION_FILES
   implicit none

   !> ffrf_last_error(NULL): a fixed, read-only text
   character(kind=c_char), target, save :: null_handle_message(33) = [character(kind=c_char) &
      :: 'f', 'f', 'r', 'f', ':', ' ', 'N', 'U', 'L', 'L', ' ', 'c', 'a', 's', 'e', ' ', 'h', &
      'a', 'n', 'd', 'l', 'e', ' ', '(', 'n', 'o', ' ', 'c', 'a', 's', 'e', ')', c_null_char]

contains

   module procedure from_c
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
   end procedure from_c

   module procedure status_of
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
   end procedure status_of

   module procedure bad_call
      type(error_t), allocatable :: error
      call fatal_error(error, FFRF_BAD_CALL, message)
      stat = status_of(h, error)
   end procedure bad_call

   !> The handle behind `c`, or null.
   function handle_of(c) result(h)
      type(c_ptr), intent(in) :: c
      type(capi_handle_t), pointer :: h
      h => null()
      if (c_associated(c)) call c_f_pointer(c, h)
   end function handle_of

   !> The prologue of ffrf_case_open and ffrf_case_new: a new handle stored in *c; false with
   !> stat = FFRF_BAD_CALL when c is NULL (no handle to keep a message in).
   logical function new_handle(c, h, stat)
      type(c_ptr), intent(in) :: c
      type(capi_handle_t), pointer, intent(out) :: h
      integer(c_int), intent(out) :: stat
      type(c_ptr), pointer :: out
      new_handle = c_associated(c)
      stat = merge(0_c_int, int(FFRF_BAD_CALL, c_int), new_handle)
      if (.not. new_handle) return
      call c_f_pointer(c, out)
      allocate (h)
      out = c_loc(h)
   end function new_handle

   module procedure ready
      ready = got_handle(c, h, stat)
      if (.not. ready .or. all(required)) return
      stat = bad_call(h, message)
      ready = .false.
   end procedure ready

   module procedure put_int
      integer(c_int), pointer :: p
      if (.not. c_associated(pointer)) return
      call c_f_pointer(pointer, p)
      p = int(value, c_int)
   end procedure put_int

   module procedure put_reals
      real(c_double), pointer :: p(:)
      if (.not. c_associated(array)) return
      call c_f_pointer(array, p, [size(values)])
      p = values
   end procedure put_reals

   module procedure got_handle
      h => handle_of(c)
      got_handle = associated(h)
      stat = merge(0_c_int, int(FFRF_BAD_CALL, c_int), got_handle)
   end procedure got_handle

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

   module procedure copy_out
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
   end procedure copy_out

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

   module procedure count_entry
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      integer :: count
      if (.not. got_handle(c, h, stat)) return
      select case (which)
      case ('ffrf_body_count')
         call h%case%body_count(count, error)
      case ('ffrf_marker_count')
         call h%case%marker_count(int(index) + 1, count, error)
      case ('ffrf_joint_count')
         call h%case%joint_count(count, error)
      case default
         call h%case%sensor_count(count, error)
      end select
      stat = put_count(h, which, count, error, n)
   end procedure count_entry

   module procedure name_entry
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      character(len=:), allocatable :: name
      if (.not. got_handle(c, h, stat)) return
      select case (which)
      case ('ffrf_body_name')
         call h%case%body_name(int(index) + 1, name, error)
      case ('ffrf_joint_name')
         call h%case%joint_name(int(index) + 1, name, error)
      case default
         call h%case%sensor_name(int(index) + 1, name, error)
      end select
      stat = status_of(h, error)
      if (stat == 0) stat = copy_name(h, which, name, buf, length)
   end procedure name_entry

   module procedure ffrf_version
      call put_int(major, FFRF_VERSION_MAJOR)
      call put_int(minor, FFRF_VERSION_MINOR)
      call put_int(patch, FFRF_VERSION_PATCH)
   end procedure ffrf_version

   module procedure ffrf_case_open
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      if (.not. new_handle(c, h, stat)) return
      if (.not. c_associated(case_file)) then
         stat = bad_call(h, 'ffrf_case_open: case_file is NULL')
         return
      end if
      ! one open at a time in the process, the C strings' copies included: under load, ctest
      ! capi_threads saw a case path arrive cut to the length of another thread's path (1 run
      ! in about 20; the cause inside the copy or its temporaries was not found)
      call enter_serial_section(SECTION_FILES)
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
      call leave_serial_section(SECTION_FILES)
      stat = status_of(h, error)
   end procedure ffrf_case_open

   module procedure ffrf_case_new
      type(capi_handle_t), pointer :: h
      if (.not. new_handle(c, h, stat)) return
      call h%case%new()
      h%message = [c_null_char]
   end procedure ffrf_case_new

   module procedure ffrf_case_run
      type(capi_handle_t), pointer :: h
      type(error_t), allocatable :: error
      if (.not. got_handle(c, h, stat)) return
      call h%case%run(error)
      stat = status_of(h, error)
   end procedure ffrf_case_run

   module procedure ffrf_last_error
      type(capi_handle_t), pointer :: h
      h => handle_of(c)
      if (.not. associated(h)) then
         message = c_loc(null_handle_message)
         return
      end if
      if (.not. allocated(h%message)) h%message = [c_null_char]
      message = c_loc(h%message)
   end procedure ffrf_last_error

   module procedure ffrf_case_close
      type(capi_handle_t), pointer :: h
      h => handle_of(c)
      if (.not. associated(h)) return
      call h%case%close()
      deallocate (h)
   end procedure ffrf_case_close

end submodule ffrf_capi_handle
