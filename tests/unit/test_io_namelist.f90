!> Tests of the strict case reading (ffrf_input_nml_source, ffrf_input_case): the resolved input
!> echo of every case in input/ is bitwise the one the solver wrote before the strict reader (the
!> reference files in tests/data/input_echo were written by case_echo of the previous reader;
!> since issue 23 a flexible body's num_modes = -1, "not given", is left out so that the echo
!> reads back), so no value of a valid case changes; lines of any length; quotes and repeat counts handed to the
!> namelist read unchanged; FILE:LINE of a key for the readers' cross checks; the structural
!> errors named by line.
module test_io_namelist
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_input_nml_source, only: nml_source_t
   use ffrf_input_case, only: case_input_t, read_case, case_echo, case_groups
   use ffrf_testing, only: unittest_t, new_unittest, check, test_input_dir
   implicit none
   private
   public :: collect_io_namelist

contains

   subroutine collect_io_namelist(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [ &
         new_unittest('echo_of_inputs_unchanged', test_echo_unchanged), &
         new_unittest('sensor_echo_reads_back', test_sensor_echo), &
         new_unittest('pose_keys_read_and_echoed', test_pose_echo), &
         new_unittest('long_line', test_long_line), &
         new_unittest('quotes_and_repeat_counts', test_quotes_and_repeats), &
         new_unittest('key_location', test_key_location), &
         new_unittest('structure_errors', test_structure_errors)]
   end subroutine collect_io_namelist

   !> case_echo of every case in input/ equals the echo of the reader before this work.
   subroutine test_echo_unchanged(error)
      type(error_t), allocatable, intent(out) :: error
      character(len=*), parameter :: names(12) = [character(len=20) :: 'conrod', 'crank_rc1', &
         'crank_rc1_rbe2', 'crank_rc2', 'crank_rc2_rbe2', 'crank_rc3', 'crank_rc3_rbe2', &
         'engine_rc1', 'engine_rc1_manual', 'engine_rc2', 'engine_rc3', 'engine_rigid']
      type(case_input_t) :: case
      character(len=:), allocatable :: echo, reference
      integer :: k, i
      do k = 1, size(names)
         call read_case(test_input_dir() // '/' // trim(names(k)) // '.nml', case, error)
         if (allocated(error)) return
         echo = case_echo(case)
         call read_whole(data_dir() // '/input_echo/' // trim(names(k)) // '.txt', reference, &
            error)
         if (allocated(error)) return
         if (echo /= reference .or. len(echo) /= len(reference)) then
            do i = 1, min(len(echo), len(reference))
               if (echo(i:i) /= reference(i:i)) exit
            end do
            call fatal_error(error, FFRF_INPUT_ERROR, trim(names(k)) // ': echo differs at ' // &
               'character ' // str(i) // ': "' // echo(max(1, i - 20):min(len(echo), i + 20)) // &
               '" against "' // reference(max(1, i - 20):min(len(reference), i + 20)) // '"')
            return
         end if
      end do
   end subroutine test_echo_unchanged

   !> The &sensor groups are in the echo, one line each with the keys their type needs, and the
   !> echo reads back to the same echo (tests/data/sensors/slider_wheel.nml, 11 sensors); a
   !> mechanism without a crank has no crank keys in its &mechanism line.
   subroutine test_sensor_echo(error)
      type(error_t), allocatable, intent(out) :: error
      type(case_input_t) :: case, again
      character(len=:), allocatable :: echo, file_name
      integer :: unit, stat
      file_name = own_file('sensor_echo.nml')
      call read_case(data_dir() // '/sensors/slider_wheel.nml', case, error)
      if (allocated(error)) return
      call check(error, '11 sensors read', size(case%mechanism%sensors) == 11)
      if (allocated(error)) return
      echo = case_echo(case)
      call check(error, 'a joint sensor echoed', index(echo, '&sensor name = ''bearing_angle''' &
         // ', type = ''joint_coordinate'', joint = ''bearing'' /') > 0)
      if (allocated(error)) return
      call check(error, 'a marker sensor echoed', index(echo, '&sensor name = ' // &
         '''slider_position'', type = ''position'', body = ''slider'', marker = ''S'' /') > 0)
      if (allocated(error)) return
      call check(error, 'no crank key in a crank-less echo', index(echo, 'crank') == 0)
      if (allocated(error)) return
      open (newunit=unit, file=file_name, status='replace', action='write', iostat=stat)
      if (stat == 0) write (unit, '(a)', iostat=stat) echo
      if (stat == 0) close (unit, iostat=stat)
      call check(error, 'echo written to ' // file_name, stat == 0)
      if (allocated(error)) return
      call read_case(file_name, again, error)
      if (allocated(error)) return
      call check(error, 'the echo reads back to the same echo', case_echo(again) == echo)
   end subroutine test_sensor_echo

   !> &body orientation is the rotation matrix by rows (its columns the body axes): a 90 degree
   !> turn about z given as rows 0 -1 0 / 1 0 0 / 0 0 1 has A(1, 2) = -1 and body x = global y;
   !> velocity and angular_velocity are read as given; the echo has the three keys and reads
   !> back to the same values bitwise (17 digits), and a body without them has none in its echo.
   subroutine test_pose_echo(error)
      type(error_t), allocatable, intent(out) :: error
      type(case_input_t) :: case, again
      character(len=:), allocatable :: echo, file_name, again_name
      character(len=*), parameter :: nl = new_line('a'), rest = &
         '&marker body = ''arm'', name = ''hinge'', position = 0, 0, 0 /' // nl // &
         '&marker body = ''ground'', name = ''hinge'', position = 0, 0, 0 /' // nl // &
         '&joint name = ''pivot'', type = ''revolute'', body1 = ''ground'', marker1 = ' // &
         '''hinge'', body2 = ''arm'', marker2 = ''hinge'' /' // nl
      character(len=*), parameter :: arm = '&body name = ''arm'', type = ''rigid'', ' // &
         'mass = 1.0, inertia = 0.01, 0.01, 0.01, 0, 0, 0'
      file_name = own_file('pose.nml')
      again_name = own_file('pose_again.nml')
      call write_text(file_name, arm // ', orientation = 0, -1, 0, 1, 0, 0, 0, 0, 1, ' // &
         'velocity = 0.1, 0.2, 0.3, angular_velocity = 0, 0, 2.5 /' // nl // rest, error)
      if (.not. allocated(error)) call read_case(file_name, case, error)
      if (allocated(error)) return
      associate (m => case%motions(1))
         call check(error, 'orientation by rows: A(1, 2) = -1, A(2, 1) = 1, body x = global y', &
            all(m%orientation == reshape([0.0_dp, 1.0_dp, 0.0_dp, -1.0_dp, 0.0_dp, 0.0_dp, &
            0.0_dp, 0.0_dp, 1.0_dp], [3, 3])))
         if (allocated(error)) return
         call check(error, 'velocity and angular_velocity read', &
            all(m%velocity == [0.1_dp, 0.2_dp, 0.3_dp]) .and. &
            all(m%angular_velocity == [0.0_dp, 0.0_dp, 2.5_dp]))
         if (allocated(error)) return
      end associate
      echo = case_echo(case)
      call check(error, 'the pose keys are echoed', index(echo, ', orientation = ') > 0 .and. &
         index(echo, ', velocity = ') > 0 .and. index(echo, ', angular_velocity = ') > 0)
      if (.not. allocated(error)) call write_text(again_name, echo, error)
      if (.not. allocated(error)) call read_case(again_name, again, error)
      if (allocated(error)) return
      call check(error, 'the echo reads back to the same pose', &
         all(again%motions(1)%orientation == case%motions(1)%orientation) .and. &
         all(again%motions(1)%velocity == case%motions(1)%velocity) .and. &
         all(again%motions(1)%angular_velocity == case%motions(1)%angular_velocity))
      if (allocated(error)) return
      call write_text(file_name, arm // ' /' // nl // rest, error)
      if (.not. allocated(error)) call read_case(file_name, case, error)
      if (allocated(error)) return
      echo = case_echo(case)
      call check(error, 'no pose key in the echo of a body without them', &
         index(echo, 'orientation') == 0 .and. index(echo, 'velocity') == 0)
   end subroutine test_pose_echo

   !> A scratch file of this test program in the working folder: its name starts with the
   !> program's own name, so that the plain and the _checked builds, run in parallel from the
   !> same folder, never write the same file.
   function own_file(suffix) result(name)
      character(len=*), intent(in) :: suffix
      character(len=:), allocatable :: name
      character(len=4096) :: program
      integer :: slash
      call get_command_argument(0, program)
      slash = index(program, '/', back=.true.)
      name = trim(program(slash + 1:)) // '_' // suffix
   end function own_file

   !> Write `text` to a new file.
   subroutine write_text(file_name, text, error)
      character(len=*), intent(in) :: file_name, text
      type(error_t), allocatable, intent(out) :: error
      integer :: unit, stat
      open (newunit=unit, file=file_name, status='replace', action='write', iostat=stat)
      if (stat == 0) write (unit, '(a)', iostat=stat) text
      if (stat == 0) close (unit, iostat=stat)
      call check(error, 'written: ' // file_name, stat == 0)
   end subroutine write_text

   !> A 5000-character line is read whole: the key after column 4000 arrives.
   subroutine test_long_line(error)
      type(error_t), allocatable, intent(out) :: error
      type(nml_source_t) :: src
      call src%parse('t.nml', '&modes' // repeat(' ', 4000) // 'num_modes = 7 /' // &
         new_line('a'), case_groups(), error)
      if (allocated(error)) return
      call check(error, 'num_modes after column 4000 is found', &
         src%has_key('modes', 1, 'num_modes'))
      if (allocated(error)) return
      call check(error, 'where: ' // src%where('modes', 1, 'num_modes'), &
         src%where('modes', 1, 'num_modes') == 't.nml:1: &modes num_modes = 7')
   end subroutine test_long_line

   !> Doubled quotes stay doubled, "..." strings are re-quoted with ', r*value is expanded.
   subroutine test_quotes_and_repeats(error)
      type(error_t), allocatable, intent(out) :: error
      type(nml_source_t) :: src
      character(len=:), allocatable :: text
      integer :: unit
      character(len=200) :: line
      character(len=*), parameter :: expected(5) = [character(len=60) :: '&run', &
         'title = ''it''''s "x"''', '/', '&marker', 'position = 0.5, 0.5, 0.5']
      integer :: k
      text = '&run title = "it''s ""x""" /' // new_line('a') // &
         '&marker position = 3*0.5 /' // new_line('a')
      call src%parse('t.nml', text, case_groups(), error)
      if (allocated(error)) return
      open (newunit=unit, status='scratch', action='readwrite', form='formatted')
      call src%write_namelist(unit, error)
      if (allocated(error)) return
      do k = 1, size(expected)
         read (unit, '(a)') line
         if (trim(line) /= trim(expected(k))) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'canonical line ' // str(k) // ': "' // &
               trim(line) // '", expected "' // trim(expected(k)) // '"')
            exit
         end if
      end do
      close (unit)
   end subroutine test_quotes_and_repeats

   !> where() names file, line, group, key and value; a missing key names the group's line.
   subroutine test_key_location(error)
      type(error_t), allocatable, intent(out) :: error
      type(nml_source_t) :: src
      character(len=*), parameter :: nl = new_line('a')
      call src%parse('c.nml', '! comment' // nl // '&body name = ''a'' /' // nl // nl // &
         '&body name = ''b'',' // nl // '   young = 1.0e9 /' // nl, case_groups(), error)
      if (allocated(error)) return
      call check(error, 'where(young): ' // src%where('body', 2, 'young'), &
         src%where('body', 2, 'young') == 'c.nml:5: &body young = 1.0e9')
      if (allocated(error)) return
      call check(error, 'where(absent): ' // src%where('body', 1, 'young'), &
         src%where('body', 1, 'young') == 'c.nml:2: &body #1 (young not given)')
      if (allocated(error)) return
      call check(error, 'group counts', src%count('body') == 2 .and. src%count('joint') == 0)
   end subroutine test_key_location

   !> Structural errors name the right line, in our words.
   subroutine test_structure_errors(error)
      type(error_t), allocatable, intent(out) :: error
      character(len=*), parameter :: nl = new_line('a')
      call expect('&modes num_modes = 4' // nl // '&run /' // nl, &
         'e.nml:1: &modes: not closed by ''/'' before the next group on line 2')
      if (allocated(error)) return
      call expect('&run /' // nl // '&run /' // nl, 'e.nml:2: &run: a second &run group')
      if (allocated(error)) return
      call expect(nl // '&run / &run /' // nl, 'e.nml:2: &run: text after the closing ''/''')
      if (allocated(error)) return
      call expect('&run title = ''a'', title = ''b'' /' // nl, &
         'e.nml:1: &run title = ''b'': given twice')
      if (allocated(error)) return
      call expect('&run title = ''abc /' // nl, 'e.nml:1: &run title = ''abc /: the string ' // &
         'is not closed')
      if (allocated(error)) return
      call expect('&modes tolerance = 1d-1 /' // nl, 'e.nml:1: &modes tolerance = 1d-1: out of ' &
         // 'range; give a finite real in [0, 0.01)')
      if (allocated(error)) return
      call expect('&body geometric_stiffness = yes /' // nl, &
         'e.nml:1: &body geometric_stiffness = yes: not a logical')
      if (allocated(error)) return
      call expect('&run title = ''a&body'' /' // nl, 'e.nml:1: &run title = ''a&body'': holds &')
      if (allocated(error)) return
      call expect('&run title = ''a' // achar(7) // ''' /' // nl, &
         'e.nml:1: &run title = ''a?: a control character (code 7)')
   contains
      subroutine expect(text, start)
         character(len=*), intent(in) :: text, start
         type(nml_source_t) :: src
         type(error_t), allocatable :: parse_error
         call src%parse('e.nml', text, case_groups(), parse_error)
         if (.not. allocated(parse_error)) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'no error for "' // text // '"')
         else if (index(parse_error%message, start) /= 1) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'message "' // parse_error%message // &
               '" does not start with "' // start // '"')
         end if
      end subroutine expect
   end subroutine test_structure_errors

   subroutine read_whole(file_name, text, error)
      character(len=*), intent(in) :: file_name
      character(len=:), allocatable, intent(out) :: text
      type(error_t), allocatable, intent(out) :: error
      integer :: unit, stat, size_bytes
      open (newunit=unit, file=file_name, access='stream', form='unformatted', status='old', &
         action='read', iostat=stat)
      if (stat /= 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'cannot open ' // file_name)
         return
      end if
      inquire (unit=unit, size=size_bytes)
      allocate (character(len=size_bytes) :: text)
      read (unit) text
      close (unit)
   end subroutine read_whole

   function data_dir() result(dir)
      character(len=:), allocatable :: dir
      integer :: length, stat
      call get_environment_variable('FFRF_TEST_DATA_DIR', length=length, status=stat)
      if (stat /= 0 .or. length == 0) then
         dir = 'tests/data'
         return
      end if
      allocate (character(len=length) :: dir)
      call get_environment_variable('FFRF_TEST_DATA_DIR', dir)
   end function data_dir

   pure function str(n) result(text)
      integer, intent(in) :: n
      character(len=:), allocatable :: text
      character(len=16) :: buffer
      write (buffer, '(i0)') n
      text = trim(buffer)
   end function str

end module test_io_namelist

program main_io_namelist
   use ffrf_testing, only: unittest_t, run_suite
   use test_io_namelist, only: collect_io_namelist
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_io_namelist(tests)
   call run_suite('test_io_namelist', tests)
end program main_io_namelist
