!> The starting pose of a body through the Fortran API (ffrf_case_t%set_pose; issue 24, body
!> pose). Usage: test_pose_fortran POSE_FREE_CASE POSED_CASE MESH_DIR
!> (tests/capi/pose_pendulum.nml and pose_pendulum_posed.nml: a rigid rod hinged at its end,
!> without and with the pose in the namelist).
!>  - the pose-free case given the posed case's pose by set_pose (in two calls: absent arguments
!>    keep the values of the first) and advanced to t_end in 0.1 s chunks equals, bitwise, the
!>    posed case advanced alike (q, v of the rod, the tip sensor, the hinge reaction);
!>  - refusals: bad body index (FFRF_BAD_CALL), a matrix that is not orthonormal and a
!>    reflection (FFRF_INPUT_ERROR naming the body and the defect), after the first advance
!>    (FFRF_BAD_CALL).
program test_pose_fortran
   use ffrf, only: ffrf_case_t, error_t, dp, FFRF_BAD_CALL, FFRF_INPUT_ERROR
   use api_checks, only: expect
   implicit none
   type(ffrf_case_t) :: api, nml
   type(error_t), allocatable :: error
   character(len=512) :: free_case, posed_case, mesh_dir
   ! the rotation A (body -> global) of pose_pendulum_posed.nml, whose rows it gives
   real(dp), parameter :: A(3, 3) = reshape([0.6_dp, 0.0_dp, -0.8_dp, 0.0_dp, 1.0_dp, 0.0_dp, &
      0.8_dp, 0.0_dp, 0.6_dp], [3, 3])
   real(dp), allocatable :: q1(:), v1(:), q2(:), v2(:), s1(:), s2(:)
   real(dp) :: f1(3, 2), m1(3, 2), f2(3, 2), m2(3, 2), bent(3, 3)
   integer :: failures, k
   failures = 0
   call get_command_argument(1, free_case)
   call get_command_argument(2, posed_case)
   call get_command_argument(3, mesh_dir)

   call api%open(trim(free_case), error, mesh_dir=trim(mesh_dir))
   call expect(error, failures, 0, '')
   call api%set_pose(2, error, position=[0.3_dp, 0.0_dp, -0.4_dp])
   call expect(error, failures, FFRF_BAD_CALL, 'body 1 does not exist')
   bent = A
   bent(1, 1) = 0.6_dp + 1.0e-6_dp
   call api%set_pose(1, error, orientation=bent)
   call expect(error, failures, FFRF_INPUT_ERROR, '"rod": the orientation is not orthonormal')
   call api%set_pose(1, error, orientation=-A)
   call expect(error, failures, FFRF_INPUT_ERROR, '"rod": the orientation has det = -1')
   call api%set_pose(1, error, velocity=[-0.8_dp, 0.0_dp, -0.6_dp], &
      angular_velocity=[0.0_dp, 2.0_dp, 0.0_dp])
   call expect(error, failures, 0, '')
   call api%set_pose(1, error, position=[0.3_dp, 0.0_dp, -0.4_dp], orientation=A)
   call expect(error, failures, 0, '')
   call nml%open(trim(posed_case), error, mesh_dir=trim(mesh_dir))
   call expect(error, failures, 0, '')

   do k = 0, 5
      call api%advance(0.1_dp * k, error)
      call expect(error, failures, 0, '')
      call nml%advance(0.1_dp * k, error)
      call expect(error, failures, 0, '')
      call api%body_state(1, q1, v1, error)
      call nml%body_state(1, q2, v2, error)
      call api%sensor_values(1, s1, error)
      call nml%sensor_values(1, s2, error)
      call api%joint_reaction(1, f1, m1, error)
      call nml%joint_reaction(1, f2, m2, error)
      if (any(q1 /= q2) .or. any(v1 /= v2) .or. any(s1 /= s2) .or. any(f1 /= f2) .or. &
         any(m1 /= m2)) then
         print '(a, f4.1, a)', 'FAIL: at t = ', 0.1_dp * k, ' s the API pose run differs ' // &
            'from the namelist pose run'
         print '(a, 7es24.16)', '  q api ', q1
         print '(a, 7es24.16)', '  q nml ', q2
         failures = failures + 1
      end if
   end do
   ! the tip is the hinge end: on the pivot, and the rod moved away from its start
   if (maxval(abs(s1)) > 1.0e-9_dp .or. abs(q1(1) - 0.3_dp) < 1.0e-2_dp) then
      print '(a, 3es12.4, a, es12.4)', 'FAIL: tip ', s1, ', x = ', q1(1)
      failures = failures + 1
   end if
   call api%set_pose(1, error, position=[0.3_dp, 0.0_dp, -0.4_dp])
   call expect(error, failures, FFRF_BAD_CALL, 'the motion has started')
   call api%close()
   call nml%close()
   if (failures > 0) then
      print '(i0, a)', failures, ' failures'
      error stop 1
   end if
   print '(a)', 'fortran pose: all checks passed'
end program test_pose_fortran
