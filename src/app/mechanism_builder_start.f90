!> The starting state of a mechanism being built (ffrf_app_mechanism_builder): the pose assembled
!> from the &body poses, checked against elastic closure, and the velocities projected.
submodule (ffrf_app_mechanism_builder) ffrf_app_mechanism_builder_start
   implicit none

contains

   module procedure starting_state
      integer :: k, offset
      real(dp) :: angle, tolerance
      real(dp), allocatable :: q_given(:), v_given(:)
      logical :: moving
      allocate (q(mech%num_coordinates()), v(mech%num_coordinates()), source=0.0_dp)
      do k = 1, size(bodies)
         offset = mech%bodies(bodies(k)%index)%offset
         associate (motion => resolved%bodies(k)%motion)
            q(offset + 1:offset + 3) = motion%position
            if (rotated(motion%orientation)) then
               q(offset + 4:offset + 7) = euler_from_rotation(motion%orientation)
            else
               q(offset + 4) = 1.0_dp
            end if
         end associate
      end do
      moving = any([(any(resolved%bodies(k)%motion%velocity /= 0.0_dp) .or. &
         any(resolved%bodies(k)%motion%angular_velocity /= 0.0_dp), k = 1, size(bodies))])
      q_given = q
      angle = case%mechanism%mechanism%crank_angle_deg * pi / 180.0_dp
      ! The joints close to the integrator's constraint tolerance: a mesh's virtual nodes are
      ! off their ideal places by round-off of the mesh (~1e-8 m on the crank), which a few
      ! modes cannot always absorb exactly (a 1e-11 m misfit was seen on the reference engine).
      tolerance = resolved%mechanism%integrator%newton_atol
      if (mech%rotor > 0) then
         call mech%assemble(q, 0.0_dp, error, rotor_angle=angle, tolerance=tolerance)
      else
         call mech%assemble(q, 0.0_dp, error, tolerance=tolerance)
      end if
      v_given = given_velocities(resolved, bodies, mech, q)
      if (allocated(error)) then
         ! (reported below)
      else if (mech%rotor > 0 .and. moving) then
         call mech%initial_velocities(q, 0.0_dp, v, error, &
            rotor_speed=case%mechanism%mechanism%crank_speed, guess=v_given)
      else if (mech%rotor > 0) then
         call mech%initial_velocities(q, 0.0_dp, v, error, &
            rotor_speed=case%mechanism%mechanism%crank_speed)
      else if (moving) then
         call mech%initial_velocities(q, 0.0_dp, v, error, guess=v_given)
      else
         call mech%initial_velocities(q, 0.0_dp, v, error)
      end if
      if (allocated(error)) then
         call add_context(error, 'assembling the starting pose (check the &body positions, ' // &
            'orientations and &marker points: the joints must nearly close)')
         return
      end if
      do k = 1, size(bodies)
         call log_assembly(trim(resolved%bodies(k)%name), &
            mech%bodies(bodies(k)%index)%offset, q_given, v_given, q, v, log)
         call check_assembly_deformation(trim(resolved%bodies(k)%name), bodies(k), &
            q(mech%bodies(bodies(k)%index)%offset + 8:), log, error)
         if (allocated(error)) return
      end do
   end procedure starting_state

   !> The assembly may move a flexible body's modal coordinates (from zero) to close its joints
   !> on the round-off of the mesh's virtual nodes (~1e-8 m on the reference crank); it must
   !> not close a gap of the given geometry by deforming the body (a 0.3 m link stretched to
   !> a ground point 5 m away, issue 24). Refused when an interface's elastic displacement
   !> Psi_v zeta exceeds 1e-3 of the body's size (its mesh's bounding-box diagonal), a strain
   !> no linear FFRF body should start with; the log states the largest one otherwise.
   subroutine check_assembly_deformation(name, body, zeta, log, error)
      character(len=*), intent(in) :: name
      type(built_body_t), intent(in) :: body
      !> The body's modal coordinates after the assembly (and what follows them, unused)
      real(dp), intent(in) :: zeta(:)
      type(logger_t), intent(in) :: log
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: limit = 1.0e-3_dp
      real(dp) :: size_m, largest, u
      integer :: i, worst
      if (body%num_modes == 0 .or. .not. allocated(body%modes%mesh%xyz) .or. &
         .not. allocated(body%modes%virtual_node_shape)) return
      associate (shape => body%modes%virtual_node_shape, xyz => body%modes%mesh%xyz)
         if (size(shape, 2) /= body%num_modes) return
         size_m = norm2(maxval(xyz, dim=2) - minval(xyz, dim=2))
         largest = 0.0_dp
         worst = 1
         do i = 1, size(shape, 1) / 6
            u = norm2(matmul(shape(6 * i - 5:6 * i - 3, :), zeta(:body%num_modes)))
            if (u > largest) then
               largest = u
               worst = i
            end if
         end do
      end associate
      call log%info('assembly', 'body "' // name // '": largest elastic displacement of an ' &
         // 'interface ' // to_str(largest, 3) // ' m (' // to_str(largest / size_m, 3) // &
         ' of its size ' // to_str(size_m, 4) // ' m)')
      if (largest > limit * size_m) call fatal_error(error, FFRF_INPUT_ERROR, &
         'assembling the starting pose: the joints close only by deforming body "' // name // &
         '": its interface "' // body%modes%interfaces(worst)%name // '" moves ' // &
         to_str(largest, 3) // ' m elastically, more than ' // to_str(limit) // ' of the ' // &
         'body''s size (' // to_str(size_m, 4) // ' m); check the &marker points and &body ' // &
         'positions: the joints must close with the bodies undeformed')
   end subroutine check_assembly_deformation

   !> The starting velocities of the &body keys at the assembled pose q: the frame origin's
   !> velocity and the Euler-parameter rates theta_dot = G(theta)^T omega / 4 of the global
   !> angular velocity (G G^T = 4 I, G theta = 0); modal rates zero.
   function given_velocities(resolved, bodies, mech, q) result(v)
      type(model_t), intent(in) :: resolved
      type(built_body_t), intent(in) :: bodies(:)
      type(mechanism_t), intent(in) :: mech
      real(dp), intent(in) :: q(:)
      real(dp) :: v(size(q))
      integer :: k, offset
      v = 0.0_dp
      do k = 1, size(bodies)
         offset = mech%bodies(bodies(k)%index)%offset
         associate (motion => resolved%bodies(k)%motion)
            v(offset + 1:offset + 3) = motion%velocity
            v(offset + 4:offset + 7) = 0.25_dp * matmul(transpose(euler_g(q(offset + 4:offset &
               + 7))), motion%angular_velocity)
         end associate
      end do
   end function given_velocities

   !> One log line: how far the assembly moved a body (its frame origin, m) and changed its
   !> velocity (of the frame origin, m/s) from the &body keys.
   subroutine log_assembly(name, offset, q_given, v_given, q, v, log)
      character(len=*), intent(in) :: name
      !> The body's coordinates are q(offset + 1:)
      integer, intent(in) :: offset
      real(dp), intent(in) :: q_given(:), v_given(:), q(:), v(:)
      type(logger_t), intent(in) :: log
      real(dp) :: rates(3)
      rates = matmul(euler_g(q(offset + 4:offset + 7)), v(offset + 4:offset + 7) - &
         v_given(offset + 4:offset + 7))
      call log%info('assembly', 'body "' // name // '": moved ' // &
         to_str(norm2(q(offset + 1:offset + 3) - q_given(offset + 1:offset + 3)), 3) // &
         ' m, velocity changed ' // to_str(norm2(v(offset + 1:offset + 3) - &
         v_given(offset + 1:offset + 3)), 3) // ' m/s, angular velocity changed ' // &
         to_str(norm2(rates), 3) // ' rad/s')
   end subroutine log_assembly

   module procedure rotated
      rotated = any(orientation /= identity3())
   end procedure rotated

end submodule ffrf_app_mechanism_builder_start
