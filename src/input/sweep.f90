!> Batch runs from the command line: the task index of a job array, sweep tables and output-name
!> templates, turned into overrides of the case (ffrf_input_overrides).
!>   - task index: --task N, else the first of SLURM_ARRAY_TASK_ID, PBS_ARRAY_INDEX, LSB_JOBINDEX
!>     that is set (LSF sets LSB_JOBINDEX = 0 outside job arrays: 0 counts as not set there);
!>   - sweep table (--sweep TABLE.csv): a CSV file whose header names override keys
!>     (`modes.num_modes,interface[B2].rc`) and whose row N (1-based, header not counted; blank
!>     lines and lines starting with '#' skipped) gives their values for task N. A field may be
!>     quoted with double quotes to hold commas (`"0, 0, 1"`), "" inside them for a quote;
!>   - output template (--output NAME): {case} is the case file's name without folder and
!>     extension, {task} the task index; the name becomes the override run.output.
!> Every problem is an input error (FFRF_INPUT_ERROR) naming the table line or the option.
module ffrf_input_sweep
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR, FFRF_IO_ERROR
   use ffrf_core_kinds, only: i8
   use ffrf_core_strings, only: to_str, to_lower
   use ffrf_core_posix, only: check_input_file
   use ffrf_input_nml_source, only: UTF8_BOM
   use ffrf_input_overrides, only: override_t, parse_override_key
   implicit none
   private
   public :: job_task_index, expand_output_name, read_sweep_row, batch_overrides, NO_TASK

   !> No task index (neither --task nor a job-array variable)
   integer, parameter :: NO_TASK = -1
   !> Longest line of a sweep table read
   integer, parameter :: MAX_LINE = 65536
   !> Largest sweep table read (bytes): 64 MiB, a million rows of 64 characters
   integer(i8), parameter :: MAX_TABLE_BYTES = 64_i8 * 1024_i8**2
   !> The job-array variables, in the order they are looked at
   character(len=*), parameter :: TASK_VARIABLES(3) = [character(len=19) :: &
      'SLURM_ARRAY_TASK_ID', 'PBS_ARRAY_INDEX', 'LSB_JOBINDEX']

   !> One field of a table line, and a line's fields.
   type :: field_t
      character(len=:), allocatable :: text
   end type field_t
   type :: field_list_t
      type(field_t), allocatable :: items(:)
   end type field_list_t

contains

   !> The task index: `given` (from --task; NO_TASK when not given), else the first job-array
   !> variable set (module header); NO_TASK when none. `source` says where it came from.
   subroutine job_task_index(given, task, source, error)
      integer, intent(in) :: given
      integer, intent(out) :: task
      character(len=:), allocatable, intent(out) :: source
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: text
      integer :: k, length, stat
      task = given
      source = '--task'
      if (given /= NO_TASK) return
      do k = 1, size(TASK_VARIABLES)
         ! the length first, then the whole value (a long value is an error, never "unset")
         call get_environment_variable(trim(TASK_VARIABLES(k)), length=length, status=stat)
         if (stat /= 0 .or. length == 0) cycle
         if (allocated(text)) deallocate (text)
         allocate (character(len=length) :: text)
         call get_environment_variable(trim(TASK_VARIABLES(k)), text, status=stat)
         if (verify(text, '0123456789') /= 0 .or. length > 9) then
            call fatal_error(error, FFRF_INPUT_ERROR, trim(TASK_VARIABLES(k)) // ' = "' // &
               shown(text) // '" (' // to_str(length) // ' characters): not a task index ' // &
               '(a non-negative integer of at most 9 digits)')
            return
         end if
         read (text, *) task
         if (TASK_VARIABLES(k) == 'LSB_JOBINDEX' .and. task == 0) then
            task = NO_TASK
            cycle
         end if
         source = trim(TASK_VARIABLES(k))
         return
      end do
      source = ''
   end subroutine job_task_index

   !> At most 60 characters of `text` for a message, control characters as '?'.
   pure function shown(text) result(short)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: short
      integer :: k
      short = text(:min(len(text), 60))
      do k = 1, len(short)
         if (iachar(short(k:k)) < 32 .or. iachar(short(k:k)) == 127) short(k:k) = '?'
      end do
      if (len(text) > 60) short = short // '...'
   end function shown

   !> `template` with {case} -> case_name and {task} -> task; {task} with task = NO_TASK and any
   !> other {...} are errors.
   subroutine expand_output_name(template, case_name, task, name, error)
      character(len=*), intent(in) :: template, case_name
      integer, intent(in) :: task
      character(len=:), allocatable, intent(out) :: name
      type(error_t), allocatable, intent(out) :: error
      integer :: pos, close_brace
      character(len=:), allocatable :: field
      name = ''
      pos = 1
      do while (pos <= len(template))
         if (template(pos:pos) /= '{') then
            name = name // template(pos:pos)
            pos = pos + 1
            cycle
         end if
         close_brace = index(template(pos:), '}')
         if (close_brace == 0) then
            call fail('a "{" without "}"')
            return
         end if
         field = template(pos + 1:pos + close_brace - 2)
         select case (field)
         case ('case')
            name = name // case_name
         case ('task')
            if (task == NO_TASK) then
               call fail('{task} needs a task index: --task N, or a job array ' // &
                  '(SLURM_ARRAY_TASK_ID, PBS_ARRAY_INDEX or LSB_JOBINDEX set)')
               return
            end if
            name = name // to_str(task)
         case default
            call fail('unknown field {' // field // '}; the fields are {case} and {task}')
            return
         end select
         pos = pos + close_brace
      end do
   contains
      subroutine fail(problem)
         character(len=*), intent(in) :: problem
         call fatal_error(error, FFRF_INPUT_ERROR, '--output ''' // template // ''': ' // problem)
      end subroutine fail
   end subroutine expand_output_name

   !> Row `row` (1-based) of the sweep table `file_name` as overrides, origin
   !> "FILE:LINE KEY". Every row must have as many fields as the header.
   subroutine read_sweep_row(file_name, row, overrides, error)
      character(len=*), intent(in) :: file_name
      integer, intent(in) :: row
      type(override_t), allocatable, intent(out) :: overrides(:)
      type(error_t), allocatable, intent(out) :: error
      character(len=MAX_LINE) :: buffer
      character(len=512) :: msg
      type(field_list_t) :: header, fields, chosen
      character(len=:), allocatable :: line, problem
      integer :: unit, stat, line_number, rows, chosen_line, k, length, j
      logical :: have_header
      ! a regular file of bounded size: a FIFO would block, a folder is no table (exit 3)
      call check_input_file(file_name, '--sweep table', MAX_TABLE_BYTES, error)
      if (allocated(error)) return
      open (newunit=unit, file=file_name, status='old', action='read', iostat=stat, iomsg=msg)
      if (stat /= 0) then
         call fatal_error(error, FFRF_IO_ERROR, 'cannot open the sweep table "' // file_name // &
            '": ' // trim(msg))
         return
      end if
      have_header = .false.
      rows = 0
      chosen_line = 0
      line_number = 0
      do
         read (unit, '(a)', iostat=stat, iomsg=msg, size=length, advance='no') buffer
         if (is_iostat_end(stat)) exit
         line_number = line_number + 1
         if (stat /= 0 .and. .not. is_iostat_eor(stat)) then
            call fail(FFRF_IO_ERROR, file_name // ':' // to_str(line_number) // &
               ': cannot read: ' // trim(msg))
            return
         end if
         if (stat == 0) then
            call fail(FFRF_INPUT_ERROR, file_name // ':' // to_str(line_number) // &
               ': a line longer than ' // to_str(MAX_LINE) // ' characters')
            return
         end if
         line = trim(buffer(:length))
         ! a UTF-8 byte-order mark (spreadsheets write one) before the header is skipped
         if (line_number == 1 .and. len(line) >= 3) then
            if (line(1:3) == UTF8_BOM) line = line(4:)
         end if
         if (len(line) > 0) then
            if (line(len(line):) == achar(13)) line = line(:len(line) - 1)
         end if
         if (len_trim(line) == 0) cycle
         k = verify(line, ' ' // achar(9))
         if (line(k:k) == '#') cycle
         call split_fields(line, fields, problem)
         if (len(problem) > 0) then
            call fail(FFRF_INPUT_ERROR, file_name // ':' // to_str(line_number) // ': ' // &
               problem)
            return
         end if
         if (.not. have_header) then
            header = fields
            have_header = .true.
            cycle
         end if
         rows = rows + 1
         if (size(fields%items) /= size(header%items)) then
            call fail(FFRF_INPUT_ERROR, file_name // ':' // to_str(line_number) // ': ' // &
               to_str(size(fields%items)) // ' values, the header names ' // &
               to_str(size(header%items)) // ' keys (' // joined(header) // ')')
            return
         end if
         if (rows == row) then
            chosen = fields
            chosen_line = line_number
         end if
      end do
      close (unit)
      if (.not. have_header) then
         call fatal_error(error, FFRF_INPUT_ERROR, file_name // ': an empty sweep table; ' // &
            'give a header of override keys (modes.num_modes,interface[B2].rc) and rows of values')
         return
      end if
      if (row < 1 .or. row > rows) then
         call fatal_error(error, FFRF_INPUT_ERROR, file_name // ': row ' // to_str(row) // &
            ' asked (the task index), the table has ' // to_str(rows) // ' rows (1..' // &
            to_str(rows) // ')')
         return
      end if
      allocate (overrides(size(header%items)))
      do k = 1, size(header%items)
         call parse_override_key(header%items(k)%text, overrides(k), problem)
         if (len(problem) > 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, file_name // ': column ' // to_str(k) // &
               ' "' // header%items(k)%text // '" of the header: ' // problem)
            return
         end if
         do j = 1, k - 1
            if (to_lower(overrides(j)%group) == to_lower(overrides(k)%group) .and. &
               overrides(j)%name == overrides(k)%name .and. &
               to_lower(overrides(j)%key) == to_lower(overrides(k)%key)) then
               call fatal_error(error, FFRF_INPUT_ERROR, file_name // ': column ' // &
                  to_str(k) // ' "' // header%items(k)%text // '" of the header names the ' // &
                  'key of column ' // to_str(j) // ' again; give each key once')
               return
            end if
         end do
         overrides(k)%value = chosen%items(k)%text
         overrides(k)%origin = file_name // ':' // to_str(chosen_line) // ' ' // &
            header%items(k)%text
      end do
   contains
      subroutine fail(code, message)
         integer, intent(in) :: code
         character(len=*), intent(in) :: message
         call fatal_error(error, code, message)
         close (unit)
      end subroutine fail
   end subroutine read_sweep_row

   !> The overrides of a batch run, in the order they apply (a later one wins): the sweep row
   !> (`sweep_file` /= ''; row = the task index), then `sets` (--set, in order), then the output
   !> name (`output_template` /= '': run.output, origin "--output"). `task`: --task N or NO_TASK.
   subroutine batch_overrides(case_name, sweep_file, task, sets, output_template, overrides, &
      error)
      character(len=*), intent(in) :: case_name, sweep_file, output_template
      integer, intent(in) :: task
      type(override_t), intent(in) :: sets(:)
      type(override_t), allocatable, intent(out) :: overrides(:)
      type(error_t), allocatable, intent(out) :: error
      type(override_t), allocatable :: rows(:)
      type(override_t) :: output
      character(len=:), allocatable :: source, name
      integer :: index_value
      call job_task_index(task, index_value, source, error)
      if (allocated(error)) return
      allocate (rows(0))
      if (len(sweep_file) > 0) then
         if (index_value == NO_TASK) then
            call fatal_error(error, FFRF_INPUT_ERROR, '--sweep ' // sweep_file // ': which ' // &
               'row? give --task N or run as a job array (SLURM_ARRAY_TASK_ID, ' // &
               'PBS_ARRAY_INDEX or LSB_JOBINDEX set)')
            return
         end if
         call read_sweep_row(sweep_file, index_value, rows, error)
         if (allocated(error)) return
      end if
      overrides = [rows, sets]
      if (len(output_template) > 0) then
         call expand_output_name(output_template, case_name, index_value, name, error)
         if (allocated(error)) return
         output%group = 'run'
         output%name = ''
         output%key = 'output'
         output%value = name
         output%origin = '--output'
         overrides = [overrides, output]
      end if
   end subroutine batch_overrides

   !> "a, b, c" of a field list.
   function joined(list) result(text)
      type(field_list_t), intent(in) :: list
      character(len=:), allocatable :: text
      integer :: k
      text = ''
      do k = 1, size(list%items)
         if (k > 1) text = text // ', '
         text = text // list%items(k)%text
      end do
   end function joined

   !> The comma-separated fields of a CSV line, blanks around them removed, "..." unquoted.
   subroutine split_fields(line, list, problem)
      character(len=*), intent(in) :: line
      type(field_list_t), intent(out) :: list
      character(len=:), allocatable, intent(out) :: problem
      character(len=:), allocatable :: field
      integer :: pos
      logical :: quoted
      problem = ''
      allocate (list%items(0))
      pos = 1
      do
         field = ''
         quoted = .false.
         do while (pos <= len(line))
            if (line(pos:pos) /= ' ' .and. line(pos:pos) /= achar(9)) exit
            pos = pos + 1
         end do
         if (pos <= len(line)) then
            if (line(pos:pos) == '"') then
               quoted = .true.
               pos = pos + 1
               do
                  if (pos > len(line)) then
                     problem = 'a field opened by " is not closed on its line'
                     return
                  end if
                  if (line(pos:pos) == '"') then
                     if (pos < len(line)) then
                        if (line(pos + 1:pos + 1) == '"') then
                           field = field // '"'
                           pos = pos + 2
                           cycle
                        end if
                     end if
                     pos = pos + 1
                     exit
                  end if
                  field = field // line(pos:pos)
                  pos = pos + 1
               end do
            end if
         end if
         do while (pos <= len(line))
            if (line(pos:pos) == ',') exit
            if (quoted .and. line(pos:pos) /= ' ') then
               problem = 'text after a quoted field: "' // line(pos:) // '"'
               return
            end if
            field = field // line(pos:pos)
            pos = pos + 1
         end do
         if (.not. quoted) field = trim(field)
         call add_field(list, field)
         if (pos > len(line)) exit
         pos = pos + 1
      end do
   end subroutine split_fields

   subroutine add_field(list, text)
      type(field_list_t), intent(inout) :: list
      character(len=*), intent(in) :: text
      type(field_t), allocatable :: grown(:)
      integer :: k, n
      n = size(list%items)
      allocate (grown(n + 1))
      do k = 1, n
         call move_alloc(list%items(k)%text, grown(k)%text)
      end do
      grown(n + 1)%text = text
      call move_alloc(grown, list%items)
   end subroutine add_field

end module ffrf_input_sweep
