!> Namelist group &run (optional, single): what the run is called and where its results go.
!>   title            free text, echoed in the results and the log (at most 256 characters)
!>   output           results file (HDF5), relative to the output directory; default <case>.h5.
!>                    At most 256 characters; a relative path without '..' (outputs stay inside
!>                    --output-dir)
!>   mode_shapes_msh  Gmsh file to animate the modes (default <case>_modes.msh; 'none': no file);
!>                    same rules as output
!>   log_level        'quiet', 'info' (default) or 'debug'
!>   export           a list of words (export_choices of ffrf_core_choices), blank-separated:
!>                    'exudyn' writes <stem>_<body>.exudyn.hdf5 per flexible body of a modal run
!>                    (docs/results.md "Exudyn export"); default '' (no export)
!> Types, lengths and choices are checked by ffrf_input_nml_source from run_keys; the output
!> paths by ffrf_input_case.
module ffrf_input_nml_run
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_lower
   use ffrf_core_choices, only: choice_t, choice_words, choice_position, export_choices
   use ffrf_core_log, only: LOG_QUIET, LOG_INFO, LOG_DEBUG
   use ffrf_input_nml_common, only: namelist_read_error
   use ffrf_input_nml_source, only: key_spec_t, string_key, choice_key
   implicit none
   private
   public :: run_input_t, read_run_group, run_keys, log_level_code, check_export, export_kinds

   !> The &run log_level table (LOG_* of ffrf_core_log; docs/developer.md "One table per
   !> choice")
   type(choice_t), parameter :: log_level_choices(*) = [choice_t('quiet', LOG_QUIET), &
      choice_t('info', LOG_INFO), choice_t('debug', LOG_DEBUG)]

   !> Resolved &run input.
   type :: run_input_t
      character(len=256) :: title = ''
      character(len=256) :: output = ''
      character(len=256) :: mode_shapes_msh = ''
      character(len=16) :: log_level = 'info'
      !> Exports beside the results: words of export_choices, blank-separated ('' none)
      character(len=256) :: export = ''
   end type run_input_t

contains

   !> Keys of &run, their types and what is allowed (module header).
   function run_keys() result(keys)
      type(key_spec_t), allocatable :: keys(:)
      keys = [string_key('title', 256), string_key('output', 256), &
         string_key('mode_shapes_msh', 256), choice_key('log_level', 16, &
         choice_words(log_level_choices)), string_key('export', 256)]
   end function run_keys

   !> Read &run from an open case file (optional group; defaults kept when absent).
   subroutine read_run_group(unit, input, error)
      integer, intent(in) :: unit
      type(run_input_t), intent(inout) :: input
      type(error_t), allocatable, intent(out) :: error
      character(len=256) :: title, output, mode_shapes_msh, export
      character(len=16) :: log_level
      character(len=512) :: msg
      integer :: stat
      namelist /run/ title, output, mode_shapes_msh, log_level, export
      title = input%title
      output = input%output
      mode_shapes_msh = input%mode_shapes_msh
      log_level = input%log_level
      export = input%export
      rewind (unit)
      read (unit, nml=run, iostat=stat, iomsg=msg)
      if (is_iostat_end(stat)) return
      if (stat /= 0) then
         call namelist_read_error(error, 'run', 0, msg, &
            'title, output, mode_shapes_msh, log_level, export')
         return
      end if
      ! log_level's word was checked by the key spec (run_keys)
      log_level = to_lower(log_level)
      input = run_input_t(title, output, mode_shapes_msh, log_level, to_lower(export))
   end subroutine read_run_group

   !> The logger level (LOG_QUIET, LOG_INFO, LOG_DEBUG of ffrf_core_log) of a &run log_level
   !> word ('quiet', 'info', 'debug'; any case); LOG_INFO for any other word.
   pure integer function log_level_code(word)
      character(len=*), intent(in) :: word
      integer :: position
      position = choice_position(log_level_choices, word)
      log_level_code = LOG_INFO
      if (position > 0) log_level_code = log_level_choices(position)%kind
   end function log_level_code

   !> Every word of &run export is a word of export_choices; `where` starts the message
   !> (FILE:LINE: &run export = 'value').
   subroutine check_export(where, export, error)
      character(len=*), intent(in) :: where, export
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: words(:)
      integer :: k
      words = export_words(export)
      do k = 1, size(words)
         if (choice_position(export_choices, words(k)) > 0) cycle
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': ''' // trim(words(k)) // &
            ''' is no export; use blank-separated words of: ' // choice_words(export_choices))
         return
      end do
   end subroutine check_export

   !> The kinds (EXPORT_* of ffrf_core_choices) of the words of &run export, in their order,
   !> each once; a word no table row holds is left out (check_export refuses it on input).
   pure function export_kinds(export) result(kinds)
      character(len=*), intent(in) :: export
      integer, allocatable :: kinds(:)
      character(len=:), allocatable :: words(:)
      integer :: k, position
      words = export_words(export)
      allocate (kinds(0))
      do k = 1, size(words)
         position = choice_position(export_choices, words(k))
         if (position == 0) cycle
         if (any(kinds == export_choices(position)%kind)) cycle
         kinds = [kinds, export_choices(position)%kind]
      end do
   end function export_kinds

   !> The blank-separated words of `text`.
   pure function export_words(text) result(words)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: words(:)
      integer :: i, first, n
      allocate (character(len=max(1, len(text))) :: words(len(text)))
      n = 0
      first = 0
      do i = 1, len(text) + 1
         if (i <= len(text)) then
            if (text(i:i) /= ' ' .and. text(i:i) /= achar(9) .and. text(i:i) /= ',') then
               if (first == 0) first = i
               cycle
            end if
         end if
         if (first == 0) cycle
         n = n + 1
         words(n) = text(first:i - 1)
         first = 0
      end do
      words = words(1:n)
   end function export_words

end module ffrf_input_nml_run
