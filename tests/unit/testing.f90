!> Minimal unit-test harness: a test is a subroutine with `error` out; a suite is a list of
!> named tests run by `run_suite`, which prints one line per test and a closing count.
module ffrf_testing
   use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   implicit none
   private
   public :: unittest_t, new_unittest, run_suite, check_close, check, test_input_dir, test_mesh_dir
   public :: report, test_data_dir

   abstract interface
      subroutine test_procedure(error)
         import :: error_t
         type(error_t), allocatable, intent(out) :: error
      end subroutine test_procedure
   end interface

   !> One named test.
   type :: unittest_t
      character(len=:), allocatable :: name
      procedure(test_procedure), pointer, nopass :: run => null()
   end type unittest_t

contains

   function new_unittest(name, run) result(test)
      character(len=*), intent(in) :: name
      procedure(test_procedure) :: run
      type(unittest_t) :: test
      test%name = name
      test%run => run
   end function new_unittest

   !> Run every test of `tests` (or only the one named on the command line); exit code 1 if any
   !> failed. Closing line: "N passed, N failed".
   subroutine run_suite(suite_name, tests)
      character(len=*), intent(in) :: suite_name
      type(unittest_t), intent(in) :: tests(:)
      type(error_t), allocatable :: error
      character(len=256) :: only
      integer :: i, passed, failed
      only = ''
      if (command_argument_count() > 0) call get_command_argument(1, only)
      passed = 0
      failed = 0
      do i = 1, size(tests)
         if (len_trim(only) > 0 .and. trim(only) /= tests(i)%name) cycle
         call tests(i)%run(error)
         if (allocated(error)) then
            failed = failed + 1
            write (output_unit, '(a)') '  FAIL ' // suite_name // '/' // tests(i)%name // ': ' // &
               error%message
            deallocate (error)
         else
            passed = passed + 1
            write (output_unit, '(a)') '  ok   ' // suite_name // '/' // tests(i)%name
         end if
         flush (output_unit)
      end do
      write (output_unit, '(a)') suite_name // ': ' // to_str(passed) // ' passed, ' // &
         to_str(failed) // ' failed'
      if (failed > 0 .or. passed == 0) error stop 1
   end subroutine run_suite

   !> Passes if |actual - expected| <= max(atol, rtol*|expected|); NaN and Inf fail.
   subroutine check_close(error, what, actual, expected, rtol, atol)
      type(error_t), allocatable, intent(out) :: error
      character(len=*), intent(in) :: what
      real(dp), intent(in) :: actual, expected
      real(dp), intent(in), optional :: rtol, atol
      real(dp) :: tol
      tol = 0.0_dp
      if (present(rtol)) tol = max(tol, rtol * abs(expected))
      if (present(atol)) tol = max(tol, atol)
      if (audit()) write (output_unit, '(a)') '       audit: ' // what // ' | measured ' // &
         to_str(abs(actual - expected), 3) // ' | tolerance ' // to_str(tol, 3) // &
         ' | expected ' // to_str(expected, 3)
      if (.not. ieee_is_finite(actual) .or. abs(actual - expected) > tol) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, what // ' = ' // to_str(actual, 12) // &
            ', expected ' // to_str(expected, 12) // ' within ' // to_str(tol, 3))
      end if
   end subroutine check_close

   !> FFRF_TEST_AUDIT set and not empty: check_close prints every measured difference beside its
   !> tolerance (the tolerance audit of tests/TOLERANCES.md).
   logical function audit()
      integer :: length
      call get_environment_variable('FFRF_TEST_AUDIT', length=length)
      audit = length > 0
   end function audit

   !> Passes if `condition` holds.
   subroutine check(error, what, condition)
      type(error_t), allocatable, intent(out) :: error
      character(len=*), intent(in) :: what
      logical, intent(in) :: condition
      if (.not. condition) call fatal_error(error, FFRF_NUMERIC_ERROR, what)
   end subroutine check

   !> A measured figure the test reports without asserting (convergence rates, sizes).
   subroutine report(text)
      character(len=*), intent(in) :: text
      write (output_unit, '(a)') '       ' // text
   end subroutine report

   !> input/ of the source tree (ctest sets FFRF_INPUT_DIR).
   function test_input_dir() result(dir)
      character(len=:), allocatable :: dir
      dir = env_or('FFRF_INPUT_DIR', 'input')
   end function test_input_dir

   !> Folder of the meshes gmsh builds as ctest fixtures (ctest sets FFRF_MESH_DIR).
   function test_mesh_dir() result(dir)
      character(len=:), allocatable :: dir
      dir = env_or('FFRF_MESH_DIR', 'meshes')
   end function test_mesh_dir

   !> The hand-written test data (tests/data): $FFRF_TEST_DATA_DIR, else relative to the build.
   function test_data_dir() result(dir)
      character(len=:), allocatable :: dir
      dir = env_or('FFRF_TEST_DATA_DIR', 'tests/data')
   end function test_data_dir

   function env_or(name, default) result(value)
      character(len=*), intent(in) :: name, default
      character(len=:), allocatable :: value
      integer :: length, stat
      call get_environment_variable(name, length=length, status=stat)
      if (stat /= 0 .or. length == 0) then
         value = default
         return
      end if
      allocate (character(len=length) :: value)
      call get_environment_variable(name, value)
   end function env_or

end module ffrf_testing
