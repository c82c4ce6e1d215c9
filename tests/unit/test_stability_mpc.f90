!> Interface reduction where it breaks (issue 4, part 2): an RBE3 (ffrf_mpc_rbe3, Nastran's
!> weighted least-squares rigid fit) on nodes that are nearly or exactly collinear, asked to
!> carry rotations through reference conditions (ffrf_mpc_reference_conditions).
!>
!> - rbe3_strip_rank_switch: 30 nodes on a flat strip of length L = 20 mm and width a L, a from
!>   1e-1 to 1e-12 (test_mpc_rbe has exact collinearity only). Where the rotation about the strip
!>   axis is flagged undefined follows from the closed-form normal matrix of the fit.
!> - collinear_interface_in_an_rc_set: collinear nodes on an oblique line with rotation RCs that
!>   do not cover the line's direction. Before this work the RC check accepted a set that left
!>   the rigid rotation about that line free (its rank test used the ideal rigid motion of the
!>   virtual node, which that interface does not carry) and the body then had a "flexible"
!>   mode at 0.001 Hz against 10 kHz for the next one, reported as a flexible mode: silent
!>   garbage, fixed in check_reference_conditions (carried_motion). The eigenvalues of a small
!>   Tet4 box with and without the free rotation are the second method.
module test_stability_mpc
   use ffrf_core_kinds, only: dp, ip, i8, pi
   use ffrf_core_error, only: error_t, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: logger_t, LOG_QUIET
   use ffrf_la_sparse, only: csr_t
   use ffrf_fe_material, only: material_t
   use ffrf_fe_assembly, only: assemble_stiffness_mass
   use ffrf_mpc_rbe2, only: rbe2_matrix
   use ffrf_mpc_rbe3, only: rbe3_matrix
   use ffrf_mpc_interface, only: interface_t, MPC_RBE3
   use ffrf_mpc_reference_conditions, only: rc_summary_t, check_reference_conditions
   use ffrf_mpc_reduction, only: reduction_t, build_reduction, FORMULATION_MULTIPLIERS
   use ffrf_modes_shift_invert, only: eigen_options_t, eigen_result_t, solve_shift_invert
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, report
   implicit none
   private
   public :: collect_stability_mpc

   !> Relative eigenvalue of the length-scaled normal matrix below which ffrf_mpc_rigid_fit calls
   !> a direction undefined (its rank_tolerance)
   real(dp), parameter :: rank_tolerance = 1.0e-10_dp
   !> Strip length (m)
   real(dp), parameter :: strip_length = 0.02_dp
   !> Cube side of the Tet4 box (m), cubes per edge
   real(dp), parameter :: cube = 0.01_dp
   integer, parameter :: cubes = 4

contains

   !> The suite.
   subroutine collect_stability_mpc(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [new_unittest('rbe3_strip_rank_switch', test_strip), &
         new_unittest('collinear_interface_in_an_rc_set', test_collinear_rc_set)]
   end subroutine collect_stability_mpc

   !> Nodes of the strip, 10 along x by 3 across (y = -a L / 2, 0, a L / 2), z = 0, centred at 0.
   function strip_nodes(aspect) result(xyz)
      real(dp), intent(in) :: aspect
      real(dp) :: xyz(3, 30)
      integer :: i, j
      do j = 1, 3
         do i = 1, 10
            xyz(:, 10 * (j - 1) + i) = [strip_length * ((i - 1) / 9.0_dp - 0.5_dp), &
               0.5_dp * aspect * strip_length * (j - 2), 0.0_dp]
         end do
      end do
   end function strip_nodes

   !> Closed form of the fit's conditioning for the strip with the virtual node at its centroid
   !> (theory.md 1.2, uniform weights): the length-scaled normal matrix is blockdiag(30 I3,
   !> J / Lc^2), J = sum (|r|^2 I - r r^T) = diag(sum y^2, sum x^2, sum x^2 + y^2) by symmetry,
   !> Lc the mean |r_i| (Nastran's length, as build_interface). Smallest over largest eigenvalue.
   real(dp) function strip_ratio(aspect)
      real(dp), intent(in) :: aspect
      real(dp) :: xyz(3, 30), sx, sy, lc
      xyz = strip_nodes(aspect)
      sx = sum(xyz(1, :)**2)
      sy = sum(xyz(2, :)**2)
      lc = sum(norm2(xyz, dim=1)) / 30.0_dp
      strip_ratio = (sy / lc**2) / max(30.0_dp, (sx + sy) / lc**2)
   end function strip_ratio

   !> The strip with all six RCs on its virtual node (its centroid), a = 1e-1 .. 1e-12 and
   !> a_s (1 +- 5 %), a_s the aspect ratio where the closed-form eigenvalue ratio (strip_ratio,
   !> 1.64 a^2) reaches rigid_fit's 1e-10: a_s = 7.82e-6. Asserted on both sides:
   !> - the flag rank_deficient is set exactly when the closed-form ratio is <= 1e-10;
   !> - not flagged: G F = I6 to 1e3 eps / ratio. G comes from the eigen decomposition of the
   !>   normal matrix (condition number 1 / ratio), so G F - I6 ~ c eps / ratio, c set by the
   !>   6 x 6 dsyev and the 30-term sums that form the normal matrix and G F: measured c <= 9.7 in
   !>   Release (1.4e-14 at a = 0.1, 2.5e-10 at 1e-3, 1.3e-5 at 1e-5, 2.1e-6 at 1.05 a_s) and
   !>   c <= 105 in the -O0 build (other summation order); 1e3 leaves a margin over both and still
   !>   bounds the error by 2.2e-3 at the switch. The six RCs are accepted (rigid rank 6): the
   !>   rotation about the strip axis is still carried, by rows 0.16 um apart at a = 1.05 a_s.
   !>   (Near the switch G F = I6 holds only to ~1e-5: the price of the normal equations; a QR
   !>   fit of W^(1/2) S would lose only eps / sqrt(ratio).)
   !> - flagged: the undefined direction is the strip axis (|n . x| = 1 to 1e-8) and the RC set
   !>   is refused with FFRF_INPUT_ERROR naming the interface and the dof: 'interface "strip":
   !>   reference condition Rx cannot be carried: its nodes are collinear ...'.
   subroutine test_strip(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: aspects(14), xyz(3, 30), weights(30), direction(3), lc, gf(6, 6), ratio
      real(dp) :: a_s, lo, hi
      real(dp), allocatable :: G(:, :), F(:, :)
      logical :: deficient
      type(interface_t) :: faces(1)
      type(rc_summary_t) :: summary
      type(error_t), allocatable :: failure
      integer :: k, i, it
      ! a_s by bisection on log(a) of the closed-form ratio
      lo = log(1.0e-7_dp)
      hi = log(1.0e-3_dp)
      do it = 1, 100
         if (strip_ratio(exp(0.5_dp * (lo + hi))) > rank_tolerance) then
            hi = 0.5_dp * (lo + hi)
         else
            lo = 0.5_dp * (lo + hi)
         end if
      end do
      a_s = exp(0.5_dp * (lo + hi))
      aspects(1:12) = [(10.0_dp**(-k), k=1, 12)]
      aspects(13:14) = [0.95_dp, 1.05_dp] * a_s
      call report('closed-form switch of the strip at a = ' // to_str(a_s, 4))
      weights = 1.0_dp
      do k = 1, size(aspects)
         xyz = strip_nodes(aspects(k))
         lc = sum(norm2(xyz, dim=1)) / 30.0_dp
         ratio = strip_ratio(aspects(k))
         call rbe3_matrix(xyz, weights, [0.0_dp, 0.0_dp, 0.0_dp], lc, G, deficient, direction, &
            error)
         if (allocated(error)) return
         call rbe2_matrix(xyz, [0.0_dp, 0.0_dp, 0.0_dp], F)
         gf = matmul(G, F)
         do i = 1, 6
            gf(i, i) = gf(i, i) - 1.0_dp
         end do
         faces(1)%name = 'strip'
         faces(1)%mpc = MPC_RBE3
         faces(1)%virtual_xyz = 0.0_dp
         faces(1)%length_scale = lc
         faces(1)%rc = .true.
         faces(1)%G = G
         faces(1)%rank_deficient = deficient
         faces(1)%undefined_direction = direction
         call check_reference_conditions(faces, [0.0_dp, 0.0_dp, 0.0_dp], summary, failure)
         call report('a = ' // to_str(aspects(k), 3) // ': closed-form ratio ' // &
            to_str(ratio, 3) // ', flagged ' // merge('yes', 'no ', deficient) // &
            ', max |G F - I6| ' // to_str(maxval(abs(gf)), 2) // ' (' // &
            to_str(maxval(abs(gf)) * ratio / epsilon(1.0_dp), 2) // ' eps / ratio), RC set ' // &
            merge('refused ', 'accepted', allocated(failure)))
         call check(error, 'a = ' // to_str(aspects(k), 3) // ': flagged ' // &
            merge('yes', 'no ', deficient) // ' with the closed-form ratio ' // &
            to_str(ratio, 3), deficient .eqv. ratio <= rank_tolerance)
         if (allocated(error)) return
         if (.not. deficient) then
            call check_close(error, 'a = ' // to_str(aspects(k), 3) // ': max |G F - I6|', &
               maxval(abs(gf)), 0.0_dp, atol=1.0e3_dp * epsilon(1.0_dp) / ratio)
            if (allocated(error)) return
            call check(error, 'a = ' // to_str(aspects(k), 3) // ': six RCs accepted', &
               .not. allocated(failure))
            if (allocated(error)) return
            call check(error, 'rigid rank 6', summary%rigid_rank == 6)
         else
            call check_close(error, 'a = ' // to_str(aspects(k), 3) // ': |n . x|', &
               abs(direction(1)), 1.0_dp, atol=1.0e-8_dp)
            if (allocated(error)) return
            call check(error, 'a = ' // to_str(aspects(k), 3) // ': RC set refused', &
               allocated(failure))
            if (allocated(error)) return
            call check(error, 'message names the interface and the dof: ' // failure%message, &
               failure%code == FFRF_INPUT_ERROR .and. index(failure%message, &
               'interface "strip": reference condition Rx cannot be carried') > 0)
         end if
         if (allocated(error)) return
         if (allocated(failure)) deallocate (failure)
      end do
   end subroutine test_strip

   !> A Tet4 box of 4 x 4 x 4 cubes (10 mm, steel) and three RBE3 interfaces on its nodes:
   !> "diagonal", the nodes (i, i, i) dx, i = 0, 1, 2, collinear along n = (1, 1, 1)/sqrt(3)
   !> through the box centre, with RCs Tx Ty Tz Rx Ry (Rx, Ry do not contain n, so the existing
   !> "cannot be carried" refusal does not apply); "on the line", the 8 nodes of the cube
   !> [3, 4]^3 dx (centroid on the same line), RC Tx; "off the line", the cube [0, 1] x [3, 4] x
   !> [0, 1] dx, RC Tz.
   !> - diagonal + on the line: the rigid rotation about the line moves none of their nodes, so
   !>   every RC row vanishes on it (|D G q| <= 1e-20 for a 1e-3 rad rotation; measured 0 and
   !>   3.4e-22). Asserted: the set is refused with FFRF_INPUT_ERROR naming the free rotation
   !>   about (0.5774, 0.5774, 0.5774) and the collinear interface. Second method: the box's
   !>   constrained modes with this set, computed without the check (build_reduction,
   !>   shift-invert at the automatic shift),
   !>   have lambda_1 <= 1e-9 lambda_2 (measured 4.0e-5 against 4.1e9 s^-2: 0.001 Hz against
   !>   10169 Hz), the free rotation; before the fix this set passed the check (rigid rank 6).
   !> - diagonal + off the line: the rotation about the line moves the second interface's
   !>   virtual node in z, so the six RCs remove every rigid motion. Asserted: accepted with
   !>   rigid rank 6, and the first constrained mode is elastic, above 1 kHz (measured 7406 Hz).
   subroutine test_collinear_rc_set(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: xyz(:, :)
      integer(ip), allocatable :: tets(:, :)
      type(interface_t) :: faces(3)
      type(rc_summary_t) :: summary
      type(error_t), allocatable :: failure
      type(eigen_result_t) :: result
      type(csr_t) :: K, M
      real(dp) :: theta(3), q_v(6), center(3), n(3)
      integer :: i
      call box_mesh(xyz, tets)
      call assemble(xyz, tets, K, M, error)
      if (allocated(error)) return
      center = 0.5_dp * cubes * cube * [1.0_dp, 1.0_dp, 1.0_dp]
      n = [1.0_dp, 1.0_dp, 1.0_dp] / sqrt(3.0_dp)
      call make_interface('diagonal', [(node_id(i, i, i), i=0, 2)], 'Tx Ty Tz Rx Ry', xyz, &
         faces(1), error)
      if (allocated(error)) return
      call make_interface('on the line', cell_nodes(3, 3, 3), 'Tx', xyz, faces(2), error)
      if (allocated(error)) return
      call make_interface('off the line', cell_nodes(0, 3, 0), 'Tz', xyz, faces(3), error)
      if (allocated(error)) return
      call check(error, 'the diagonal interface is flagged collinear along n', &
         faces(1)%rank_deficient .and. abs(abs(dot_product(faces(1)%undefined_direction, n)) - &
         1.0_dp) < 1.0e-8_dp)
      if (allocated(error)) return
      ! The rotation about the line: RC components of both virtual nodes
      theta = 1.0e-3_dp * n
      q_v = matmul(faces(1)%G, rotated(faces(1)%nodes))
      call report('rotation of 1e-3 rad about the line: diagonal q_V ' // &
         to_str(maxval(abs(q_v(1:5))), 2) // ', on the line Tx ' // &
         to_str(abs(dot_product(faces(2)%G(1, :), rotated(faces(2)%nodes))), 2))
      call check_close(error, 'RC rows of the diagonal on the rotation', maxval(abs(q_v(1:5))), &
         0.0_dp, atol=1.0e-20_dp)
      if (allocated(error)) return
      call check_close(error, 'RC row of the interface on the line on the rotation', &
         dot_product(faces(2)%G(1, :), rotated(faces(2)%nodes)), 0.0_dp, atol=1.0e-20_dp)
      if (allocated(error)) return

      call check_reference_conditions(faces(1:2), center, summary, failure)
      call check(error, 'diagonal + on the line: refused', allocated(failure))
      if (allocated(error)) return
      call report('refused: ' // failure%message)
      call check(error, 'message names the free rotation and the collinear interface: ' // &
         failure%message, failure%code == FFRF_INPUT_ERROR .and. &
         index(failure%message, '1 rigid-body motion(s) free') > 0 .and. &
         index(failure%message, '0.5774, 0.5774, 0.5774') > 0 .and. &
         index(failure%message, 'interface "diagonal" has collinear nodes') > 0)
      if (allocated(error)) return
      call box_modes(faces(1:2), K, M, xyz, result, error)
      if (allocated(error)) return
      call report('diagonal + on the line, without the check: lambda_1 ' // &
         to_str(result%eigenvalues(1), 3) // ' s^-2 (' // &
         to_str(sqrt(abs(result%eigenvalues(1))) / (2.0_dp * pi), 3) // ' Hz), lambda_2 ' // &
         to_str(result%eigenvalues(2), 4) // ' s^-2 (' // &
         to_str(sqrt(result%eigenvalues(2)) / (2.0_dp * pi), 5) // ' Hz)')
      call check_close(error, 'free rotation: lambda_1 / lambda_2', &
         result%eigenvalues(1) / result%eigenvalues(2), 0.0_dp, atol=1.0e-9_dp)
      if (allocated(error)) return

      call check_reference_conditions(faces([1, 3]), center, summary, error)
      if (allocated(error)) return
      call check(error, 'diagonal + off the line: rigid rank 6', summary%rigid_rank == 6)
      if (allocated(error)) return
      call box_modes(faces([1, 3]), K, M, xyz, result, error)
      if (allocated(error)) return
      call report('diagonal + off the line: accepted, first mode ' // &
         to_str(sqrt(result%eigenvalues(1)) / (2.0_dp * pi), 5) // ' Hz')
      call check(error, 'first mode elastic, above 1 kHz', &
         result%eigenvalues(1) > (2.0_dp * pi * 1.0e3_dp)**2)
   contains
      !> Nodal displacements of the rotation theta about the box centre, at `nodes`
      function rotated(nodes) result(q)
         integer(ip), intent(in) :: nodes(:)
         real(dp) :: q(3 * size(nodes))
         real(dp) :: r(3)
         integer :: j
         do j = 1, size(nodes)
            r = xyz(:, nodes(j)) - center
            q(3 * j - 2:3 * j) = [theta(2) * r(3) - theta(3) * r(2), &
               theta(3) * r(1) - theta(1) * r(3), theta(1) * r(2) - theta(2) * r(1)]
         end do
      end function rotated
   end subroutine test_collinear_rc_set

   !> An RBE3 interface on the given box nodes: uniform weights, virtual node at their centroid,
   !> Nastran's length scale, G by rbe3_matrix; RCs from their names.
   subroutine make_interface(name, nodes, rc, xyz, face, error)
      character(len=*), intent(in) :: name, rc
      integer(ip), intent(in) :: nodes(:)
      real(dp), intent(in) :: xyz(:, :)
      type(interface_t), intent(out) :: face
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: node_xyz(:, :)
      integer :: i
      character(len=2), parameter :: names(6) = ['Tx', 'Ty', 'Tz', 'Rx', 'Ry', 'Rz']
      face%name = name
      face%mpc = MPC_RBE3
      face%nodes = nodes
      allocate (face%weights(size(nodes)), source=1.0_dp)
      node_xyz = xyz(:, nodes)
      face%virtual_xyz = sum(node_xyz, dim=2) / size(nodes)
      face%length_scale = 0.0_dp
      do i = 1, size(nodes)
         face%length_scale = face%length_scale + norm2(node_xyz(:, i) - face%virtual_xyz) / &
            size(nodes)
      end do
      face%rc = [(index(rc, names(i)) > 0, i=1, 6)]
      call rbe3_matrix(node_xyz, face%weights, face%virtual_xyz, face%length_scale, face%G, &
         face%rank_deficient, face%undefined_direction, error)
   end subroutine make_interface

   !> Box node number of grid point (i, j, k), 0 .. cubes each.
   pure integer(ip) function node_id(i, j, k)
      integer, intent(in) :: i, j, k
      node_id = int(1 + i + (cubes + 1) * (j + (cubes + 1) * k), ip)
   end function node_id

   !> The 8 nodes of the cube with lowest corner (i, j, k).
   pure function cell_nodes(i, j, k) result(nodes)
      integer, intent(in) :: i, j, k
      integer(ip) :: nodes(8)
      integer :: a, b, c
      do c = 0, 1
         do b = 0, 1
            do a = 0, 1
               nodes(1 + a + 2 * b + 4 * c) = node_id(i + a, j + b, k + c)
            end do
         end do
      end do
   end function cell_nodes

   !> Tet4 box: each cube split into the 6 tetrahedra around its (1, 1, 1) diagonal (Kuhn), so
   !> the grid diagonal (i, i, i) is made of element edges; positive volumes.
   subroutine box_mesh(xyz, tets)
      real(dp), allocatable, intent(out) :: xyz(:, :)
      integer(ip), allocatable, intent(out) :: tets(:, :)
      integer, parameter :: orders(3, 6) = reshape([1, 2, 3, 1, 3, 2, 2, 1, 3, 2, 3, 1, 3, 1, 2, &
         3, 2, 1], [3, 6])
      integer :: i, j, k, p, b, t, corner(3)
      real(dp) :: e(3, 3), volume
      allocate (xyz(3, (cubes + 1)**3), tets(4, 6 * cubes**3))
      do k = 0, cubes
         do j = 0, cubes
            do i = 0, cubes
               xyz(:, node_id(i, j, k)) = cube * [i, j, k]
            end do
         end do
      end do
      t = 0
      do k = 0, cubes - 1
         do j = 0, cubes - 1
            do i = 0, cubes - 1
               do p = 1, 6
                  t = t + 1
                  corner = [i, j, k]
                  tets(1, t) = node_id(corner(1), corner(2), corner(3))
                  do b = 1, 3
                     corner(orders(b, p)) = corner(orders(b, p)) + 1
                     tets(b + 1, t) = node_id(corner(1), corner(2), corner(3))
                  end do
                  e = xyz(:, tets(2:4, t)) - spread(xyz(:, tets(1, t)), 2, 3)
                  volume = dot_product(e(:, 1), [e(2, 2) * e(3, 3) - e(3, 2) * e(2, 3), &
                     e(3, 2) * e(1, 3) - e(1, 2) * e(3, 3), e(1, 2) * e(2, 3) - e(2, 2) * e(1, 3)])
                  if (volume < 0.0_dp) tets([2, 3], t) = tets([3, 2], t)
               end do
            end do
         end do
      end do
   end subroutine box_mesh

   !> Steel K and M of the box.
   subroutine assemble(xyz, tets, K, M, error)
      real(dp), intent(in) :: xyz(:, :)
      integer(ip), intent(in) :: tets(:, :)
      type(csr_t), intent(out) :: K, M
      type(error_t), allocatable, intent(out) :: error
      integer(i8), allocatable :: tags(:)
      integer :: t
      tags = [(int(t, i8), t=1, size(tets, 2))]
      call assemble_stiffness_mass(xyz, tets, tags, material_t(210.0e9_dp, 0.3_dp, 7850.0_dp, &
         'steel'), K, M, error)
   end subroutine assemble

   !> The 4 lowest constrained modes of the box with the RC rows of `faces` (multipliers form,
   !> as the modal pipeline after its RC check), at the automatic shift of ffrf_modes_modal_
   !> analysis: -(2 pi f)^2, f = 1 % of sqrt(E / rho) / (box diagonal) = 746.6 Hz.
   subroutine box_modes(faces, K, M, xyz, result, error)
      type(interface_t), intent(in) :: faces(:)
      type(csr_t), intent(in) :: K, M
      real(dp), intent(in) :: xyz(:, :)
      type(eigen_result_t), intent(out) :: result
      type(error_t), allocatable, intent(out) :: error
      type(reduction_t) :: red
      type(logger_t) :: log
      real(dp) :: shift_hz
      call build_reduction(int(size(xyz, 2), ip), faces, FORMULATION_MULTIPLIERS, red, &
         error)
      if (allocated(error)) return
      shift_hz = 0.01_dp * sqrt(210.0e9_dp / 7850.0_dp) / (sqrt(3.0_dp) * cubes * cube)
      log%level = LOG_QUIET
      call solve_shift_invert(K, M, red%C, eigen_options_t(num_modes=4, &
         sigma=-(2.0_dp * pi * shift_hz)**2), result, log, error)
   end subroutine box_modes

end module test_stability_mpc

program main_stability_mpc
   use ffrf_testing, only: unittest_t, run_suite
   use test_stability_mpc, only: collect_stability_mpc
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_stability_mpc(tests)
   call run_suite('stability_mpc', tests)
end program main_stability_mpc
