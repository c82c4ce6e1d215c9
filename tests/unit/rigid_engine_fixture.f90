!> The rigid slider-crank and reference engine of scene.md as test fixtures (shared by
!> test_mbs_mechanism, test_mbs_engine_convergence and test_stability_constraints): ground,
!> crank (+ flywheel), conrod, piston as rigid bodies, one or two main bearings, crank pin,
!> piston pin, prismatic cylinder (build_slider_crank); the engine adds the in-cylinder pressure,
!> starter and load torques and starts at rest at TDC (build_engine).
module ffrf_test_rigid_engine
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t
   use ffrf_mbs_rotation, only: euler_from_axis_angle, identity3
   use ffrf_mbs_rigid_body, only: rigid_body_t, ground_t
   use ffrf_mbs_mechanism, only: mechanism_t
   use ffrf_mbs_joints, only: JOINT_PRISMATIC, JOINT_REVOLUTE
   use ffrf_mbs_mechanism_loads, only: drag_torque_t, LOAD_FORCE, LOAD_TORQUE
   use ffrf_app_engine_starter_load, only: starter_torque_t
   use ffrf_app_engine_pressure_load, only: pressure_force_t
   use ffrf_app_engine_pressure, only: pressure_input_t
   use ffrf_app_engine_slider_crank, only: piston_position
   implicit none
   private
   public :: build_engine, build_slider_crank, add_engine_loads, crank_properties, tdc_pose
   public :: parallel_axis, diagonal
   public :: crank_radius, rod_length, load_coefficient, crank_pin, piston_pin
   public :: rod_mass, rod_com, rod_inertia, piston_mass, piston_inertia
   public :: flywheel_mass, flywheel_com, flywheel_inertia

   !> Crank radius and conrod length (m), scene.md
   real(dp), parameter :: crank_radius = 0.045_dp, rod_length = 0.150_dp
   !> Crank mass properties (test_mbs_mechanism)
   real(dp), parameter :: crank_mass = 2.92_dp, crank_com(3) = [0.0_dp, 0.0175_dp, 0.0_dp]
   real(dp), parameter :: crank_inertia(3) = [4.0e-3_dp, 1.5e-3_dp, 3.5e-3_dp]
   !> Flywheel (scene.md)
   real(dp), parameter :: flywheel_mass = 4.0_dp, flywheel_com(3) = [0.0_dp, 0.0_dp, 0.080_dp]
   real(dp), parameter :: flywheel_inertia(3) = [0.016_dp, 0.016_dp, 0.030_dp]
   !> Conrod mass properties (test_mbs_mechanism)
   real(dp), parameter :: rod_mass = 0.865_dp, rod_com = 0.049_dp
   real(dp), parameter :: rod_inertia(3) = [3.3e-3_dp, 2.0e-4_dp, 3.3e-3_dp]
   !> Piston (scene.md)
   real(dp), parameter :: piston_mass = 0.45_dp, piston_inertia = 3.0e-4_dp
   !> Load coefficient c (N m s^2), scene.md
   real(dp), parameter :: load_coefficient = 3.6e-4_dp
   !> Joint numbers (order of add_joint): crank pin, piston pin
   integer, parameter :: crank_pin = 3, piston_pin = 4

contains


   !> Rigid engine: ground (1), crank + flywheel (2), conrod (3), piston (4); revolutes B1 and B3
   !> ground-crank about z at z = -/+0.0475, crank pin, piston pin, prismatic piston-ground along y;
   !> pressure on the piston, starter and load torques on the crank; started at rest at crank
   !> angle 0. Returns the consistent q, v.
   subroutine build_engine(mech, q, v, error)
      type(mechanism_t), intent(out) :: mech
      real(dp), intent(out) :: q(21), v(21)
      type(error_t), allocatable, intent(out) :: error
      ! body indices of build_slider_crank: crank 2, piston 4
      integer, parameter :: ic = 2, ip_ = 4
      call build_slider_crank(mech, .true., .true., error)
      if (allocated(error)) return
      call add_engine_loads(mech, ic, ip_, 1, error)
      if (allocated(error)) return
      q = tdc_pose()
      call mech%assemble(q, 0.0_dp, error, rotor_angle=0.0_dp)
      if (allocated(error)) return
      call mech%initial_velocities(q, 0.0_dp, v, error, rotor_speed=0.0_dp)
   end subroutine build_engine

   !> The engine's loads: the cylinder pressure on the piston (body `piston`, marker 1, along y),
   !> the starter and the load (drag c omega^2, c = load_coefficient) torques about z on the
   !> crank (body `crank`, at marker `torque_marker`: it matters for a flexible crank).
   subroutine add_engine_loads(mech, crank, piston, torque_marker, error)
      type(mechanism_t), intent(inout) :: mech
      integer, intent(in) :: crank, piston, torque_marker
      type(error_t), allocatable, intent(out) :: error
      type(pressure_force_t) :: gas
      type(starter_torque_t) :: starter
      type(drag_torque_t) :: drag
      call gas%model%init(pressure_input_t(), error)
      if (allocated(error)) return
      gas%kind = LOAD_FORCE
      gas%body = piston
      gas%marker = 1
      gas%direction = [0.0_dp, 1.0_dp, 0.0_dp]
      gas%name = 'cylinder pressure'
      call mech%add_load(gas, error)
      if (allocated(error)) return
      starter%kind = LOAD_TORQUE
      starter%body = crank
      starter%marker = torque_marker
      starter%direction = [0.0_dp, 0.0_dp, 1.0_dp]
      starter%name = 'starter'
      call mech%add_load(starter, error)
      if (allocated(error)) return
      drag%kind = LOAD_TORQUE
      drag%body = crank
      drag%marker = torque_marker
      drag%direction = [0.0_dp, 0.0_dp, 1.0_dp]
      drag%coefficient = load_coefficient
      drag%name = 'load'
      call mech%add_load(drag, error)
   end subroutine add_engine_loads

   !> Slider-crank of scene.md from rigid bodies: ground (1), crank (2), conrod (3), piston (4).
   !> Joints: main bearing(s) ground-crank revolute about z (one at z = 0, or two at z = -/+0.0475
   !> like B1 and B3), crank pin revolute, piston pin revolute, piston-ground prismatic along y.
   !> With `flywheel` the crank carries the flywheel's mass and inertia (welded, rigid).
   subroutine build_slider_crank(mech, two_bearings, flywheel, error)
      type(mechanism_t), intent(out) :: mech
      logical, intent(in) :: two_bearings, flywheel
      type(error_t), allocatable, intent(out) :: error
      type(ground_t) :: ground
      type(rigid_body_t) :: crank, rod, piston
      real(dp) :: frames(3, 3, 3), ground_xyz(3, 3), crank_xyz(3, 3), mass, chi(3), J_c(3, 3)
      real(dp) :: z_bearing
      integer :: ig, ic, ir, ip_
      z_bearing = 0.0_dp
      if (two_bearings) z_bearing = 0.0475_dp
      ! Frame 1, 3: body axes (revolutes about z); frame 2: z along y (prismatic along y)
      frames(:, :, 1) = identity3()
      frames(:, :, 2) = reshape([1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, -1.0_dp, 0.0_dp, &
         1.0_dp, 0.0_dp], [3, 3])
      frames(:, :, 3) = identity3()
      ground_xyz = reshape([0.0_dp, 0.0_dp, -z_bearing, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, &
         0.0_dp, z_bearing], [3, 3])
      crank_xyz = reshape([0.0_dp, 0.0_dp, -z_bearing, 0.0_dp, crank_radius, 0.0_dp, 0.0_dp, &
         0.0_dp, z_bearing], [3, 3])
      call ground%init(ground_xyz, frames, error)
      if (allocated(error)) return
      call crank_properties(flywheel, mass, chi, J_c)
      call crank%init(mass, chi, J_c, crank_xyz, frames(:, :, [1, 1, 1]), error)
      if (allocated(error)) return
      call rod%init(rod_mass, [0.0_dp, rod_com, 0.0_dp], diagonal(rod_inertia), &
         reshape([0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, rod_length, 0.0_dp], [3, 2]), &
         frames(:, :, [1, 1]), error)
      if (allocated(error)) return
      call piston%init(piston_mass, [0.0_dp, 0.0_dp, 0.0_dp], piston_inertia * identity3(), &
         reshape([0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp], [3, 2]), frames(:, :, 1:2), &
         error)
      if (allocated(error)) return
      call mech%add_body(ground, 'ground', ig, error)
      if (.not. allocated(error)) call mech%add_body(crank, 'crank', ic, error)
      if (.not. allocated(error)) call mech%add_body(rod, 'conrod', ir, error)
      if (.not. allocated(error)) call mech%add_body(piston, 'piston', ip_, error)
      if (.not. allocated(error)) call mech%add_joint(JOINT_REVOLUTE, 'B1', ig, 1, ic, 1, error)
      if (.not. allocated(error) .and. two_bearings) call mech%add_joint(JOINT_REVOLUTE, 'B3', &
         ig, 3, ic, 3, error)
      if (.not. allocated(error)) call mech%add_joint(JOINT_REVOLUTE, 'crank pin', ic, 2, ir, 1, &
         error)
      if (.not. allocated(error)) call mech%add_joint(JOINT_REVOLUTE, 'piston pin', ir, 2, ip_, 1, &
         error)
      if (.not. allocated(error)) call mech%add_joint(JOINT_PRISMATIC, 'cylinder', ig, 2, ip_, 2, &
         error)
      if (.not. allocated(error)) call mech%set_rotor(ic, error)
   end subroutine build_slider_crank

   !> Crank mass properties (module header), with the flywheel if asked: total mass, centre of
   !> mass and inertia about it, by parallel axes about the crank frame origin.
   subroutine crank_properties(flywheel, mass, chi, J_c)
      logical, intent(in) :: flywheel
      real(dp), intent(out) :: mass, chi(3), J_c(3, 3)
      real(dp) :: J_o(3, 3)
      mass = crank_mass
      chi = crank_mass * crank_com
      J_o = diagonal(crank_inertia) + crank_mass * parallel_axis(crank_com)
      if (flywheel) then
         mass = mass + flywheel_mass
         chi = chi + flywheel_mass * flywheel_com
         J_o = J_o + diagonal(flywheel_inertia) + flywheel_mass * parallel_axis(flywheel_com)
      end if
      chi = chi / mass
      J_c = J_o - mass * parallel_axis(chi)
   end subroutine crank_properties

   !> |c|^2 I - c c^T (parallel-axis term per unit mass).
   pure function parallel_axis(c) result(s)
      real(dp), intent(in) :: c(3)
      real(dp) :: s(3, 3)
      integer :: i
      s = -spread(c, 2, 3) * spread(c, 1, 3)
      do i = 1, 3
         s(i, i) = s(i, i) + dot_product(c, c)
      end do
   end function parallel_axis

   !> diag(d)
   pure function diagonal(d) result(a)
      real(dp), intent(in) :: d(3)
      real(dp) :: a(3, 3)
      a = 0.0_dp
      a(1, 1) = d(1)
      a(2, 2) = d(2)
      a(3, 3) = d(3)
   end function diagonal

   !> Closed-form pose at crank angle 0 (TDC): crank 2, rod 3, piston 4 (no perturbation).
   function tdc_pose() result(q)
      real(dp) :: q(21)
      q(1:3) = 0.0_dp
      q(4:7) = euler_from_axis_angle([0.0_dp, 0.0_dp, 1.0_dp], 0.0_dp)
      q(8:10) = [0.0_dp, crank_radius, 0.0_dp]
      q(11:14) = [1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp]
      q(15:17) = [0.0_dp, piston_position(0.0_dp, crank_radius, rod_length), 0.0_dp]
      q(18:21) = [1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp]
   end function tdc_pose

end module ffrf_test_rigid_engine
