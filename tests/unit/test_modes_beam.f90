!> Accuracy of the modal pipeline on a prismatic steel beam (input/beam.geo: solid circular
!> cylinder r = 10 mm, L = 200 mm along x, Tet10), against closed forms: first bending by the
!> exact Timoshenko frequency equation (Cowper's shear coefficient) and first torsion of a
!> circular shaft, free-free and clamped (an RBE2 interface with all six RCs at x = 0), within
!> 0.5 % at lc = 4 mm; the observed convergence under refinement (lc = 6, 4, 3 mm) is reported.
!> Also: an RBE3 written as constraint equations with its virtual node as unknowns adds no
!> stiffness (free-free spectrum unchanged to 1e-10), while an RBE2 does. And the explicit RC
!> matrix (B2 = null(D G) by LAPACK SVD) gives the frequencies of the scalable multiplier form.
module test_modes_beam
   use ffrf_core_kinds, only: dp, ip, pi
   use ffrf_core_error, only: error_t, add_context
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: logger_t, stage_times_t, LOG_QUIET
   use ffrf_mesh_mesh, only: mesh_t, extract_body
   use ffrf_mesh_gmsh, only: read_gmsh
   use ffrf_fe_material, only: material_t
   use ffrf_fe_assembly, only: assemble_stiffness_mass
   use ffrf_la_sparse, only: csr_t, csr_from_coo
   use ffrf_input_interface, only: interface_input_t
   use ffrf_mpc_interface, only: interface_spec_t, interface_t, build_interface
   use ffrf_input_body, only: body_input_t
   use ffrf_input_modes, only: modes_input_t
   use ffrf_modes_modal_analysis, only: body_modes_t, sigma_of_shift
   use ffrf_app_body_modes, only: compute_input_body_modes
   use ffrf_modes_shift_invert, only: eigen_options_t, eigen_result_t, solve_shift_invert
   use ffrf_test_beam_reference, only: timoshenko_free_free_hz, timoshenko_clamped_free_hz, &
      torsion_free_free_hz, torsion_clamped_free_hz, shear_coefficient_circle
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, test_mesh_dir, report
   implicit none
   private
   public :: collect_modes_beam

   real(dp), parameter :: young = 210.0e9_dp, poisson = 0.3_dp, density = 7850.0_dp
   real(dp), parameter :: radius = 0.010_dp, length = 0.200_dp
   !> Tolerances of the lc = 4 mm beam against the closed forms, each at most 10x what it
   !> measures (the errors are reported): the first bending against Timoshenko beam theory, free-
   !> free 1e-3 (measured 4.6e-4, which is the beam theory's model error: 4.5e-4 at lc = 3 mm) and
   !> clamped by an RBE2 spider 5e-3 (measured 4.4e-3: a rigid end face is not a beam clamp);
   !> the first torsion against the closed form 3e-4 (measured 6.1e-5 and 5.7e-5)
   real(dp), parameter :: bending_free_tolerance = 1.0e-3_dp
   real(dp), parameter :: bending_clamped_tolerance = 5.0e-3_dp
   real(dp), parameter :: torsion_tolerance = 3.0e-4_dp

   integer, parameter :: BENDING = 1, TORSION = 2, OTHER = 3

contains

   subroutine collect_modes_beam(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [ &
         new_unittest('free_free_bending_torsion', test_free_free), &
         new_unittest('clamped_bending_torsion', test_clamped), &
         new_unittest('convergence_under_refinement', test_convergence), &
         new_unittest('tet4_locks_in_bending', test_tet4_locking), &
         new_unittest('rbe3_adds_no_stiffness', test_rbe3_no_stiffness), &
         new_unittest('null_space_equals_multipliers', test_formulations)]
   end subroutine collect_modes_beam

   pure real(dp) function shear_modulus()
      shear_modulus = young / (2.0_dp * (1.0_dp + poisson))
   end function shear_modulus

   !> Timoshenko first bending frequency (Hz), free-free or clamped-free.
   real(dp) function bending_reference(clamped)
      logical, intent(in) :: clamped
      real(dp) :: area, second_moment, kappa
      area = pi * radius**2
      second_moment = pi * radius**4 / 4.0_dp
      kappa = shear_coefficient_circle(poisson)
      if (clamped) then
         bending_reference = timoshenko_clamped_free_hz(1, young, shear_modulus(), density, area, &
            second_moment, kappa, length)
      else
         bending_reference = timoshenko_free_free_hz(1, young, shear_modulus(), density, area, &
            second_moment, kappa, length)
      end if
   end function bending_reference

   !> Modes of the beam mesh `mesh_name`: free-free (RBE3 ends, no RC) or clamped at x = 0
   !> (RBE2 end0 with all six RCs); or with the given MPCs and RCs of the two ends.
   subroutine beam_modes(mesh_name, clamped, num_modes, body, error, mpc, rc, formulation)
      character(len=*), intent(in) :: mesh_name
      logical, intent(in) :: clamped
      integer, intent(in) :: num_modes
      type(body_modes_t), intent(out) :: body
      type(error_t), allocatable, intent(out) :: error
      character(len=*), intent(in), optional :: mpc(2), rc(2), formulation
      type(body_input_t) :: beam
      type(interface_input_t) :: ends(2)
      type(modes_input_t) :: modes
      type(logger_t) :: log
      type(stage_times_t) :: times
      beam = body_input_t('beam', mesh_name, '', young, poisson, density)
      beam%volumes(1) = 'beam'
      ends(1)%body = 'beam'
      ends(1)%name = 'end0'
      ends(2)%body = 'beam'
      ends(2)%name = 'end1'
      if (clamped) then
         ends(1)%mpc = 'RBE2'
         ends(1)%rc = 'Tx Ty Tz Rx Ry Rz'
      end if
      if (present(mpc)) ends%mpc = mpc
      if (present(rc)) ends%rc = rc
      modes%num_modes = num_modes
      if (present(formulation)) modes%formulation = formulation
      log%level = LOG_QUIET
      call compute_input_body_modes(beam, ends, modes, test_mesh_dir(), log, times, body, error)
      if (allocated(error)) call add_context(error, mesh_name)
   end subroutine beam_modes

   !> Bending, torsion or other, from the motion of the virtual node at x = L (end1): torsion
   !> turns it about x without moving it, bending moves it sideways.
   integer function mode_kind(body, mode)
      type(body_modes_t), intent(in) :: body
      integer, intent(in) :: mode
      real(dp) :: v(6), lateral, axial, twist
      v = body%virtual_node_shape(7:12, mode)
      lateral = max(abs(v(2)), abs(v(3)))
      axial = abs(v(1))
      twist = abs(v(4)) * length
      mode_kind = OTHER
      if (twist > 10.0_dp * max(lateral, axial)) mode_kind = TORSION
      if (lateral > 10.0_dp * max(twist, axial)) mode_kind = BENDING
   end function mode_kind

   !> The first (lowest) mode of a kind; 0 if none.
   integer function first_of_kind(body, kind)
      type(body_modes_t), intent(in) :: body
      integer, intent(in) :: kind
      integer :: i
      first_of_kind = 0
      do i = 1, size(body%frequency_hz)
         if (mode_kind(body, i) == kind) then
            first_of_kind = i
            return
         end if
      end do
   end function first_of_kind

   subroutine check_beam(clamped, error)
      logical, intent(in) :: clamped
      type(error_t), allocatable, intent(out) :: error
      type(body_modes_t) :: body
      real(dp) :: bending_ref, torsion_ref
      integer :: b, t
      character(len=:), allocatable :: tag
      call beam_modes('beam_lc4.msh', clamped, 8, body, error)
      if (allocated(error)) return
      bending_ref = bending_reference(clamped)
      if (clamped) then
         tag = 'clamped (RBE2 at x = 0)'
         torsion_ref = torsion_clamped_free_hz(1, shear_modulus(), density, length)
      else
         tag = 'free-free'
         torsion_ref = torsion_free_free_hz(1, shear_modulus(), density, length)
      end if
      b = first_of_kind(body, BENDING)
      t = first_of_kind(body, TORSION)
      call check(error, tag // ': a bending and a torsion mode among the first 8', &
         b > 0 .and. t > 0)
      if (allocated(error)) return
      call report(tag // ', lc = 4 mm: bending ' // to_str(body%frequency_hz(b), 8) // &
         ' Hz (Timoshenko ' // to_str(bending_ref, 8) // ', error ' // &
         to_str(body%frequency_hz(b) / bending_ref - 1.0_dp, 3) // '), torsion ' // &
         to_str(body%frequency_hz(t), 8) // ' Hz (closed form ' // to_str(torsion_ref, 8) // &
         ', error ' // to_str(body%frequency_hz(t) / torsion_ref - 1.0_dp, 3) // ')')
      call check_close(error, tag // ' first bending (Hz)', body%frequency_hz(b), bending_ref, &
         rtol=merge(bending_clamped_tolerance, bending_free_tolerance, clamped))
      if (.not. allocated(error)) call check_close(error, tag // ' bending pair partner (Hz)', &
         body%frequency_hz(b + 1), bending_ref, &
         rtol=merge(bending_clamped_tolerance, bending_free_tolerance, clamped))
      if (.not. allocated(error)) call check_close(error, tag // ' first torsion (Hz)', &
         body%frequency_hz(t), torsion_ref, rtol=torsion_tolerance)
   end subroutine check_beam

   subroutine test_free_free(error)
      type(error_t), allocatable, intent(out) :: error
      call check_beam(.false., error)
   end subroutine test_free_free

   subroutine test_clamped(error)
      type(error_t), allocatable, intent(out) :: error
      call check_beam(.true., error)
   end subroutine test_clamped

   !> Free-free first bending on lc = 6, 4, 3 mm: conforming Tet10 frequencies decrease towards
   !> the converged value; the observed order p of f(h) = f* + C h^p from the three meshes and the
   !> remaining difference to Timoshenko are reported. Asserted: monotone decrease and error at
   !> lc = 3 mm below the lc = 6 mm one.
   subroutine test_convergence(error)
      type(error_t), allocatable, intent(out) :: error
      character(len=*), parameter :: meshes(3) = [character(len=16) :: 'beam_lc6.msh', &
         'beam_lc4.msh', 'beam_lc3.msh']
      real(dp), parameter :: h(3) = [6.0_dp, 4.0_dp, 3.0_dp]
      type(body_modes_t) :: body
      real(dp) :: f(3), reference, p
      integer :: k, b
      reference = bending_reference(.false.)
      do k = 1, 3
         call beam_modes(trim(meshes(k)), .false., 4, body, error)
         if (allocated(error)) return
         b = first_of_kind(body, BENDING)
         call check(error, trim(meshes(k)) // ': a bending mode', b > 0)
         if (allocated(error)) return
         f(k) = body%frequency_hz(b)
         call report('lc = ' // to_str(h(k)) // ' mm: ' // to_str(3 * body%mesh%num_nodes) // &
            ' dofs, first bending ' // to_str(f(k), 9) // ' Hz, relative to Timoshenko ' // &
            to_str(f(k) / reference - 1.0_dp, 3))
      end do
      p = observed_order(h, f)
      call report('observed order of f(h) = f* + C h^p from lc = 6, 4, 3 mm: p = ' // &
         to_str(p, 3) // ' (Tet10 eigenvalues: 4 for smooth solutions)')
      call check(error, 'frequencies decrease under refinement: ' // to_str(f(1), 9) // &
         ' > ' // to_str(f(2), 9) // ' > ' // to_str(f(3), 9), f(1) > f(2) .and. f(2) > f(3))
   end subroutine test_convergence

   !> Linear tetrahedra lock in bending (constant strain: a bent Tet4 cannot represent a linear
   !> strain across its thickness and stores spurious shear energy), Tet10 does not. Free-free
   !> beam, Tet4 at lc = 2 mm (12,423 nodes, 37,269 dofs: more dofs than the Tet10 lc = 4 mm mesh,
   !> 43,935) against Tet10 at lc = 4 mm, both against the Timoshenko first bending frequency.
   !> Asserted: Tet4 too stiff by more than 1 % (measured +2.0 %, 44 times the Tet10 error, with
   !> fewer dofs: the locking), Tet10 within 0.1 % (measured +0.045 %).
   subroutine test_tet4_locking(error)
      type(error_t), allocatable, intent(out) :: error
      type(body_modes_t) :: tet4, tet10
      real(dp) :: reference, error4, error10
      integer :: b4, b10
      reference = bending_reference(.false.)
      call beam_modes('beam_tet4.msh', .false., 4, tet4, error)
      if (.not. allocated(error)) call beam_modes('beam_lc4.msh', .false., 4, tet10, error)
      if (allocated(error)) return
      b4 = first_of_kind(tet4, BENDING)
      b10 = first_of_kind(tet10, BENDING)
      call check(error, 'a bending mode on both meshes', b4 > 0 .and. b10 > 0)
      if (allocated(error)) return
      error4 = tet4%frequency_hz(b4) / reference - 1.0_dp
      error10 = tet10%frequency_hz(b10) / reference - 1.0_dp
      call report('first bending vs Timoshenko ' // to_str(reference, 8) // ' Hz: Tet4 (' // &
         to_str(3 * tet4%mesh%num_nodes) // ' dofs) ' // to_str(tet4%frequency_hz(b4), 8) // &
         ' Hz (' // to_str(error4, 3) // '), Tet10 (' // to_str(3 * tet10%mesh%num_nodes) // &
         ' dofs) ' // to_str(tet10%frequency_hz(b10), 8) // ' Hz (' // to_str(error10, 3) // ')')
      call check(error, 'Tet4 locks: bending ' // to_str(error4, 3) // ' above Timoshenko, ' // &
         'expected more than +1 %', error4 > 1.0e-2_dp)
      if (.not. allocated(error)) call check(error, 'Tet10 bending within 0.1 % of ' // &
         'Timoshenko: ' // to_str(error10, 3), abs(error10) < 1.0e-3_dp)
   end subroutine test_tet4_locking

   !> p with (f1 - f2)/(f2 - f3) = (h1^p - h2^p)/(h2^p - h3^p), by bisection on p in [0.5, 8].
   real(dp) function observed_order(h, f) result(p)
      real(dp), intent(in) :: h(3), f(3)
      real(dp) :: ratio, lo, hi
      integer :: it
      ratio = (f(1) - f(2)) / (f(2) - f(3))
      lo = 0.5_dp
      hi = 8.0_dp
      do it = 1, 100
         p = 0.5_dp * (lo + hi)
         if ((h(1)**p - h(2)**p) / (h(2)**p - h(3)**p) < ratio) then
            lo = p
         else
            hi = p
         end if
      end do
   end function observed_order

   !> Free-free beam with both end faces as virtual nodes whose 6 dofs are extra unknowns tied by
   !> constraint rows: RBE3 (q_V - G q_B = 0) leaves the flexible spectrum unchanged to 1e-10
   !> relative (it adds no stiffness, Nastran RBE3 semantics); RBE2 (q_B - F q_V = 0) raises it.
   subroutine test_rbe3_no_stiffness(error)
      type(error_t), allocatable, intent(out) :: error
      type(mesh_t) :: mesh, beam
      type(csr_t) :: K, M, K_aug, M_aug, C_none, C_rbe3, C_rbe2
      type(interface_t) :: ends(2)
      type(interface_spec_t) :: input
      type(eigen_options_t) :: options
      type(eigen_result_t) :: plain, with_rbe3, with_rbe2
      type(logger_t) :: log
      integer :: side, i
      call read_gmsh(test_mesh_dir() // '/beam_lc6.msh', mesh, error)
      if (.not. allocated(error)) call extract_body(mesh, ['beam'], beam, error)
      if (allocated(error)) return
      call assemble_stiffness_mass(beam%xyz, beam%tets, beam%tet_tags, &
         material_t(young, poisson, density, 'steel'), K, M, error)
      if (allocated(error)) return
      do side = 1, 2
         input%name = merge('end0', 'end1', side == 1)
         call build_interface(beam, input, ends(side), error)
         if (allocated(error)) return
      end do
      call pad(K, 12, K_aug, error)
      if (.not. allocated(error)) call pad(M, 12, M_aug, error)
      if (.not. allocated(error)) call rbe3_rows(ends, K%num_rows, C_rbe3, error)
      if (.not. allocated(error)) call rbe2_rows(ends, beam%xyz, K%num_rows, C_rbe2, error)
      if (.not. allocated(error)) call csr_from_coo(0_ip, K%num_rows, [integer(ip) ::], &
         [integer(ip) ::], [real(dp) ::], C_none, error)
      if (allocated(error)) return
      options%num_modes = 12
      options%sigma = sigma_of_shift(-10.0_dp)
      log%level = LOG_QUIET
      call solve_shift_invert(K, M, C_none, options, plain, log, error)
      if (.not. allocated(error)) call solve_shift_invert(K_aug, M_aug, C_rbe3, options, &
         with_rbe3, log, error)
      if (.not. allocated(error)) call solve_shift_invert(K_aug, M_aug, C_rbe2, options, &
         with_rbe2, log, error)
      if (allocated(error)) return
      ! Modes 1-6 are the rigid ones (~0); compare the flexible ones 7-12.
      do i = 7, 12
         call check_close(error, 'flexible eigenvalue ' // to_str(i - 6) // ' with RBE3 ' // &
            'constraints', with_rbe3%eigenvalues(i), plain%eigenvalues(i), rtol=1.0e-10_dp)
         if (allocated(error)) return
      end do
      call report('first flexible: ' // to_str(sqrt(plain%eigenvalues(7)) / (2 * pi), 10) // &
         ' Hz free, ' // to_str(sqrt(with_rbe3%eigenvalues(7)) / (2 * pi), 10) // &
         ' Hz with RBE3, ' // to_str(sqrt(with_rbe2%eigenvalues(7)) / (2 * pi), 10) // &
         ' Hz with RBE2 ends')
      call check(error, 'RBE2 ends stiffen every flexible mode', &
         all(with_rbe2%eigenvalues(7:12) > plain%eigenvalues(7:12) * (1.0_dp + 1.0e-8_dp)))
   end subroutine test_rbe3_no_stiffness

   !> Pinned-pinned beam (end0 Tx Ty Tz Rx, end1 Ty Tz): RBE3 ends, and RBE2 at end0 with RBE3 at
   !> end1; null-space and multiplier RC matrices agree to 1e-8 relative (issue tolerance; both
   !> are exact formulations of one constrained problem).
   subroutine test_formulations(error)
      type(error_t), allocatable, intent(out) :: error
      character(len=4), parameter :: mpcs(2, 2) = reshape([character(len=4) :: 'RBE3', 'RBE3', &
         'RBE2', 'RBE3'], [2, 2])
      type(body_modes_t) :: scalable, explicit
      integer :: variant, i
      do variant = 1, 2
         call beam_modes('beam_lc6.msh', .false., 6, scalable, error, mpc=mpcs(:, variant), &
            rc=[character(len=12) :: 'Tx Ty Tz Rx', 'Ty Tz'], formulation='multipliers')
         if (.not. allocated(error)) call beam_modes('beam_lc6.msh', .false., 6, explicit, error, &
            mpc=mpcs(:, variant), rc=[character(len=12) :: 'Tx Ty Tz Rx', 'Ty Tz'], &
            formulation='null_space')
         if (allocated(error)) return
         do i = 1, 6
            call check_close(error, mpcs(1, variant) // '/' // mpcs(2, variant) // ' mode ' // &
               to_str(i) // ' (Hz), null space vs multipliers', explicit%frequency_hz(i), &
               scalable%frequency_hz(i), rtol=1.0e-8_dp)
            if (allocated(error)) return
         end do
         call report(mpcs(1, variant) // '/' // mpcs(2, variant) // ' pinned-pinned: f1 = ' // &
            to_str(scalable%frequency_hz(1), 9) // ' Hz, max relative difference ' // &
            to_str(maxval(abs(explicit%frequency_hz - scalable%frequency_hz) / &
            scalable%frequency_hz), 2))
      end do
   end subroutine test_formulations

   !> A with `extra` zero rows and columns appended.
   subroutine pad(A, extra, padded, error)
      type(csr_t), intent(in) :: A
      integer, intent(in) :: extra
      type(csr_t), intent(out) :: padded
      type(error_t), allocatable, intent(out) :: error
      integer(ip), allocatable :: rows(:)
      integer(ip) :: i
      allocate (rows(size(A%col)))
      do i = 1, A%num_rows
         rows(A%row_ptr(i):A%row_ptr(i + 1) - 1) = i
      end do
      call csr_from_coo(A%num_rows + extra, A%num_cols + extra, rows, A%col, A%val, padded, error)
   end subroutine pad

   !> 6 rows per interface: q_V - G q_B = 0, virtual dofs after the n nodal ones.
   subroutine rbe3_rows(ends, n, constraints, error)
      type(interface_t), intent(in) :: ends(:)
      integer(ip), intent(in) :: n
      type(csr_t), intent(out) :: constraints
      type(error_t), allocatable, intent(out) :: error
      integer(ip), allocatable :: rows(:), cols(:)
      real(dp), allocatable :: vals(:)
      integer :: k, d, i, c
      allocate (rows(0), cols(0), vals(0))
      do k = 1, size(ends)
         do d = 1, 6
            rows = [rows, int(6 * (k - 1) + d, ip)]
            cols = [cols, n + int(6 * (k - 1) + d, ip)]
            vals = [vals, 1.0_dp]
            do i = 1, size(ends(k)%nodes)
               do c = 1, 3
                  rows = [rows, int(6 * (k - 1) + d, ip)]
                  cols = [cols, 3 * (ends(k)%nodes(i) - 1) + int(c, ip)]
                  vals = [vals, -ends(k)%G(d, 3 * (i - 1) + c)]
               end do
            end do
         end do
      end do
      call csr_from_coo(int(6 * size(ends), ip), n + int(6 * size(ends), ip), rows, cols, vals, &
         constraints, error)
   end subroutine rbe3_rows

   !> 3 rows per interface node: q_i - u_V + skew(r_i) theta_V = 0 (the RBE2 relation).
   subroutine rbe2_rows(ends, xyz, n, constraints, error)
      type(interface_t), intent(in) :: ends(:)
      real(dp), intent(in) :: xyz(:, :)
      integer(ip), intent(in) :: n
      type(csr_t), intent(out) :: constraints
      type(error_t), allocatable, intent(out) :: error
      integer(ip), allocatable :: rows(:), cols(:)
      real(dp), allocatable :: vals(:)
      real(dp) :: r(3), s(3, 3)
      integer(ip) :: row
      integer :: k, i, c, j
      allocate (rows(0), cols(0), vals(0))
      row = 0
      do k = 1, size(ends)
         do i = 1, size(ends(k)%nodes)
            r = xyz(:, ends(k)%nodes(i)) - ends(k)%virtual_xyz
            s = reshape([0.0_dp, r(3), -r(2), -r(3), 0.0_dp, r(1), r(2), -r(1), 0.0_dp], [3, 3])
            do c = 1, 3
               row = row + 1
               rows = [rows, row, row]
               cols = [cols, 3 * (ends(k)%nodes(i) - 1) + int(c, ip), n + int(6 * (k - 1) + c, ip)]
               vals = [vals, 1.0_dp, -1.0_dp]
               do j = 1, 3
                  if (s(c, j) == 0.0_dp) cycle
                  rows = [rows, row]
                  cols = [cols, n + int(6 * (k - 1) + 3 + j, ip)]
                  vals = [vals, s(c, j)]
               end do
            end do
         end do
      end do
      call csr_from_coo(row, n + int(6 * size(ends), ip), rows, cols, vals, constraints, error)
   end subroutine rbe2_rows

end module test_modes_beam

program main_modes_beam
   use ffrf_testing, only: unittest_t, run_suite
   use test_modes_beam, only: collect_modes_beam
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_modes_beam(tests)
   call run_suite('modes_beam', tests)
end program main_modes_beam
