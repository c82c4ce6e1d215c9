!> Craig-Bampton mode basis (src/modes/craig_bampton.f90; Heirman & Desmet 2010, theory.md 1.3)
!> against independent references:
!> - complete basis: static constraint modes plus ALL fixed-interface modes (dense LAPACK in the
!>   null space of the virtual-node rows) span the RC-constrained space, so Rayleigh-Ritz in it
!>   gives every RC normal-mode eigenvalue of a dense reference (LAPACK in null(C_RC)) to
!>   round-off; on a coarse Tet10 beam (fixture beam_lc40, 726 dofs) with RBE3 ends, and with
!>   an RBE2 end eliminated by the RC matrix T (three or all six of its dofs held);
!> - static completeness: the response to loads at the virtual nodes lies in the span of the
!>   static modes, so the CB basis (4 fixed-interface modes by Lanczos) reproduces the dense
!>   constrained static solution exactly (to round-off);
!> - Rayleigh-Ritz bounds on the crank (fixture crank_lc8, RC set 1): the Ritz frequencies lie
!>   above the RC normal-mode frequencies and fall as fixed-interface modes are added (nested
!>   spaces), with the first-mode error shrinking;
!> - refusal of a body without reference conditions.
module test_modes_craig_bampton
   use ffrf_core_kinds, only: dp, ip, pi
   use ffrf_core_error, only: error_t, add_context
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: logger_t, stage_times_t, LOG_QUIET
   use ffrf_mesh_mesh, only: mesh_t, extract_body
   use ffrf_mesh_gmsh, only: read_gmsh
   use ffrf_fe_material, only: material_t
   use ffrf_fe_assembly, only: assemble_stiffness_mass
   use ffrf_la_sparse, only: csr_t, csr_to_dense
   use ffrf_la_dense, only: null_space
   use ffrf_la_lapack, only: dgemm, dsygv, dgesv
   use ffrf_input_interface, only: interface_input_t
   use ffrf_mpc_interface, only: interface_spec_t, interface_t, build_interface
   use ffrf_mpc_reduction, only: reduction_t, build_reduction, reduce_matrix, &
      FORMULATION_MULTIPLIERS
   use ffrf_model_specs, only: interface_spec_of
   use ffrf_input_body, only: body_input_t
   use ffrf_input_modes, only: modes_input_t
   use ffrf_modes_shift_invert, only: eigen_options_t, eigen_result_t, solve_shift_invert
   use ffrf_modes_modal_analysis, only: body_modes_t
   use ffrf_app_body_modes, only: compute_input_body_modes
   use ffrf_modes_craig_bampton, only: cb_result_t, virtual_node_rows, rayleigh_ritz, &
      craig_bampton_modes
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, test_mesh_dir, report
   implicit none
   private
   public :: collect_modes_craig_bampton

   real(dp), parameter :: young = 210.0e9_dp, poisson = 0.3_dp, density = 7850.0_dp
   !> Coarse Tet10 beam (input/beam.geo, lc = 40 mm): 242 nodes, small enough for dense LAPACK
   character(len=*), parameter :: BEAM_MESH = 'beam_lc40.msh'

   !> A body reduced to its RC matrix: K_r, M_r, T and C_RC, interfaces.
   type :: reduced_body_t
      type(csr_t) :: K, M
      type(reduction_t) :: red
      type(interface_t), allocatable :: interfaces(:)
   end type reduced_body_t

contains

   subroutine collect_modes_craig_bampton(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [ &
         new_unittest('complete_basis_rbe3', test_complete_rbe3), &
         new_unittest('complete_basis_rbe2_eliminated', test_complete_rbe2), &
         new_unittest('complete_basis_rbe2_clamped', test_complete_rbe2_clamped), &
         new_unittest('static_response_exact', test_static_response), &
         new_unittest('crank_ritz_bounds_converge', test_crank_convergence), &
         new_unittest('free_free_refused', test_free_free_refused)]
   end subroutine collect_modes_craig_bampton

   !> The beam mesh with interfaces end0/end1 of the given MPCs and RCs, reduced by the RC
   !> matrix (multiplier formulation).
   subroutine reduced_beam(mpc, rc, body, error)
      character(len=*), intent(in) :: mpc(2), rc(2)
      type(reduced_body_t), intent(out) :: body
      type(error_t), allocatable, intent(out) :: error
      type(mesh_t) :: mesh, beam
      type(interface_input_t) :: inputs(2)
      type(interface_spec_t) :: spec
      type(csr_t) :: K, M
      integer :: i_if
      call read_gmsh(test_mesh_dir() // '/' // BEAM_MESH, mesh, error)
      if (.not. allocated(error)) call extract_body(mesh, ['beam'], beam, error)
      if (.not. allocated(error)) call assemble_stiffness_mass(beam%xyz, beam%tets, &
         beam%tet_tags, material_t(young, poisson, density, 'beam'), K, M, error)
      if (allocated(error)) return
      allocate (body%interfaces(2))
      do i_if = 1, 2
         inputs(i_if)%body = 'beam'
         inputs(i_if)%name = 'end' // to_str(i_if - 1)
         inputs(i_if)%mpc = mpc(i_if)
         inputs(i_if)%rc = rc(i_if)
         call interface_spec_of(inputs(i_if), spec, error)
         if (.not. allocated(error)) call build_interface(beam, spec, body%interfaces(i_if), error)
         if (allocated(error)) return
      end do
      call build_reduction(beam%num_nodes, body%interfaces, FORMULATION_MULTIPLIERS, body%red, &
         error)
      if (.not. allocated(error)) call reduce_matrix(body%red, K, body%K, error)
      if (.not. allocated(error)) call reduce_matrix(body%red, M, body%M, error)
   end subroutine reduced_beam

   !> All eigenvalues of K x = lambda M x on null(C) (dense: Z = null(C) by SVD, then LAPACK
   !> dsygv on Z^T K Z, Z^T M Z); with `vectors`, also the M-orthonormal eigenvectors Z V.
   subroutine dense_constrained_eigen(K, M, C, lambda, error, vectors)
      real(dp), intent(in) :: K(:, :), M(:, :), C(:, :)
      real(dp), allocatable, intent(out) :: lambda(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable, intent(out), optional :: vectors(:, :)
      real(dp), allocatable :: Z(:, :), KZ(:, :), Kz_r(:, :), Mz_r(:, :), work(:)
      integer(ip) :: n, nz, info
      integer :: rank
      n = int(size(K, 1), ip)
      if (size(C, 1) > 0) then
         call null_space(C, Z, rank, 1.0e-12_dp, error)
         if (allocated(error)) return
      else
         allocate (Z(n, n), source=0.0_dp)
         do info = 1, n
            Z(info, info) = 1.0_dp
         end do
      end if
      nz = int(size(Z, 2), ip)
      allocate (KZ(n, nz), Kz_r(nz, nz), Mz_r(nz, nz), lambda(nz), work(64 * nz))
      call dgemm('N', 'N', n, nz, n, 1.0_dp, K, n, Z, n, 0.0_dp, KZ, n)
      call dgemm('T', 'N', nz, nz, n, 1.0_dp, Z, n, KZ, n, 0.0_dp, Kz_r, nz)
      call dgemm('N', 'N', n, nz, n, 1.0_dp, M, n, Z, n, 0.0_dp, KZ, n)
      call dgemm('T', 'N', nz, nz, n, 1.0_dp, Z, n, KZ, n, 0.0_dp, Mz_r, nz)
      Kz_r = 0.5_dp * (Kz_r + transpose(Kz_r))
      Mz_r = 0.5_dp * (Mz_r + transpose(Mz_r))
      call dsygv(1_ip, merge('V', 'N', present(vectors)), 'U', nz, Kz_r, nz, Mz_r, nz, lambda, &
         work, int(size(work), ip), info)
      call check(error, 'dense reference: dsygv info = ' // to_str(info), info == 0)
      if (allocated(error)) return
      if (present(vectors)) then
         allocate (vectors(n, nz))
         call dgemm('N', 'N', n, nz, nz, 1.0_dp, Z, n, Kz_r, nz, 0.0_dp, vectors, n)
      end if
   end subroutine dense_constrained_eigen

   !> Static modes (library: the KKT factors of the Lanczos at sigma = 0) + all fixed-interface
   !> modes (dense reference) -> Rayleigh-Ritz (library) vs the dense RC normal modes. Also
   !> C_V X_s = the unit targets (1e-10, the round-off of one KKT solve). Tolerance of the
   !> eigenvalues: both sides are backward stable dense/sparse factorisations of the same
   !> pencil, whose eigenvalues carry an absolute round-off of order eps * lambda_max
   !> (toolchain.md pitfall 9): |lambda_i - lambda_ref,i| <= 100 eps lambda_max for every i
   !> (relative 100 eps lambda_max / lambda_i).
   subroutine check_complete_basis(mpc, rc, error)
      character(len=*), intent(in) :: mpc(2), rc(2)
      type(error_t), allocatable, intent(out) :: error
      type(reduced_body_t) :: body
      type(csr_t) :: C_v
      type(eigen_options_t) :: options
      type(eigen_result_t) :: lanczos
      type(logger_t) :: log
      logical, allocatable :: is_rc(:)
      real(dp), allocatable :: Kd(:, :), Md(:, :), Cv(:, :), Crc(:, :), X(:, :), Xf(:, :), &
         lambda_fixed(:), lambda_ref(:), lambda(:), Psi(:, :), residuals(:), targets(:, :), &
         unit_targets(:, :)
      real(dp) :: orthonormality, low_error, all_error, target_error, scale
      integer :: num_static, num_fixed, n, j, r
      character(len=:), allocatable :: tag

      tag = trim(mpc(1)) // ' "' // trim(rc(1)) // '" / ' // trim(mpc(2)) // ' "' // &
         trim(rc(2)) // '"'
      call reduced_beam(mpc, rc, body, error)
      if (.not. allocated(error)) call virtual_node_rows(body%interfaces, body%red, C_v, &
         is_rc, error)
      if (allocated(error)) return
      n = body%K%num_rows
      num_static = count(.not. is_rc)
      call csr_to_dense(body%K, Kd)
      call csr_to_dense(body%M, Md)
      call csr_to_dense(C_v, Cv)
      allocate (Crc(body%red%C%num_rows, n))
      if (body%red%C%num_rows > 0) call csr_to_dense(body%red%C, Crc)

      allocate (unit_targets(size(is_rc), num_static), source=0.0_dp)
      j = 0
      do r = 1, size(is_rc)
         if (is_rc(r)) cycle
         j = j + 1
         unit_targets(r, j) = 1.0_dp
      end do
      options%num_modes = 1
      options%sigma = 0.0_dp
      log%level = LOG_QUIET
      call solve_shift_invert(body%K, body%M, C_v, options, lanczos, log, error, &
         constraint_targets=unit_targets, constraint_solutions=X)
      if (allocated(error)) return
      ! C_V X_s: unit target on its own non-RC row, zero on every other row (RC rows included)
      targets = matmul(Cv, X)
      j = 0
      target_error = 0.0_dp
      do r = 1, size(is_rc)
         if (is_rc(r)) then
            target_error = max(target_error, maxval(abs(targets(r, :))))
            cycle
         end if
         j = j + 1
         targets(r, j) = targets(r, j) - 1.0_dp
         target_error = max(target_error, maxval(abs(targets(r, :))))
      end do
      call report(tag // ': ' // to_str(size(is_rc)) // ' virtual-node rows, ' // &
         to_str(num_static) // ' static modes, max |C_V X_s - E| = ' // to_str(target_error, 2))
      call check_close(error, tag // ': max |C_V X_s - E|', target_error, 0.0_dp, &
         atol=1.0e-10_dp)
      if (allocated(error)) return

      call dense_constrained_eigen(Kd, Md, Cv, lambda_fixed, error, Xf)
      if (.not. allocated(error)) call dense_constrained_eigen(Kd, Md, Crc, lambda_ref, error)
      if (allocated(error)) return
      num_fixed = size(lambda_fixed)
      call check(error, tag // ': basis size ' // to_str(num_static + num_fixed) // &
         ' = dimension of the RC-constrained space ' // to_str(size(lambda_ref)), &
         num_static + num_fixed == size(lambda_ref))
      if (allocated(error)) return
      X = reshape([X, Xf], [n, num_static + num_fixed])
      call rayleigh_ritz(body%K, body%M, body%red%C, X, lambda, Psi, residuals, orthonormality, &
         error)
      if (allocated(error)) return
      low_error = maxval(abs(lambda(1:20) - lambda_ref(1:20)) / lambda_ref(1:20))
      all_error = maxval(abs(lambda - lambda_ref)) / lambda_ref(size(lambda_ref))
      scale = sqrt(lambda_ref(1)) / (2.0_dp * pi)
      call report(tag // ': ' // to_str(size(lambda)) // ' Ritz values vs dense RC normal ' // &
         'modes (f1 = ' // to_str(scale, 7) // ' Hz, lambda_max / lambda_1 = ' // &
         to_str(lambda_ref(size(lambda_ref)) / lambda_ref(1), 3) // '): max |difference| / ' // &
         'lambda_max ' // to_str(all_error, 2) // ' (tolerance 100 eps = ' // &
         to_str(100.0_dp * epsilon(1.0_dp), 2) // '), max relative difference of the lowest ' // &
         '20 ' // to_str(low_error, 2) // '; max |Psi^T M Psi - I| = ' // &
         to_str(orthonormality, 2))
      call check_close(error, tag // ': max |lambda_i - lambda_ref,i| / lambda_max', &
         all_error, 0.0_dp, atol=100.0_dp * epsilon(1.0_dp))
      if (.not. allocated(error)) call check_close(error, tag // ': max |Psi^T M Psi - I|', &
         orthonormality, 0.0_dp, atol=1.0e-10_dp)
   end subroutine check_complete_basis

   !> RBE3 at both ends, statically determinate RC set: end0 Tx Ty Tz Rx, end1 Ty Tz (C_RC has
   !> six dense rows, handled by multipliers).
   subroutine test_complete_rbe3(error)
      type(error_t), allocatable, intent(out) :: error
      call check_complete_basis([character(len=4) :: 'RBE3', 'RBE3'], &
         [character(len=16) :: 'Tx Ty Tz Rx', 'Ty Tz'], error)
   end subroutine test_complete_rbe3

   !> end0 an RBE2 with RCs Tx Ty Tz (eliminated by T: its rotation rows pick T's columns, its
   !> translation rows vanish and are dropped), end1 an RBE3 with Ty Tz Rx.
   subroutine test_complete_rbe2(error)
      type(error_t), allocatable, intent(out) :: error
      call check_complete_basis([character(len=4) :: 'RBE2', 'RBE3'], &
         [character(len=16) :: 'Tx Ty Tz', 'Ty Tz Rx'], error)
   end subroutine test_complete_rbe2

   !> end0 an RBE2 clamped by all six RCs (every row of its virtual node eliminated by T, so the
   !> RCs are all in T, none in C_V), end1 a free RBE3: the six static modes are those of end1.
   subroutine test_complete_rbe2_clamped(error)
      type(error_t), allocatable, intent(out) :: error
      call check_complete_basis([character(len=4) :: 'RBE2', 'RBE3'], &
         [character(len=17) :: 'Tx Ty Tz Rx Ry Rz', ''], error)
   end subroutine test_complete_rbe2_clamped

   !> Loads at the virtual nodes f = G_0^T f_V0 + G_1^T f_V1 on the RBE3 beam (RCs as in
   !> test_complete_rbe3): the dense constrained static solution [[K, C^T], [C, 0]] [u; mu] =
   !> [f; 0] (LAPACK dgesv) against the CB basis with 4 fixed-interface modes (library, Lanczos),
   !> u_CB = Psi diag(1/omega^2) Psi^T f. Exact in exact arithmetic (u minimises the energy for
   !> its own virtual-node motion, so it is a combination of static modes); tolerance 1e-8
   !> relative, round-off of the stiff solve (measured value reported).
   subroutine test_static_response(error)
      type(error_t), allocatable, intent(out) :: error
      type(reduced_body_t) :: body
      type(cb_result_t) :: cb
      type(eigen_options_t) :: options
      type(logger_t) :: log
      real(dp), allocatable :: Kd(:, :), Crc(:, :), A(:, :), rhs(:, :), f(:), u_cb(:), z(:)
      integer(ip), allocatable :: pivots(:)
      real(dp), parameter :: load_end0(6) = [0.0_dp, 0.0_dp, 0.0_dp, 5.0_dp, 7.0_dp, -3.0_dp]
      real(dp), parameter :: load_end1(6) = [1.0e3_dp, 2.0e3_dp, -1.5e3_dp, 10.0_dp, -20.0_dp, &
         30.0_dp]
      real(dp) :: scale, difference
      integer(ip) :: n, nc, info
      integer :: i

      call reduced_beam([character(len=4) :: 'RBE3', 'RBE3'], &
         [character(len=16) :: 'Tx Ty Tz Rx', 'Ty Tz'], body, error)
      if (allocated(error)) return
      n = body%K%num_rows
      nc = body%red%C%num_rows
      allocate (f(n), source=0.0_dp)
      associate (e0 => body%interfaces(1), e1 => body%interfaces(2))
         do i = 1, size(e0%nodes)
            f(3 * e0%nodes(i) - 2:3 * e0%nodes(i)) = matmul(transpose(e0%G(:, 3 * i - 2:3 * i)), &
               load_end0)
         end do
         do i = 1, size(e1%nodes)
            f(3 * e1%nodes(i) - 2:3 * e1%nodes(i)) = f(3 * e1%nodes(i) - 2:3 * e1%nodes(i)) + &
               matmul(transpose(e1%G(:, 3 * i - 2:3 * i)), load_end1)
         end do
      end associate

      ! Dense reference, the C rows scaled to max |K_ii|
      call csr_to_dense(body%K, Kd)
      allocate (Crc(nc, n))
      call csr_to_dense(body%red%C, Crc)
      scale = 0.0_dp
      do i = 1, n
         scale = max(scale, abs(Kd(i, i)))
      end do
      do i = 1, nc
         Crc(i, :) = Crc(i, :) * scale / maxval(abs(Crc(i, :)))
      end do
      allocate (A(n + nc, n + nc), source=0.0_dp)
      A(1:n, 1:n) = Kd
      A(1:n, n + 1:) = transpose(Crc)
      A(n + 1:, 1:n) = Crc
      allocate (rhs(n + nc, 1), source=0.0_dp)
      rhs(1:n, 1) = f
      allocate (pivots(n + nc))
      call dgesv(n + nc, 1_ip, A, n + nc, pivots, rhs, n + nc, info)
      call check(error, 'dense static solve: dgesv info = ' // to_str(info), info == 0)
      if (allocated(error)) return

      log%level = LOG_QUIET
      options%sigma = -(2.0_dp * pi * 100.0_dp)**2
      call craig_bampton_modes(body%K, body%M, body%red, body%interfaces, 4_ip, options, log, cb, &
         error)
      if (allocated(error)) return
      z = matmul(f, cb%vectors) / cb%eigenvalues
      u_cb = matmul(cb%vectors, z)
      difference = norm2(u_cb - rhs(1:n, 1)) / norm2(rhs(1:n, 1))
      call report('static response to virtual-node loads: ' // to_str(cb%num_static) // &
         ' static + ' // to_str(cb%num_fixed) // ' fixed-interface modes, |u_CB - u| / |u| = ' &
         // to_str(difference, 2) // ', |u| = ' // to_str(norm2(rhs(1:n, 1)), 4) // ' m')
      call check_close(error, 'static response, |u_CB - u| / |u|', difference, 0.0_dp, &
         atol=1.0e-8_dp)
   end subroutine test_static_response

   !> Crank (crank_lc8 fixture), RBE3, RC set 1 (B1 Tx Ty Tz, B3 Tx Ty Tz Rz).
   subroutine crank_modes(basis, num_modes, body, error)
      character(len=*), intent(in) :: basis
      integer, intent(in) :: num_modes
      type(body_modes_t), intent(out) :: body
      type(error_t), allocatable, intent(out) :: error
      type(body_input_t) :: crank
      type(interface_input_t) :: faces(3)
      type(modes_input_t) :: modes
      type(logger_t) :: log
      type(stage_times_t) :: times
      character(len=2), parameter :: names(3) = ['B1', 'B2', 'B3']
      character(len=12), parameter :: rc(3) = [character(len=12) :: 'Tx Ty Tz', '', &
         'Tx Ty Tz Rz']
      integer :: k
      crank%name = 'crank'
      crank%mesh_file = 'crank_lc8.msh'
      crank%volumes(1) = 'crank'
      do k = 1, 3
         faces(k)%body = 'crank'
         faces(k)%name = names(k)
         faces(k)%rc = rc(k)
      end do
      modes%num_modes = num_modes
      modes%basis = basis
      log%level = LOG_QUIET
      call compute_input_body_modes(crank, faces, modes, test_mesh_dir(), &
         log, times, body, error)
      if (allocated(error)) call add_context(error, basis // ', ' // to_str(num_modes) // ' modes')
   end subroutine crank_modes

   !> Rayleigh-Ritz: every Ritz frequency of the CB basis lies above the RC normal-mode one of the
   !> same index (the CB space is a subspace of the RC-constrained space), and adding fixed-
   !> interface modes (2 -> 6, nested spaces) lowers every Ritz frequency. Tolerance 1e-9
   !> relative: the Lanczos tolerance of the normal and fixed-interface modes enters the Ritz
   !> values squared. The first-mode error must shrink; the errors are reported.
   subroutine test_crank_convergence(error)
      type(error_t), allocatable, intent(out) :: error
      type(body_modes_t) :: normal, cb2, cb6
      real(dp) :: e2, e6
      integer :: i
      call crank_modes('rc_normal', 6, normal, error)
      if (.not. allocated(error)) call crank_modes('craig_bampton', 2, cb2, error)
      if (.not. allocated(error)) call crank_modes('craig_bampton', 6, cb6, error)
      if (allocated(error)) return
      call check(error, 'CB basis sizes: ' // to_str(size(cb2%frequency_hz)) // ' and ' // &
         to_str(size(cb6%frequency_hz)) // ', expected 11 static + 2 and 11 + 6', &
         size(cb2%frequency_hz) == 13 .and. size(cb6%frequency_hz) == 17 .and. &
         cb6%num_static == 11)
      if (allocated(error)) return
      do i = 1, 6
         call check(error, 'mode ' // to_str(i) // ': CB (6 fixed) ' // &
            to_str(cb6%frequency_hz(i), 10) // ' Hz below the RC normal mode ' // &
            to_str(normal%frequency_hz(i), 10) // ' Hz', &
            cb6%frequency_hz(i) >= normal%frequency_hz(i) * (1.0_dp - 1.0e-9_dp))
         if (.not. allocated(error)) call check(error, 'mode ' // to_str(i) // ': CB (2 ' // &
            'fixed) ' // to_str(cb2%frequency_hz(i), 10) // ' Hz below CB (6 fixed) ' // &
            to_str(cb6%frequency_hz(i), 10) // ' Hz', &
            cb2%frequency_hz(i) >= cb6%frequency_hz(i) * (1.0_dp - 1.0e-9_dp))
         if (allocated(error)) return
      end do
      e2 = cb2%frequency_hz(1) / normal%frequency_hz(1) - 1.0_dp
      e6 = cb6%frequency_hz(1) / normal%frequency_hz(1) - 1.0_dp
      call report('crank RC set 1: f1 = ' // to_str(normal%frequency_hz(1), 8) // &
         ' Hz (normal modes); CB relative error ' // to_str(e2, 3) // ' (2 fixed-interface ' // &
         'modes), ' // to_str(e6, 3) // ' (6); f6: ' // to_str(cb2%frequency_hz(6) / &
         normal%frequency_hz(6) - 1.0_dp, 3) // ', ' // to_str(cb6%frequency_hz(6) / &
         normal%frequency_hz(6) - 1.0_dp, 3))
      call check(error, 'first-mode error shrinks with fixed-interface modes: ' // &
         to_str(e2, 3) // ' -> ' // to_str(e6, 3), e6 < e2)
   end subroutine test_crank_convergence

   !> A body without reference conditions has no floating frame for CB: refused by name.
   subroutine test_free_free_refused(error)
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: expected
      type(body_input_t) :: beam
      type(interface_input_t) :: ends(2)
      type(modes_input_t) :: modes
      type(logger_t) :: log
      type(stage_times_t) :: times
      type(body_modes_t) :: body
      beam = body_input_t('beam', BEAM_MESH, '', young, poisson, density)
      beam%volumes(1) = 'beam'
      ends(1)%body = 'beam'
      ends(1)%name = 'end0'
      ends(2)%body = 'beam'
      ends(2)%name = 'end1'
      modes%num_modes = 4
      modes%basis = 'craig_bampton'
      log%level = LOG_QUIET
      call compute_input_body_modes(beam, ends, modes, test_mesh_dir(), &
         log, times, body, expected)
      call check(error, 'free-free body with basis = craig_bampton refused', allocated(expected))
      if (allocated(error)) return
      call report('message: ' // expected%message)
      call check(error, 'message names the missing reference conditions: ' // &
         expected%message, index(expected%message, 'reference conditions') > 0)
   end subroutine test_free_free_refused

end module test_modes_craig_bampton

program main_modes_craig_bampton
   use ffrf_testing, only: unittest_t, run_suite
   use test_modes_craig_bampton, only: collect_modes_craig_bampton
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_modes_craig_bampton(tests)
   call run_suite('modes_craig_bampton', tests)
end program main_modes_craig_bampton
