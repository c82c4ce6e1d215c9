!> Checks shared by the Fortran API test programs (test_pose_fortran, test_export_fortran).
module api_checks
   use ffrf, only: error_t
   implicit none
   private
   public :: expect

contains

   !> The last call gave code `code` (0: no error) with `fragment` in its message; a miss is
   !> printed and counted in `failures`.
   subroutine expect(error, failures, code, fragment)
      type(error_t), allocatable, intent(in) :: error
      integer, intent(inout) :: failures
      integer, intent(in) :: code
      character(len=*), intent(in) :: fragment
      if (code == 0) then
         if (allocated(error)) then
            print '(a)', 'FAIL: unexpected error: ' // error%message
            failures = failures + 1
         end if
      else if (.not. allocated(error)) then
         print '(a, i0)', 'FAIL: no error; expected code ', code
         failures = failures + 1
      else if (error%code /= code .or. index(error%message, fragment) == 0) then
         print '(a, i0, a)', 'FAIL: code ', error%code, ', message "' // error%message // &
            '"; expected "' // fragment // '"'
         failures = failures + 1
      end if
   end subroutine expect
end module api_checks
