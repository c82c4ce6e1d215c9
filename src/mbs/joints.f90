!> Joints between two markers: marker marker_a of body a and marker marker_b of body b (either
!> may be the ground, ffrf_mbs_rigid_body's ground_t, a body without coordinates). A joint gives
!> its constraint equations Phi(q_a, q_b) = 0 and the Jacobian blocks dPhi/dq_a, dPhi/dq_b from
!> the markers' positions, axes and their exact Jacobians (body_t), so it does not care whether
!> a body is rigid or flexible (Nikravesh, Computer-Aided Analysis of Mechanical Systems, 1988,
!> ch. 7, and Shabana, Dynamics of Multibody Systems, 3rd ed., ch. 3: joints from dot products
!> of body-fixed vectors; theory.md 3.5: joints at virtual nodes).
!>
!> Notation: r_a, r_b marker positions, d = r_b - r_a; x_a, y_a, z_a the axes of marker a and
!> x_b, y_b, z_b those of marker b (columns of the marker orientations, global components).
!> Each joint is a list of three kinds of scalar equations:
!>     position       d_c = 0             (c = global component x, y or z)
!>     lateral        u_a . d = 0         (u_a an axis of marker a)
!>     perpendicular  u_a . w_b = 0       (u_a an axis of marker a, w_b one of marker b)
!> The joint axis is the markers' local z axis; in the assembled pose the two marker frames
!> coincide (the perpendicularity equations also hold for some flipped poses, e.g. z_b = -z_a:
!> assemble from a pose near the intended one).
!>
!> | kind        | equations                                          | n | free relative motion   |
!> |-------------|----------------------------------------------------|---|------------------------|
!> | spherical   | d = 0                                              | 3 | 3 rotations            |
!> | revolute    | d = 0, x_a.z_b = 0, y_a.z_b = 0                    | 5 | rotation about z       |
!> | universal   | d = 0, x_a.y_b = 0                                 | 4 | about x_a and y_b      |
!> | prismatic   | x_a.d = y_a.d = 0, x_a.z_b = y_a.z_b = x_a.y_b = 0 | 5 | translation along z    |
!> | fixed       | d = 0, x_a.z_b = 0, y_a.z_b = 0, x_a.y_b = 0       | 6 | none                   |
!> | cylindrical | x_a.d = y_a.d = 0, x_a.z_b = y_a.z_b = 0           | 4 | rotation about and     |
!> |             |                                                    |   | translation along z    |
!>
!> Universal joint (Cardan): the shafts are the z axes of the markers; the cross has its arm
!> fixed in body a along x_a and its arm fixed in body b along y_b, kept perpendicular. It
!> transmits the torque about the shafts (a relative twist about z breaks x_a.y_b = 0).
!>
!> Reactions (joint_reaction): with the equations of motion M q'' = f - Phi_q^T lambda
!> (theory.md 3.4/4), the constraint force on body b is -Phi_qb^T lambda. It is the virtual work
!> of a force F_b at marker b and a moment M_b (global components), the action of body a on body
!> b through the joint, and likewise F_a, M_a at marker a on body a:
!>     position c:      F_b = -lambda e_c,           F_a = +lambda e_c
!>     lateral u_a:     F_b = -lambda u_a,           F_a = +lambda u_a,  M_a = -lambda u_a x d
!>     perpendicular:   M_b = +lambda u_a x w_b,     M_a = -lambda u_a x w_b
!> (summed over the equations). F_a = -F_b, and the moments balance about a common point. The
!> identity -lambda^T Phi_qb v_b = F_b . r_b_dot + M_b . omega_b (and the same for a) holds for
!> every velocity on the constraint |theta| = 1 (the unit test checks it).
!>
!> Constraint stiffness (constraint_hessian): the blocks of d(Phi_q^T lambda)/dq =
!> sum_i lambda_i d^2 Phi_i/dq^2 for the Newton iteration. A table joint forms it exactly: with
!> P = dr/dq, U = du_a/dq, W = dw_b/dq (the exact marker Jacobians) and the bodies'
!> marker_hessian for the second derivatives of r and of the axes,
!>     position c:     lambda (e_c . r_b'' - e_c . r_a'')
!>     lateral u_a:    lambda (d . u_a'' + u_a . (r_b'' - r_a'')) - lambda (U^T P_a + P_a^T U)
!>                     on (a, a), lambda U^T P_b on (a, b)
!>     perpendicular:  lambda (w_b . u_a'' + u_a . w_b''), lambda U^T W on (a, b).
!> The joint_t default is a central difference of `jacobian` over the joint's two bodies.
module ffrf_mbs_joints
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_choices, only: choice_t, choice_words, choice_name
   use ffrf_mbs_body, only: body_t
   use ffrf_mbs_dae_system, only: fd_step
   use ffrf_mbs_rotation, only: cross3
   implicit none
   private
   public :: joint_t, table_joint_t, kind_joint_t
   public :: new_joint, joint_reaction, joint_choices, joint_kind_name
   public :: JOINT_SPHERICAL, JOINT_REVOLUTE, JOINT_UNIVERSAL, JOINT_PRISMATIC, JOINT_FIXED
   public :: JOINT_CYLINDRICAL
   public :: EQ_POSITION, EQ_LATERAL, EQ_PERPENDICULAR

   !> Equation kind: a global component of d = r_b - r_a
   integer, parameter :: EQ_POSITION = 1
   !> Equation kind: u_a . d, u_a an axis of marker a
   integer, parameter :: EQ_LATERAL = 2
   !> Equation kind: u_a . w_b, axes of markers a and b
   integer, parameter :: EQ_PERPENDICULAR = 3

   !> Largest number of equations of a table joint
   integer, parameter :: max_table_equations = 6

   !> Joint kinds, as new_joint and mechanism_t%add_joint take them (the model maps the &joint
   !> type words onto them: ffrf_model_mechanism)
   integer, parameter :: JOINT_SPHERICAL = 1, JOINT_REVOLUTE = 2, JOINT_UNIVERSAL = 3, &
      JOINT_PRISMATIC = 4, JOINT_FIXED = 5, JOINT_CYLINDRICAL = 6

   !> The joint kinds' table: the &joint type words, the kinds they stand for and the names in
   !> messages and results (joint_kind_name), in the order messages list them
   !> (docs/developer.md "One table per choice")
   type(choice_t), parameter :: joint_choices(*) = [choice_t('revolute', JOINT_REVOLUTE), &
      choice_t('prismatic', JOINT_PRISMATIC), choice_t('spherical', JOINT_SPHERICAL), &
      choice_t('universal', JOINT_UNIVERSAL), choice_t('fixed', JOINT_FIXED), &
      choice_t('cylindrical', JOINT_CYLINDRICAL)]

   !> The equations of each kind (the module header's table), kind_equations(:, :, JOINT_*):
   !> columns [equation kind EQ_*, index a, index b]; for EQ_POSITION index a is the global
   !> component, otherwise the marker axes (1 = x, 2 = y, 3 = z) of a and b; zero columns after
   !> the last equation. A named constant: evaluated at compile time; one kind per row of
   !> joint_choices (JOINT_* numbered 1, 2, ...), so a row without its equations (or the other
   !> way round) does not compile.
   integer, parameter :: kind_equations(3, max_table_equations, size(joint_choices)) = &
      reshape([ &
      ! JOINT_SPHERICAL: d = 0
      EQ_POSITION, 1, 0, EQ_POSITION, 2, 0, EQ_POSITION, 3, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, &
      ! JOINT_REVOLUTE: d = 0, x_a.z_b = 0, y_a.z_b = 0
      EQ_POSITION, 1, 0, EQ_POSITION, 2, 0, EQ_POSITION, 3, 0, &
      EQ_PERPENDICULAR, 1, 3, EQ_PERPENDICULAR, 2, 3, 0, 0, 0, &
      ! JOINT_UNIVERSAL: d = 0, x_a.y_b = 0
      EQ_POSITION, 1, 0, EQ_POSITION, 2, 0, EQ_POSITION, 3, 0, EQ_PERPENDICULAR, 1, 2, &
      0, 0, 0, 0, 0, 0, &
      ! JOINT_PRISMATIC: x_a.d = 0, y_a.d = 0, x_a.z_b = 0, y_a.z_b = 0, x_a.y_b = 0
      EQ_LATERAL, 1, 0, EQ_LATERAL, 2, 0, EQ_PERPENDICULAR, 1, 3, EQ_PERPENDICULAR, 2, 3, &
      EQ_PERPENDICULAR, 1, 2, 0, 0, 0, &
      ! JOINT_FIXED: d = 0, x_a.z_b = 0, y_a.z_b = 0, x_a.y_b = 0
      EQ_POSITION, 1, 0, EQ_POSITION, 2, 0, EQ_POSITION, 3, 0, &
      EQ_PERPENDICULAR, 1, 3, EQ_PERPENDICULAR, 2, 3, EQ_PERPENDICULAR, 1, 2, &
      ! JOINT_CYLINDRICAL: x_a.d = 0, y_a.d = 0, x_a.z_b = 0, y_a.z_b = 0
      EQ_LATERAL, 1, 0, EQ_LATERAL, 2, 0, EQ_PERPENDICULAR, 1, 3, EQ_PERPENDICULAR, 2, 3, &
      0, 0, 0, 0, 0, 0], [3, max_table_equations, size(joint_choices)])

   !> A joint: num_equations algebraic equations Phi(q_a, q_b) = 0 between marker_a of body a and
   !> marker_b of body b.
   type, abstract :: joint_t
      !> Number of constraint equations
      integer :: num_equations = 0
      !> Marker of body a and of body b (set by connect)
      integer :: marker_a = 0, marker_b = 0
      !> Its kind (JOINT_*, set by new_joint)
      integer :: kind = 0
   contains
      !> The name of its kind ('revolute', ...: joint_kind_name of its JOINT_* kind)
      procedure :: kind_name => joint_kind_name_of
      !> Phi(q_a, q_b)
      procedure(joint_residual), deferred :: residual
      !> dPhi/dq_a, dPhi/dq_b
      procedure(joint_jacobian), deferred :: jacobian
      !> Force and moment transmitted, from the multipliers (see the module header)
      procedure(joint_reaction_interface), deferred :: reaction
      !> Attach to the markers of two bodies (checks that they exist)
      procedure :: connect => joint_connect
      !> Blocks of d(Phi_q^T lambda)/dq (default: central differences of `jacobian`)
      procedure :: constraint_hessian => joint_constraint_hessian_fd
      !> Phi and dPhi/dq_a, dPhi/dq_b in one call (default: `residual`, then `jacobian`)
      procedure :: residual_jacobian => joint_residual_jacobian
   end type joint_t

   abstract interface
      !> Constraint residuals.
      pure subroutine joint_residual(self, body_a, q_a, body_b, q_b, phi)
         import :: joint_t, body_t, dp
         implicit none
         !> The joint
         class(joint_t), intent(in) :: self
         !> Body a (rigid, flexible or ground)
         class(body_t), intent(in) :: body_a
         !> Coordinates of body a (body_a%num_coordinates)
         real(dp), intent(in) :: q_a(:)
         !> Body b
         class(body_t), intent(in) :: body_b
         !> Coordinates of body b (body_b%num_coordinates)
         real(dp), intent(in) :: q_b(:)
         !> Phi, num_equations (m for positions, 1 for axis products)
         real(dp), intent(out) :: phi(:)
      end subroutine joint_residual

      !> Constraint Jacobian blocks (exact partial derivatives, all Euler-parameter directions).
      pure subroutine joint_jacobian(self, body_a, q_a, body_b, q_b, jac_a, jac_b)
         import :: joint_t, body_t, dp
         implicit none
         !> The joint
         class(joint_t), intent(in) :: self
         !> Body a
         class(body_t), intent(in) :: body_a
         !> Coordinates of body a
         real(dp), intent(in) :: q_a(:)
         !> Body b
         class(body_t), intent(in) :: body_b
         !> Coordinates of body b
         real(dp), intent(in) :: q_b(:)
         !> dPhi/dq_a, num_equations x body_a%num_coordinates
         real(dp), intent(out) :: jac_a(:, :)
         !> dPhi/dq_b, num_equations x body_b%num_coordinates
         real(dp), intent(out) :: jac_b(:, :)
      end subroutine joint_jacobian

      !> Reaction force and moment from the multipliers.
      pure subroutine joint_reaction_interface(self, body_a, q_a, body_b, q_b, lambda, force, &
            moment)
         import :: joint_t, body_t, dp
         implicit none
         !> The joint
         class(joint_t), intent(in) :: self
         !> Body a
         class(body_t), intent(in) :: body_a
         !> Coordinates of body a
         real(dp), intent(in) :: q_a(:)
         !> Body b
         class(body_t), intent(in) :: body_b
         !> Coordinates of body b
         real(dp), intent(in) :: q_b(:)
         !> Multipliers of the joint's equations, num_equations
         real(dp), intent(in) :: lambda(:)
         !> Global force (N): column 1 on body a at marker a, column 2 on body b at marker b
         real(dp), intent(out) :: force(3, 2)
         !> Global moment (N m): column 1 on body a, column 2 on body b
         real(dp), intent(out) :: moment(3, 2)
      end subroutine joint_reaction_interface
   end interface

   !> A joint defined by a table of position, lateral and perpendicular equations (module
   !> header); residual, Jacobian and reaction are common to all such joints.
   type, abstract, extends(joint_t) :: table_joint_t
   contains
      !> Equations as columns [kind (EQ_*), index a, index b]: for EQ_POSITION index a is the
      !> global component; otherwise the marker axes (1 = x, 2 = y, 3 = z) of a and b; unused
      !> columns (kind 0) after the last equation
      procedure(joint_table), deferred :: equation_table
      procedure :: connect => table_joint_connect
      procedure :: residual => table_joint_residual
      procedure :: jacobian => table_joint_jacobian
      procedure :: residual_jacobian => table_joint_residual_jacobian
      procedure :: reaction => table_joint_reaction
      procedure :: constraint_hessian => table_joint_constraint_hessian
   end type table_joint_t

   abstract interface
      !> Equation table (3, max_table_equations), unused columns zero.
      pure function joint_table(self) result(table)
         import :: table_joint_t, max_table_equations
         implicit none
         class(table_joint_t), intent(in) :: self
         integer :: table(3, max_table_equations)
      end function joint_table
   end interface

   !> A joint of one of the JOINT_* kinds: its equations are the kind's column of
   !> kind_equations (the module header's table).
   type, extends(table_joint_t) :: kind_joint_t
   contains
      procedure :: equation_table => kind_joint_table
   end type kind_joint_t

contains

   ! ----------------------------------------------------------------------------------------------
   ! Factory and common procedures

   !> Allocate a joint of `kind` (a JOINT_* of joint_choices: its equations are the kind's
   !> column of kind_equations). Any other value is an FFRF_INPUT_ERROR listing the valid
   !> kinds. The joint still has to be connected to its markers (connect).
   subroutine new_joint(kind, joint, error)
      !> Joint kind (JOINT_*)
      integer, intent(in) :: kind
      !> The new joint
      class(joint_t), allocatable, intent(out) :: joint
      type(error_t), allocatable, intent(out) :: error
      if (choice_name(joint_choices, kind, '') == '') then
         call fatal_error(error, FFRF_INPUT_ERROR, 'joint kind ' // to_str(kind) // &
            ' is unknown; valid kinds: JOINT_* of ffrf_mbs_joints (' // &
            choice_words(joint_choices) // ')')
         return
      end if
      allocate (kind_joint_t :: joint)
      joint%kind = kind
      select type (joint)
      class is (table_joint_t)
         joint%num_equations = table_size(joint%equation_table())
      end select
   end subroutine new_joint

   !> The name of joint kind `kind` ('revolute', ...; 'unknown' for a value that is no kind),
   !> for messages and results.
   pure function joint_kind_name(kind) result(name)
      !> Joint kind (JOINT_*)
      integer, intent(in) :: kind
      character(len=:), allocatable :: name
      name = choice_name(joint_choices, kind)
   end function joint_kind_name

   !> The name of the joint's kind (joint_kind_name).
   pure function joint_kind_name_of(self) result(name)
      class(joint_t), intent(in) :: self
      character(len=:), allocatable :: name
      name = joint_kind_name(self%kind)
   end function joint_kind_name_of

   !> Attach the joint to marker marker_a of body a and marker_b of body b; checks that the
   !> markers exist.
   subroutine joint_connect(self, body_a, marker_a, body_b, marker_b, error)
      !> The joint
      class(joint_t), intent(inout) :: self
      !> Body a
      class(body_t), intent(in) :: body_a
      !> Marker number on body a
      integer, intent(in) :: marker_a
      !> Body b
      class(body_t), intent(in) :: body_b
      !> Marker number on body b
      integer, intent(in) :: marker_b
      type(error_t), allocatable, intent(out) :: error
      call check_marker(body_a, marker_a, 'a')
      if (.not. allocated(error)) call check_marker(body_b, marker_b, 'b')
      if (allocated(error)) return
      self%marker_a = marker_a
      self%marker_b = marker_b
   contains
      !> Marker `marker` must be one of the body's.
      subroutine check_marker(body, marker, end)
         class(body_t), intent(in) :: body
         integer, intent(in) :: marker
         character(len=*), intent(in) :: end
         if (marker < 1 .or. marker > body%num_markers) call fatal_error(error, &
            FFRF_INPUT_ERROR, self%kind_name() // ' joint: marker ' // to_str(marker) // &
            ' of body ' // end // ' does not exist; the body has ' // &
            to_str(body%num_markers) // ' markers (interfaces)')
      end subroutine check_marker
   end subroutine joint_connect

   !> Phi and its Jacobian blocks (the residual and jacobian procedures, one after the other).
   pure subroutine joint_residual_jacobian(self, body_a, q_a, body_b, q_b, phi, jac_a, jac_b)
      !> The joint
      class(joint_t), intent(in) :: self
      !> Body a
      class(body_t), intent(in) :: body_a
      !> Coordinates of body a
      real(dp), intent(in) :: q_a(:)
      !> Body b
      class(body_t), intent(in) :: body_b
      !> Coordinates of body b
      real(dp), intent(in) :: q_b(:)
      !> Phi, num_equations
      real(dp), intent(out) :: phi(:)
      !> dPhi/dq_a, num_equations x body_a%num_coordinates
      real(dp), intent(out) :: jac_a(:, :)
      !> dPhi/dq_b, num_equations x body_b%num_coordinates
      real(dp), intent(out) :: jac_b(:, :)
      call self%residual(body_a, q_a, body_b, q_b, phi)
      call self%jacobian(body_a, q_a, body_b, q_b, jac_a, jac_b)
   end subroutine joint_residual_jacobian

   !> Blocks of d(Phi_q^T lambda)/dq by central differences of `jacobian` over q_a and q_b:
   !> K_aa = d(jac_a^T lambda)/dq_a, K_ab = d(jac_a^T lambda)/dq_b, K_bb = d(jac_b^T lambda)/dq_b
   !> (the (b, a) block is K_ab^T).
   pure subroutine joint_constraint_hessian_fd(self, body_a, q_a, body_b, q_b, lambda, K_aa, &
         K_ab, K_bb)
      !> The joint
      class(joint_t), intent(in) :: self
      !> Body a
      class(body_t), intent(in) :: body_a
      !> Coordinates of body a
      real(dp), intent(in) :: q_a(:)
      !> Body b
      class(body_t), intent(in) :: body_b
      !> Coordinates of body b
      real(dp), intent(in) :: q_b(:)
      !> Multipliers of the joint's equations
      real(dp), intent(in) :: lambda(:)
      !> (a, a) block, n_a x n_a
      real(dp), intent(out) :: K_aa(:, :)
      !> (a, b) block, n_a x n_b
      real(dp), intent(out) :: K_ab(:, :)
      !> (b, b) block, n_b x n_b
      real(dp), intent(out) :: K_bb(:, :)
      real(dp) :: xa(size(q_a)), xb(size(q_b)), delta
      real(dp) :: ja_p(self%num_equations, size(q_a)), jb_p(self%num_equations, size(q_b))
      real(dp) :: ja_m(self%num_equations, size(q_a)), jb_m(self%num_equations, size(q_b))
      integer :: j
      xa = q_a
      xb = q_b
      do j = 1, size(q_a)
         delta = fd_step(q_a(j))
         xa(j) = q_a(j) + delta
         call self%jacobian(body_a, xa, body_b, xb, ja_p, jb_p)
         xa(j) = q_a(j) - delta
         call self%jacobian(body_a, xa, body_b, xb, ja_m, jb_m)
         xa(j) = q_a(j)
         K_aa(:, j) = matmul(lambda, ja_p - ja_m) / (2.0_dp * delta)
      end do
      do j = 1, size(q_b)
         delta = fd_step(q_b(j))
         xb(j) = q_b(j) + delta
         call self%jacobian(body_a, xa, body_b, xb, ja_p, jb_p)
         xb(j) = q_b(j) - delta
         call self%jacobian(body_a, xa, body_b, xb, ja_m, jb_m)
         xb(j) = q_b(j)
         K_ab(:, j) = matmul(lambda, ja_p - ja_m) / (2.0_dp * delta)
         K_bb(:, j) = matmul(lambda, jb_p - jb_m) / (2.0_dp * delta)
      end do
   end subroutine joint_constraint_hessian_fd

   !> Exact blocks of d(Phi_q^T lambda)/dq of a table joint (module header).
   pure subroutine table_joint_constraint_hessian(self, body_a, q_a, body_b, q_b, lambda, &
         K_aa, K_ab, K_bb)
      class(table_joint_t), intent(in) :: self
      !> Body a
      class(body_t), intent(in) :: body_a
      !> Coordinates of body a
      real(dp), intent(in) :: q_a(:)
      !> Body b
      class(body_t), intent(in) :: body_b
      !> Coordinates of body b
      real(dp), intent(in) :: q_b(:)
      !> Multipliers of the joint's equations
      real(dp), intent(in) :: lambda(:)
      !> (a, a) block, n_a x n_a
      real(dp), intent(out) :: K_aa(:, :)
      !> (a, b) block, n_a x n_b
      real(dp), intent(out) :: K_ab(:, :)
      !> (b, b) block, n_b x n_b
      real(dp), intent(out) :: K_bb(:, :)
      integer :: table(3, max_table_equations)
      real(dp) :: frame_a(3, 3), frame_b(3, 3), d(3), u(3), w(3)
      real(dp) :: pos_a(3, body_a%num_coordinates), pos_b(3, body_b%num_coordinates)
      real(dp) :: axis_a(3, body_a%num_coordinates, 3), axis_b(3, body_b%num_coordinates, 3)
      real(dp) :: wr_a(3), wr_b(3), wx_a(3, 3), wx_b(3, 3)
      real(dp) :: hess_a(body_a%num_coordinates, body_a%num_coordinates)
      real(dp) :: hess_b(body_b%num_coordinates, body_b%num_coordinates)
      integer :: i, ia, ib
      table = self%equation_table()
      call table_kinematics(self, table, body_a, q_a, body_b, q_b, frame_a, frame_b, d, pos_a, &
         pos_b, axis_a, axis_b)
      ! Weights of the second derivatives of the markers' positions and axes, and the products
      ! of first derivatives
      wr_a = 0.0_dp
      wr_b = 0.0_dp
      wx_a = 0.0_dp
      wx_b = 0.0_dp
      K_ab = 0.0_dp
      K_aa = 0.0_dp
      do i = 1, table_size(table)
         select case (table(1, i))
         case (EQ_POSITION)
            wr_b(table(2, i)) = wr_b(table(2, i)) + lambda(i)
            wr_a(table(2, i)) = wr_a(table(2, i)) - lambda(i)
         case (EQ_LATERAL)
            ia = table(2, i)
            u = frame_a(:, ia)
            wx_a(:, ia) = wx_a(:, ia) + lambda(i) * d
            wr_a = wr_a - lambda(i) * u
            wr_b = wr_b + lambda(i) * u
            call add_product(-lambda(i), axis_a(:, :, ia), pos_a, K_aa)
            call add_product(-lambda(i), pos_a, axis_a(:, :, ia), K_aa)
            call add_product(lambda(i), axis_a(:, :, ia), pos_b, K_ab)
         case default
            ia = table(2, i)
            ib = table(3, i)
            u = frame_a(:, ia)
            w = frame_b(:, ib)
            wx_a(:, ia) = wx_a(:, ia) + lambda(i) * w
            wx_b(:, ib) = wx_b(:, ib) + lambda(i) * u
            call add_product(lambda(i), axis_a(:, :, ia), axis_b(:, :, ib), K_ab)
         end select
      end do
      if (body_a%num_coordinates > 0) then
         call body_a%marker_hessian(q_a, self%marker_a, wr_a, wx_a, hess_a)
         K_aa = K_aa + hess_a
      end if
      K_bb = 0.0_dp
      if (body_b%num_coordinates > 0) then
         call body_b%marker_hessian(q_b, self%marker_b, wr_b, wx_b, hess_b)
         K_bb = hess_b
      end if
   end subroutine table_joint_constraint_hessian

   !> K <- K + s X^T Y for X (3 x n_x), Y (3 x n_y): element by element, without the transpose
   !> and product temporaries of matmul(transpose(X), Y).
   pure subroutine add_product(s, X, Y, K)
      real(dp), intent(in) :: s, X(:, :), Y(:, :)
      real(dp), intent(inout) :: K(:, :)
      integer :: i, j
      do j = 1, size(Y, 2)
         do i = 1, size(X, 2)
            K(i, j) = K(i, j) + s * (X(1, i) * Y(1, j) + X(2, i) * Y(2, j) + X(3, i) * Y(3, j))
         end do
      end do
   end subroutine add_product

   !> Force and moment that the joint transmits for the multipliers lambda (module header):
   !> force(:, 1), moment(:, 1) act on body a at marker a, force(:, 2), moment(:, 2) on body b
   !> at marker b; global components (N, N m).
   pure subroutine joint_reaction(joint, body_a, q_a, body_b, q_b, lambda, force, moment)
      !> The joint
      class(joint_t), intent(in) :: joint
      !> Body a
      class(body_t), intent(in) :: body_a
      !> Coordinates of body a
      real(dp), intent(in) :: q_a(:)
      !> Body b
      class(body_t), intent(in) :: body_b
      !> Coordinates of body b
      real(dp), intent(in) :: q_b(:)
      !> Multipliers of the joint's equations
      real(dp), intent(in) :: lambda(:)
      !> Force (N): column 1 on body a, column 2 on body b
      real(dp), intent(out) :: force(3, 2)
      !> Moment (N m): column 1 on body a, column 2 on body b
      real(dp), intent(out) :: moment(3, 2)
      call joint%reaction(body_a, q_a, body_b, q_b, lambda, force, moment)
   end subroutine joint_reaction

   !> connect, and the number of equations from the table.
   subroutine table_joint_connect(self, body_a, marker_a, body_b, marker_b, error)
      !> The joint
      class(table_joint_t), intent(inout) :: self
      !> Body a
      class(body_t), intent(in) :: body_a
      !> Marker number on body a
      integer, intent(in) :: marker_a
      !> Body b
      class(body_t), intent(in) :: body_b
      !> Marker number on body b
      integer, intent(in) :: marker_b
      type(error_t), allocatable, intent(out) :: error
      self%num_equations = table_size(self%equation_table())
      call joint_connect(self, body_a, marker_a, body_b, marker_b, error)
   end subroutine table_joint_connect

   !> Phi from the equation table.
   pure subroutine table_joint_residual(self, body_a, q_a, body_b, q_b, phi)
      class(table_joint_t), intent(in) :: self
      !> Body a
      class(body_t), intent(in) :: body_a
      !> Coordinates of body a
      real(dp), intent(in) :: q_a(:)
      !> Body b
      class(body_t), intent(in) :: body_b
      !> Coordinates of body b
      real(dp), intent(in) :: q_b(:)
      !> Phi, num_equations
      real(dp), intent(out) :: phi(:)
      integer :: table(3, max_table_equations)
      real(dp) :: frame_a(3, 3), frame_b(3, 3), d(3)
      integer :: i
      table = self%equation_table()
      call marker_frames(self, body_a, q_a, body_b, q_b, frame_a, frame_b, d)
      do i = 1, table_size(table)
         select case (table(1, i))
         case (EQ_POSITION)
            phi(i) = d(table(2, i))
         case (EQ_LATERAL)
            phi(i) = dot_product(frame_a(:, table(2, i)), d)
         case default
            phi(i) = dot_product(frame_a(:, table(2, i)), frame_b(:, table(3, i)))
         end select
      end do
   end subroutine table_joint_residual

   !> Phi (as table_joint_residual) and dPhi/dq_a, dPhi/dq_b from one evaluation of each marker's
   !> kinematics, with the markers' exact Jacobians:
   !>     position c:     -(dr_a/dq_a)_c,                  (dr_b/dq_b)_c
   !>     lateral u_a:    d^T du_a/dq_a - u_a^T dr_a/dq_a,  u_a^T dr_b/dq_b
   !>     perpendicular:  w_b^T du_a/dq_a,                 u_a^T dw_b/dq_b
   pure subroutine table_joint_residual_jacobian(self, body_a, q_a, body_b, q_b, phi, jac_a, &
         jac_b)
      class(table_joint_t), intent(in) :: self
      !> Body a
      class(body_t), intent(in) :: body_a
      !> Coordinates of body a
      real(dp), intent(in) :: q_a(:)
      !> Body b
      class(body_t), intent(in) :: body_b
      !> Coordinates of body b
      real(dp), intent(in) :: q_b(:)
      !> Phi, num_equations
      real(dp), intent(out) :: phi(:)
      !> dPhi/dq_a, num_equations x body_a%num_coordinates
      real(dp), intent(out) :: jac_a(:, :)
      !> dPhi/dq_b, num_equations x body_b%num_coordinates
      real(dp), intent(out) :: jac_b(:, :)
      integer :: table(3, max_table_equations)
      real(dp) :: frame_a(3, 3), frame_b(3, 3), d(3), u(3), w(3)
      real(dp) :: pos_a(3, body_a%num_coordinates), pos_b(3, body_b%num_coordinates)
      real(dp) :: axis_a(3, body_a%num_coordinates, 3), axis_b(3, body_b%num_coordinates, 3)
      integer :: i, c
      table = self%equation_table()
      call table_kinematics(self, table, body_a, q_a, body_b, q_b, frame_a, frame_b, d, pos_a, &
         pos_b, axis_a, axis_b)
      ! Row by row as explicit 3-term products (matmul of a 3-vector by a row section would
      ! build a temporary per equation)
      do i = 1, table_size(table)
         select case (table(1, i))
         case (EQ_POSITION)
            phi(i) = d(table(2, i))
            jac_a(i, :) = -pos_a(table(2, i), :)
            jac_b(i, :) = pos_b(table(2, i), :)
         case (EQ_LATERAL)
            u = frame_a(:, table(2, i))
            phi(i) = dot_product(u, d)
            do c = 1, size(jac_a, 2)
               jac_a(i, c) = dot_product(d, axis_a(:, c, table(2, i))) - &
                  dot_product(u, pos_a(:, c))
            end do
            do c = 1, size(jac_b, 2)
               jac_b(i, c) = dot_product(u, pos_b(:, c))
            end do
         case default
            u = frame_a(:, table(2, i))
            w = frame_b(:, table(3, i))
            phi(i) = dot_product(u, w)
            do c = 1, size(jac_a, 2)
               jac_a(i, c) = dot_product(w, axis_a(:, c, table(2, i)))
            end do
            do c = 1, size(jac_b, 2)
               jac_b(i, c) = dot_product(u, axis_b(:, c, table(3, i)))
            end do
         end select
      end do
   end subroutine table_joint_residual_jacobian

   !> dPhi/dq_a, dPhi/dq_b of a table joint (table_joint_residual_jacobian without Phi).
   pure subroutine table_joint_jacobian(self, body_a, q_a, body_b, q_b, jac_a, jac_b)
      class(table_joint_t), intent(in) :: self
      !> Body a
      class(body_t), intent(in) :: body_a
      !> Coordinates of body a
      real(dp), intent(in) :: q_a(:)
      !> Body b
      class(body_t), intent(in) :: body_b
      !> Coordinates of body b
      real(dp), intent(in) :: q_b(:)
      !> dPhi/dq_a, num_equations x body_a%num_coordinates
      real(dp), intent(out) :: jac_a(:, :)
      !> dPhi/dq_b, num_equations x body_b%num_coordinates
      real(dp), intent(out) :: jac_b(:, :)
      real(dp) :: phi(self%num_equations)
      call table_joint_residual_jacobian(self, body_a, q_a, body_b, q_b, phi, jac_a, jac_b)
   end subroutine table_joint_jacobian

   !> Reaction force and moment on each body from the multipliers (module header).
   pure subroutine table_joint_reaction(self, body_a, q_a, body_b, q_b, lambda, force, moment)
      class(table_joint_t), intent(in) :: self
      !> Body a
      class(body_t), intent(in) :: body_a
      !> Coordinates of body a
      real(dp), intent(in) :: q_a(:)
      !> Body b
      class(body_t), intent(in) :: body_b
      !> Coordinates of body b
      real(dp), intent(in) :: q_b(:)
      !> Multipliers, num_equations
      real(dp), intent(in) :: lambda(:)
      !> Force (N): column 1 on body a at marker a, column 2 on body b at marker b
      real(dp), intent(out) :: force(3, 2)
      !> Moment (N m): column 1 on body a, column 2 on body b
      real(dp), intent(out) :: moment(3, 2)
      integer :: table(3, max_table_equations)
      real(dp) :: frame_a(3, 3), frame_b(3, 3), d(3), u(3), uxw(3)
      integer :: i
      table = self%equation_table()
      call marker_frames(self, body_a, q_a, body_b, q_b, frame_a, frame_b, d)
      force = 0.0_dp
      moment = 0.0_dp
      do i = 1, table_size(table)
         select case (table(1, i))
         case (EQ_POSITION)
            force(table(2, i), 1) = force(table(2, i), 1) + lambda(i)
            force(table(2, i), 2) = force(table(2, i), 2) - lambda(i)
         case (EQ_LATERAL)
            u = frame_a(:, table(2, i))
            force(:, 1) = force(:, 1) + lambda(i) * u
            force(:, 2) = force(:, 2) - lambda(i) * u
            moment(:, 1) = moment(:, 1) - lambda(i) * cross3(u, d)
         case default
            uxw = cross3(frame_a(:, table(2, i)), frame_b(:, table(3, i)))
            moment(:, 1) = moment(:, 1) - lambda(i) * uxw
            moment(:, 2) = moment(:, 2) + lambda(i) * uxw
         end select
      end do
   end subroutine table_joint_reaction

   !> The markers' frames and d = r_b - r_a, from which a table joint's rows are written.
   pure subroutine marker_frames(self, body_a, q_a, body_b, q_b, frame_a, frame_b, d)
      class(table_joint_t), intent(in) :: self
      class(body_t), intent(in) :: body_a, body_b
      real(dp), intent(in) :: q_a(:), q_b(:)
      real(dp), intent(out) :: frame_a(3, 3), frame_b(3, 3), d(3)
      frame_a = body_a%marker_orientation(q_a, self%marker_a)
      frame_b = body_b%marker_orientation(q_b, self%marker_b)
      d = body_b%marker_position(q_b, self%marker_b) - body_a%marker_position(q_a, self%marker_a)
   end subroutine marker_frames

   !> marker_frames with the markers' position Jacobians pos_a, pos_b (3 x n) and the axis
   !> Jacobians axis_a, axis_b (3 x n x 3) of the axes that appear in `table` (the others are
   !> not set), from one marker_kinematics call per body.
   pure subroutine table_kinematics(self, table, body_a, q_a, body_b, q_b, frame_a, frame_b, d, &
         pos_a, pos_b, axis_a, axis_b)
      class(table_joint_t), intent(in) :: self
      integer, intent(in) :: table(:, :)
      class(body_t), intent(in) :: body_a, body_b
      real(dp), intent(in) :: q_a(:), q_b(:)
      real(dp), intent(out) :: frame_a(3, 3), frame_b(3, 3), d(3)
      real(dp), intent(out) :: pos_a(:, :), pos_b(:, :)
      real(dp), intent(inout) :: axis_a(:, :, :), axis_b(:, :, :)
      real(dp) :: r_a(3), r_b(3)
      logical :: need_a(3), need_b(3)
      integer :: i
      need_a = .false.
      need_b = .false.
      do i = 1, table_size(table)
         if (table(1, i) /= EQ_POSITION) need_a(table(2, i)) = .true.
         if (table(1, i) == EQ_PERPENDICULAR) need_b(table(3, i)) = .true.
      end do
      call body_a%marker_kinematics(q_a, self%marker_a, need_a, r_a, frame_a, pos_a, axis_a)
      call body_b%marker_kinematics(q_b, self%marker_b, need_b, r_b, frame_b, pos_b, axis_b)
      d = r_b - r_a
   end subroutine table_kinematics

   !> Number of equations in a table (columns before the first of kind 0).
   pure function table_size(table) result(n)
      integer, intent(in) :: table(:, :)
      integer :: n
      do n = 0, size(table, 2) - 1
         if (table(1, n + 1) == 0) return
      end do
      n = size(table, 2)
   end function table_size

   !> The equations of the joint's kind (kind_equations).
   pure function kind_joint_table(self) result(table)
      class(kind_joint_t), intent(in) :: self
      integer :: table(3, max_table_equations)
      table = kind_equations(:, :, self%kind)
   end function kind_joint_table

end module ffrf_mbs_joints
