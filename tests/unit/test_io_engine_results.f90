!> Tests of ffrf_app_engine_results, the progressive writer of the engine time histories. Steps are
!> analytic functions of the step index; HDF5 stores IEEE doubles bit for bit, so every value
!> read back must equal the one written exactly (tolerance 0). A kill is simulated by copying
!> the file's bytes from disk after 550 steps with 100 steps per flush: the copy is what a killed
!> process leaves, and must hold exactly the 500 flushed steps with status 'running'.
!> Files go to tests/series/ under the working directory (ctest runs in the build tree), named
!> after the executable (the _checked variant never shares a file); the non-checked ones are
!> read by tests/postprocess/check_engine_series.py.
module test_io_engine_results
   use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_io_hdf5, only: h5_file_t, H5_READ_ONLY
   use ffrf_app_engine_results, only: engine_results_t
   use ffrf_testing, only: unittest_t, new_unittest, check
   implicit none
   private
   public :: collect_io_engine_results

   !> Time step of the synthetic run (s)
   real(dp), parameter :: DT = 1.0e-3_dp
   !> Mean crank speed (rad/s): 1234 steps cover 185 rad, more than 14 engine cycles
   real(dp), parameter :: W0 = 150.0_dp
   real(dp), parameter :: PI = 3.14159265358979323846_dp
   !> Modes of the two flexible bodies and number of joints
   integer, parameter :: MODES_CRANK = 3, MODES_ROD = 2, NUM_JOINTS = 2

contains

   subroutine collect_io_engine_results(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [ &
         new_unittest('complete_run_exact', test_complete_run), &
         new_unittest('killed_run_keeps_flushed_steps', test_killed_run), &
         new_unittest('error_missing_folder', test_missing_folder), &
         new_unittest('error_misuse', test_misuse)]
   end subroutine collect_io_engine_results

   ! ------------------------------------------------------------------ synthetic steps

   !> Scalars of step k (0-based): t, crank angle, speed, pressure, 4 energies.
   pure function scalars_of(k) result(s)
      integer, intent(in) :: k
      real(dp) :: s(8)
      real(dp) :: t
      t = k * DT
      s(1) = t
      s(2) = W0 * t + 0.05_dp * sin(2 * PI * t)
      s(3) = W0 + 0.1_dp * PI * cos(2 * PI * t)
      s(4) = 1.0e5_dp * (1 + 20 * sin(s(2) / 2)**2)
      s(5:8) = [0.5_dp * s(3)**2, 1.0e-3_dp * t**2, 3 * t, 1.0e-6_dp * exp(-t)]
   end function scalars_of

   !> Modal coordinates of step k: crank (3) then rod (2).
   pure function modal_of(k) result(q)
      integer, intent(in) :: k
      real(dp) :: q(MODES_CRANK + MODES_ROD)
      integer :: j
      do j = 1, size(q)
         q(j) = 1.0e-4_dp * sin(j * W0 * k * DT + j)
      end do
   end function modal_of

   !> Body coordinates of step k as `record` takes them: [R; theta; zeta] of the crank, then
   !> of the rod (R and theta: a turn about z at speed W0, R along a small circle).
   pure function coordinates_of(k) result(c)
      integer, intent(in) :: k
      real(dp) :: c(14 + MODES_CRANK + MODES_ROD)
      real(dp) :: q(MODES_CRANK + MODES_ROD)
      q = modal_of(k)
      c(1:7) = pose_of(k, 1)
      c(8:7 + MODES_CRANK) = q(1:MODES_CRANK)
      c(8 + MODES_CRANK:14 + MODES_CRANK) = pose_of(k, 2)
      c(15 + MODES_CRANK:) = q(MODES_CRANK + 1:)
   end function coordinates_of

   !> Reference position and Euler parameters of body b at step k.
   pure function pose_of(k, b) result(p)
      integer, intent(in) :: k, b
      real(dp) :: p(7)
      real(dp) :: phi
      phi = W0 * k * DT
      p = [0.01_dp * b * cos(phi), 0.01_dp * sin(phi), 0.0_dp, cos(phi / 2), 0.0_dp, 0.0_dp, &
         sin(phi / 2)]
   end function pose_of

   !> Reactions of step k (12, NUM_JOINTS).
   pure function reactions_of(k) result(r)
      integer, intent(in) :: k
      real(dp) :: r(12, NUM_JOINTS)
      integer :: i, j
      do j = 1, NUM_JOINTS
         do i = 1, 12
            r(i, j) = 1.0e3_dp * cos(W0 * k * DT + i) + 17.0_dp * j
         end do
      end do
   end function reactions_of

   !> tests/series/<executable>_<suffix>.h5
   function series_file(suffix) result(name)
      character(len=*), intent(in) :: suffix
      character(len=:), allocatable :: name
      character(len=512) :: exe
      integer :: slash
      call get_command_argument(0, exe)
      slash = index(exe, '/', back=.true.)
      name = 'tests/series/' // trim(exe(slash + 1:)) // '_' // suffix // '.h5'
   end function series_file

   !> Create a writer with two bodies and two joints, record steps 0 .. num_steps - 1.
   subroutine write_steps(writer, file_name, num_steps, error)
      type(engine_results_t), intent(inout) :: writer
      character(len=*), intent(in) :: file_name
      integer, intent(in) :: num_steps
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: s(8)
      integer :: k
      call writer%create(file_name, 'series_test', 'synthetic engine series', 'RC set 2', &
         'RBE3', '&run /', error)
      if (.not. allocated(error)) call writer%set_steps_per_flush(100, error)
      if (.not. allocated(error)) call writer%add_body_series('crank', MODES_CRANK, error)
      if (.not. allocated(error)) call writer%add_body_series('rod', MODES_ROD, error)
      if (.not. allocated(error)) call writer%add_joint_series('main_bearing', error)
      if (.not. allocated(error)) call writer%add_joint_series('piston_pin', error)
      if (allocated(error)) return
      do k = 0, num_steps - 1
         s = scalars_of(k)
         call writer%record(s(1), s(2), s(3), s(4), s(5:8), coordinates_of(k), reactions_of(k), &
            error)
         if (allocated(error)) return
      end do
   end subroutine write_steps

   !> Open `file_name` and check status, and that every series holds steps 0 .. num_steps - 1
   !> exactly (tolerance 0: HDF5 stores the bytes).
   subroutine check_file(file_name, status, num_steps, error)
      character(len=*), intent(in) :: file_name, status
      integer, intent(in) :: num_steps
      type(error_t), allocatable, intent(out) :: error
      character(len=*), parameter :: paths(8) = [character(len=35) :: '/time/t', &
         '/time/crank_angle', '/time/crank_speed', '/time/pressure', '/energy/kinetic', &
         '/energy/strain', '/energy/external_work', '/energy/numerical_dissipation']
      character(len=*), parameter :: joints(NUM_JOINTS) = [character(len=12) :: &
         'main_bearing', 'piston_pin']
      type(h5_file_t) :: h5
      type(error_t), allocatable :: closing
      real(dp), allocatable :: v1(:), v2(:, :)
      character(len=:), allocatable :: text
      real(dp) :: expected(8, 0:num_steps - 1), q(5, 0:num_steps - 1)
      real(dp) :: r(12, NUM_JOINTS, 0:num_steps - 1), pose(7, 2, 0:num_steps - 1)
      integer :: i, k

      do k = 0, num_steps - 1
         expected(:, k) = scalars_of(k)
         q(:, k) = modal_of(k)
         r(:, :, k) = reactions_of(k)
         pose(:, 1, k) = pose_of(k, 1)
         pose(:, 2, k) = pose_of(k, 2)
      end do
      call h5%open(file_name, H5_READ_ONLY, error)
      if (allocated(error)) return
      call h5%get_status(text, error)
      if (.not. allocated(error)) call check(error, 'status "' // text // '", expected "' // &
         status // '"', text == status)
      if (.not. allocated(error)) call h5%read_attribute('/engine', 'rc_set', text, error)
      if (.not. allocated(error)) call check(error, 'rc_set "' // text // '"', text == 'RC set 2')
      if (.not. allocated(error)) call h5%read_attribute('/engine', 'mpc', text, error)
      if (.not. allocated(error)) call check(error, 'mpc "' // text // '"', text == 'RBE3')
      do i = 1, size(paths)
         if (allocated(error)) exit
         call h5%read_real(trim(paths(i)), v1, error)
         if (.not. allocated(error)) call check(error, trim(paths(i)) // ' has ' // &
            to_str(size(v1)) // ' steps, expected ' // to_str(num_steps), size(v1) == num_steps)
         if (.not. allocated(error)) call check(error, trim(paths(i)) // ' differs, max ' // &
            to_str(maxval(abs(v1 - expected(i, :)))), all(v1 == expected(i, :)))
      end do
      if (.not. allocated(error)) call h5%read_real('/bodies/crank/modal_coordinates', v2, error)
      if (.not. allocated(error)) call check(error, 'crank modal coordinates shape ' // &
         to_str(size(v2, 1)) // ' x ' // to_str(size(v2, 2)), &
         size(v2, 1) == MODES_CRANK .and. size(v2, 2) == num_steps)
      if (.not. allocated(error)) call check(error, 'crank modal coordinates differ', &
         all(v2 == q(1:MODES_CRANK, :)))
      if (.not. allocated(error)) call h5%read_real('/bodies/rod/euler_parameters', v2, error)
      if (.not. allocated(error)) call check(error, 'rod Euler parameters shape ' // &
         to_str(size(v2, 1)) // ' x ' // to_str(size(v2, 2)), &
         size(v2, 1) == 4 .and. size(v2, 2) == num_steps)
      if (.not. allocated(error)) call check(error, 'rod Euler parameters differ', &
         all(v2 == pose(4:7, 2, :)))
      if (.not. allocated(error)) call h5%read_real('/bodies/crank/position', v2, error)
      if (.not. allocated(error)) call check(error, 'crank position differs', &
         all(v2 == pose(1:3, 1, :)))
      if (.not. allocated(error)) call h5%read_real('/bodies/rod/modal_coordinates', v2, error)
      if (.not. allocated(error)) call check(error, 'rod modal coordinates shape ' // &
         to_str(size(v2, 1)) // ' x ' // to_str(size(v2, 2)), &
         size(v2, 1) == MODES_ROD .and. size(v2, 2) == num_steps)
      if (.not. allocated(error)) call check(error, 'rod modal coordinates differ', &
         all(v2 == q(MODES_CRANK + 1:, :)))
      do i = 1, NUM_JOINTS
         if (allocated(error)) exit
         call h5%read_real('/joints/' // trim(joints(i)) // '/reaction', v2, error)
         if (.not. allocated(error)) call check(error, trim(joints(i)) // ' reaction shape ' // &
            to_str(size(v2, 1)) // ' x ' // to_str(size(v2, 2)), &
            size(v2, 1) == 12 .and. size(v2, 2) == num_steps)
         if (.not. allocated(error)) call check(error, trim(joints(i)) // ' reaction differs', &
            all(v2 == r(:, i, :)))
      end do
      call h5%close(closing)
      if (.not. allocated(error) .and. allocated(closing)) call move_alloc(closing, error)
   end subroutine check_file

   ! ------------------------------------------------------------------ tests

   !> 1234 steps, 100 per flush, finish: every series complete and exact, timings written.
   subroutine test_complete_run(error)
      type(error_t), allocatable, intent(out) :: error
      type(engine_results_t) :: writer
      type(h5_file_t) :: h5
      type(error_t), allocatable :: closing
      character(len=:), allocatable :: file_name, stages(:)
      real(dp), allocatable :: seconds(:)
      logical :: timings_ok
      file_name = series_file('complete')
      call write_steps(writer, file_name, 1234, error)
      if (.not. allocated(error)) call check(error, 'num_steps ' // to_str(writer%num_steps()), &
         writer%num_steps() == 1234)
      if (.not. allocated(error)) call writer%finish('complete', &
         [character(len=11) :: 'setup', 'integration', 'total'], [0.25_dp, 1.5_dp, 1.75_dp], error)
      if (.not. allocated(error)) call check_file(file_name, 'complete', 1234, error)
      if (allocated(error)) return
      call h5%open(file_name, H5_READ_ONLY, error)
      if (.not. allocated(error)) call h5%read_string_list('/timings/stage', stages, error)
      if (.not. allocated(error)) call h5%read_real('/timings/seconds', seconds, error)
      if (.not. allocated(error)) then
         timings_ok = size(stages) == 3 .and. size(seconds) == 3
         if (timings_ok) timings_ok = trim(stages(3)) == 'total' .and. &
            all(seconds == [0.25_dp, 1.5_dp, 1.75_dp])
         call check(error, 'timings /timings/stage and /timings/seconds', timings_ok)
      end if
      call h5%close(closing)
      if (.not. allocated(error) .and. allocated(closing)) call move_alloc(closing, error)
   end subroutine test_complete_run

   !> 550 steps, 100 per flush, no finish: a byte copy of the file on disk (what a kill
   !> leaves) opens and holds exactly the 500 flushed steps with status 'running'. Then finish
   !> with an error message: the original holds all 550 steps and that message as status.
   subroutine test_killed_run(error)
      type(error_t), allocatable, intent(out) :: error
      type(engine_results_t) :: writer
      character(len=:), allocatable :: file_name, killed_name
      character(len=*), parameter :: failure = 'Newton iteration did not converge at t = 0.55 s'
      character(len=0) :: no_stages(0)
      real(dp) :: no_seconds(0)
      file_name = series_file('abandoned')
      killed_name = series_file('killed')
      call write_steps(writer, file_name, 550, error)
      if (.not. allocated(error)) call copy_file(file_name, killed_name, error)
      if (.not. allocated(error)) call check_file(killed_name, 'running', 500, error)
      if (.not. allocated(error)) call writer%finish(failure, no_stages, no_seconds, error)
      if (.not. allocated(error)) call check_file(file_name, failure, 550, error)
   end subroutine test_killed_run

   !> Creating a file in a missing folder: an error naming the file.
   subroutine test_missing_folder(error)
      type(error_t), allocatable, intent(out) :: error
      type(engine_results_t) :: writer
      type(error_t), allocatable :: failed
      character(len=*), parameter :: name = 'no_such_folder_series/engine.h5'
      call writer%create(name, 'c', 't', 'RC set 1', 'RBE3', '&run /', failed)
      call check(error, 'create in a missing folder gave no error', allocated(failed))
      if (allocated(error)) return
      call check(error, 'message does not name the file: ' // failed%message, &
         index(failed%message, name) > 0)
   end subroutine test_missing_folder

   !> Wrong sizes, a NaN, a body added after the first step: errors, nothing recorded.
   subroutine test_misuse(error)
      type(error_t), allocatable, intent(out) :: error
      type(engine_results_t) :: writer
      type(error_t), allocatable :: failed
      real(dp) :: s(8), nan, q(MODES_CRANK + MODES_ROD)
      character(len=0) :: no_stages(0)
      real(dp) :: no_seconds(0)
      call write_steps(writer, series_file('misuse'), 3, error)
      if (allocated(error)) return
      s = scalars_of(3)
      q = modal_of(3)
      call writer%record(s(1), s(2), s(3), s(4), s(5:8), q(1:4), reactions_of(3), failed)
      call check(error, 'too few body coordinates accepted', allocated(failed))
      if (allocated(error)) return
      nan = ieee_value(nan, ieee_quiet_nan)
      call writer%record(s(1), s(2), nan, s(4), s(5:8), coordinates_of(3), reactions_of(3), &
         failed)
      call check(error, 'NaN crank speed accepted', allocated(failed))
      if (allocated(error)) return
      call writer%add_body_series('late', 2, failed)
      call check(error, 'body added after the first step', allocated(failed))
      if (allocated(error)) return
      call check(error, 'steps ' // to_str(writer%num_steps()) // ', expected 3', &
         writer%num_steps() == 3)
      if (.not. allocated(error)) call writer%finish('complete', no_stages, no_seconds, error)
      if (.not. allocated(error)) call check_file(series_file('misuse'), 'complete', 3, error)
   end subroutine test_misuse

   !> Copy a file byte for byte (stream access).
   subroutine copy_file(source, dest, error)
      character(len=*), intent(in) :: source, dest
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: bytes
      integer :: unit_in, unit_out, stat, nbytes
      open (newunit=unit_in, file=source, access='stream', form='unformatted', action='read', &
         status='old', iostat=stat)
      if (stat == 0) inquire (unit=unit_in, size=nbytes)
      if (stat /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'cannot open ' // source)
         return
      end if
      allocate (character(len=nbytes) :: bytes)
      read (unit_in, iostat=stat) bytes
      close (unit_in)
      if (stat == 0) open (newunit=unit_out, file=dest, access='stream', &
         form='unformatted', action='write', status='replace', iostat=stat)
      if (stat == 0) then
         write (unit_out, iostat=stat) bytes
         close (unit_out)
      end if
      if (stat /= 0) call fatal_error(error, FFRF_NUMERIC_ERROR, 'cannot copy ' // source // &
         ' to ' // dest)
   end subroutine copy_file

end module test_io_engine_results

program main_io_engine_results
   use ffrf_testing, only: unittest_t, run_suite
   use test_io_engine_results, only: collect_io_engine_results
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_io_engine_results(tests)
   call run_suite('io_engine_results', tests)
end program main_io_engine_results
