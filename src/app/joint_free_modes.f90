!> The modes a body's joints leave free (issue 30, part 1; docs/theory.md section 8).
!>
!> A body's candidate modes (RC normal modes: the reference conditions hold only some virtual-node
!> dofs) can move an interface in a way its joint forbids: a revolute bearing holds the two
!> rotations of its virtual node across the axis, a prismatic guide every rotation. In the
!> assembly such a mode cannot be excited (its modal coordinate is held at zero by the joint
!> equations, which the integrator then finds redundant or nearly so); it carries no strain
!> energy and selecting it models nothing. What the body can do in the assembly is the part of
!> the candidate space the joints allow.
!>
!> Linearised joint equations in the starting pose (every body at its &body position and
!> orientation A_b, ffrf_app_mechanism_builder, global components; the two ends of a joint at one point r_j with one
!> frame E_j = [x y z], z the joint axis). Unknowns: a small rigid motion (dx_b, dtheta_b) of
!> every body b (about the global origin: any point gives the same span) and the modal
!> coordinates eta of body k (its other flexible bodies move rigidly here). An end of a joint on
!> body b moves by
!>     du = dx_b + dtheta_b x r_j (+ Psi_u,i eta),   dphi = dtheta_b (+ Psi_r,i eta)
!> (Psi_u,i, Psi_r,i: the translation and rotation rows of the virtual-node shapes of interface
!> i of body k, turned to global by A_k; ffrf_mbs_joints: the marker axes of an interface are the body axes). A joint
!> locks the relative motion components (du_2 - du_1, dphi_2 - dphi_1) in its frame:
!>     spherical T xyz; revolute T xyz, R xy; universal T xyz, R z; prismatic T xy, R xyz;
!>     fixed T xyz, R xyz; cylindrical T xy, R xy
!> (the linearisation of the equations of ffrf_mbs_joints: x_a.z_b = 0 holds R y, y_a.z_b = 0
!> R x, x_a.y_b = 0 R z, x_a.d = 0 T x). Stacked: C_r r + C_eta eta = 0, rotations scaled by
!> the body's size L (rows and rigid rotation columns) so that all entries are lengths.
!>
!> Free modal motions: eta with C_eta eta in range(C_r), i.e. the null space of
!> A = (I - Q Q^T) C_eta, Q an orthonormal basis of range(C_r) (SVD). A right singular vector of
!> A with singular value above LOCK_RTOL max|C_eta| is locked; the others span the free space N
!> (orthonormal, num_candidates x num_free). The modes in it: Rayleigh-Ritz of the body in the
!> span of Phi N, with mass-normalised candidates (Phi^T M Phi = I, Phi^T K Phi = Omega^2):
!>     N^T Omega^2 N y = omega^2 y,  modes Phi W, W = N Y (M-orthonormal, K-diagonal),
!> the lowest constrained modes of the body whose interfaces move as the joints allow, within
!> the candidates (their frequencies lie above those of the candidates: interlacing). A
!> candidate's free share ||N^T e_j||^2 in [0, 1] says how much of it survives.
module ffrf_app_joint_free_modes
   use ffrf_core_kinds, only: dp, pi
   use ffrf_core_error, only: error_t
   use ffrf_core_strings, only: to_str
   use ffrf_la_dense, only: singular_values, symmetric_eigen, skew
   use ffrf_model_model, only: model_t
   use ffrf_mbs_rotation, only: frame_from_axis, identity3
   use ffrf_mbs_joints, only: JOINT_SPHERICAL, JOINT_REVOLUTE, JOINT_UNIVERSAL, &
      JOINT_PRISMATIC, JOINT_FIXED, JOINT_CYLINDRICAL
   use ffrf_modes_modal_analysis, only: body_modes_t
   use ffrf_mpc_interface, only: VIRTUAL_NODE_POSITION
   use ffrf_modes_fingerprint, only: set_joint_projection
   implicit none
   private
   public :: joint_locks_t, joint_free_modes, locked_components, LOCK_RTOL

   !> A right singular vector of the locked part A with a singular value above LOCK_RTOL times
   !> the largest |entry| of C_eta is locked (the free ones sit at round-off of the eigenvectors,
   !> ~1e-12 here; a mode that touches a lock by 1e-6 of its size is still held by it)
   real(dp), parameter :: LOCK_RTOL = 1.0e-7_dp
   !> Rank tolerance of the rigid part C_r (exact geometry)
   real(dp), parameter :: RIGID_RTOL = 1.0e-10_dp
   character(len=2), parameter :: COMPONENT(6) = ['Tx', 'Ty', 'Tz', 'Rx', 'Ry', 'Rz']

   !> What the joints did to a body's candidates.
   type :: joint_locks_t
      !> Candidates, locked combinations, free modes (num_candidates - num_locked)
      integer :: num_candidates = 0, num_locked = 0
      !> Frequencies of the candidates as computed (Hz)
      real(dp), allocatable :: candidate_hz(:)
      !> Free share of each candidate, ||N^T e_j||^2 (1: untouched by the joints, 0: locked)
      real(dp), allocatable :: free_share(:)
      !> W (num_candidates x num_free): the free modes in the candidates
      real(dp), allocatable :: combination(:, :)
      !> The joint components the candidates move: "joint 'main_bearing_B1' Rx Ry; ..." (in
      !> the joint frames, z along the axis)
      character(len=:), allocatable :: locks
   end type joint_locks_t

contains

   !> Replace the modes of model body k by the modes its joints leave free (module header).
   subroutine joint_free_modes(model, k, modes, locks, error)
      !> The case resolved (joints with model body indices, marker handles and axes; body
      !> positions; rigid and ground markers)
      type(model_t), intent(in) :: model
      integer, intent(in) :: k
      !> In: the candidates of body k (mass-normalised); out: its free modes, ascending
      type(body_modes_t), intent(inout) :: modes
      type(joint_locks_t), intent(out) :: locks
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: C_r(:, :), C_eta(:, :), A(:, :), Q(:, :), N(:, :), W(:, :)
      real(dp), allocatable :: s(:), free_omega2(:), row_norm(:), Y(:, :)
      !> Per row: component (2 characters) and joint name
      character(len=66), allocatable :: row_label(:)
      character(len=64) :: previous
      real(dp) :: scale, length
      integer :: nc, rank_r, rank_a, i, j, big

      nc = size(modes%frequency_hz)
      locks%num_candidates = nc
      locks%candidate_hz = modes%frequency_hz
      locks%locks = ''
      if (nc == 0) then
         allocate (locks%free_share(0), locks%combination(0, 0))
         return
      end if
      length = body_length(modes)
      call lock_equations(model, k, modes, length, C_r, C_eta, row_label)
      scale = maxval([0.0_dp, abs(C_eta)])
      ! Q: orthonormal basis of range(C_r), the left singular vectors of C_r (the right ones
      ! of its transpose)
      call singular_values(transpose(C_r), s, error, v=Q)
      if (allocated(error)) return
      rank_r = count(s > RIGID_RTOL * maxval([0.0_dp, s]))
      Q = Q(:, 1:rank_r)
      A = C_eta - matmul(Q, matmul(transpose(Q), C_eta))
      call singular_values(A, s, error, v=N)
      if (allocated(error)) return
      rank_a = count(s > LOCK_RTOL * scale)
      locks%num_locked = rank_a
      ! N: right singular vectors rank_a + 1 .. nc
      N = N(:, rank_a + 1:nc)
      locks%free_share = sum(N**2, dim=2)
      ! the joint components the candidates move (rows of C_eta), grouped per joint
      row_norm = norm2(C_eta, dim=2)
      previous = ''
      do i = 1, size(row_label)
         if (row_norm(i) <= LOCK_RTOL * scale) cycle
         if (row_label(i)(3:) /= previous) then
            previous = row_label(i)(3:)
            locks%locks = locks%locks // '; joint ''' // trim(previous) // ''''
         end if
         locks%locks = locks%locks // ' ' // row_label(i)(1:2)
      end do
      if (len(locks%locks) > 2) locks%locks = locks%locks(3:)
      ! Rayleigh-Ritz in span(Phi N): N^T Omega^2 N y = omega^2 y
      free_omega2 = (2.0_dp * pi * modes%frequency_hz)**2
      W = matmul(transpose(N), N * spread(free_omega2, 2, size(N, 2)))
      allocate (Y(size(W, 1), size(W, 1)))
      deallocate (free_omega2)
      allocate (free_omega2(size(W, 1)))
      if (size(W, 1) > 0) call symmetric_eigen(W, free_omega2, Y, error)
      if (allocated(error)) return
      W = matmul(N, Y)
      ! a sign fixed by the candidates (not by the eigen solver's kernel): the largest |entry|
      ! of each free mode's combination positive (the first of near-equal ones)
      do j = 1, size(W, 2)
         big = 1
         do i = 2, nc
            if (abs(W(i, j)) > abs(W(big, j)) * (1.0_dp + 1.0e-9_dp)) big = i
         end do
         if (W(big, j) < 0.0_dp) W(:, j) = -W(:, j)
      end do
      locks%combination = W
      call combine_modes(modes, W, sqrt(max(free_omega2, 0.0_dp)) / (2.0_dp * pi))
      call set_joint_projection(modes%fingerprint, 'free of the joint locks: ' // &
         to_str(size(W, 2)) // ' combinations of ' // to_str(nc) // ' candidates (' // &
         to_str(rank_a) // ' locked)')
   end subroutine joint_free_modes

   !> "Tx Ty Rz": the components a joint kind locks, in its frame (module header).
   pure function locked_components(kind) result(locked)
      integer, intent(in) :: kind
      logical :: locked(6)
      select case (kind)
      case (JOINT_SPHERICAL)
         locked = [.true., .true., .true., .false., .false., .false.]
      case (JOINT_REVOLUTE)
         locked = [.true., .true., .true., .true., .true., .false.]
      case (JOINT_UNIVERSAL)
         locked = [.true., .true., .true., .false., .false., .true.]
      case (JOINT_PRISMATIC)
         locked = [.true., .true., .false., .true., .true., .true.]
      case (JOINT_FIXED)
         locked = .true.
      case (JOINT_CYLINDRICAL)
         locked = [.true., .true., .false., .true., .true., .false.]
      case default
         locked = .false.
      end select
   end function locked_components

   !> The linearised joint equations C_r r + C_eta eta = 0 of every joint of the model (module
   !> header), rotations times `length`; a label per row.
   subroutine lock_equations(model, k, modes, length, C_r, C_eta, row_label)
      type(model_t), intent(in) :: model
      integer, intent(in) :: k
      type(body_modes_t), intent(in) :: modes
      real(dp), intent(in) :: length
      real(dp), allocatable, intent(out) :: C_r(:, :), C_eta(:, :)
      character(len=66), allocatable, intent(out) :: row_label(:)
      real(dp) :: frame(3, 3), point(3), motion(6, 6 * size(model%bodies)), &
         modal(6, size(modes%frequency_hz))
      logical :: locked(6)
      integer :: j, c, side, b, nb, nc, row
      nb = size(model%bodies)
      nc = size(modes%frequency_hz)
      row = 0
      do j = 1, size(model%mechanism%joints)
         row = row + count(locked_components(model%mechanism%joints(j)%kind))
      end do
      allocate (C_r(row, 6 * nb), C_eta(row, nc), source=0.0_dp)
      allocate (row_label(row))
      row = 0
      do j = 1, size(model%mechanism%joints)
         associate (joint => model%mechanism%joints(j))
            locked = locked_components(joint%kind)
            frame = frame_from_axis(joint%axis)
            point = joint_point(j)
            motion = 0.0_dp
            modal = 0.0_dp
            ! relative motion: end 2 minus end 1
            do side = 1, 2
               b = joint%body(side)
               if (b <= 0) cycle
               call add_rigid(motion(:, 6 * b - 5:6 * b), point, merge(-1.0_dp, 1.0_dp, &
                  side == 1))
               if (b == k) modal = modal + merge(-1.0_dp, 1.0_dp, side == 1) * &
                  interface_rows(joint%marker(side))
            end do
            do c = 1, 6
               if (.not. locked(c)) cycle
               row = row + 1
               if (c <= 3) then
                  C_r(row, :) = matmul(frame(:, c), motion(1:3, :))
                  C_eta(row, :) = matmul(frame(:, c), modal(1:3, :))
               else
                  C_r(row, :) = length * matmul(frame(:, c - 3), motion(4:6, :))
                  C_eta(row, :) = length * matmul(frame(:, c - 3), modal(4:6, :))
               end if
               row_label(row) = COMPONENT(c) // joint%name
            end do
         end associate
      end do

   contains

      !> +-[I, -[r]_x / L; 0, I] (rotation columns scaled by 1/L: unknowns L dtheta).
      subroutine add_rigid(block, r, sign)
         real(dp), intent(inout) :: block(6, 6)
         real(dp), intent(in) :: r(3), sign
         integer :: i
         do i = 1, 3
            block(i, i) = block(i, i) + sign
            block(3 + i, 3 + i) = block(3 + i, 3 + i) + sign / length
         end do
         ! dtheta x r = -[r]_x dtheta
         block(1:3, 4:6) = block(1:3, 4:6) - sign / length * skew(r)
      end subroutine add_rigid

      !> The virtual-node shapes [Psi_u; Psi_r] of interface i of body k.
      function interface_rows(i) result(rows)
         integer, intent(in) :: i
         real(dp) :: rows(6, nc)
         rows = modes%virtual_node_shape(6 * i - 5:6 * i, :)
         associate (A => model%bodies(k)%motion%orientation)
            if (any(A /= identity3())) then
               rows(1:3, :) = matmul(A, rows(1:3, :))
               rows(4:6, :) = matmul(A, rows(4:6, :))
            end if
         end associate
      end function interface_rows

      !> Global position in the starting pose of the point x_bar (body frame) of model body bb.
      function placed(bb, x_bar) result(r)
         integer, intent(in) :: bb
         real(dp), intent(in) :: x_bar(3)
         real(dp) :: r(3)
         associate (motion => model%bodies(bb)%motion)
            if (any(motion%orientation /= identity3())) then
               r = motion%position + matmul(motion%orientation, x_bar)
            else
               r = motion%position + x_bar
            end if
         end associate
      end function placed

      !> The point of joint j in the starting pose: its end on body k (the virtual node), else a
      !> rigid body's or the ground's &marker, else an interface placed by position (the ends
      !> coincide in the starting pose); the body position when none of these is known.
      function joint_point(jj) result(r)
         integer, intent(in) :: jj
         real(dp) :: r(3)
         integer :: rule, s
         associate (joint => model%mechanism%joints(jj))
            ! each rule tried on both ends before the next one
            do rule = 1, 3
               do s = 1, 2
                  if (end_point(rule, joint%body(s), joint%marker(s), r)) return
               end do
            end do
            r = model%bodies(joint%body(1))%motion%position
         end associate
      end function joint_point

      !> The point of a joint end (model body bb, 0: the ground; marker handle) by joint_point's
      !> rule 1 (the end on body k), 2 (a ground or rigid body's &marker) or 3 (an interface
      !> placed by position); .false. and r unchanged when the rule does not apply to the end.
      logical function end_point(rule, bb, handle, r) result(found)
         integer, intent(in) :: rule, bb, handle
         real(dp), intent(inout) :: r(3)
         found = .false.
         select case (rule)
         case (1)
            found = bb == k
            if (found) r = placed(k, modes%interfaces(handle)%virtual_xyz)
         case (2)
            if (bb == 0) then
               found = .true.
               r = model%mechanism%markers(handle)%position
            else if (model%bodies(bb)%rigid) then
               found = .true.
               r = placed(bb, model%mechanism%markers(handle)%position)
            end if
         case (3)
            found = model%bodies(bb)%interfaces(handle)%virtual_node == VIRTUAL_NODE_POSITION
            if (found) r = placed(bb, model%bodies(bb)%interfaces(handle)%position)
         end select
      end function end_point

   end subroutine lock_equations

   !> The body's size: the largest distance between its virtual nodes (its bounding-box
   !> diagonal with one interface).
   pure function body_length(modes) result(length)
      type(body_modes_t), intent(in) :: modes
      real(dp) :: length
      integer :: i, j
      length = 0.0_dp
      do i = 1, size(modes%interfaces)
         do j = i + 1, size(modes%interfaces)
            length = max(length, norm2(modes%interfaces(i)%virtual_xyz - &
               modes%interfaces(j)%virtual_xyz))
         end do
      end do
      if (length <= 0.0_dp) length = norm2(maxval(modes%mesh%xyz, dim=2) - &
         minval(modes%mesh%xyz, dim=2))
      if (length <= 0.0_dp) length = 1.0_dp
   end function body_length

   !> Modes Phi W at the frequencies given; the residual of a free mode is the largest of the
   !> candidates it combines (the eigen solver's accuracy beneath it).
   subroutine combine_modes(modes, W, frequency_hz)
      type(body_modes_t), intent(inout) :: modes
      real(dp), intent(in) :: W(:, :), frequency_hz(:)
      real(dp), allocatable :: residual(:)
      integer :: j
      modes%frequency_hz = frequency_hz
      modes%shape = matmul(modes%shape, W)
      modes%virtual_node_shape = matmul(modes%virtual_node_shape, W)
      if (allocated(modes%residual)) then
         allocate (residual(size(W, 2)))
         do j = 1, size(W, 2)
            residual(j) = maxval([0.0_dp, pack(modes%residual, abs(W(:, j)) > 1.0e-12_dp)])
         end do
         call move_alloc(residual, modes%residual)
      end if
   end subroutine combine_modes

end module ffrf_app_joint_free_modes
