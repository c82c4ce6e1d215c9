!> The exports of &run export beside the results of a modal run, dispatched per word (the one
!> place a run calls them from): 'exudyn' writes each flexible body as `<stem>_<body>.exudyn.hdf5`
!> (ffrf_io_exudyn_body; docs/results.md "Exudyn export"), `<stem>` the results file without its
!> extension.
module ffrf_app_body_export
   use ffrf_core_error, only: error_t
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: logger_t, stage_timer_t
   use ffrf_core_paths, only: stem_of
   use ffrf_core_choices, only: EXPORT_EXUDYN
   use ffrf_la_sparse, only: csr_t
   use ffrf_modes_modal_analysis, only: body_modes_t
   use ffrf_io_exudyn_body, only: write_exudyn_body
   use ffrf_input_nml_run, only: export_kinds
   implicit none
   private
   public :: export_body, exports_matrices, exudyn_file_name

contains

   !> True when an export of `export` (the &run export words) needs the bodies' M and K.
   pure logical function exports_matrices(export)
      character(len=*), intent(in) :: export
      exports_matrices = any(export_kinds(export) == EXPORT_EXUDYN)
   end function exports_matrices

   !> Write every export of `export` for one body whose modes are computed.
   subroutine export_body(export, results_file, body, M, K, log, error)
      !> &run export words
      character(len=*), intent(in) :: export
      !> The run's results file (the exports sit beside it)
      character(len=*), intent(in) :: results_file
      !> The body with its modes
      type(body_modes_t), intent(in) :: body
      !> The body's FE mass and stiffness matrices (those its modes come from)
      type(csr_t), intent(in) :: M, K
      !> Progress log
      type(logger_t), intent(in) :: log
      type(error_t), allocatable, intent(out) :: error
      integer, allocatable :: kinds(:)
      type(stage_timer_t) :: timer
      character(len=:), allocatable :: file_name
      integer :: i_kind
      kinds = export_kinds(export)
      do i_kind = 1, size(kinds)
         call timer%begin()
         select case (kinds(i_kind))
         case (EXPORT_EXUDYN)
            file_name = exudyn_file_name(results_file, body%name)
            call write_exudyn_body(file_name, body, M, K, error)
            if (allocated(error)) return
            call log%info('output', 'Exudyn body written: ' // file_name // ' ... ' // &
               to_str(timer%seconds(), 3) // ' s')
         end select
      end do
   end subroutine export_body

   !> `<stem>_<body>.exudyn.hdf5` beside the results file `<stem>.<ext>` (Exudyn's
   !> FEMinterface.LoadFromFile takes an HDF5 file by its '.hdf5' ending only).
   pure function exudyn_file_name(results_file, body_name) result(name)
      character(len=*), intent(in) :: results_file, body_name
      character(len=:), allocatable :: name
      name = stem_of(results_file) // '_' // body_name // '.exudyn.hdf5'
   end function exudyn_file_name

end module ffrf_app_body_export
