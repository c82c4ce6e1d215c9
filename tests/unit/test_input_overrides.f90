!> Tests of the batch command line's input layer (ffrf_input_overrides, ffrf_input_sweep): the
!> override syntax GROUP.KEY=VALUE / GROUP[NAME].KEY=VALUE, its injection into the checked case
!> text (the value read is the one a case file with that value gives, a bad value gets the
!> namelist's own message after the override's origin), sweep table rows, output templates and
!> the task index. Reads no mesh; well under a second.
module test_input_overrides
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR, FFRF_IO_ERROR
   use ffrf_input_nml_source, only: nml_source_t
   use ffrf_input_case, only: case_groups
   use ffrf_input_overrides, only: override_t, parse_override, apply_overrides, overrides_echo
   use ffrf_input_sweep, only: job_task_index, expand_output_name, read_sweep_row, &
      batch_overrides, NO_TASK
   use ffrf_testing, only: unittest_t, new_unittest, check
   implicit none
   private
   public :: collect_input_overrides

   character(len=*), parameter :: NL = new_line('a')
   !> A case text: two interfaces of one body, &modes
   character(len=*), parameter :: CASE_TEXT = &
      '&body name = ''crank'', mesh_file = ''c.msh'' /' // NL // &
      '&interface body = ''crank'', name = ''B1'', rc = ''Tx'' /' // NL // &
      '&interface body = ''crank'', name = ''B2'', rc = ''Tx Ty'' /' // NL // &
      '&modes num_modes = 8 /' // NL

contains

   subroutine collect_input_overrides(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [ &
         new_unittest('override_syntax', test_override_syntax), &
         new_unittest('set_equals_text', test_set_equals_text), &
         new_unittest('set_errors', test_set_errors), &
         new_unittest('namelist_messages', test_namelist_messages), &
         new_unittest('output_template', test_output_template), &
         new_unittest('sweep_rows', test_sweep_rows), &
         new_unittest('sweep_errors', test_sweep_errors), &
         new_unittest('batch_order', test_batch_order)]
   end subroutine collect_input_overrides

   !> GROUP.KEY=VALUE and GROUP[NAME].KEY=VALUE split as written; malformed keys refused.
   subroutine test_override_syntax(error)
      type(error_t), allocatable, intent(out) :: error
      type(override_t) :: ov
      call parse_override('modes.num_modes=12', ov, error)
      if (allocated(error)) return
      call check(error, 'single group', ov%group == 'modes' .and. ov%name == '' .and. &
         ov%key == 'num_modes' .and. ov%value == '12' .and. ov%origin == '--set modes.num_modes')
      if (allocated(error)) return
      call parse_override('body[crank].mesh_file=meshes/crank_lc4.msh', ov, error)
      if (allocated(error)) return
      call check(error, 'named group, value with "/" and "."', ov%group == 'body' .and. &
         ov%name == 'crank' .and. ov%key == 'mesh_file' .and. &
         ov%value == 'meshes/crank_lc4.msh' .and. ov%origin == '--set body[crank].mesh_file')
      if (allocated(error)) return
      call parse_override('interface[B2].rc=Tx Ty=z', ov, error)
      if (allocated(error)) return
      call check(error, 'the first "=" ends the key', ov%value == 'Tx Ty=z')
      if (allocated(error)) return
      call expect_error('modes.num_modes', '--set modes.num_modes: no "="')
      if (allocated(error)) return
      call expect_error('num_modes=3', '--set num_modes=3: not GROUP.KEY or GROUP[NAME].KEY')
      if (allocated(error)) return
      call expect_error('interface[].rc=Tx', '--set interface[].rc=Tx: not GROUP.KEY')
      if (allocated(error)) return
      call expect_error('interface[B2]rc=Tx', '--set interface[B2]rc=Tx: not GROUP.KEY')
      if (allocated(error)) return
      call expect_error('modes.2x=1', '--set modes.2x=1: not GROUP.KEY')
   contains
      subroutine expect_error(text, start)
         character(len=*), intent(in) :: text, start
         type(error_t), allocatable :: got
         call parse_override(text, ov, got)
         call expect_message(got, text, start, error)
      end subroutine expect_error
   end subroutine test_override_syntax

   !> The canonical text after the overrides is the one of a case file written with their
   !> values: a single group, a named repeatable group (bare and quoted strings), a single group
   !> the text leaves out (made), a later override winning over an earlier one.
   subroutine test_set_equals_text(error)
      type(error_t), allocatable, intent(out) :: error
      type(nml_source_t) :: src
      character(len=*), parameter :: edited = &
         '&body name = ''crank'', mesh_file = ''c.msh'' /' // NL // &
         '&interface body = ''crank'', name = ''B1'', rc = ''Tx'' /' // NL // &
         '&interface body = ''crank'', name = ''B2'', rc = ''Tx Ty Tz'' /' // NL // &
         '&modes num_modes = 4 /' // NL // &
         '&run title = ''it''''s'' /' // NL
      call src%parse('c.nml', CASE_TEXT, case_groups(), error)
      if (allocated(error)) return
      call apply_overrides(src, [set('modes.num_modes=6'), set('interface[B2].rc=Tx Ty Tz'), &
         set('run.title=''it''''s'''), set('modes.num_modes=4')], error)
      if (allocated(error)) return
      call check(error, 'canonical text: ' // canonical(src) // ' against ' // &
         canonical_of(edited), canonical(src) == canonical_of(edited))
      if (allocated(error)) return
      call check(error, 'where names the override: ' // src%where('interface', 2, 'rc'), &
         src%where('interface', 2, 'rc') == '--set interface[B2].rc = Tx Ty Tz')
      if (allocated(error)) return
      call check(error, 'at names the override: ' // src%at('modes', 1, 'num_modes'), &
         src%at('modes', 1, 'num_modes') == '--set modes.num_modes')
      if (allocated(error)) return
      call check(error, 'a key not overridden keeps its line: ' // &
         src%where('interface', 1, 'rc'), src%where('interface', 1, 'rc') == &
         'c.nml:2: &interface rc = ''Tx''')
      if (allocated(error)) return
      call check(error, 'echo lines: ' // overrides_echo([set('modes.num_modes=4')]), &
         overrides_echo([set('modes.num_modes=4')]) == '! --set modes.num_modes = 4' // NL)
   contains
      function canonical_of(text) result(out)
         character(len=*), intent(in) :: text
         character(len=:), allocatable :: out
         type(nml_source_t) :: other
         call other%parse('e.nml', text, case_groups(), error)
         out = canonical(other)
      end function canonical_of
   end subroutine test_set_equals_text

   !> Unknown group or key, a name not found, a repeatable group without a name, a single
   !> group with one: input errors naming the override and what is allowed.
   subroutine test_set_errors(error)
      type(error_t), allocatable, intent(out) :: error
      call expect_set_error('interface[B9].rc=Tx', '--set interface[B9].rc: no &interface ' // &
         'named "B9" in c.nml (names: B1, B2)', error)
      if (allocated(error)) return
      call expect_set_error('modes.num_modez=3', '--set modes.num_modez: unknown key ' // &
         'num_modez of &modes; the keys of &modes are num_modes, ', error)
      if (allocated(error)) return
      call expect_set_error('mode.num_modes=3', '--set mode.num_modes: unknown namelist ' // &
         'group &mode; groups are &run, &body', error)
      if (allocated(error)) return
      call expect_set_error('interface.rc=Tx', '--set interface.rc: &interface is a ' // &
         'repeatable group; choose one by its name, interface[NAME].rc=VALUE (names: B1, B2)', &
         error)
      if (allocated(error)) return
      call expect_set_error('modes[x].num_modes=3', '--set modes[x].num_modes: &modes is ' // &
         'a single group', error)
      if (allocated(error)) return
      call expect_set_error('marker[m].position=0, 0, 0', '--set marker[m].position: no ' // &
         '&marker named "m" in c.nml (names: none)', error)
      if (allocated(error)) return
      call expect_set_error('modes.num_modes=4 5', '--set modes.num_modes = 4, 5: 2 value(s) ' &
         // 'given, num_modes takes exactly 1', error)
   end subroutine test_set_errors

   !> A bad value set by an override gets the message a case file with it gets, the override's
   !> origin in place of FILE:LINE: &group.
   subroutine test_namelist_messages(error)
      type(error_t), allocatable, intent(out) :: error
      call same('modes', 'num_modes', 'four', 'four', error)
      if (allocated(error)) return
      call same('modes', 'num_modes', '0', '0', error)
      if (allocated(error)) return
      call same('modes', 'tolerance', '1d-1', '1d-1', error)
      if (allocated(error)) return
      call same('modes', 'formulation', 'lagrange', '''lagrange''', error)
      if (allocated(error)) return
      call same('body', 'young', 'steel', 'steel', error)
      if (allocated(error)) return
      call same('run', 'title', 'a&body', '''a&body''', error)
   contains
      !> group.key=value (command line) against key = file_value in the group (case file)
      subroutine same(group, key, value, file_value, error)
         character(len=*), intent(in) :: group, key, value, file_value
         type(error_t), allocatable, intent(out) :: error
         type(nml_source_t) :: src
         type(error_t), allocatable :: from_file, from_set
         character(len=:), allocatable :: text, selector, file_head, set_head
         selector = group
         if (group == 'body') selector = 'body[crank]'
         if (group == 'body') then
            text = '&body name = ''crank'', ' // key // ' = ' // file_value // ' /' // NL
         else
            text = CASE_TEXT // '&' // group // ' ' // key // ' = ' // file_value // ' /' // NL
            if (group == 'modes') text = CASE_TEXT(:index(CASE_TEXT, '&modes') - 1) // &
               '&modes ' // key // ' = ' // file_value // ' /' // NL
         end if
         call src%parse('c.nml', text, case_groups(), from_file)
         if (.not. allocated(from_file)) then
            call fatal_error(error, FFRF_INPUT_ERROR, text // ': accepted')
            return
         end if
         call src%parse('c.nml', CASE_TEXT, case_groups(), error)
         if (allocated(error)) return
         call apply_overrides(src, [set(selector // '.' // key // '=' // value)], from_set)
         if (.not. allocated(from_set)) then
            call fatal_error(error, FFRF_INPUT_ERROR, selector // '.' // key // '=' // value // &
               ': accepted')
            return
         end if
         file_head = '&' // group // ' ' // key // ' = ' // file_value // ': '
         set_head = '--set ' // selector // '.' // key // ' = ' // value // ': '
         call check(error, 'same message: "' // from_set%message // '" and "' // &
            from_file%message // '"', index(from_set%message, set_head) == 1 .and. &
            index(from_file%message, file_head) > 0 .and. &
            from_set%message(len(set_head) + 1:) == from_file%message(index(from_file%message, &
            file_head) + len(file_head):) .and. from_set%code == from_file%code)
      end subroutine same
   end subroutine test_namelist_messages

   !> {case} and {task} filled in; {task} without a task index and unknown fields refused.
   subroutine test_output_template(error)
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: got
      character(len=:), allocatable :: name, source
      integer :: task
      call expand_output_name('out/{case}_{task}.h5', 'crank_rc1', 17, name, error)
      if (allocated(error)) return
      call check(error, 'template: ' // name, name == 'out/crank_rc1_17.h5')
      if (allocated(error)) return
      call expand_output_name('{case}.h5', 'crank_rc1', NO_TASK, name, error)
      if (allocated(error)) return
      call check(error, '{case} without a task: ' // name, name == 'crank_rc1.h5')
      if (allocated(error)) return
      call expand_output_name('{case}_{task}.h5', 'c', NO_TASK, name, got)
      call check(error, '{task} without a task index', allocated(got))
      if (allocated(error)) return
      call check(error, '{task} message: ' // got%message, index(got%message, &
         '--output ''{case}_{task}.h5'': {task} needs a task index: --task N, or a job array') &
         == 1 .and. got%code == FFRF_INPUT_ERROR)
      if (allocated(error)) return
      call expand_output_name('{run}.h5', 'c', 1, name, got)
      call check(error, 'unknown field', allocated(got))
      if (allocated(error)) return
      call check(error, 'unknown field message: ' // got%message, got%message == &
         '--output ''{run}.h5'': unknown field {run}; the fields are {case} and {task}')
      if (allocated(error)) return
      call expand_output_name('a{case.h5', 'c', 1, name, got)
      call check(error, 'unclosed brace', allocated(got))
      if (allocated(error)) return
      call job_task_index(4, task, source, error)
      if (allocated(error)) return
      call check(error, '--task wins', task == 4 .and. source == '--task')
   end subroutine test_output_template

   !> Row N of a table: comments and blank lines skipped, quoted fields with commas, values
   !> trimmed, origins FILE:LINE KEY.
   subroutine test_sweep_rows(error)
      type(error_t), allocatable, intent(out) :: error
      type(override_t), allocatable :: rows(:)
      character(len=:), allocatable :: file
      file = own_name('rows.csv')
      call write_file(file, '# a sweep' // NL // 'modes.num_modes, interface[B2].rc, ' // &
         'run.title' // NL // NL // '4,Tx,"a, b"' // NL // ' 6 , Tx Ty , "say ""hi"""' // &
         achar(13) // NL)
      call read_sweep_row(file, 2, rows, error)
      if (allocated(error)) return
      call check(error, 'row 2: 3 overrides', size(rows) == 3)
      if (allocated(error)) return
      call check(error, 'row 2 values: ' // rows(1)%value // '|' // rows(2)%value // '|' // &
         rows(3)%value, rows(1)%value == '6' .and. rows(2)%value == 'Tx Ty' .and. &
         rows(3)%value == 'say "hi"')
      if (allocated(error)) return
      call check(error, 'row 2 keys', rows(2)%group == 'interface' .and. rows(2)%name == 'B2' &
         .and. rows(2)%key == 'rc')
      if (allocated(error)) return
      call check(error, 'origin: ' // rows(2)%origin, rows(2)%origin == file // &
         ':5 interface[B2].rc')
      if (allocated(error)) return
      call read_sweep_row(file, 1, rows, error)
      if (allocated(error)) return
      call check(error, 'row 1 quoted comma: ' // rows(3)%value, rows(3)%value == 'a, b' .and. &
         rows(1)%value == '4')
      call remove_file(file)
   end subroutine test_sweep_rows

   !> Row out of range, a wrong column count, a bad header key, an empty table, a missing file.
   subroutine test_sweep_errors(error)
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: file
      type(override_t), allocatable :: rows(:)
      type(error_t), allocatable :: got
      file = own_name('errors.csv')
      call write_file(file, 'modes.num_modes' // NL // '4' // NL // '6' // NL)
      call expect(file, 3, file // ': row 3 asked (the task index), the table has 2 rows (1..2)')
      if (allocated(error)) return
      call expect(file, 0, file // ': row 0 asked')
      if (allocated(error)) return
      call write_file(file, 'modes.num_modes,interface[B2].rc' // NL // '4,Tx' // NL // &
         '6' // NL)
      call expect(file, 1, file // ':3: 1 values, the header names 2 keys (modes.num_modes, ' &
         // 'interface[B2].rc)')
      if (allocated(error)) return
      call write_file(file, 'modes.num_modes,rc' // NL // '4,Tx' // NL)
      call expect(file, 1, file // ': column 2 "rc" of the header: not GROUP.KEY')
      if (allocated(error)) return
      call write_file(file, '# nothing' // NL)
      call expect(file, 1, file // ': an empty sweep table')
      if (allocated(error)) return
      call read_sweep_row('test_input_overrides_missing.csv', 1, rows, got)
      call check(error, 'a missing table: a file error', allocated(got))
      if (allocated(error)) return
      call check(error, 'missing: ' // got%message, got%code == FFRF_IO_ERROR .and. &
         index(got%message, '--sweep table "test_input_overrides_missing.csv" does not ' // &
         'exist') == 1)
      call remove_file(file)
   contains
      subroutine expect(name, row, start)
         character(len=*), intent(in) :: name, start
         integer, intent(in) :: row
         type(override_t), allocatable :: rows(:)
         type(error_t), allocatable :: got
         call read_sweep_row(name, row, rows, got)
         call expect_message(got, name, start, error)
      end subroutine expect
   end subroutine test_sweep_errors

   !> The sweep row first, then --set (a later override wins), then --output.
   subroutine test_batch_order(error)
      type(error_t), allocatable, intent(out) :: error
      type(override_t), allocatable :: all(:)
      type(error_t), allocatable :: got
      character(len=:), allocatable :: file
      file = own_name('batch.csv')
      call write_file(file, 'modes.num_modes' // NL // '4' // NL // '6' // NL)
      call batch_overrides('crank', file, 2, [set('modes.num_modes=9')], '{case}_{task}.h5', &
         all, error)
      if (allocated(error)) return
      call check(error, 'order: row, --set, --output', size(all) == 3)
      if (allocated(error)) return
      call check(error, 'values: ' // all(1)%value // ' ' // all(2)%value // ' ' // &
         all(3)%value, all(1)%value == '6' .and. all(2)%value == '9' .and. &
         all(3)%value == 'crank_2.h5' .and. all(3)%key == 'output' .and. &
         all(3)%origin == '--output')
      if (allocated(error)) return
      ! without --task and with no job-array variable set (this test's environment)
      call batch_overrides('crank', file, NO_TASK, [override_t ::], '', all, got)
      call check(error, 'a sweep without a task index', allocated(got))
      if (allocated(error)) return
      call check(error, 'message: ' // got%message, index(got%message, '--sweep ' // file // &
         ': which row? give --task N or run as a job array') == 1)
      call remove_file(file)
   end subroutine test_batch_order

   ! ---------------------------------------------------------------------------------------------

   function set(text) result(ov)
      character(len=*), intent(in) :: text
      type(override_t) :: ov
      type(error_t), allocatable :: error
      call parse_override(text, ov, error)
      if (allocated(error)) error stop 'test_input_overrides: bad test override'
   end function set

   !> The canonical namelist text of a source (what the group readers read).
   function canonical(src) result(text)
      type(nml_source_t), intent(in) :: src
      character(len=:), allocatable :: text
      type(error_t), allocatable :: error
      character(len=400) :: line
      integer :: unit, stat
      open (newunit=unit, status='scratch', action='readwrite', form='formatted')
      call src%write_namelist(unit, error)
      text = ''
      do
         read (unit, '(a)', iostat=stat) line
         if (stat /= 0) exit
         text = text // trim(line) // '|'
      end do
      close (unit)
   end function canonical

   !> Expect an override on CASE_TEXT to fail with a message starting `start`.
   subroutine expect_set_error(text, start, error)
      character(len=*), intent(in) :: text, start
      type(error_t), allocatable, intent(out) :: error
      type(nml_source_t) :: src
      type(error_t), allocatable :: got
      call src%parse('c.nml', CASE_TEXT, case_groups(), error)
      if (allocated(error)) return
      call apply_overrides(src, [set(text)], got)
      call expect_message(got, text, start, error)
   end subroutine expect_set_error

   !> `got` is an input error whose message starts with `start`; `what` names the case.
   subroutine expect_message(got, what, start, error)
      type(error_t), allocatable, intent(in) :: got
      character(len=*), intent(in) :: what, start
      type(error_t), allocatable, intent(out) :: error
      if (.not. allocated(got)) then
         call fatal_error(error, FFRF_INPUT_ERROR, what // ': accepted')
      else if (index(got%message, start) /= 1 .or. got%code /= FFRF_INPUT_ERROR) then
         call fatal_error(error, FFRF_INPUT_ERROR, what // ': "' // got%message // &
            '", expected "' // start // '..."')
      end if
   end subroutine expect_message

   subroutine remove_file(name)
      character(len=*), intent(in) :: name
      integer :: unit, stat
      open (newunit=unit, file=name, status='old', iostat=stat)
      if (stat == 0) close (unit, status='delete')
   end subroutine remove_file

   subroutine write_file(name, text)
      character(len=*), intent(in) :: name, text
      integer :: unit
      open (newunit=unit, file=name, status='replace', action='write', access='stream', &
         form='unformatted')
      write (unit) text
      close (unit)
   end subroutine write_file

   !> A file name of this test program's own (the plain and the _checked executables run at
   !> the same time and must not share a file): <executable>_<suffix>.
   function own_name(suffix) result(name)
      character(len=*), intent(in) :: suffix
      character(len=:), allocatable :: name
      character(len=512) :: program
      call get_command_argument(0, program)
      name = trim(program(index(program, '/', back=.true.) + 1:)) // '_' // suffix
   end function own_name

end module test_input_overrides

program main_input_overrides
   use test_input_overrides, only: collect_input_overrides
   use ffrf_testing, only: unittest_t, run_suite
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_input_overrides(tests)
   call run_suite('test_input_overrides', tests)
end program main_input_overrides
