!> Reference conditions (RCs) D q_V = 0 on the virtual nodes of a body (Cammarata et al. 2022,
!> theory.md section 2). They must remove the six rigid-body motions (rank(D R) = 6, R the rigid
!> motions of the virtual nodes as their interfaces carry them: an interface with collinear
!> nodes does not see the rotation about their line); each RC must be carried by its interface
!> (no dependent rows); more than six independent RCs make the set hyperstatic: it also
!> constrains deformation.
module ffrf_mpc_reference_conditions
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_la_dense, only: skew, singular_values, numerical_rank, symmetric_eigen
   use ffrf_mpc_interface, only: interface_t, DOF_NAMES, MPC_RBE2, dofs_text
   implicit none
   private
   public :: rc_summary_t, check_reference_conditions, describe_rigid_motion

   !> What the RC set does to the body.
   type :: rc_summary_t
      !> Number of RC equations (rows of D)
      integer :: num_rc = 0
      !> Rank of D R: 6 when all rigid motions are removed, 0 for a free-free body
      integer :: rigid_rank = 0
      !> num_rc - 6 when positive: constraints on deformation (hyperstatic set)
      integer :: redundancy = 0
      !> No RC at all: free-free modes, six rigid modes to skip
      logical :: free_free = .false.
      !> Rigid-body motions the RC set leaves free: 6 - rigid_rank (6 for a free-free body, 0
      !> for an accepted RC set, which must remove all six)
      integer :: num_free = 0
      !> Those motions as columns 1..num_free, orthonormal, in the scaled coordinates
      !> [t; theta * length] of a body motion u(x) = t + theta x (x - reference_point)
      real(dp) :: free_motions(6, 6) = 0.0_dp
      !> Point the rotations are about (m) and the length their columns are scaled by (m)
      real(dp) :: reference_point(3) = 0.0_dp
      real(dp) :: length = 1.0_dp
   end type rc_summary_t

contains

   !> Check an RC set. Refused: a rigid-body motion left free (names it), or an RC an interface
   !> cannot carry (collinear nodes and a rotation RC about that line). A hyperstatic set passes
   !> with `redundancy` > 0 for the caller to log.
   subroutine check_reference_conditions(interfaces, reference_point, summary, error)
      !> Interfaces of the body
      type(interface_t), intent(in) :: interfaces(:)
      !> Point the rigid rotations are described about (e.g. the centre of mass), m
      real(dp), intent(in) :: reference_point(3)
      !> Result
      type(rc_summary_t), intent(out) :: summary
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: d_r(:, :), s(:), v(:, :)
      real(dp) :: length, rigid(6, 6)
      integer :: k, d, row
      character(len=:), allocatable :: collinear

      call check_carried(interfaces, error)
      if (allocated(error)) return

      summary%num_rc = 0
      do k = 1, size(interfaces)
         summary%num_rc = summary%num_rc + count(interfaces(k)%rc)
      end do
      ! Rows of D R: the RC components of each virtual node's rigid motion, rotations scaled by the
      ! body size so that the rank test is dimensionless.
      length = 0.0_dp
      do k = 1, size(interfaces)
         length = max(length, norm2(interfaces(k)%virtual_xyz - reference_point), &
            interfaces(k)%length_scale)
      end do
      if (length <= 0.0_dp) length = 1.0_dp
      summary%reference_point = reference_point
      summary%length = length
      if (summary%num_rc == 0) then
         summary%free_free = .true.
         summary%num_free = 6
         summary%free_motions = 0.0_dp
         do k = 1, 6
            summary%free_motions(k, k) = 1.0_dp
         end do
         return
      end if

      allocate (d_r(summary%num_rc, 6))
      row = 0
      collinear = ''
      do k = 1, size(interfaces)
         rigid = virtual_node_rigid_motion(interfaces(k)%virtual_xyz - reference_point, length)
         if (interfaces(k)%rank_deficient) then
            ! Only what the interface carries: the rotation about the line of its nodes moves
            ! none of them, so its RCs cannot forbid it (test_stability_mpc: accepted before,
            ! the body then had a "flexible" mode at 0.001 Hz)
            call carried_motion(interfaces(k), length, rigid, error)
            if (allocated(error)) return
            collinear = collinear // '; interface "' // interfaces(k)%name // '" has ' // &
               'collinear nodes and cannot carry the rotation about (' // &
               vector_text(interfaces(k)%undefined_direction, 1.0e-6_dp) // ') through them'
         end if
         do d = 1, 6
            if (.not. interfaces(k)%rc(d)) cycle
            row = row + 1
            d_r(row, :) = rigid(d, :)
         end do
      end do
      call singular_values(d_r, s, error, v)
      if (allocated(error)) return
      summary%rigid_rank = numerical_rank(s, 1.0e-8_dp)
      ! null(D R): the right singular vectors past the rank (v is 6 x 6)
      summary%num_free = 6 - summary%rigid_rank
      summary%free_motions = 0.0_dp
      if (summary%num_free > 0) summary%free_motions(:, 1:summary%num_free) = &
         v(:, summary%rigid_rank + 1:6)
      if (summary%rigid_rank < 6) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'the reference conditions (' // &
            rc_set_text(interfaces) // ') leave ' // to_str(6 - summary%rigid_rank) // &
            ' rigid-body motion(s) free, e.g. the ' // &
            describe_rigid_motion(v(:, summary%rigid_rank + 1), reference_point, length) // &
            '; add reference conditions that forbid it (six independent ones are needed)' // &
            collinear)
         return
      end if
      summary%redundancy = max(0, summary%num_rc - 6)
   end subroutine check_reference_conditions

   !> Rigid motion of a virtual node at offset r from the reference point, for the body motion
   !> (t, theta * length): u_V = t + theta x r, theta_V = theta (6 x 6).
   pure function virtual_node_rigid_motion(r, length) result(rigid)
      real(dp), intent(in) :: r(3), length
      real(dp) :: rigid(6, 6)
      integer :: i
      rigid = 0.0_dp
      do i = 1, 3
         rigid(i, i) = 1.0_dp
         rigid(3 + i, 3 + i) = 1.0_dp / length
      end do
      rigid(1:3, 4:6) = -skew(r) / length
      ! Rotation RC rows compare with translations after scaling by the body size.
      rigid(4:6, :) = rigid(4:6, :) * length
   end function virtual_node_rigid_motion

   !> Columns of `rigid` (virtual-node motions [u; theta * length] of the body rigid motions, from
   !> virtual_node_rigid_motion) replaced by the motions a rank-deficient interface carries. Its
   !> G (ffrf_mpc_rigid_fit) is the pseudo-inverse fit, so for a rigid motion q_V = G F q_V,rigid
   !> with G F = E^-1 (I - z z^T) E, E = diag(1, 1, 1, Lc, Lc, Lc) the fit's length scaling and z
   !> the unit scaled virtual-node motion that moves no node (the rotation about the nodes' line):
   !> the left null vector of E G. Without G (an interface built by hand) z = (0, n), n the
   !> undefined direction, which is exact for a virtual node on the nodes' line.
   subroutine carried_motion(face, length, rigid, error)
      !> A rank-deficient interface
      type(interface_t), intent(in) :: face
      !> Body length the rotation rows and columns of `rigid` are scaled by (m)
      real(dp), intent(in) :: length
      !> Ideal rigid motions of the virtual node on entry, the carried ones on exit (6 x 6)
      real(dp), intent(inout) :: rigid(6, 6)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: scale(6), gram(6, 6), values(6), vectors(6, 6), z(6)
      real(dp), allocatable :: scaled(:, :)
      integer :: k
      ! rigid's rows are [u; theta * length]; the fit's scaled ones [u; theta * Lc]
      scale = [1.0_dp, 1.0_dp, 1.0_dp, face%length_scale / length, face%length_scale / length, &
         face%length_scale / length]
      if (allocated(face%G)) then
         scaled = face%G
         do k = 4, 6
            scaled(k, :) = scaled(k, :) * face%length_scale
         end do
         gram = matmul(scaled, transpose(scaled))
         call symmetric_eigen(gram, values, vectors, error)
         if (allocated(error)) return
         z = vectors(:, 1)
      else
         z = [0.0_dp, 0.0_dp, 0.0_dp, face%undefined_direction / norm2(face%undefined_direction)]
      end if
      do k = 1, 6
         rigid(k, :) = rigid(k, :) * scale(k)
      end do
      rigid = rigid - spread(z, 2, 6) * spread(matmul(z, rigid), 1, 6)
      do k = 1, 6
         rigid(k, :) = rigid(k, :) / scale(k)
      end do
   end subroutine carried_motion

   !> Each RC must be carried: an interface whose nodes cannot define the rotation about some
   !> axis (collinear nodes) cannot forbid that rotation (dependent row of D G), and an RBE2 whose
   !> rotation about that axis is not forbidden leaves a virtual dof without stiffness.
   subroutine check_carried(interfaces, error)
      type(interface_t), intent(in) :: interfaces(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: n(3), in_span
      integer :: k, worst
      do k = 1, size(interfaces)
         if (.not. interfaces(k)%rank_deficient) cycle
         n = interfaces(k)%undefined_direction
         in_span = sum(merge(n**2, 0.0_dp, interfaces(k)%rc(4:6)))
         worst = maxloc(abs(n), dim=1, mask=interfaces(k)%rc(4:6))
         if (in_span > 1.0_dp - 1.0e-6_dp) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'interface "' // interfaces(k)%name // &
               '": reference condition ' // DOF_NAMES(3 + worst) // ' cannot be carried: ' // &
               'its nodes are collinear, so the rotation about (' // &
               vector_text(n, 1.0e-6_dp) // &
               ') is undefined (dependent RC row); remove that rotation from rc or use a face ' // &
               'whose nodes are not on one line')
            return
         end if
         if (interfaces(k)%mpc == MPC_RBE2) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'interface "' // interfaces(k)%name // &
               '" (RBE2): its nodes are collinear, so the virtual-node rotation about (' // &
               vector_text(n, 1.0e-6_dp) // ') is undefined; forbid it in rc or use RBE3')
            return
         end if
      end do
   end subroutine check_carried

   !> "rotation about an axis along (0, 0, 1) through (0, 0, 0)" or "translation along (1, 0, 0)"
   !> for a rigid motion (t, theta * length).
   function describe_rigid_motion(motion, reference_point, length) result(text)
      !> Rigid motion [t; theta * length]
      real(dp), intent(in) :: motion(6)
      !> Point rotations are about (m)
      real(dp), intent(in) :: reference_point(3)
      !> Scale used for theta (m)
      real(dp), intent(in) :: length
      character(len=:), allocatable :: text
      real(dp) :: t(3), theta(3), point(3)
      t = motion(1:3)
      theta = motion(4:6) / length
      if (norm2(theta) * length <= 1.0e-6_dp * norm2(motion)) then
         text = 'translation along (' // vector_text(t / norm2(t), 1.0e-6_dp) // ')'
      else
         ! u(x) = t + theta x (x - x0): the axis passes through x0 + theta x t / |theta|^2.
         point = reference_point + cross(theta, t) / dot_product(theta, theta)
         text = 'rotation about an axis along (' // vector_text(theta / norm2(theta), 1.0e-6_dp) &
            // ') through (' // vector_text(point, 1.0e-6_dp * length) // ') m'
      end if
   end function describe_rigid_motion

   function rc_set_text(interfaces) result(text)
      type(interface_t), intent(in) :: interfaces(:)
      character(len=:), allocatable :: text
      integer :: k
      text = ''
      do k = 1, size(interfaces)
         if (.not. any(interfaces(k)%rc)) cycle
         if (len(text) > 0) text = text // '; '
         text = text // interfaces(k)%name // ': ' // dofs_text(interfaces(k)%rc)
      end do
   end function rc_set_text

   !> "x, y, z" with 4 significant digits; entries below `zero` (round-off) print as 0.
   function vector_text(v, zero) result(text)
      real(dp), intent(in) :: v(3), zero
      character(len=:), allocatable :: text
      real(dp) :: r(3)
      r = merge(0.0_dp, v, abs(v) < zero)
      text = to_str(r(1), 4) // ', ' // to_str(r(2), 4) // ', ' // to_str(r(3), 4)
   end function vector_text

   pure function cross(a, b) result(c)
      real(dp), intent(in) :: a(3), b(3)
      real(dp) :: c(3)
      c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
   end function cross

end module ffrf_mpc_reference_conditions
