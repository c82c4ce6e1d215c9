!> Modal geometric stiffness (ffrf_modes_modal_geometric_stiffness) of the scaled spin-up beam
!> (input/spin_beam.geo, ffrf_test_spin_beam: L = 10 m, 0.2 x 0.2 m, Tet10, clamped at the root
!> by an RBE2 with six RCs, an RBE3 without RCs at the tip, 6 modes = the first three bending
!> pairs) against closed forms:
!> - the static centrifugal stretch of a spin about z: tip axial displacement
!>   u(L) = rho Omega^2 L^3 / (3 E) (the bar with N(x) = rho A Omega^2 (L^2 - x^2)/2); a spin
!>   about the beam axis x stretches only the cross-section;
!> - the frequencies of the FFRF body linearised about a steady spin Omega e_z (flexible_body_t:
!>   K_ff + the tangents of its quadratic velocity vector, which hold the centrifugal softening,
!>   the Coriolis terms and, when set, K_G(omega); the quadratic eigenproblem solved exactly as
!>   a 2m x 2m first-order system): flapwise (out of the plane of rotation, z)
!>   omega_f^2 = omega_0^2 + K(Omega_bar) Omega^2, chordwise (in the plane, y) omega_c^2 =
!>   omega_f^2 - Omega^2, K(Omega_bar) = (lambda^2 - lambda_0^2)/Omega_bar^2 from the rotating
!>   Euler-Bernoulli cantilever (ffrf_test_spin_beam%rotating_lambda: 1.1923, 1.1770, 1.1314 at
!>   Omega_bar = 1, 4, 10; the first-order Southwell coefficient 1.1933); without K_G linear
!>   FFRF gives omega_c^2 = omega_0^2 - Omega^2 and omega_f^2 = omega_0^2 (no stiffening).
!>   The coefficients are compared, not the frequencies, so that the 3D model's own omega_0
!>   (+0.25 % over Euler-Bernoulli on lc = 0.2 m, +0.12 % on 0.1 m) cancels.
!> Tolerances from the measured errors (report lines), see each test.
module test_modes_geometric_stiffness
   use ffrf_core_kinds, only: dp, ip, pi
   use ffrf_core_error, only: error_t, add_context
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: logger_t, stage_times_t, LOG_QUIET
   use ffrf_la_sparse, only: csr_t
   use ffrf_input_interface, only: interface_input_t
   use ffrf_input_body, only: body_input_t
   use ffrf_input_modes, only: modes_input_t
   use ffrf_modes_modal_analysis, only: body_modes_t
   use ffrf_app_body_modes, only: compute_input_body_modes
   use ffrf_model_model, only: body_spec_of
   use ffrf_modes_modal_geometric_stiffness, only: compute_modal_geometric_stiffness
   use ffrf_mbs_rotation, only: euler_g_bar
   use ffrf_mbs_flexible_body, only: flexible_body_t
   use ffrf_test_spin_beam, only: rotating_lambda, southwell_coefficient, reference_frequency, &
      BEAM_LENGTH, BEAM_YOUNG, BEAM_POISSON, BEAM_DENSITY
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, report, test_mesh_dir
   implicit none
   private
   public :: collect_modes_geometric_stiffness

   interface
      !> LAPACK: eigenvalues of a general matrix.
      subroutine dgeev(jobvl, jobvr, n, a, lda, wr, wi, vl, ldvl, vr, ldvr, work, lwork, info)
         import :: dp, ip
         implicit none
         character, intent(in) :: jobvl, jobvr
         integer(ip), intent(in) :: n, lda, ldvl, ldvr, lwork
         real(dp), intent(inout) :: a(lda, n)
         real(dp), intent(out) :: wr(n), wi(n), vl(ldvl, n), vr(ldvr, n), work(lwork)
         integer(ip), intent(out) :: info
      end subroutine dgeev
   end interface

   !> Modes kept: the first three bending pairs (torsion comes after the fourth pair)
   integer, parameter :: num_modes = 6

contains

   subroutine collect_modes_geometric_stiffness(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [ &
         new_unittest('centrifugal_static_stretch', test_static_stretch), &
         new_unittest('rotating_cantilever_frequencies', test_rotating_frequencies), &
         new_unittest('linear_ffrf_softens_chordwise', test_linear_ffrf), &
         new_unittest('mesh_study', test_mesh_study)]
   end subroutine collect_modes_geometric_stiffness

   !> The beam's modes on mesh `mesh_name`, its FE mass matrix and its FFRF body, with the modal
   !> geometric stiffness set if `stiffening`; `u` the static displacements of the six cases.
   subroutine spin_beam(mesh_name, stiffening, body, flexible, u, error, poisson)
      character(len=*), intent(in) :: mesh_name
      logical, intent(in) :: stiffening
      type(body_modes_t), intent(out) :: body
      type(flexible_body_t), intent(out) :: flexible
      real(dp), allocatable, intent(out) :: u(:, :)
      type(error_t), allocatable, intent(out) :: error
      !> Poisson's ratio instead of BEAM_POISSON
      real(dp), intent(in), optional :: poisson
      type(body_input_t) :: beam
      type(interface_input_t) :: ends(2)
      type(modes_input_t) :: modes
      type(logger_t) :: log
      type(stage_times_t) :: times
      type(csr_t) :: M
      real(dp), allocatable :: K_G(:, :, :), virtual_xyz(:, :)
      integer :: k
      beam = body_input_t('beam', mesh_name, '', BEAM_YOUNG, BEAM_POISSON, BEAM_DENSITY)
      beam%volumes(1) = 'beam'
      if (present(poisson)) beam%poisson = poisson
      ends(1)%body = 'beam'
      ends(1)%name = 'root'
      ends(1)%mpc = 'RBE2'
      ends(1)%rc = 'Tx Ty Tz Rx Ry Rz'
      ends(2)%body = 'beam'
      ends(2)%name = 'tip'
      modes%num_modes = num_modes
      log%level = LOG_QUIET
      call compute_input_body_modes(beam, ends, modes, test_mesh_dir(), &
         log, times, body, error, &
         mass_matrix=M)
      if (allocated(error)) then
         call add_context(error, mesh_name)
         return
      end if
      allocate (virtual_xyz(3, size(body%interfaces)))
      do k = 1, size(body%interfaces)
         virtual_xyz(:, k) = body%interfaces(k)%virtual_xyz
      end do
      call flexible%init(M, body%mesh%xyz, body%shape, (2.0_dp * pi * body%frequency_hz)**2, &
         body%virtual_node_shape, virtual_xyz, error)
      if (allocated(error)) return
      call compute_modal_geometric_stiffness(body_spec_of(beam), body, log, times, K_G, error, &
         static_displacement=u)
      if (allocated(error)) return
      if (stiffening) call flexible%set_geometric_stiffness(K_G, error)
   end subroutine spin_beam

   !> Natural frequencies (rad/s, ascending) of the modal equations of `flexible` linearised about
   !> a steady spin omega_z e_z at zeta = 0: M_ff zeta'' + C zeta' + (K_ff + K) zeta = 0 with
   !> K, C the zeta blocks of -df_v/dq, -df_v/dv (the rotation itself prescribed), as the
   !> imaginary parts of the eigenvalues of [[0, I], [-M^-1 (K_ff + K), -M^-1 C]] (M_ff = I to
   !> round-off for mass-normalised modes, used as I).
   subroutine linearised_frequencies(flexible, omega_z, frequencies, error)
      type(flexible_body_t), intent(in) :: flexible
      real(dp), intent(in) :: omega_z
      real(dp), intent(out) :: frequencies(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: q(flexible%num_coordinates), v(flexible%num_coordinates)
      real(dp) :: K(flexible%num_coordinates, flexible%num_coordinates)
      real(dp) :: C(flexible%num_coordinates, flexible%num_coordinates)
      real(dp) :: A(2 * flexible%num_modes, 2 * flexible%num_modes), wr(2 * flexible%num_modes)
      real(dp) :: wi(2 * flexible%num_modes), vl(1, 1), vr(1, 1), work(64 * flexible%num_modes)
      real(dp), allocatable :: positive(:)
      real(dp) :: G_bar(3, 4)
      integer(ip) :: info, n2
      integer :: m, j
      m = flexible%num_modes
      n2 = int(2 * m, ip)
      q = 0.0_dp
      q(4) = 1.0_dp
      v = 0.0_dp
      G_bar = euler_g_bar(q(4:7))
      v(4:7) = 0.25_dp * matmul([0.0_dp, 0.0_dp, omega_z], G_bar)
      call flexible%quadratic_velocity_tangents(q, v, K, C)
      A = 0.0_dp
      do j = 1, m
         A(j, m + j) = 1.0_dp
         K(7 + j, 7 + j) = K(7 + j, 7 + j) + flexible%stiffness(j)
      end do
      A(m + 1:, 1:m) = -K(8:, 8:)
      A(m + 1:, m + 1:) = -C(8:, 8:)
      call dgeev('N', 'N', n2, A, n2, wr, wi, vl, 1_ip, vr, 1_ip, work, int(size(work), ip), &
         info)
      if (info /= 0) then
         call check(error, 'dgeev failed, info = ' // to_str(info), .false.)
         return
      end if
      positive = pack(wi, wi > 0.0_dp)
      call check(error, to_str(size(positive)) // ' oscillating eigenvalue pairs for ' // &
         to_str(m) // ' modes at Omega = ' // to_str(omega_z) // ' rad/s (an unstable or ' // &
         'overdamped mode?)', size(positive) == m)
      if (allocated(error)) return
      do j = 1, m
         frequencies(j) = minval(positive)
         positive(minloc(positive, 1)) = huge(1.0_dp)
      end do
   end subroutine linearised_frequencies

   !> Flapwise and chordwise stiffening coefficients (omega^2 - omega_0^2)/Omega^2 of the first
   !> bending pair at Omega = Omega_bar sqrt(EI/(rho A L^4)): chordwise the lower frequency,
   !> flapwise the upper. At rest, the structured mesh splits the pair by 4e-4 in omega^2 with
   !> eigenvectors that need not lie along y and z, so omega_0^2 of each plane is the Rayleigh
   !> quotient of the pair's stiffness diag(omega_1^2, omega_2^2) along the direction in which
   !> the pair moves the tip in that plane (the tip RBE3's virtual-node rows y and z).
   subroutine stiffening_coefficients(flexible, speed_parameter, chordwise, flapwise, error)
      type(flexible_body_t), intent(in) :: flexible
      real(dp), intent(in) :: speed_parameter
      real(dp), intent(out) :: chordwise, flapwise
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: spinning(num_modes), omega, direction(2), rest_sq(2)
      integer :: plane
      do plane = 1, 2
         ! tip (interface 2) virtual-node rows: 7..9 translation; y = 8, z = 9
         direction = flexible%virtual_shapes(7 + plane, 1:2)
         rest_sq(plane) = sum(direction**2 * flexible%stiffness(1:2)) / sum(direction**2)
      end do
      omega = speed_parameter * reference_frequency()
      call linearised_frequencies(flexible, omega, spinning, error)
      if (allocated(error)) return
      chordwise = (spinning(1)**2 - rest_sq(1)) / omega**2
      flapwise = (spinning(2)**2 - rest_sq(2)) / omega**2
   end subroutine stiffening_coefficients

   !> Spin about z: tip axial displacement (RBE3 virtual node of the tip) of u^(3) (per unit
   !> Omega^2) vs rho L^3/(3 E); the spin about y gives the same stretch, the spin about x none.
   !> With nu = 0 the bar is in uniaxial stress: measured ratio 1.000000105, asserted 1e-6 (the
   !> Tet10 displacement is quadratic per layer, u(x) is cubic). With nu = 0.3 the rigid root
   !> face stops the cross-section's Poisson contraction where N is largest, a stiffer root:
   !> measured ratio 0.99833 (lc 0.2 m), asserted within 0.5 %. The spin about x stretches
   !> nothing: asserted below 1e-4 of the z stretch (measured 9e-9 and 6e-5 relative).
   subroutine test_static_stretch(error)
      type(error_t), allocatable, intent(out) :: error
      type(body_modes_t) :: body
      type(flexible_body_t) :: flexible
      real(dp), allocatable :: u(:, :)
      real(dp), allocatable :: face(:)
      real(dp), parameter :: poissons(2) = [0.0_dp, BEAM_POISSON], rtol(2) = [1.0e-6_dp, &
         5.0e-3_dp]
      real(dp) :: tip(6, 3), expected
      integer :: c, i, k
      expected = BEAM_DENSITY * BEAM_LENGTH**3 / (3.0_dp * BEAM_YOUNG)
      do k = 1, 2
         call spin_beam('spin_beam_lc20.msh', .true., body, flexible, u, error, &
            poisson=poissons(k))
         if (allocated(error)) return
         associate (f => body%interfaces(2))
            allocate (face(3 * size(f%nodes)))
            do c = 1, 3
               do i = 1, size(f%nodes)
                  face(3 * i - 2:3 * i) = u(3 * (f%nodes(i) - 1) + [1, 2, 3], c)
               end do
               tip(:, c) = matmul(f%G, face)
            end do
            deallocate (face)
         end associate
         call report('nu = ' // to_str(poissons(k)) // ': tip axial displacement per ' // &
            'Omega^2: spin about z ' // to_str(tip(1, 3), 8) // ', about y ' // &
            to_str(tip(1, 2), 8) // ', about x ' // to_str(tip(1, 1), 3) // ' m s^2; ' // &
            'closed form rho L^3/(3 E) = ' // to_str(expected, 8) // ' (ratio ' // &
            to_str(tip(1, 3) / expected, 8) // ')')
         call check_close(error, 'spin about z: tip stretch', tip(1, 3), expected, &
            rtol=rtol(k))
         if (.not. allocated(error)) call check_close(error, 'spin about y: tip stretch', &
            tip(1, 2), expected, rtol=rtol(k))
         if (.not. allocated(error)) call check_close(error, 'spin about x: tip stretch', &
            tip(1, 1), 0.0_dp, atol=1.0e-4_dp * expected)
         if (allocated(error)) return
      end do
   end subroutine test_static_stretch

   !> With K_G: flapwise and chordwise coefficients at Omega_bar = 1, 4, 10 vs the rotating
   !> Euler-Bernoulli cantilever (module header), and at Omega_bar = 1 vs the first-order
   !> Southwell coefficient 1.1933 (within 2e-3: the exact coefficient there is 1.1923).
   !> Measured (lc 0.2 m, 6 modes), flapwise: +0.17 %, +0.21 %, +0.54 % at Omega_bar = 1, 4, 10;
   !> chordwise 0.1945, 0.1798, 0.1378 against 0.1922, 0.1769, 0.1313; 1.1942 against the
   !> Southwell 1.1933. Parts: the modal truncation (three modes per plane, a Ritz estimate from
   !> above: +0.002 %, +0.045 %, +0.37 % of the coefficient for an Euler-Bernoulli beam,
   !> computed with 60 Hermite elements) and the 3D model on this mesh (+0.15 %; +0.06 % on
   !> lc = 0.1 m, test_mesh_study). Asserted: 0.5 % of the coefficient, 1 % at Omega_bar = 10.
   subroutine test_rotating_frequencies(error)
      type(error_t), allocatable, intent(out) :: error
      type(body_modes_t) :: body
      type(flexible_body_t) :: flexible
      real(dp), allocatable :: u(:, :)
      real(dp), parameter :: speeds(3) = [1.0_dp, 4.0_dp, 10.0_dp], rtol(3) = [5.0e-3_dp, &
         5.0e-3_dp, 1.0e-2_dp]
      real(dp) :: chordwise, flapwise, exact
      integer :: k
      call spin_beam('spin_beam_lc20.msh', .true., body, flexible, u, error)
      if (allocated(error)) return
      do k = 1, size(speeds)
         call stiffening_coefficients(flexible, speeds(k), chordwise, flapwise, error)
         if (allocated(error)) return
         exact = (rotating_lambda(speeds(k))**2 - rotating_lambda(0.0_dp)**2) / speeds(k)**2
         call report('Omega_bar = ' // to_str(speeds(k)) // ': flapwise ' // &
            to_str(flapwise, 6) // ' (Euler-Bernoulli ' // to_str(exact, 6) // ', ' // &
            to_str(100.0_dp * (flapwise / exact - 1.0_dp), 3) // ' %), chordwise ' // &
            to_str(chordwise, 6) // ' (' // to_str(exact - 1.0_dp, 6) // ')')
         call check_close(error, 'flapwise coefficient at Omega_bar = ' // to_str(speeds(k)), &
            flapwise, exact, rtol=rtol(k))
         if (allocated(error)) return
         call check_close(error, 'chordwise coefficient at Omega_bar = ' // to_str(speeds(k)), &
            chordwise, exact - 1.0_dp, atol=rtol(k) * exact)
         if (allocated(error)) return
         if (k == 1) then
            call report('first-order Southwell coefficient (closed-form mode) ' // &
               to_str(southwell_coefficient(), 6))
            call check_close(error, 'flapwise coefficient at Omega_bar = 1 vs Southwell', &
               flapwise, southwell_coefficient(), atol=2.0e-3_dp)
            if (allocated(error)) return
         end if
      end do
   end subroutine test_rotating_frequencies

   !> Without K_G (linear modal FFRF): chordwise coefficient -1 (omega_c^2 = omega_0^2 -
   !> Omega^2: unstable above omega_0), flapwise 0, at Omega_bar = 1 and 3 (below omega_0 =
   !> 3.516 sqrt(EI/(rho A L^4))). Both are exact in the modal model up to the in-plane motion's
   !> axial components; measured -1.00009 / -7e-5 (Omega_bar = 1), -1.000001 / -1.5e-4 (3);
   !> asserted 1e-3 absolute.
   subroutine test_linear_ffrf(error)
      type(error_t), allocatable, intent(out) :: error
      type(body_modes_t) :: body
      type(flexible_body_t) :: flexible
      real(dp), allocatable :: u(:, :)
      real(dp), parameter :: speeds(2) = [1.0_dp, 3.0_dp]
      real(dp) :: chordwise, flapwise
      integer :: k
      call spin_beam('spin_beam_lc20.msh', .false., body, flexible, u, error)
      if (allocated(error)) return
      do k = 1, size(speeds)
         call stiffening_coefficients(flexible, speeds(k), chordwise, flapwise, error)
         if (allocated(error)) return
         call report('linear FFRF, Omega_bar = ' // to_str(speeds(k)) // ': chordwise ' // &
            to_str(chordwise, 8) // ', flapwise ' // to_str(flapwise, 8))
         call check_close(error, 'linear FFRF chordwise coefficient', chordwise, -1.0_dp, &
            atol=1.0e-3_dp)
         if (.not. allocated(error)) call check_close(error, 'linear FFRF flapwise coefficient', &
            flapwise, 0.0_dp, atol=1.0e-3_dp)
         if (allocated(error)) return
      end do
   end subroutine test_linear_ffrf

   !> Mesh study: the coefficients at Omega_bar = 4 on lc = 0.2 m (909 nodes) and 0.1 m (5025
   !> nodes), and the frequency at rest; the change bounds the discretisation error of the
   !> coarse mesh used by the other tests (asserted below the 0.5 % they allow). Measured:
   !> frequency at rest 1.00251 / 1.00119 times Euler-Bernoulli, flapwise 1.17934 / 1.17813
   !> (Euler-Bernoulli 1.17687, three-mode Ritz 1.17740).
   subroutine test_mesh_study(error)
      type(error_t), allocatable, intent(out) :: error
      type(body_modes_t) :: body
      type(flexible_body_t) :: flexible
      real(dp), allocatable :: u(:, :)
      character(len=*), parameter :: meshes(2) = ['spin_beam_lc20.msh', 'spin_beam_lc10.msh']
      real(dp) :: chordwise(2), flapwise(2), rest(2), exact
      integer :: k
      do k = 1, 2
         call spin_beam(meshes(k), .true., body, flexible, u, error)
         if (allocated(error)) return
         call stiffening_coefficients(flexible, 4.0_dp, chordwise(k), flapwise(k), error)
         if (allocated(error)) return
         rest(k) = sqrt(flexible%stiffness(1)) / (reference_frequency() * &
            rotating_lambda(0.0_dp))
         call report(meshes(k) // ' (' // to_str(body%mesh%num_nodes) // ' nodes): omega_0 / ' &
            // 'Euler-Bernoulli ' // to_str(rest(k), 8) // ', flapwise ' // &
            to_str(flapwise(k), 6) // ', chordwise ' // to_str(chordwise(k), 6))
      end do
      exact = (rotating_lambda(4.0_dp)**2 - rotating_lambda(0.0_dp)**2) / 16.0_dp
      call check_close(error, 'flapwise coefficient, lc 0.2 vs 0.1 m', flapwise(1), &
         flapwise(2), rtol=5.0e-3_dp)
      if (.not. allocated(error)) call check_close(error, 'flapwise coefficient, lc 0.1 m vs ' &
         // 'Euler-Bernoulli', flapwise(2), exact, rtol=5.0e-3_dp)
   end subroutine test_mesh_study

end module test_modes_geometric_stiffness

program main_modes_geometric_stiffness
   use ffrf_testing, only: unittest_t, run_suite
   use test_modes_geometric_stiffness, only: collect_modes_geometric_stiffness
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_modes_geometric_stiffness(tests)
   call run_suite('modes_geometric_stiffness', tests)
end program main_modes_geometric_stiffness
