!> `use ffrf_c` (the C API's interfaces for Fortran callers): version, a missing case file
!> (FFRF_FILE_ERROR with its message), a call on the failed handle (FFRF_BAD_CALL), close; an
!> interface on a node set of a body that does not exist (FFRF_BAD_CALL with its message).
program test_ffrf_c
   use, intrinsic :: iso_c_binding
   use ffrf_c
   implicit none
   integer(c_int) :: major, minor, patch, stat, n
   type(c_ptr) :: c
   character(kind=c_char), target :: file(64)
   character(len=*), parameter :: name = 'no/such.nml'
   integer :: i
   call ffrf_version(major, minor, patch)
   do i = 1, len(name)
      file(i) = name(i:i)
   end do
   file(len(name) + 1) = c_null_char
   stat = ffrf_case_open(c_loc(file), c_null_ptr, c_null_ptr, c)
   print '(i0, ".", i0, ".", i0, " status ", i0, ": ", a)', major, minor, patch, stat, &
      ffrf_c_string(ffrf_last_error(c))
   if (stat /= FFRF_FILE_ERROR .or. index(ffrf_c_string(ffrf_last_error(c)), &
      'does not exist') == 0) error stop 1
   stat = ffrf_body_count(c, n)
   print '(a, i0, a)', 'body_count status ', stat, ': ' // ffrf_c_string(ffrf_last_error(c))
   if (stat /= FFRF_BAD_CALL .or. index(ffrf_c_string(ffrf_last_error(c)), &
      'the case is not open') == 0) error stop 1
   call ffrf_case_close(c)
   stat = ffrf_case_new(c)
   if (stat /= FFRF_OK) error stop 1
   stat = ffrf_case_add_interface_nodes(c, 0_c_int, 'set' // c_null_char, FFRF_RBE3, 3_c_int, &
      [0_c_int, 1_c_int, 2_c_int], c_null_ptr, c_null_ptr, c_null_ptr)
   print '(a, i0, a)', 'add_interface_nodes status ', stat, ': ' // &
      ffrf_c_string(ffrf_last_error(c))
   if (stat /= FFRF_BAD_CALL .or. index(ffrf_c_string(ffrf_last_error(c)), &
      'body 0 does not exist') == 0) error stop 1
   call ffrf_case_close(c)
   if (major < 0 .or. minor < 0 .or. patch < 0) error stop 1
end program test_ffrf_c
