!> ffrf batch driver: `ffrf CASE.nml|- [--check] [--mesh-dir DIR] [--output-dir DIR]
!> [--quiet|--debug] [--no-overwrite] [--restart RESULTS] [--set GROUP[NAME].KEY=VALUE]...
!> [--sweep TABLE.csv] [--task N] [--output NAME] [--threads N] [--print-input]`,
!> `ffrf --version`. Overrides, sweep rows and output names are made by the input layer
!> (src/input/overrides.f90, src/input/sweep.f90).
!> Reads the arguments, runs the case, prints an error and exits non-zero on failure:
!> 2 bad input, 3 file input/output, 4 numerical failure, 5 interrupted by a signal,
!> 1 bad command line.
!> MPI build: `mpirun -np N ffrf CASE.nml`; every rank parses the same command line and runs the
!> case on MPI_COMM_WORLD, rank 0 alone prints and writes, and every rank exits with the same
!> code (the error of the lowest failing rank; ffrf_driver_ranks).
program ffrf_driver
   use, intrinsic :: iso_fortran_env, only: error_unit, output_unit
   use, intrinsic :: iso_c_binding, only: c_int
   use ffrf, only: error_t, logger_t, run_options_t, run_modal, run_mechanism, check_case, &
      case_input_t, FFRF_INPUT_ERROR, FFRF_IO_ERROR, FFRF_NUMERIC_ERROR, &
      FFRF_INTERRUPTED, LOG_QUIET, LOG_DEBUG, install_signal_handlers, signals_restart_calls, &
      ignore_file_size_signal, override_t, parse_override, batch_overrides, NO_TASK, &
      read_case_with_overrides, case_echo, case_name_of, set_blas_threads, build_versions, &
      reserve_blas_buffers, fit_blas_address_limit, exit_guard
   use ffrf_driver_ranks, only: start_ranks, end_ranks
   implicit none
   interface
      !> C's exit(): ends the run with a status and no runtime banner (ERROR STOP prints one).
      subroutine c_exit(status) bind(c, name='exit')
         import :: c_int
         implicit none
         integer(c_int), value :: status
      end subroutine c_exit
   end interface
   type(error_t), allocatable :: error
   type(run_options_t) :: options
   type(logger_t) :: log
   type(case_input_t) :: case
   character(len=:), allocatable :: case_file, arg, sweep_file, output_template
   type(override_t), allocatable :: sets(:), overrides(:)
   logical :: check_only, print_input
   integer :: i, task, threads, threads_used, k, num_sets
   character(len=120) :: versions(8)

   ! under ulimit -v: again with one BLAS thread (OpenBLAS's workers could spin forever)
   call fit_blas_address_limit()
   call start_ranks(options%parallel, error)
   if (allocated(error)) call fail(error)
   options%mesh_dir = ''
   options%output_dir = ''
   options%restart_file = ''
   case_file = ''
   check_only = .false.
   print_input = .false.
   sweep_file = ''
   output_template = ''
   task = NO_TASK
   threads = 0
   allocate (sets(16))
   num_sets = 0
   i = 0
   do while (i < command_argument_count())
      i = i + 1
      arg = argument(i)
      select case (arg)
      case ('-h', '--help')
         if (options%parallel%is_root()) call usage(output_unit)
         call finish(0)
      case ('--mesh-dir', '--output-dir')
         if (i == command_argument_count()) call bad_usage(arg // ' needs a folder')
         i = i + 1
         call check_not_empty(arg, argument(i), 'a folder')
         if (arg == '--mesh-dir') options%mesh_dir = argument(i)
         if (arg == '--output-dir') options%output_dir = argument(i)
      case ('--restart')
         if (i == command_argument_count()) call bad_usage(arg // ' needs a results file')
         i = i + 1
         call check_not_empty(arg, argument(i), 'a results or .checkpoint file')
         options%restart_file = argument(i)
      case ('--no-overwrite')
         options%overwrite = .false.
      case ('--quiet')
         options%log_level = LOG_QUIET
      case ('--debug')
         options%log_level = LOG_DEBUG
      case ('--check')
         check_only = .true.
      case ('--print-input')
         print_input = .true.
      case ('--version')
         versions = build_versions()
         do k = 1, size(versions)
            if (options%parallel%is_root()) write (output_unit, '(a)') trim(versions(k))
         end do
         call finish(0)
      case ('--set', '--sweep', '--output', '--task', '--threads')
         if (i == command_argument_count()) call bad_usage(arg // ' needs a value')
         i = i + 1
         select case (arg)
         case ('--set')
            call check_not_empty(arg, argument(i), 'GROUP.KEY=VALUE')
         case ('--sweep')
            call check_not_empty(arg, argument(i), 'a table file')
         case ('--output')
            call check_not_empty(arg, argument(i), 'a file name')
         case default
            call check_not_empty(arg, argument(i), 'a whole number')
         end select
         select case (arg)
         case ('--set')
            ! grown by doubling: 20 000 options take linear time (docs/batch.md "Batch runs")
            if (num_sets == size(sets)) call grow(sets)
            num_sets = num_sets + 1
            call parse_override(argument(i), sets(num_sets), error)
            if (allocated(error)) call fail(error)
         case ('--sweep')
            sweep_file = argument(i)
         case ('--output')
            output_template = argument(i)
         case ('--task')
            task = whole_number(arg, argument(i))
         case ('--threads')
            threads = whole_number(arg, argument(i))
            if (threads < 1) call bad_usage('--threads ' // argument(i) // ': give 1 or more')
         end select
      case default
         if (len(arg) == 0) call bad_usage('an empty argument where the case file is ' // &
            'expected; give CASE.nml or -')
         if (index(arg, '-') == 1 .and. arg /= '-') call bad_usage('unknown option ' // arg)
         if (len(case_file) > 0) call bad_usage('one case file only (got ' // case_file // &
            ' and ' // arg // ')')
         case_file = arg
      end select
   end do
   if (len(case_file) == 0) call bad_usage('no case file given')
   options%sweep_file = sweep_file

   ! an allocation failure the Fortran runtime ends the run for: exit 4 with an error line
   call exit_guard(.true.)
   ! SIGTERM & co. end a run cleanly after its current step; a file size limit makes writes fail
   call install_signal_handlers(error)
   if (.not. allocated(error)) call signals_restart_calls(error)
   if (.not. allocated(error)) call ignore_file_size_signal()
   log%unit = output_unit
   if (.not. allocated(error)) call batch_overrides(case_name_of(case_file), sweep_file, task, &
      sets(:num_sets), output_template, overrides, error)
   if (.not. allocated(error)) call read_case_with_overrides(case_file, overrides, case, error)
   if (.not. allocated(error) .and. print_input) then
      if (options%parallel%is_root()) write (output_unit, '(a)', advance='no') case_echo(case)
      call finish(0)
   end if
   ! MPI: one BLAS thread per rank unless asked otherwise (ranks x threads would oversubscribe)
   if (options%parallel%num_ranks > 1 .and. threads == 0) then
      call get_environment_variable('OPENBLAS_NUM_THREADS', length=k)
      if (k == 0) threads = 1
   end if
   if (.not. allocated(error) .and. threads > 0) then
      call set_blas_threads(threads, threads_used, error)
      if (.not. allocated(error) .and. options%log_level /= LOG_QUIET .and. &
         options%parallel%is_root()) write (output_unit, '(a, i0)') 'BLAS threads: ', threads_used
   end if
   ! OpenBLAS's work buffers taken now: a buffer mapped later under an address-space limit
   ! would spin forever in OpenBLAS (issue 23)
   if (.not. allocated(error) .and. .not. check_only) call reserve_blas_buffers(error)
   if (.not. allocated(error)) then
      if (check_only) then
         call check_case(case, options, log, error)
      else if (case%is_mechanism) then
         call run_mechanism(case, options, log, error)
      else
         call run_modal(case, options, log, error)
      end if
   end if
   ! every rank leaves with the same error, if any (one process: nothing to agree)
   call options%parallel%agree(error)
   if (allocated(error)) call fail(error)
   call finish(0)

contains

   !> Print the error (rank 0) and exit with its code.
   subroutine fail(error)
      type(error_t), intent(in) :: error
      if (options%parallel%is_root()) write (error_unit, '(a)') 'ffrf: error: ' // &
         error%message
      select case (error%code)
      case (FFRF_INPUT_ERROR, FFRF_IO_ERROR, FFRF_NUMERIC_ERROR, FFRF_INTERRUPTED)
         call finish(error%code)
      case default
         call finish(1)
      end select
   end subroutine fail

   !> End the run with exit status `code` (MPI build: after MPI_Finalize).
   subroutine finish(code)
      integer, intent(in) :: code
      call exit_guard(.false.)
      flush (output_unit)
      flush (error_unit)
      call end_ranks()
      call c_exit(int(code, c_int))
   end subroutine finish

   !> An option's value must not be empty (`--output ''` would otherwise be taken as not given:
   !> `--restart ''` after an interrupted run would start again from t_start).
   subroutine check_not_empty(option, value, what)
      character(len=*), intent(in) :: option, value, what
      if (len(value) == 0) call bad_usage(option // ' '''': an empty value; give ' // what)
   end subroutine check_not_empty

   !> Twice the room for --set options, keeping those parsed (moved, not copied).
   subroutine grow(list)
      type(override_t), allocatable, intent(inout) :: list(:)
      type(override_t), allocatable :: bigger(:)
      integer :: k
      allocate (bigger(2 * size(list)))
      do k = 1, size(list)
         call move_alloc(list(k)%group, bigger(k)%group)
         call move_alloc(list(k)%name, bigger(k)%name)
         call move_alloc(list(k)%key, bigger(k)%key)
         call move_alloc(list(k)%value, bigger(k)%value)
         call move_alloc(list(k)%origin, bigger(k)%origin)
      end do
      call move_alloc(bigger, list)
   end subroutine grow

   !> The non-negative whole number after `option` (bad command line otherwise).
   integer function whole_number(option, text) result(n)
      character(len=*), intent(in) :: option, text
      integer :: stat
      n = -1
      if (len(text) > 0 .and. len(text) <= 9 .and. verify(text, '0123456789') == 0) &
         read (text, *, iostat=stat) n
      if (n < 0) call bad_usage(option // ' ' // text // ': not a whole number')
   end function whole_number

   function argument(k) result(text)
      integer, intent(in) :: k
      character(len=:), allocatable :: text
      integer :: length
      call get_command_argument(k, length=length)
      allocate (character(len=length) :: text)
      call get_command_argument(k, text)
   end function argument

   subroutine usage(unit)
      integer, intent(in) :: unit
      write (unit, '(a)') 'usage: ffrf CASE.nml|- [--check] [--mesh-dir DIR] ' // &
         '[--output-dir DIR] [--quiet|--debug] [--no-overwrite] [--restart RESULTS]'
      write (unit, '(a)') '            [--set GROUP[NAME].KEY=VALUE]... [--sweep TABLE.csv] ' // &
         '[--task N] [--output NAME] [--threads N] [--print-input]'
      write (unit, '(a)') '       ffrf --version'
      write (unit, '(a)') '  A modal case computes the constrained normal modes of the ' // &
         'bodies of CASE.nml'
      write (unit, '(a)') '  and writes <output>.h5 (HDF5 results) and <output>_modes.msh (gmsh).'
      write (unit, '(a)') '  A mechanism case (one with &joint groups) also integrates the motion'
      write (unit, '(a)') '  with generalized-alpha and writes the time histories to <output>.h5'
      write (unit, '(a)') '  and each flexible body''s deformation to ' // &
         '<output>_<body>_animation.msh.'
      write (unit, '(a)') '  --mesh-dir DIR    folder of relative mesh files ' // &
         '(default: the case folder)'
      write (unit, '(a)') '  --output-dir DIR  folder of the results (default: current folder)'
      write (unit, '(a)') '  --check           read and check the case and its meshes, then ' // &
         'stop (exit 0: no error found); nothing is computed or written'
      write (unit, '(a)') '  -                 as CASE: read the case from standard input ' // &
         '(named "stdin"; relative meshes from the current folder)'
      write (unit, '(a)') '  --no-overwrite    refuse to start when the results file exists ' // &
         '(default: replace it when the run has finished)'
      write (unit, '(a)') '  --restart FILE    continue the mechanism run whose results (or ' // &
         '.checkpoint) file is FILE to the case''s t_end'
      write (unit, '(a)') '  --set G.KEY=V      set KEY of the single group &G to V (repeatable), ' &
         // 'e.g. --set modes.num_modes=12'
      write (unit, '(a)') '  --set G[NAME].KEY=V  the same for the repeatable group &G named ' // &
         'NAME, e.g. --set interface[B2].rc=Tx; V as in the namelist (a string may be unquoted)'
      write (unit, '(a)') '  --sweep TABLE.csv  apply row N of TABLE (header: override keys ' // &
         'G.KEY or G[NAME].KEY; one row of values per task), N the task index'
      write (unit, '(a)') '  --task N          the task index (default: SLURM_ARRAY_TASK_ID, ' // &
         'PBS_ARRAY_INDEX or LSB_JOBINDEX)'
      write (unit, '(a)') '  --output NAME     results file, relative to --output-dir; ' // &
         '{case}: the case name, {task}: the task index (e.g. ''{case}_{task}.h5'')'
      write (unit, '(a)') '  --threads N       BLAS (OpenBLAS) threads (default: ' // &
         'OPENBLAS_NUM_THREADS, else every core)'
      write (unit, '(a)') '  --print-input     print the resolved case (overrides applied), ' // &
         'then stop'
      write (unit, '(a)') '  --version         print the versions of ffrf and its libraries, ' // &
         'then stop'
      write (unit, '(a)') '  Exit codes: 0 done, 1 bad command line, 2 bad input, 3 file ' // &
         'input/output (disk full, output locked by another run), 4 numerical failure, ' // &
         '5 interrupted by a signal (SIGTERM, SIGINT, SIGHUP, SIGUSR1, SIGXCPU)'
   end subroutine usage

   subroutine bad_usage(message)
      character(len=*), intent(in) :: message
      if (options%parallel%is_root()) write (error_unit, '(a)') 'ffrf: error: ' // message // &
         ' (ffrf --help for usage)'
      call finish(1)
   end subroutine bad_usage

end program ffrf_driver
