!> The exports of a case through the Fortran API (ffrf_case_t%set_export; issue 26, &run export).
!> Usage: test_export_fortran CASE MESH_DIR OUT_DIR
!> CASE is a modal case without &run export (xdmf_beam_tet4_plain.nml of tests/regression/
!> xdmf.cmake: the Tet4 beam, 4 modes, results <stem>.h5).
!>  - an unknown word is refused (FFRF_INPUT_ERROR naming it, the case left as it was);
!>  - 'xdmf exudyn' set, the case run with an output folder: OUT_DIR/<stem>.xdmf and
!>    OUT_DIR/<stem>_beam.exudyn.hdf5 exist (ctest capi_export_fortran_xdmf then reads the XDMF
!>    back with meshio: every mode bitwise equal to the results file's);
!>  - a call after the run is refused (FFRF_BAD_CALL).
program test_export_fortran
   use ffrf, only: ffrf_case_t, error_t, FFRF_BAD_CALL, FFRF_INPUT_ERROR
   use api_checks, only: expect
   implicit none
   type(ffrf_case_t) :: api
   type(error_t), allocatable :: error
   character(len=512) :: case_file, mesh_dir, out_dir
   character(len=:), allocatable :: stem
   integer :: failures
   failures = 0
   call get_command_argument(1, case_file)
   call get_command_argument(2, mesh_dir)
   call get_command_argument(3, out_dir)
   stem = trim(out_dir) // '/xdmf_beam_tet4_plain'

   call api%open(trim(case_file), error, mesh_dir=trim(mesh_dir), output_dir=trim(out_dir))
   call expect(error, failures, 0, '')
   call api%set_export('xdmf vtk', error)
   call expect(error, failures, FFRF_INPUT_ERROR, 'export = "vtk" is not an export format')
   call api%set_export('xdmf exudyn', error)
   call expect(error, failures, 0, '')
   call api%run(error)
   call expect(error, failures, 0, '')
   call expect_file(stem // '.xdmf')
   call expect_file(stem // '_beam.exudyn.hdf5')
   call api%set_export('xdmf', error)
   call expect(error, failures, FFRF_BAD_CALL, '')
   call api%close()
   if (failures > 0) then
      print '(i0, a)', failures, ' failures'
      error stop 1
   end if
   print '(a)', 'fortran export: all checks passed'
contains

   !> The run wrote `path`.
   subroutine expect_file(path)
      character(len=*), intent(in) :: path
      logical :: exists
      inquire (file=path, exist=exists)
      if (.not. exists) then
         print '(a)', 'FAIL: no file ' // path
         failures = failures + 1
      end if
   end subroutine expect_file
end program test_export_fortran
