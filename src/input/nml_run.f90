!> Namelist group &run (optional, single): what the run is called and where its results go.
!>   title            free text, echoed in the results and the log (at most 256 characters)
!>   output           results file (HDF5), relative to the output directory; default <case>.h5.
!>                    At most 256 characters; a relative path without '..' (outputs stay inside
!>                    --output-dir)
!>   mode_shapes_msh  Gmsh file to animate the modes (default <case>_modes.msh; 'none': no file);
!>                    same rules as output
!>   log_level        'quiet', 'info' (default) or 'debug'
!>   export           files written beside the results file, a list of words of export_choices
!>                    (ffrf_core_choices), blank-separated: 'xdmf' (<stem>.xdmf for ParaView),
!>                    'exudyn' (<stem>_<body>.exudyn.hdf5 per flexible body, modal or mechanism,
!>                    docs/results.md "Exudyn export"); default '' (none). The words are checked
!>                    by ffrf_input_case (choice_kinds of ffrf_core_choices)
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
   public :: run_input_t, read_run_group, run_keys, log_level_code

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
      !> Export words, lower case, blank-separated ('': none)
      character(len=64) :: export = ''
   end type run_input_t

contains

   !> Keys of &run, their types and what is allowed (module header).
   function run_keys() result(keys)
      type(key_spec_t), allocatable :: keys(:)
      keys = [string_key('title', 256), string_key('output', 256), &
         string_key('mode_shapes_msh', 256), choice_key('log_level', 16, &
         choice_words(log_level_choices)), string_key('export', 64)]
   end function run_keys

   !> Read &run from an open case file (optional group; defaults kept when absent).
   subroutine read_run_group(unit, input, error)
      integer, intent(in) :: unit
      type(run_input_t), intent(inout) :: input
      type(error_t), allocatable, intent(out) :: error
      character(len=256) :: title, output, mode_shapes_msh
      character(len=16) :: log_level
      character(len=64) :: export
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

end module ffrf_input_nml_run
