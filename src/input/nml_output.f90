!> Namelist group &output (optional, single; mechanism runs): which histories a mechanism run
!> writes, at what rate, compressed or not, and whether it may start when its predicted size does
!> not fit in the output folder (docs/results.md "Output rate, peaks, compression, size").
!>   every_steps        write every N-th integrator step (>= 1; default 1: every step)
!>   every_seconds      write at the first step at or after each multiple of T (s) of simulated
!>                      time (> 0; default 0: off); not together with every_steps > 1
!>   histories          what to write: 'all' (default), 'none', 'bodies', 'joints', 'energies',
!>                      'sensors', or the name of a body, joint or sensor (1 to 64 entries);
!>                      /time/t (and the engine's /time series) are always written
!>   peaks              with a reduced rate, each history's min and max over each output interval
!>                      and their times under /peaks (default .true.)
!>   compression        deflate level of the histories, after a byte shuffle (0 none, default;
!>                      1 fastest .. 9 smallest)
!>   ignore_free_space  start even when the predicted size exceeds the output folder's free space
!>                      (default .false.: the run refuses to start, exit 3)
module ffrf_input_nml_output
   use, intrinsic :: iso_fortran_env, only: iostat_end
   use ffrf_core_kinds, only: dp, i8
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_lower, to_str
   use ffrf_input_nml_common, only: namelist_read_error
   use ffrf_input_nml_source, only: key_spec_t, string_key, integer_key, real_key, logical_key
   implicit none
   private
   public :: output_input_t, read_output_group, output_keys, output_echo, check_history_names, &
      MAX_HISTORIES, HISTORY_WORDS

   !> Entries of &output histories
   integer, parameter :: MAX_HISTORIES = 64
   !> The words of &output histories besides names
   character(len=*), parameter :: HISTORY_WORDS = 'all, none, bodies, joints, energies, sensors'

   !> Resolved &output input (defaults: every step, every history, no compression).
   type :: output_input_t
      integer :: every_steps = 1
      real(dp) :: every_seconds = 0.0_dp
      character(len=64) :: histories(MAX_HISTORIES) = ''
      logical :: peaks = .true.
      integer :: compression = 0
      logical :: ignore_free_space = .false.
   end type output_input_t

contains

   !> Keys of &output, their types and what is allowed (module header).
   function output_keys() result(keys)
      type(key_spec_t), allocatable :: keys(:)
      keys = [integer_key('every_steps', 1_i8, 1000000000_i8), &
         real_key('every_seconds', 0.0_dp, huge(1.0_dp), 's'), &
         string_key('histories', 64, MAX_HISTORIES), logical_key('peaks'), &
         integer_key('compression', 0_i8, 9_i8), logical_key('ignore_free_space')]
   end function output_keys

   !> Read the optional &output group from an open case file into `input`, whose values stay
   !> for the keys not given (all of them when the group is absent).
   subroutine read_output_group(unit, input, error)
      integer :: every_steps, compression, stat, k
      real(dp) :: every_seconds
      integer, intent(in) :: unit
      type(output_input_t), intent(inout) :: input
      type(error_t), allocatable, intent(out) :: error
      character(len=64) :: histories(MAX_HISTORIES)
      logical :: peaks, ignore_free_space
      character(len=512) :: msg
      namelist /output/ every_steps, every_seconds, histories, peaks, compression, &
         ignore_free_space
      ! the defaults are input's values: a namelist read leaves absent keys untouched
      every_steps = input%every_steps
      every_seconds = input%every_seconds
      compression = input%compression
      histories = input%histories
      rewind (unit)
      peaks = input%peaks
      ignore_free_space = input%ignore_free_space
      read (unit, nml=output, iostat=stat, iomsg=msg)
      select case (stat)
      case (0)
      case (iostat_end)
         return   ! the group is optional
      case default
         call namelist_read_error(error, 'output', 0, msg, 'every_steps, every_seconds, ' // &
            'histories, peaks, compression, ignore_free_space')
         return
      end select
      if (every_steps > 1 .and. every_seconds > 0.0_dp) then
         call fatal_error(error, FFRF_INPUT_ERROR, '&output: every_steps and every_seconds ' // &
            'both given; give one rate (every_seconds = 0 or every_steps = 1)')
         return
      end if
      do k = 1, MAX_HISTORIES
         if (any(to_lower(trim(histories(k))) == ['all     ', 'none    ', 'bodies  ', &
            'joints  ', 'energies', 'sensors '])) histories(k) = to_lower(histories(k))
      end do
      input = output_input_t(every_steps, every_seconds, histories, peaks, compression, &
         ignore_free_space)
   end subroutine read_output_group

   !> The &output line of the case echo; '' when every key has its default (the echo, the
   !> results' /input and the restart fingerprint of a case without &output stay as before).
   function output_echo(input) result(text)
      type(output_input_t), intent(in) :: input
      character(len=:), allocatable :: text
      character(len=32) :: number
      integer :: k
      text = ''
      if (input%every_steps == 1 .and. input%every_seconds == 0.0_dp .and. &
         all(input%histories == '') .and. input%peaks .and. input%compression == 0 .and. &
         .not. input%ignore_free_space) return
      write (number, '(i0)') input%every_steps
      text = '&output every_steps = ' // trim(number)
      text = text // ', every_seconds = ' // to_str(input%every_seconds, 12) // ', histories ='
      if (all(input%histories == '')) text = text // ' ''all'''
      do k = 1, MAX_HISTORIES
         if (len_trim(input%histories(k)) > 0) text = text // ' ''' // &
            trim(input%histories(k)) // ''''
      end do
      write (number, '(i0)') input%compression
      text = text // ', peaks = ' // trim(merge('.true. ', '.false.', input%peaks)) // &
         ', compression = ' // trim(number) // ', ignore_free_space = ' // &
         trim(merge('.true. ', '.false.', input%ignore_free_space)) // ' /' // new_line('a')
   end function output_echo

   !> Every entry of &output histories is a word of HISTORY_WORDS or one of `names` (the case's
   !> bodies, joints and sensors).
   subroutine check_history_names(input, names, error)
      type(output_input_t), intent(in) :: input
      character(len=*), intent(in) :: names(:)
      type(error_t), allocatable, intent(out) :: error
      integer :: k
      do k = 1, MAX_HISTORIES
         associate (entry => input%histories(k))
            if (len_trim(entry) == 0) cycle
            if (index(', ' // HISTORY_WORDS // ',', ', ' // trim(entry) // ',') > 0) cycle
            if (any(names == entry)) cycle
            call fatal_error(error, FFRF_INPUT_ERROR, '&output histories: "' // trim(entry) // &
               '" is no body, joint or sensor of the case nor one of ' // HISTORY_WORDS // &
               '; give one of these')
            return
         end associate
      end do
   end subroutine check_history_names

end module ffrf_input_nml_output
