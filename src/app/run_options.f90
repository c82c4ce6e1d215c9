!> Run options shared by the modal and the mechanism run: where inputs come from and results go,
!> how much to log, overwrite and restart (the driver fills them from its command line).
module ffrf_app_run_options
   use ffrf_core_log, only: logger_t, LOG_QUIET
   use ffrf_core_parallel, only: parallel_t
   implicit none
   private
   public :: run_options_t, set_log_level

   !> Where inputs come from and results go, and how much to log.
   type :: run_options_t
      !> Folder of relative mesh files ('' = the case file's folder)
      character(len=:), allocatable :: mesh_dir
      !> Folder of the results ('' = current folder)
      character(len=:), allocatable :: output_dir
      !> Log level from the command line (-1: take &run log_level)
      integer :: log_level = -1
      !> Replace an existing results file when the run has finished (--no-overwrite: refuse
      !> to start when it exists)
      logical :: overwrite = .true.
      !> Results (or checkpoint) file of an earlier run of the case to continue from
      !> (--restart FILE; '' = start from t_start)
      character(len=:), allocatable :: restart_file
      !> The --sweep table the case's overrides came from ('' or unallocated: none); an input
      !> no output may overwrite (ffrf_app_output_paths)
      character(len=:), allocatable :: sweep_file
      !> The ranks of the run (MPI build: the driver's MPI_COMM_WORLD, the API's communicator;
      !> default one process); only rank 0 logs and writes files
      type(parallel_t) :: parallel
   end type run_options_t

contains

   !> The log level of the command line options, else that of the case (LOG_* of ffrf_core_log;
   !> the &run log_level word is mapped by ffrf_input_nml_run log_level_code).
   subroutine set_log_level(log, options, case_level)
      type(logger_t), intent(inout) :: log
      type(run_options_t), intent(in) :: options
      !> The case's level (LOG_QUIET, LOG_INFO or LOG_DEBUG)
      integer, intent(in) :: case_level
      log%level = options%log_level
      if (log%level < 0) log%level = case_level
      if (.not. options%parallel%is_root()) log%level = LOG_QUIET
   end subroutine set_log_level

end module ffrf_app_run_options
