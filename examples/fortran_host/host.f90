!> A Fortran host loop over ffrf (`use ffrf`, ffrf_case_t): the reference engine advanced in
!> 1 ms steps with the host's own load torque at the crank, T = -c omega |omega| (the case's
!> `drag` load, c = 3.6e-4 N m s^2), computed from the crank speed at the start of each step
!> and held constant over it; compared with the engine run with its own `drag` load, which the
!> integrator evaluates at every time step (the run the ffrf driver makes; ffrf_case_run and
!> ffrf_mechanism_advance take the driver's very steps, tests/capi).
!>
!> Error of holding the torque. Over a step [t_k, t_k + D] the held torque misses
!> T(t) - T(t_k) ~ T'(t_k) (t - t_k), an angular impulse of T' D^2 / 2 per step; summed over the
!> steps it is (D / 2) (T(t) - T(0)): the held torque lags by half a step. On the crank axis,
!> with an effective inertia J >= J_min = flywheel + crank about the axis (the conrod and the
!> piston only add), the crank speed differs by at most
!>     |d omega| <= (D / 2) max |T(t) - T(0)| / J_min        (T(0) = 0: the engine starts at rest)
!> and the crank angle by at most t_end times that. The program derives J_min from the model
!> (flywheel 0.030 kg m^2 about its axis in the case; the crank's mass properties through the
!> API), prints both bounds and the measured differences, and fails if a difference passes
!> its bound.
!>
!> Usage: host CASE_DIR MESH_DIR OUT_DIR   (CASE_DIR holds engine_rc1.nml; MESH_DIR the lc 8 mm
!> meshes crank_lc8.msh, conrod_lc8.msh; OUT_DIR receives the two short case files)
program fortran_host
   use ffrf, only: ffrf_case_t, error_t, dp
   implicit none
   !> Host step (s), run length (s), drag coefficient of the case (N m s^2)
   real(dp), parameter :: step = 1.0e-3_dp, t_end = 0.05_dp, c = 3.6e-4_dp
   !> Flywheel inertia about the crank axis in engine_rc1.nml (kg m^2; its centre is on it)
   real(dp), parameter :: flywheel_inertia = 0.030_dp
   !> Crank: body 1 of the case; its marker 3 is interface B3, where the drag load acts
   integer, parameter :: crank = 1, crank_b3 = 3
   integer, parameter :: num_steps = nint(t_end / step)
   type(ffrf_case_t) :: reference, host
   type(error_t), allocatable :: error
   character(len=512) :: case_dir, mesh_dir, out_dir
   real(dp) :: angle_ref(0:num_steps), speed_ref(0:num_steps), angle(0:num_steps), &
      speed(0:num_steps), torque, max_torque, mass, center(3), inertia(3, 3), j_min, &
      bound_speed, bound_angle, diff_speed, diff_angle, cpu(4)
   integer :: k

   call get_command_argument(1, case_dir)
   call get_command_argument(2, mesh_dir)
   call get_command_argument(3, out_dir)
   call write_cases(trim(case_dir) // '/engine_rc1.nml', trim(out_dir))

   ! The reference: the case's own drag load, 1 ms chunks (the driver's steps)
   call reference%open(trim(out_dir) // '/host_drag.nml', error, mesh_dir=trim(mesh_dir))
   call check(error)
   call reference%advance(0.0_dp, error)
   call check(error)
   call reference%crank_state(angle_ref(0), speed_ref(0), error)
   call cpu_time(cpu(1))
   do k = 1, num_steps
      call reference%advance(k * step, error)
      call check(error)
      call reference%crank_state(angle_ref(k), speed_ref(k), error)
      call check(error)
   end do
   call cpu_time(cpu(2))

   ! The host: no drag load in the case; T = -c omega |omega| held over each 1 ms step
   call host%open(trim(out_dir) // '/host_free.nml', error, mesh_dir=trim(mesh_dir))
   call check(error)
   call host%advance(0.0_dp, error)
   call check(error)
   call host%crank_state(angle(0), speed(0), error)
   max_torque = 0.0_dp
   call cpu_time(cpu(3))
   do k = 1, num_steps
      torque = -c * speed(k - 1) * abs(speed(k - 1))
      max_torque = max(max_torque, abs(torque))
      call host%set_marker_load(crank, crank_b3, [0.0_dp, 0.0_dp, 0.0_dp], &
         [0.0_dp, 0.0_dp, torque], error)
      call check(error)
      call host%advance(k * step, error)
      call check(error)
      call host%crank_state(angle(k), speed(k), error)
      call check(error)
   end do
   call cpu_time(cpu(4))
   ! the torque at t_end counts too for max |T(t) - T(0)|
   max_torque = max(max_torque, c * speed(num_steps)**2)

   ! The bound: J_min = flywheel + crank about the axis (parallel axes from the centre of mass)
   call host%mass_properties(crank, mass, center, inertia, error)
   call check(error)
   j_min = flywheel_inertia + inertia(3, 3) + mass * (center(1)**2 + center(2)**2)
   bound_speed = 0.5_dp * step * max_torque / j_min
   bound_angle = t_end * bound_speed
   diff_speed = maxval(abs(speed - speed_ref))
   diff_angle = maxval(abs(angle - angle_ref))
   print '(a, f8.4, a, f10.4, a, f10.6, a)', 'fortran_host: t_end = ', t_end, &
      ' s; crank speed ', speed(num_steps), ' rad/s, angle ', angle(num_steps), ' rad'
   print '(a, es10.3, a, es10.3, a)', 'fortran_host: largest host torque ', max_torque, &
      ' N m, J_min = ', j_min, ' kg m^2'
   print '(a, es10.3, a, es10.3, a)', 'fortran_host: crank speed difference ', diff_speed, &
      ' rad/s, bound (D/2) max|T| / J_min = ', bound_speed, ' rad/s'
   print '(a, es10.3, a, es10.3, a)', 'fortran_host: crank angle difference ', diff_angle, &
      ' rad, bound t_end * that = ', bound_angle, ' rad'
   ! (some 50 ms of CPU each: an indication, not a benchmark)
   print '(a, f8.3, a, f8.3, a)', 'fortran_host: integration CPU time: drag run ', &
      cpu(2) - cpu(1), ' s, host loop ', cpu(4) - cpu(3), ' s'
   call reference%close()
   call host%close()
   if (diff_speed > bound_speed .or. diff_angle > bound_angle) then
      print '(a)', 'fortran_host: FAILED: a difference passes its bound'
      error stop 1
   end if
   if (.not. (diff_speed > 0.0_dp)) then
      print '(a)', 'fortran_host: FAILED: no difference at all (is the host torque applied?)'
      error stop 1
   end if
   print '(a)', 'fortran_host: host loop matches the drag run within the bound'

contains

   !> Stop the example with the message of a failed call.
   subroutine check(error)
      type(error_t), allocatable, intent(in) :: error
      if (.not. allocated(error)) return
      print '(a, i0, a)', 'fortran_host: error ', error%code, ': ' // error%message
      error stop 1
   end subroutine check

   !> host_drag.nml and host_free.nml from engine_rc1.nml: lc 8 mm meshes, 10 modes per flexible
   !> body, h = 1e-4 s, t_end; host_free without the `drag` load.
   subroutine write_cases(source, folder)
      character(len=*), intent(in) :: source, folder
      character(len=1024) :: line
      character(len=:), allocatable :: text
      integer :: in, drag, free, stat
      open (newunit=in, file=source, status='old', action='read', iostat=stat)
      if (stat /= 0) then
         print '(a)', 'fortran_host: cannot read ' // source
         error stop 1
      end if
      open (newunit=drag, file=folder // '/host_drag.nml', status='replace', action='write')
      open (newunit=free, file=folder // '/host_free.nml', status='replace', action='write')
      do
         read (in, '(a)', iostat=stat) line
         if (stat /= 0) exit
         text = trim(line)
         call replace(text, "'crank.msh'", "'crank_lc8.msh'")
         call replace(text, "'conrod.msh'", "'conrod_lc8.msh'")
         call replace(text, "selection = 'auto'", "selection = 'manual'")
         call replace(text, '&integrator t_end = 2.0', '&integrator h = 1.0e-4, t_end = 0.05')
         call replace(text, "type = 'flexible',", "type = 'flexible', num_modes = 10,")
         write (drag, '(a)') text
         if (index(text, "type = 'drag'") == 0) write (free, '(a)') text
      end do
      close (in)
      close (drag)
      close (free)
   end subroutine write_cases

   !> Replace the first `old` in text by `new`.
   subroutine replace(text, old, new)
      character(len=:), allocatable, intent(inout) :: text
      character(len=*), intent(in) :: old, new
      integer :: i
      i = index(text, old)
      if (i > 0) text = text(:i - 1) // new // text(i + len(old):)
   end subroutine replace

end program fortran_host
