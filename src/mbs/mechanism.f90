!> A mechanism: bodies (rigid, flexible, ground), joints between their markers, applied loads, an
!> optional driving constraint, seen by the generalized-alpha integrator as a `dae_system_t`
!> (theory.md sections 3 to 4).
!>
!> Coordinates: the concatenation of the bodies' q in the order of add_body (the ground has none).
!> Constraint rows, in this order: every joint's equations (order of add_joint), one row per
!> driver of a joint (order of add_driver; ffrf_mbs_joint_driver), the driving
!> constraint if set (1 row), then one Euler-parameter normalisation theta^T theta - 1 = 0 per body
!> with Euler parameters, i.e. every body with at least 7 coordinates (rigid: q = [R; theta];
!> flexible: q = [R; theta; zeta]; theory.md 3.1).
!>
!>     M(q)  = blockdiag(M_b(q_b))                                          (theory.md 3.3)
!>     f     = sum_b [f_v,b + Q_e,b] + sum_loads (L_r^T F + L_w^T M) + gravity (theory.md 3.4, 3.5)
!>             + sum_springs (L_r,a^T f n - L_r,b^T f n)   (ffrf_mbs_spring_damper)
!>             + sum_torsion_springs T S_w^T z_a           (ffrf_mbs_torsion_spring, theory.md 3.8)
!>             + sum_bushings (-E^T (K e + C e'))          (ffrf_mbs_bushing, theory.md 3.9)
!>     Phi_q = joint blocks dPhi/dq_a, dPhi/dq_b (ffrf_mbs_joints), the drive row, rows 2 theta^T
!>
!> Rotor angle and speed. The rotor is an optional chosen body (set_rotor) whose turning about the
!> global z axis the loads may depend on (mechanism_loads: magnitude(t, angle, speed)); an
!> application gives it its own meaning (a shaft, a wheel, a rotating link). Its angle phi
!> is the rotation of its reference frame about z, the twist angle of the swing-twist
!> decomposition of its Euler parameters, phi = 2 atan2(e3, e0) (exact when the body turns about z
!> only). atan2 gives phi modulo 2 pi (theta and -theta differ by 2 pi), so the angle is unwrapped
!> against a reference phi_ref, the angle at the last accepted step (accepted_step hook, or
!> assemble / set_rotor_reference): phi = phi_ref + wrap(phi_raw - phi_ref) with wrap into
!> [-pi, pi). This counts revolutions correctly while the rotor turns less than pi per step.
!> The rotor speed is the z component of the global angular velocity omega = G(theta) theta_dot.
!> Without a rotor both are 0 and no load sees them.
!>
!> Driving constraint (set_drive): the reference frame of a body turns about z by a prescribed
!> f(t). Equation Phi_d = n(f) . (A(theta) e_x) = 0 with n(f) = (-sin f, cos f, 0): for a rotation
!> by phi about z it is sin(phi - f) (Nikravesh 1988, ch. 7, driving constraints). Rheonomic:
!>     Phi_t = f' n_f . A e_x,   Phi_tt = (f'' n_f - f'^2 n) . A e_x,
!> with n_f = dn/df = -(cos f, sin f, 0),
!> and its acceleration right-hand side is analytic (below).
!>
!> Drivers of joints (add_driver): a revolute angle or a prismatic travel prescribed over time,
!> one row each, with exact Jacobian, Phi_t, Phi_tt, Phi_qt, second derivatives (the Newton
!> tangent and the convective term (Phi_q v)_q v of the acceleration right-hand side; exact for
!> rigid bodies, for flexible ones as exact as body_t%marker_hessian): ffrf_mbs_joint_driver.
!>
!> Overridden time terms and tangents:
!> - constraint_rate: analytic (only the drive and driver rows depend on t).
!> - acceleration_rhs g = -(Phi_q v)_q v - 2 Phi_qt v - Phi_tt (theory.md 4.3): analytic on the
!>   Euler rows (-2 theta_dot^T theta_dot) and the drive row (A is quadratic in theta: the second
!>   derivative of A(theta) b along theta_dot is 2 (A(theta_dot) + I) b) and the drivers' rows
!>   (ffrf_mbs_joint_driver); joint rows by a central difference of Phi_q(q + s v) v in s
!>   (joints do not depend on t), s = eps**(1/3) relative.
!> - stiffness, damping, constraint_stiffness, mass_stiffness (analytic_tangents = .true., the
!>   default): assembled per body and per joint, without differences over the mechanism:
!>   * constraint stiffness d(Phi_q^T lambda)/dq: joints exact (joint_t%constraint_hessian from
!>     the bodies' marker_hessian: exact for rigid bodies; for flexible ones exact but for the
!>     second derivative of the exponential map of the marker rotation, a 3 x 3 central
!>     difference), drive row exact (n . A(theta) e_x is quadratic in theta), drivers' rows
!>     as the joints (ffrf_mbs_joint_driver driver_hessian), Euler rows exact (2 lambda I4);
!>   * stiffness -df/dq and damping -df/dq': bodies' force_tangents (exact: rigid and FFRF
!>     quadratic velocity vectors, modal K_ff and D_ff); loads: the marker force at fixed
!>     magnitude by body%marker_force_tangent (rigid exact; flexible exact but for the derivative
!>     of the exponential map's tangent operator, a 3 x 3 difference) plus the magnitude's
!>     dependence on the rotor angle and speed (exact d(angle)/dtheta, d(speed)/d(theta,
!>     theta_dot); d(magnitude)/d(angle, speed) from load_t%magnitude_rates (a central difference
!>     of the scalar load law unless the load gives exact derivatives); gravity exact;
!>   * mass stiffness d(M a)/dq: body%mass_stiffness (rigid and flexible exact).
!>   analytic_tangents = .false. selects dae_system_t's central differences over the whole
!>   mechanism (2 n evaluations each per factorisation), the reference the tests compare with.
!>
!> Consistent initial state (assemble, initial_velocities): Gauss-Newton on Phi(q, t) = 0, plus
!> optionally the rotor angle equation, each step the minimum-norm least-squares solution of
!> Phi_q dq = -Phi by a complete orthogonal factorisation (LAPACK dgelsy, rank-revealing: the 3D
!> mechanisms are over-constrained, theory.md 4.3); then v from Phi_q v = -Phi_t (+ the rotor
!> speed) in the same least-squares sense.
module ffrf_mbs_mechanism
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t
   use ffrf_mbs_dae_system, only: dae_system_t
   use ffrf_la_block_sparse, only: block_sparse_t
   use ffrf_mbs_body, only: body_t
   use ffrf_mbs_joints, only: joint_t
   use ffrf_mbs_mechanism_loads, only: load_t, drive_law_t
   use ffrf_mbs_spring_damper, only: spring_damper_t, spring_state_t
   use ffrf_mbs_torsion_spring, only: torsion_spring_t, torsion_state_t
   use ffrf_mbs_bushing, only: bushing_t, bushing_state_t
   use ffrf_mbs_joint_driver, only: joint_driver_t
   implicit none
   private
   public :: mechanism_t, mechanism_body_t, mechanism_joint_t, mechanism_load_t

   !> A body of the mechanism and where its coordinates and normalisation row sit.
   type :: mechanism_body_t
      !> The body (rigid_body_t, ground_t, flexible_body_t, ...)
      class(body_t), allocatable :: body
      !> Name for messages and output
      character(len=:), allocatable :: name
      !> Its coordinates are q(offset + 1 : offset + body%num_coordinates)
      integer :: offset = 0
      !> Row of its Euler-parameter normalisation (0: none, e.g. the ground)
      integer :: euler_row = 0
   end type mechanism_body_t

   !> A joint of the mechanism with the bodies it connects.
   type :: mechanism_joint_t
      !> The joint (connected to its markers)
      class(joint_t), allocatable :: joint
      !> Name for messages and output
      character(len=:), allocatable :: name
      !> Mechanism indices of body a and body b
      integer :: body_a = 0, body_b = 0
      !> Its equations are rows offset + 1 : offset + num_equations
      integer :: offset = 0
   end type mechanism_joint_t

   !> An applied load.
   type :: mechanism_load_t
      !> The load
      class(load_t), allocatable :: load
   end type mechanism_load_t

   !> Bodies, joints, loads and an optional drive, as a constrained system (module header).
   type, extends(dae_system_t) :: mechanism_t
      !> Bodies in the order of add_body
      type(mechanism_body_t), allocatable :: bodies(:)
      !> Joints in the order of add_joint
      type(mechanism_joint_t), allocatable :: joints(:)
      !> Applied loads
      type(mechanism_load_t), allocatable :: loads(:)
      !> Spring-dampers between markers (ffrf_mbs_spring_damper), order of add_spring
      type(spring_damper_t), allocatable :: springs(:)
      !> Torsion spring-dampers about joints (ffrf_mbs_torsion_spring), order of
      !> add_torsion_spring
      type(torsion_spring_t), allocatable :: torsion_springs(:)
      !> 6-dof bushings between markers (ffrf_mbs_bushing), order of add_bushing
      type(bushing_t), allocatable :: bushings(:)
      !> Drivers of joints (ffrf_mbs_joint_driver), order of add_driver; rows after the joints'
      type(joint_driver_t), allocatable :: drivers(:)
      !> Number of coordinates and of constraint rows
      integer :: n = 0, nc = 0
      !> Gravity acceleration, global (m/s^2); zero (off) by default; rigid and flexible bodies
      !> (theory.md 3.6)
      real(dp) :: gravity(3) = 0.0_dp
      !> Mechanism index of the rotor body (0: none; rotor angle and speed are then zero)
      integer :: rotor = 0
      !> Unwrapped rotor angle at the last accepted step (rad)
      real(dp) :: rotor_reference = 0.0_dp
      !> Mechanism index of the driven body (0: no driving constraint)
      integer :: drive_body = 0
      !> Row of the driving constraint (0: none)
      integer :: drive_row = 0
      !> Prescribed rotation of the driven body about z
      class(drive_law_t), allocatable :: drive
      !> Tangents of the Newton iteration assembled per body and joint (module header); .false.:
      !> central differences over the whole mechanism (dae_system_t defaults, the reference)
      logical :: analytic_tangents = .true.
      !> -df/dq' computed with the last stiffness, for the damping call at the same state
      !> (and K_t with it), block-sparse by body (block_groups)
      type(block_sparse_t), private :: stiffness_cache, damping_cache
      real(dp), allocatable, private :: cache_q(:), cache_v(:)
      !> Work matrix of the dense interfaces (constraint and mass stiffness)
      type(block_sparse_t), private :: work_blocks
      real(dp), private :: cache_t = 0.0_dp
   contains
      !> Add a body (copied); returns its mechanism index
      procedure :: add_body => mechanism_add_body
      !> Add a joint by kind between markers of two bodies
      procedure :: add_joint => mechanism_add_joint
      !> Add an applied load (copied)
      procedure :: add_load => mechanism_add_load
      !> Add a spring-damper between two markers of two bodies
      procedure :: add_spring => mechanism_add_spring
      !> Length, rate and tension of spring s at a state
      procedure :: spring_state => mechanism_spring_state
      !> Potential energy of the springs, sum k (l - L0)^2 / 2 (J)
      procedure :: spring_energy => mechanism_spring_energy
      !> Free lengths not given are set to the lengths at q (the starting pose)
      procedure :: set_spring_free_lengths => mechanism_set_spring_free_lengths
      !> Add a torsion spring-damper about a revolute or cylindrical joint
      procedure :: add_torsion_spring => mechanism_add_torsion_spring
      !> Angle, rate and torque of torsion spring s at a state
      procedure :: torsion_state => mechanism_torsion_state
      !> Potential energy of the torsion springs, sum k (phi - phi0)^2 / 2 (J)
      procedure :: torsion_energy => mechanism_torsion_energy
      !> Start of the torsion springs: unwrapping references and the free angles not given
      procedure :: set_torsion_start => mechanism_set_torsion_start
      !> The torsion springs' unwrapping references (a restart state), and setting them
      procedure :: torsion_references => mechanism_torsion_references
      procedure :: set_torsion_references => mechanism_set_torsion_references
      !> Add a 6-dof bushing between two markers of two bodies
      procedure :: add_bushing => mechanism_add_bushing
      !> Deflections, rates and element force of bushing s at a state
      procedure :: bushing_state => mechanism_bushing_state
      !> Potential energy of the bushings, sum e^T K e / 2 (J)
      procedure :: bushing_energy => mechanism_bushing_energy
      !> Choose the rotor body (rotor angle and speed for the loads)
      procedure :: set_rotor => mechanism_set_rotor
      !> Set the unwrapping reference of the rotor angle from q (near a known angle)
      procedure :: set_rotor_reference => mechanism_set_rotor_reference
      !> Prescribe a body's rotation about z (driving constraint)
      procedure :: set_drive => mechanism_set_drive
      !> Prescribe a revolute joint's angle or a prismatic joint's travel (a driver)
      procedure :: add_driver => mechanism_add_driver
      !> Coordinate, rate and driving torque or force of driver d at a state
      procedure :: driver_state => mechanism_driver_state
      !> Coordinates of body b out of q
      procedure :: body_coordinates => mechanism_body_coordinates
      !> Unwrapped rotor angle (rad)
      procedure :: rotor_angle => mechanism_rotor_angle
      !> Rotor speed (rad/s)
      procedure :: rotor_speed => mechanism_rotor_speed
      !> Generalized applied force: loads and gravity
      procedure :: applied_force => mechanism_applied_force
      !> Kinetic energy (J)
      procedure :: kinetic_energy => mechanism_kinetic_energy
      !> Strain energy of the flexible bodies (J)
      procedure :: strain_energy => mechanism_strain_energy
      !> Power of the applied loads and gravity (W)
      procedure :: applied_power => mechanism_applied_power
      !> Reaction force and moment of joint j from the multipliers
      procedure :: reaction => mechanism_reaction
      !> Solve Phi(q, t) = 0 (and the rotor angle) by minimum-norm Gauss-Newton
      procedure :: assemble => mechanism_assemble
      !> Velocities with Phi_q v = -Phi_t (and the rotor speed), minimum norm
      procedure :: initial_velocities => mechanism_initial_velocities
      ! dae_system_t
      procedure :: num_coordinates => mechanism_num_coordinates
      procedure :: num_constraints => mechanism_num_constraints
      procedure :: mass => mechanism_mass
      procedure :: force => mechanism_force
      procedure :: constraints => mechanism_constraints
      procedure :: constraint_jacobian => mechanism_constraint_jacobian
      procedure :: constraints_and_jacobian => mechanism_constraints_and_jacobian
      procedure :: constraint_rate => mechanism_constraint_rate
      procedure :: acceleration_rhs => mechanism_acceleration_rhs
      procedure :: accepted_step => mechanism_accepted_step
      procedure :: protected_rows => mechanism_protected_rows
      procedure :: stiffness => mechanism_stiffness
      procedure :: damping => mechanism_damping
      procedure :: constraint_stiffness => mechanism_constraint_stiffness
      procedure :: mass_stiffness => mechanism_mass_stiffness
      procedure :: mass_sparse => mechanism_mass_sparse
      procedure :: constraints_and_jacobian_sparse => mechanism_constraints_and_jacobian_sparse
      procedure :: tangents_sparse => mechanism_tangents_sparse
   end type mechanism_t

   interface
      !> Add a copy of `body`; `index` is its mechanism index for joints, loads, rotor and drive.
      module subroutine mechanism_add_body(self, body, name, index, error)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> Initialised body (rigid_body_t%init, ground_t%init, flexible_body_t%init)
         class(body_t), intent(in) :: body
         !> Name for messages
         character(len=*), intent(in) :: name
         !> Mechanism index of the new body
         integer, intent(out) :: index
         type(error_t), allocatable, intent(out) :: error
      end subroutine mechanism_add_body

      !> Add a joint of `kind` (JOINT_* of ffrf_mbs_joints: new_joint) between marker_a of body a
      !> and marker_b of body b (mechanism indices).
      module subroutine mechanism_add_joint(self, kind, name, body_a, marker_a, body_b, &
         marker_b, error)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> Joint kind (JOINT_REVOLUTE, ... of ffrf_mbs_joints)
         integer, intent(in) :: kind
         !> Name for messages
         character(len=*), intent(in) :: name
         !> Mechanism index of body a
         integer, intent(in) :: body_a
         !> Marker of body a
         integer, intent(in) :: marker_a
         !> Mechanism index of body b
         integer, intent(in) :: body_b
         !> Marker of body b
         integer, intent(in) :: marker_b
         type(error_t), allocatable, intent(out) :: error
      end subroutine mechanism_add_joint

      !> Add a copy of an applied load; its direction is normalised here.
      module subroutine mechanism_add_load(self, load, error)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> The load (body, marker, kind, direction and its own data set)
         class(load_t), intent(in) :: load
         type(error_t), allocatable, intent(out) :: error
      end subroutine mechanism_add_load

      !> Add a copy of a spring-damper (bodies and markers as mechanism indices;
      !> ffrf_mbs_spring_damper). Refused: an unknown body or marker, both ends on one body, k < 0
      !> or c < 0.
      module subroutine mechanism_add_spring(self, spring, error)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> The spring (free_length < 0: set later by set_spring_free_lengths)
         type(spring_damper_t), intent(in) :: spring
         type(error_t), allocatable, intent(out) :: error
      end subroutine mechanism_add_spring

      !> Length, direction, rate and tension of spring s at (q, v).
      module function mechanism_spring_state(self, s, q, v) result(state)
         !> The mechanism
         class(mechanism_t), intent(in) :: self
         !> Spring number (order of add_spring)
         integer, intent(in) :: s
         !> Coordinates and velocities, n
         real(dp), intent(in) :: q(:), v(:)
         type(spring_state_t) :: state
      end function mechanism_spring_state

      !> Potential energy of the springs, sum k (l - L0)^2 / 2 (J).
      module function mechanism_spring_energy(self, q) result(energy)
         !> The mechanism
         class(mechanism_t), intent(in) :: self
         !> Coordinates, n
         real(dp), intent(in) :: q(:)
         real(dp) :: energy
      end function mechanism_spring_energy

      !> Every spring without a free length (free_length < 0) gets its length at q; a zero
      !> length there is an error (the spring would have no direction).
      module subroutine mechanism_set_spring_free_lengths(self, q, error)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> Coordinates of the starting pose, n
         real(dp), intent(in) :: q(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine mechanism_set_spring_free_lengths

      !> Add a copy of a torsion spring-damper about joint spring%joint (a mechanism joint
      !> number; ffrf_mbs_torsion_spring), its bodies and markers taken from the joint. Refused:
      !> an unknown joint, a joint neither revolute nor cylindrical, k < 0 or c < 0.
      module subroutine mechanism_add_torsion_spring(self, spring, error)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> The torsion spring (free_angle_given = .false.: set by set_torsion_start)
         type(torsion_spring_t), intent(in) :: spring
         type(error_t), allocatable, intent(out) :: error
      end subroutine mechanism_add_torsion_spring

      !> Angle (unwrapped), rate and torque of torsion spring s at (q, v).
      module function mechanism_torsion_state(self, s, q, v) result(state)
         !> The mechanism
         class(mechanism_t), intent(in) :: self
         !> Torsion spring number (order of add_torsion_spring)
         integer, intent(in) :: s
         !> Coordinates and velocities, n
         real(dp), intent(in) :: q(:), v(:)
         type(torsion_state_t) :: state
      end function mechanism_torsion_state

      !> Potential energy of the torsion springs, sum k (phi - phi0)^2 / 2 (J).
      module function mechanism_torsion_energy(self, q) result(energy)
         !> The mechanism
         class(mechanism_t), intent(in) :: self
         !> Coordinates, n
         real(dp), intent(in) :: q(:)
         real(dp) :: energy
      end function mechanism_torsion_energy

      !> At the starting pose q: each torsion spring's unwrapping reference becomes its angle
      !> in (-pi, pi], and a spring without a free angle gets that angle as free angle.
      module subroutine mechanism_set_torsion_start(self, q)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> Coordinates of the starting pose, n
         real(dp), intent(in) :: q(:)
      end subroutine mechanism_set_torsion_start

      !> The unwrapping reference of every torsion spring (rad; empty without torsion springs):
      !> the angle at the last accepted step, which counts the whole turns (a restart state).
      module function mechanism_torsion_references(self) result(references)
         !> The mechanism
         class(mechanism_t), intent(in) :: self
         real(dp), allocatable :: references(:)
      end function mechanism_torsion_references

      !> Set every torsion spring's unwrapping reference (a restart); FFRF_INPUT_ERROR when
      !> the count differs from the mechanism's torsion springs.
      module subroutine mechanism_set_torsion_references(self, references, error)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> One per torsion spring, in their order (rad)
         real(dp), intent(in) :: references(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine mechanism_set_torsion_references

      !> Add the applied generalized forces to f (present), or their tangents to K_t (-df/dq)
      !> and C_t (-df/dq') (both present): loads, force elements, gravity (mechanism_applied.f90).
      module subroutine add_applied_terms(self, q, v, t, error, f, K_t, C_t)
         type(mechanism_t), intent(in) :: self
         real(dp), intent(in) :: q(:), v(:)
         real(dp), intent(in) :: t
         type(error_t), allocatable, intent(out) :: error
         real(dp), intent(inout), optional :: f(:)
         type(block_sparse_t), intent(inout), optional :: K_t, C_t
      end subroutine add_applied_terms

      !> Add a copy of a bushing (bodies and markers as mechanism indices; ffrf_mbs_bushing).
      !> Refused: an unknown body or marker, both ends on one body, a negative entry.
      module subroutine mechanism_add_bushing(self, bushing, error)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> The bushing
         type(bushing_t), intent(in) :: bushing
         type(error_t), allocatable, intent(out) :: error
      end subroutine mechanism_add_bushing

      !> Deflections e = [d; phi], rates and element force K e + C e' of bushing s at (q, v).
      module function mechanism_bushing_state(self, s, q, v) result(state)
         !> The mechanism
         class(mechanism_t), intent(in) :: self
         !> Bushing number (order of add_bushing)
         integer, intent(in) :: s
         !> Coordinates and velocities, n
         real(dp), intent(in) :: q(:), v(:)
         type(bushing_state_t) :: state
      end function mechanism_bushing_state

      !> Potential energy of the bushings, sum e^T K e / 2 (J).
      module function mechanism_bushing_energy(self, q) result(energy)
         !> The mechanism
         class(mechanism_t), intent(in) :: self
         !> Coordinates, n
         real(dp), intent(in) :: q(:)
         real(dp) :: energy
      end function mechanism_bushing_energy

      !> Add the force elements' generalized forces to f (present), or their tangents to K_t
      !> (-df/dq) and C_t (-df/dq') (both present): springs, torsion springs, bushings, in this
      !> order (force_element_t%terms; its numeric errors).
      module subroutine add_force_element_terms(self, q, v, t, error, f, K_t, C_t)
         type(mechanism_t), intent(in) :: self
         real(dp), intent(in) :: q(:), v(:)
         real(dp), intent(in) :: t
         type(error_t), allocatable, intent(out) :: error
         real(dp), intent(inout), optional :: f(:)
         type(block_sparse_t), intent(inout), optional :: K_t, C_t
      end subroutine add_force_element_terms

      !> After an accepted step: each torsion spring's angle becomes its unwrapping reference.
      module subroutine update_torsion_references(self, q)
         type(mechanism_t), intent(inout) :: self
         real(dp), intent(in) :: q(:)
      end subroutine update_torsion_references

      !> The rotor is body `body` (with Euler parameters); its angle is unwrapped from 0.
      module subroutine mechanism_set_rotor(self, body, error)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> Mechanism index of the rotor
         integer, intent(in) :: body
         type(error_t), allocatable, intent(out) :: error
      end subroutine mechanism_set_rotor

      !> Unwrap the rotor angle of q against `angle` (rad) and keep the result as the reference.
      module subroutine mechanism_set_rotor_reference(self, q, angle)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> Coordinates, n
         real(dp), intent(in) :: q(:)
         !> A rotor angle within pi of the one of q (rad)
         real(dp), intent(in) :: angle
      end subroutine mechanism_set_rotor_reference

      !> Prescribe the rotation about z of body `body` as law%evaluate(t) (one rheonomic row).
      module subroutine mechanism_set_drive(self, body, law, error)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> Mechanism index of the driven body (with Euler parameters)
         integer, intent(in) :: body
         !> The law f(t), f', f''
         class(drive_law_t), intent(in) :: law
         type(error_t), allocatable, intent(out) :: error
      end subroutine mechanism_set_drive

      !> Add a driver of joint driver%joint (revolute or prismatic; ffrf_mbs_joint_driver).
      module subroutine mechanism_add_driver(self, driver, error)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> The driver (name, joint, law, rate, offset; kind and row are set here)
         type(joint_driver_t), intent(in) :: driver
         type(error_t), allocatable, intent(out) :: error
      end subroutine mechanism_add_driver

      !> Driver d at (q, v, lambda): [coordinate (rad or m), rate, torque or force tau = -lambda
      !> (N m or N, on body b about or along the joint axis)].
      module function mechanism_driver_state(self, d, q, v, lambda) result(values)
         !> The mechanism
         class(mechanism_t), intent(in) :: self
         !> Driver number (order of add_driver)
         integer, intent(in) :: d
         !> Coordinates, velocities (n), multipliers (nc)
         real(dp), intent(in) :: q(:), v(:), lambda(:)
         real(dp) :: values(3)
      end function mechanism_driver_state

      !> q(offset + 1 : offset + num_coordinates) of body b (empty for the ground).
      module pure function mechanism_body_coordinates(self, q, b) result(qb)
         !> The mechanism
         class(mechanism_t), intent(in) :: self
         !> Coordinates (or velocities), n
         real(dp), intent(in) :: q(:)
         !> Mechanism index of the body
         integer, intent(in) :: b
         real(dp) :: qb(self%bodies(b)%body%num_coordinates)
      end function mechanism_body_coordinates

      !> Unwrapped rotor angle phi_ref + wrap(2 atan2(e3, e0) - phi_ref) (module header); 0 without
      !> a rotor.
      module pure function mechanism_rotor_angle(self, q) result(angle)
         !> The mechanism
         class(mechanism_t), intent(in) :: self
         !> Coordinates, n
         real(dp), intent(in) :: q(:)
         real(dp) :: angle
      end function mechanism_rotor_angle

      !> Rotor speed e_z . G(theta) theta_dot (rad/s); 0 without a rotor.
      module pure function mechanism_rotor_speed(self, q, v) result(speed)
         !> The mechanism
         class(mechanism_t), intent(in) :: self
         !> Coordinates, n
         real(dp), intent(in) :: q(:)
         !> Velocities, n
         real(dp), intent(in) :: v(:)
         real(dp) :: speed
      end function mechanism_rotor_speed

      !> Generalized force of the loads (L_r^T F + L_w^T M at their markers, theory.md 3.5) and of
      !> gravity (rigid bodies: m g at the centre of mass; flexible: theory.md 3.6).
      module subroutine mechanism_applied_force(self, q, v, t, f, error)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> Coordinates, n
         real(dp), intent(in) :: q(:)
         !> Velocities, n
         real(dp), intent(in) :: v(:)
         !> Time (s)
         real(dp), intent(in) :: t
         !> Generalized applied force, n
         real(dp), intent(out) :: f(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine mechanism_applied_force

      !> Kinetic energy sum_b v_b^T M_b(q_b) v_b / 2 (J).
      module pure function mechanism_kinetic_energy(self, q, v) result(energy)
         !> The mechanism
         class(mechanism_t), intent(in) :: self
         !> Coordinates, n
         real(dp), intent(in) :: q(:)
         !> Velocities, n
         real(dp), intent(in) :: v(:)
         real(dp) :: energy
      end function mechanism_kinetic_energy

      !> Strain energy of the flexible bodies, sum zeta^T K_ff zeta / 2 (J); 0 for rigid ones.
      module pure function mechanism_strain_energy(self, q) result(energy)
         !> The mechanism
         class(mechanism_t), intent(in) :: self
         !> Coordinates, n
         real(dp), intent(in) :: q(:)
         real(dp) :: energy
      end function mechanism_strain_energy

      !> Power of the applied loads and gravity, Q_applied . v (W): integrated over time it is the
      !> work that enters the energy balance kinetic + strain + dissipated = work.
      module subroutine mechanism_applied_power(self, q, v, t, power, error)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> Coordinates, n
         real(dp), intent(in) :: q(:)
         !> Velocities, n
         real(dp), intent(in) :: v(:)
         !> Time (s)
         real(dp), intent(in) :: t
         !> Power (W)
         real(dp), intent(out) :: power
         type(error_t), allocatable, intent(out) :: error
      end subroutine mechanism_applied_power

      !> Force and moment of joint j on its two bodies from the multipliers of all rows
      !> (joint_reaction: column 1 on body a at marker a, column 2 on body b at marker b).
      module subroutine mechanism_reaction(self, j, q, lambda, force, moment)
         !> The mechanism
         class(mechanism_t), intent(in) :: self
         !> Joint number (order of add_joint)
         integer, intent(in) :: j
         !> Coordinates, n
         real(dp), intent(in) :: q(:)
         !> Multipliers of all constraint rows, nc
         real(dp), intent(in) :: lambda(:)
         !> Force (N), global: column 1 on body a, column 2 on body b
         real(dp), intent(out) :: force(3, 2)
         !> Moment (N m), global
         real(dp), intent(out) :: moment(3, 2)
      end subroutine mechanism_reaction

      !> n.
      module integer function mechanism_num_coordinates(self) result(num)
         !> The mechanism
         class(mechanism_t), intent(in) :: self
      end function mechanism_num_coordinates

      !> nc (joint rows, drive row, Euler rows).
      module integer function mechanism_num_constraints(self) result(num)
         !> The mechanism
         class(mechanism_t), intent(in) :: self
      end function mechanism_num_constraints

      !> The Euler-parameter normalisation rows: the redundant-row search keeps them, so that
      !> an over-constrained loop drops a joint row, never a body's normalisation.
      module subroutine mechanism_protected_rows(self, protect)
         !> The mechanism
         class(mechanism_t), intent(in) :: self
         !> .true. on the Euler rows, nc
         logical, intent(out) :: protect(:)
      end subroutine mechanism_protected_rows

      !> M = blockdiag(M_b(q_b)).
      module subroutine mechanism_mass(self, q, M, error)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> Coordinates, n
         real(dp), intent(in) :: q(:)
         !> Mass matrix, n x n
         real(dp), intent(out) :: M(:, :)
         type(error_t), allocatable, intent(out) :: error
      end subroutine mechanism_mass

      !> f = sum_b (f_v + Q_e) + applied loads + gravity.
      module subroutine mechanism_force(self, q, v, t, f, error)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> Coordinates, n
         real(dp), intent(in) :: q(:)
         !> Velocities, n
         real(dp), intent(in) :: v(:)
         !> Time (s)
         real(dp), intent(in) :: t
         !> Generalized forces, n
         real(dp), intent(out) :: f(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine mechanism_force

      !> Phi: joint equations, drive row, Euler normalisations.
      module subroutine mechanism_constraints(self, q, t, phi, error)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> Coordinates, n
         real(dp), intent(in) :: q(:)
         !> Time (s)
         real(dp), intent(in) :: t
         !> Residuals, nc
         real(dp), intent(out) :: phi(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine mechanism_constraints

      !> Phi_q: joint blocks, drive row n^T d(A e_x)/dtheta, Euler rows 2 theta^T.
      module subroutine mechanism_constraint_jacobian(self, q, t, Phi_q, error)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> Coordinates, n
         real(dp), intent(in) :: q(:)
         !> Time (s)
         real(dp), intent(in) :: t
         !> dPhi/dq, nc x n
         real(dp), intent(out) :: Phi_q(:, :)
         type(error_t), allocatable, intent(out) :: error
      end subroutine mechanism_constraint_jacobian

      !> Phi and Phi_q in one pass over the joints (each joint evaluates its markers once).
      module subroutine mechanism_constraints_and_jacobian(self, q, t, phi, Phi_q, error)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> Coordinates, n
         real(dp), intent(in) :: q(:)
         !> Time (s)
         real(dp), intent(in) :: t
         !> Residuals, nc
         real(dp), intent(out) :: phi(:)
         !> dPhi/dq, nc x n
         real(dp), intent(out) :: Phi_q(:, :)
         type(error_t), allocatable, intent(out) :: error
      end subroutine mechanism_constraints_and_jacobian

      !> Phi_t: zero except the drive row, f' n_f . A e_x (module header).
      module subroutine mechanism_constraint_rate(self, q, t, phi_t, error)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> Coordinates, n
         real(dp), intent(in) :: q(:)
         !> Time (s)
         real(dp), intent(in) :: t
         !> dPhi/dt, nc
         real(dp), intent(out) :: phi_t(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine mechanism_constraint_rate

      !> g = -(Phi_q v)_q v - 2 Phi_qt v - Phi_tt (module header): analytic on the drive and Euler
      !> rows, central difference in s of Phi_q(q + s v) v on the joint rows.
      module subroutine mechanism_acceleration_rhs(self, q, v, t, g, error)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> Coordinates, n
         real(dp), intent(in) :: q(:)
         !> Velocities, n
         real(dp), intent(in) :: v(:)
         !> Time (s)
         real(dp), intent(in) :: t
         !> Right-hand side of Phi_q q'' = g, nc
         real(dp), intent(out) :: g(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine mechanism_acceleration_rhs

      !> After an accepted step: the state must be finite; the rotor angle becomes the new
      !> unwrapping reference.
      module subroutine mechanism_accepted_step(self, t, q, v, qdd, lambda, error)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> Time reached (s)
         real(dp), intent(in) :: t
         !> Coordinates, n
         real(dp), intent(in) :: q(:)
         !> Velocities, n
         real(dp), intent(in) :: v(:)
         !> Accelerations, n
         real(dp), intent(in) :: qdd(:)
         !> Multipliers, nc
         real(dp), intent(in) :: lambda(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine mechanism_accepted_step

      !> K_t = -df/dq (module header: per body and load; differences if .not. analytic_tangents).
      module subroutine mechanism_stiffness(self, q, v, t, K_t, error)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> Coordinates, n
         real(dp), intent(in) :: q(:)
         !> Velocities, n
         real(dp), intent(in) :: v(:)
         !> Time (s)
         real(dp), intent(in) :: t
         !> -df/dq, n x n
         real(dp), intent(out) :: K_t(:, :)
         type(error_t), allocatable, intent(out) :: error
      end subroutine mechanism_stiffness

      !> C_t = -df/dq' (module header; reuses the stiffness call's result at the same state).
      module subroutine mechanism_damping(self, q, v, t, C_t, error)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> Coordinates, n
         real(dp), intent(in) :: q(:)
         !> Velocities, n
         real(dp), intent(in) :: v(:)
         !> Time (s)
         real(dp), intent(in) :: t
         !> -df/dq', n x n
         real(dp), intent(out) :: C_t(:, :)
         type(error_t), allocatable, intent(out) :: error
      end subroutine mechanism_damping

      !> d(Phi_q^T lambda)/dq: joints, drive row and Euler rows (module header).
      module subroutine mechanism_constraint_stiffness(self, q, t, lambda, K_c, error)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> Coordinates, n
         real(dp), intent(in) :: q(:)
         !> Time (s)
         real(dp), intent(in) :: t
         !> Multipliers, nc
         real(dp), intent(in) :: lambda(:)
         !> d(Phi_q^T lambda)/dq, n x n
         real(dp), intent(out) :: K_c(:, :)
         type(error_t), allocatable, intent(out) :: error
      end subroutine mechanism_constraint_stiffness

      !> d(M(q) a)/dq for a fixed a: blockdiag of the bodies' mass_stiffness.
      module subroutine mechanism_mass_stiffness(self, q, a, K_m, error)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> Coordinates, n
         real(dp), intent(in) :: q(:)
         !> Acceleration held fixed, n
         real(dp), intent(in) :: a(:)
         !> d(M a)/dq, n x n
         real(dp), intent(out) :: K_m(:, :)
         type(error_t), allocatable, intent(out) :: error
      end subroutine mechanism_mass_stiffness

      !> Solve Phi(q, t) = 0 from an approximate q by Gauss-Newton, each step the minimum-norm
      !> least-squares correction (dgelsy). With rotor_angle, the rotor's rotation about z is fixed
      !> too (equation n(angle) . A e_x = 0, as the drive) and becomes the unwrapping reference.
      !> Converged when max |Phi| <= tolerance (default 1e-12).
      module subroutine mechanism_assemble(self, q, t, error, rotor_angle, tolerance, iterations)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> Coordinates: approximate in, assembled out, n
         real(dp), intent(inout) :: q(:)
         !> Time (s), for a driving constraint
         real(dp), intent(in) :: t
         type(error_t), allocatable, intent(out) :: error
         !> Rotor angle to assemble at (rad); needs set_rotor
         real(dp), intent(in), optional :: rotor_angle
         !> Largest |Phi_i| accepted (default 1e-12)
         real(dp), intent(in), optional :: tolerance
         !> Gauss-Newton iterations used
         integer, intent(out), optional :: iterations
      end subroutine mechanism_assemble

      !> Velocities v with Phi_q v = -Phi_t, and the rotor speed if given, in the minimum-norm
      !> least-squares sense (dgelsy); error if the residual exceeds 1e-10 of the scale. With
      !> `guess`, v = guess + dv with the minimum-norm dv (the projection of the guess onto the
      !> velocity constraints in the coordinates' Euclidean norm).
      module subroutine mechanism_initial_velocities(self, q, t, v, error, rotor_speed, guess)
         !> The mechanism
         class(mechanism_t), intent(inout) :: self
         !> Assembled coordinates, n
         real(dp), intent(in) :: q(:)
         !> Time (s)
         real(dp), intent(in) :: t
         !> Velocities, n
         real(dp), intent(out) :: v(:)
         type(error_t), allocatable, intent(out) :: error
         !> Rotor speed (rad/s); needs set_rotor
         real(dp), intent(in), optional :: rotor_speed
         !> Velocities to start from, n (e.g. the &body velocity keys)
         real(dp), intent(in), optional :: guess(:)
      end subroutine mechanism_initial_velocities

      !> M = blockdiag(M_b(q_b)), block-sparse by body (block_groups).
      module subroutine mechanism_mass_sparse(self, q, M, error)
         class(mechanism_t), intent(inout) :: self
         real(dp), intent(in) :: q(:)                 !< coordinates, n
         type(block_sparse_t), intent(inout) :: M     !< n x n
         type(error_t), allocatable, intent(out) :: error
      end subroutine mechanism_mass_sparse

      !> Phi and Phi_q, Phi_q block-sparse (one row group per row, the bodies as column groups).
      module subroutine mechanism_constraints_and_jacobian_sparse(self, q, t, phi, Phi_q, error)
         class(mechanism_t), intent(inout) :: self
         real(dp), intent(in) :: q(:), t              !< coordinates (n), time (s)
         real(dp), intent(out) :: phi(:)              !< Phi, nc
         type(block_sparse_t), intent(inout) :: Phi_q !< nc x n
         type(error_t), allocatable, intent(out) :: error
      end subroutine mechanism_constraints_and_jacobian_sparse

      !> K = -df/dq + d(M a)/dq + d(Phi_q^T lambda)/dq and C = -df/dq', block-sparse by body
      !> (the same blocks as the dense tangents; differences if .not. analytic_tangents).
      module subroutine mechanism_tangents_sparse(self, q, v, a, t, lambda, K, C, error)
         class(mechanism_t), intent(inout) :: self
         !> Coordinates, velocities, accelerations (n), time (s), multipliers (nc)
         real(dp), intent(in) :: q(:), v(:), a(:), t, lambda(:)
         !> The tangents, n x n
         type(block_sparse_t), intent(inout) :: K, C
         type(error_t), allocatable, intent(out) :: error
      end subroutine mechanism_tangents_sparse

      !> S set up (if not already) as an n x n (rows = .false.) or nc x n block-sparse matrix
      !> with the bodies as column groups (and as row groups when square; else one group per
      !> row), all values zero.
      module subroutine block_groups(self, S, constraint_rows)
         type(mechanism_t), intent(in) :: self
         type(block_sparse_t), intent(inout) :: S
         !> Rows are the constraint rows
         logical, intent(in) :: constraint_rows
      end subroutine block_groups

      ! shared by the submodules (their bodies in mechanism_build.f90, mechanism_equations.f90)
      !> b is a body of the mechanism (1..number of bodies).
      pure logical module function valid_body(self, b)
         type(mechanism_t), intent(in) :: self
         integer, intent(in) :: b
      end function valid_body

      !> Where body b sits in q: coordinates k + 1 : k + nb.
      pure module subroutine body_layout(self, b, k, nb)
         type(mechanism_t), intent(in) :: self
         integer, intent(in) :: b
         integer, intent(out) :: k, nb
      end subroutine body_layout

      !> Where bodies a and b sit in q: coordinates ka + 1 : ka + na of a, kb + 1 : kb + nb of b.
      pure module subroutine pair_layout(self, body_a, body_b, ka, na, kb, nb)
         type(mechanism_t), intent(in) :: self
         integer, intent(in) :: body_a, body_b
         integer, intent(out) :: ka, na, kb, nb
      end subroutine pair_layout

      !> Rows of bodies a and b in q ([a's; b's]) and the number of a's.
      pure module subroutine pair_rows(self, body_a, body_b, rows, na)
         type(mechanism_t), intent(in) :: self
         integer, intent(in) :: body_a, body_b
         integer, allocatable, intent(out) :: rows(:)
         integer, intent(out) :: na
      end subroutine pair_rows

      !> The checks of a two-body force element `what` (spring, bushing) named `name`: both
      !> bodies added by add_body, two different ones, each marker one of its body's, and its
      !> coefficients (coefficients_ok, else the error says `refusal`).
      module subroutine check_pair_ends(self, what, name, body_a, marker_a, body_b, marker_b, &
         coefficients_ok, refusal, error)
         type(mechanism_t), intent(in) :: self
         character(len=*), intent(in) :: what, name
         integer, intent(in) :: body_a, marker_a, body_b, marker_b
         logical, intent(in) :: coefficients_ok
         character(len=*), intent(in) :: refusal
         type(error_t), allocatable, intent(out) :: error
      end subroutine check_pair_ends

      !> Number of bodies added (0 before the first).
      pure integer module function num_bodies(self)
         type(mechanism_t), intent(in) :: self
      end function num_bodies

      !> Number of joints added (0 before the first).
      pure integer module function num_joints(self)
         type(mechanism_t), intent(in) :: self
      end function num_joints

      !> n(f) = (-sin f, cos f, 0): normal of the driven x axis at angle f.
      pure module function drive_normal(angle) result(normal)
         real(dp), intent(in) :: angle
         real(dp) :: normal(3)
      end function drive_normal
   end interface

end module ffrf_mbs_mechanism
