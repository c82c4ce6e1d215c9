!> Spectra you can trust through the modal pipeline (issue 22; ffrf_modes_modal_analysis,
!> theory.md 5.6-5.8) on finite-element bodies:
!>
!> - free_crank_few_modes[_block]: the free-free crank (crank.msh, lc 6 mm, no interfaces) with
!>   num_modes = 1, 2, 3 (refused before: ARPACK converged on five of the six zero eigenvalues)
!>   gives the first flexible modes of a 12-mode ARPACK run: frequencies to 1e-9 (the issue's
!>   bound) and shapes to 1e-6 in the M-norm (an eigenvector is accurate to about its residual
!>   over the relative gap to its neighbour: up to 1e-9 / 0.03 at the default tolerance).
!> - symmetric_cube: a free cube of 3 x 3 x 3 cells, each cut into 24 Tet4 by its centre and
!>   its face centres, so that the mesh has the cube's 48 symmetries and its spectrum exact
!>   pairs and triplets (round-off of the element matrices apart: ~1e-15 relative). gmsh 4.8's
!>   transfinite and extruded tetrahedra split a square bar's bending pairs by 5e-4 (measured):
!>   not exact enough, so the mesh is built here. Reference: the dense generalized eigenproblem
!>   of the same K and M (LAPACK dsygv), its six zero eigenvalues skipped. Asserted with both
!>   eigensolvers: every returned frequency equals the dense one to 1e-9 (dsygv is backward
!>   stable: eps lambda_max / lambda_1 ~ 1e-13 here), every member of every multiplet is
!>   returned, and a num_modes that ends inside a triplet returns the whole triplet.
!> - symmetric_cube_rbe2_face: the same cube with an RBE2 on its top face (eliminated: rigid
!>   modes in the reduced coordinates) against the dense T^T K T, T^T M T problem, 1e-9.
!> - hinged_cubes: two such cubes that share one edge (one node-connected piece) are refused
!>   with a message naming the face-connected parts and the hinge, not the spectrum.
!> - crank_max_frequency: crank RC set 1 (RBE3) with max_frequency_hz = 20 kHz returns exactly
!>   the modes of a 40-mode run below 20 kHz: the same count, frequencies to 1e-9 and shapes to
!>   1e-6 (M-norm; modes 12 and 13 are 1.1 % apart).
module test_modes_free_spectra
   use ffrf_core_kinds, only: dp, ip, i8, pi
   use ffrf_core_error, only: error_t, fatal_error, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: logger_t, stage_times_t, LOG_QUIET
   use ffrf_la_sparse, only: csr_t, csr_matvec, csr_to_dense
   use ffrf_la_lapack, only: dsygv
   use ffrf_mesh_mesh, only: mesh_t
   use ffrf_mpc_interface, only: interface_spec_t, MPC_RBE2
   use ffrf_mpc_reduction, only: reduction_t, build_reduction, reduce_matrix, &
      FORMULATION_MULTIPLIERS
   use ffrf_input_interface, only: interface_input_t, parse_dofs
   use ffrf_input_body, only: body_input_t
   use ffrf_input_modes, only: modes_input_t
   use ffrf_modes_input, only: body_spec_t, modes_spec_t
   use ffrf_modes_modal_analysis, only: body_modes_t, compute_body_modes
   use ffrf_modes_shift_invert, only: MULTIPLET_RTOL
   use ffrf_app_body_modes, only: compute_input_body_modes
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, report, test_mesh_dir
   implicit none
   private
   public :: collect_modes_free_spectra

   real(dp), parameter :: rtol_frequency = 1.0e-9_dp, max_shape_difference = 1.0e-6_dp

contains

   subroutine collect_modes_free_spectra(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [ &
         new_unittest('free_crank_few_modes', test_free_crank_arpack), &
         new_unittest('free_crank_few_modes_block', test_free_crank_block), &
         new_unittest('symmetric_cube', test_symmetric_cube), &
         new_unittest('symmetric_cube_rbe2_face', test_cube_rbe2), &
         new_unittest('hinged_cubes', test_hinged_cubes), &
         new_unittest('crank_max_frequency', test_crank_max_frequency)]
   end subroutine collect_modes_free_spectra

   subroutine test_free_crank_arpack(error)
      type(error_t), allocatable, intent(out) :: error
      call free_crank('arpack', error)
   end subroutine test_free_crank_arpack

   subroutine test_free_crank_block(error)
      type(error_t), allocatable, intent(out) :: error
      call free_crank('block', error)
   end subroutine test_free_crank_block

   !> Module header: num_modes 1, 2, 3 against a 12-mode ARPACK run.
   subroutine free_crank(eigensolver, error)
      character(len=*), intent(in) :: eigensolver
      type(error_t), allocatable, intent(out) :: error
      type(body_modes_t) :: reference, body
      type(csr_t) :: M
      integer :: nev, j
      real(dp) :: shape_difference
      call crank_modes(12, 'arpack', [interface_input_t ::], 0.0_dp, reference, error, M)
      if (allocated(error)) return
      call report('12 modes (arpack): ' // to_str(reference%frequency_hz(1), 10) // ' .. ' // &
         to_str(reference%frequency_hz(12), 10) // ' Hz, rigid <= ' // &
         to_str(maxval(abs(reference%rigid_frequency_hz)), 2) // ' Hz, Sturm count ' // &
         to_str(reference%eigen%sturm_count))
      do nev = 1, 3
         call crank_modes(nev, eigensolver, [interface_input_t ::], 0.0_dp, body, error)
         if (allocated(error)) return
         shape_difference = 0.0_dp
         do j = 1, nev
            shape_difference = max(shape_difference, m_distance(M, body%shape(:, j), &
               reference%shape(:, j)))
         end do
         call report(eigensolver // ', num_modes = ' // to_str(nev) // ': ' // &
            to_str(size(body%frequency_hz)) // ' modes from ' // &
            to_str(body%frequency_hz(1), 10) // ' Hz, max rel. difference ' // &
            to_str(maxval(abs(body%frequency_hz - reference%frequency_hz(1:nev)) / &
            reference%frequency_hz(1:nev)), 2) // ', shapes ' // to_str(shape_difference, 2) &
            // ', Sturm ' // to_str(body%eigen%sturm_count) // ', ' // &
            to_str(body%eigen%num_recoveries) // ' recoveries')
         call check(error, eigensolver // ', num_modes = ' // to_str(nev) // ': ' // &
            to_str(size(body%frequency_hz)) // ' modes returned', size(body%frequency_hz) == nev)
         if (allocated(error)) return
         do j = 1, nev
            call check_close(error, eigensolver // ', num_modes = ' // to_str(nev) // &
               ': mode ' // to_str(j) // ' (Hz)', body%frequency_hz(j), &
               reference%frequency_hz(j), rtol=rtol_frequency)
            if (allocated(error)) return
         end do
         call check_close(error, eigensolver // ', num_modes = ' // to_str(nev) // &
            ': shapes, max M-norm difference', shape_difference, 0.0_dp, &
            atol=max_shape_difference)
         if (allocated(error)) return
         call check(error, eigensolver // ': proven, six rigid modes counted (Sturm ' // &
            to_str(body%eigen%sturm_count) // ')', body%eigen%sturm_checked .and. &
            body%eigen%sturm_count == nev + 6 .and. body%eigen%num_rigid == 6)
         if (allocated(error)) return
      end do
   end subroutine free_crank

   !> Module header: the free cube with exact multiplets against the dense reference.
   subroutine test_symmetric_cube(error)
      type(error_t), allocatable, intent(out) :: error
      character(len=6), parameter :: solvers(2) = ['arpack', 'block ']
      type(mesh_t) :: mesh
      type(body_modes_t) :: body
      type(csr_t) :: K, M
      real(dp), allocatable :: dense(:), hz(:)
      integer :: s, nev, last, j
      call cube_mesh(reshape([0, 0, 0], [3, 1]), 3, mesh)
      call cube_modes(mesh, 20, 'arpack', body, error, K, M)
      if (allocated(error)) return
      call dense_spectrum(K, M, dense, error)
      if (allocated(error)) return
      ! skip the six rigid modes; frequencies of the flexible ones
      hz = sqrt(max(dense(7:), 0.0_dp)) / (2.0_dp * pi)
      call report('dense reference: rigid |lambda| <= ' // to_str(maxval(abs(dense(1:6))), 2) &
         // ' s^-2, first flexible ' // to_str(hz(1), 8) // ' Hz; multiplicities of the ' // &
         'lowest 20:' // multiplicities(hz(1:multiplet_end(hz, 20))))
      call check(error, 'the cube has pairs and triplets', index(multiplicities(hz(1:20)), &
         ' 2') > 0 .and. index(multiplicities(hz(1:20)), ' 3') > 0)
      if (allocated(error)) return
      do s = 1, 2
         nev = multiplet_end(hz, 20)
         call cube_modes(mesh, nev, trim(solvers(s)), body, error)
         if (allocated(error)) return
         call report(trim(solvers(s)) // ': ' // to_str(size(body%frequency_hz)) // ' modes, ' &
            // to_str(body%eigen%num_recoveries) // ' recoveries, max rel. difference to ' // &
            'the dense ' // to_str(maxval(abs(body%frequency_hz - hz(1:nev)) / hz(1:nev)), 2))
         call check_frequencies(trim(solvers(s)), body%frequency_hz, hz(1:nev), error)
         if (allocated(error)) return
         ! num_modes ending on the first member of the first triplet
         j = 1
         do while (multiplet_end(hz, j) - j + 1 /= 3)
            j = multiplet_end(hz, j) + 1
         end do
         last = multiplet_end(hz, j)
         call cube_modes(mesh, j, trim(solvers(s)), body, error)
         if (allocated(error)) return
         call report(trim(solvers(s)) // ': num_modes = ' // to_str(j) // ' (first member of ' &
            // 'a triplet at ' // to_str(hz(j), 8) // ' Hz): ' // &
            to_str(size(body%frequency_hz)) // ' modes returned')
         call check_frequencies(trim(solvers(s)) // ', triplet cut by num_modes', &
            body%frequency_hz, hz(1:last), error)
         if (allocated(error)) return
      end do
   end subroutine test_symmetric_cube

   !> The free cube with an RBE2 on the nodes of its top face (a node set, no reference
   !> condition): the face nodes are eliminated (q_B = F q_V, T is not the identity), so the
   !> rigid modes are deflated in the reduced coordinates (virtual-node motion for the face).
   !> Reference: the dense eigenproblem of T^T K T, T^T M T (ffrf_mpc_reduction, LAPACK),
   !> its six zero eigenvalues skipped; 8 modes to 1e-9 with both eigensolvers.
   subroutine test_cube_rbe2(error)
      type(error_t), allocatable, intent(out) :: error
      character(len=6), parameter :: solvers(2) = ['arpack', 'block ']
      type(mesh_t) :: mesh
      type(body_modes_t) :: body
      type(interface_spec_t) :: face(1)
      type(reduction_t) :: red
      type(csr_t) :: K, M, K_r, M_r
      real(dp), allocatable :: dense(:), hz(:)
      integer :: s, nev
      call cube_mesh(reshape([0, 0, 0], [3, 1]), 3, mesh)
      face(1)%name = 'top'
      face(1)%mpc = MPC_RBE2
      face(1)%nodes = pack([(int(s, ip), s=1, mesh%num_nodes)], &
         mesh%xyz(3, :) >= maxval(mesh%xyz(3, :)) - 1.0e-12_dp)
      call cube_modes(mesh, 8, 'arpack', body, error, K, M, face)
      if (allocated(error)) return
      call build_reduction(body%mesh%num_nodes, body%interfaces, FORMULATION_MULTIPLIERS, red, &
         error)
      if (.not. allocated(error)) call reduce_matrix(red, K, K_r, error)
      if (.not. allocated(error)) call reduce_matrix(red, M, M_r, error)
      if (allocated(error)) return
      call dense_spectrum(K_r, M_r, dense, error)
      if (allocated(error)) return
      hz = sqrt(max(dense(7:), 0.0_dp)) / (2.0_dp * pi)
      nev = multiplet_end(hz, 8)
      call report('RBE2 top face (' // to_str(size(face(1)%nodes)) // ' nodes): ' // &
         to_str(red%num_reduced) // ' reduced coordinates of ' // to_str(3 * mesh%num_nodes) // &
         ', dense rigid |lambda| <= ' // to_str(maxval(abs(dense(1:6))), 2) // &
         ' s^-2; multiplicities' // multiplicities(hz(1:nev)))
      do s = 1, 2
         call cube_modes(mesh, nev, trim(solvers(s)), body, error, interfaces=face)
         if (allocated(error)) return
         call report(trim(solvers(s)) // ': max rel. difference to the dense ' // &
            to_str(maxval(abs(body%frequency_hz - hz(1:nev)) / hz(1:nev)), 2) // ', rigid ' // &
            '<= ' // to_str(maxval(abs(body%rigid_frequency_hz)), 2) // ' Hz')
         call check_frequencies(trim(solvers(s)) // ', RBE2 face', body%frequency_hz, &
            hz(1:nev), error)
         if (allocated(error)) return
      end do
   end subroutine test_cube_rbe2

   !> Module header: two cubes joined along one edge.
   subroutine test_hinged_cubes(error)
      type(error_t), allocatable, intent(out) :: error
      type(mesh_t) :: mesh
      type(body_modes_t) :: body
      type(error_t), allocatable :: failure
      call cube_mesh(reshape([0, 0, 0, 2, 2, 0], [3, 2]), 2, mesh)
      call cube_modes(mesh, 4, 'arpack', body, failure)
      if (.not. allocated(failure)) call report('not refused: ' // &
         to_str(body%frequency_hz(1), 6) // ' .. ' // to_str(body%frequency_hz(4), 6) // ' Hz')
      call check(error, 'hinged cubes refused', allocated(failure))
      if (allocated(error)) return
      call report('message: ' // failure%message)
      call check(error, 'FFRF_NUMERIC_ERROR naming the face-connected parts and the hinge: ' // &
         failure%message, failure%code == FFRF_NUMERIC_ERROR .and. &
         index(failure%message, 'flexible mode(s) at') > 0 .and. &
         index(failure%message, '2 parts that share no face') > 0 .and. &
         index(failure%message, 'hinge') > 0 .and. index(failure%message, 'loose') == 0)
   end subroutine test_hinged_cubes

   !> Module header: max_frequency_hz = 20 kHz against 40 modes, crank RC set 1.
   subroutine test_crank_max_frequency(error)
      type(error_t), allocatable, intent(out) :: error
      type(interface_input_t) :: faces(3)
      type(body_modes_t) :: sliced, reference
      type(csr_t) :: M
      real(dp) :: shape_difference
      integer :: j, below
      call crank_face(faces(1), 'B1', 'Tx Ty Tz', error)
      if (.not. allocated(error)) call crank_face(faces(2), 'B2', '', error)
      if (.not. allocated(error)) call crank_face(faces(3), 'B3', 'Tx Ty Tz Rz', error)
      if (allocated(error)) return
      call crank_modes(40, 'arpack', faces, 0.0_dp, reference, error, M)
      if (allocated(error)) return
      ! num_modes 10000: what the reader sets when max_frequency_hz comes alone
      call crank_modes(10000, 'arpack', faces, 20000.0_dp, sliced, error)
      if (allocated(error)) return
      below = count(reference%frequency_hz < 20000.0_dp)
      shape_difference = 0.0_dp
      do j = 1, min(below, size(sliced%frequency_hz))
         shape_difference = max(shape_difference, m_distance(M, sliced%shape(:, j), &
            reference%shape(:, j)))
      end do
      call report('40 modes: ' // to_str(below) // ' below 20 kHz; max_frequency_hz = ' // &
         '20000: ' // to_str(size(sliced%frequency_hz)) // ' modes (' // &
         to_str(sliced%eigen%num_windows) // ' window(s), proven at ' // &
         to_str(sliced%eigen%sturm_count) // ' below the bound), shapes ' // &
         to_str(shape_difference, 2))
      call check_frequencies('max_frequency_hz = 20000', sliced%frequency_hz, &
         reference%frequency_hz(1:below), error)
      if (allocated(error)) return
      call check_close(error, 'shapes, max M-norm difference', shape_difference, 0.0_dp, &
         atol=max_shape_difference)
   end subroutine test_crank_max_frequency

   ! ---------------------------------------------------------------------------------------------

   !> Frequencies equal in number and to rtol_frequency.
   subroutine check_frequencies(label, actual, expected, error)
      character(len=*), intent(in) :: label
      real(dp), intent(in) :: actual(:), expected(:)
      type(error_t), allocatable, intent(out) :: error
      integer :: j
      call check(error, label // ': ' // to_str(size(actual)) // ' modes, expected ' // &
         to_str(size(expected)), size(actual) == size(expected))
      if (allocated(error)) return
      do j = 1, size(expected)
         call check_close(error, label // ': mode ' // to_str(j) // ' (Hz)', actual(j), &
            expected(j), rtol=rtol_frequency)
         if (allocated(error)) return
      end do
   end subroutine check_frequencies

   !> Modes of crank.msh (lc 6 mm, Tet10, steel) with the given interfaces (none: free-free).
   subroutine crank_modes(num_modes, eigensolver, faces, max_frequency_hz, body, error, M)
      integer, intent(in) :: num_modes
      character(len=*), intent(in) :: eigensolver
      type(interface_input_t), intent(in) :: faces(:)
      real(dp), intent(in) :: max_frequency_hz
      type(body_modes_t), intent(out) :: body
      type(error_t), allocatable, intent(out) :: error
      type(csr_t), intent(out), optional :: M
      type(body_input_t) :: crank
      type(modes_input_t) :: modes
      type(logger_t) :: log
      type(stage_times_t) :: times
      crank = body_input_t('crank', 'crank.msh', '', 210.0e9_dp, 0.3_dp, 7850.0_dp)
      crank%volumes(1) = 'crank'
      modes%num_modes = num_modes
      modes%eigensolver = eigensolver
      modes%max_frequency_hz = max_frequency_hz
      log%level = LOG_QUIET
      call compute_input_body_modes(crank, faces, modes, test_mesh_dir(), log, times, body, &
         error, mass_matrix=M)
   end subroutine crank_modes

   !> An RBE3 interface of the crank on face `name` with reference conditions `rc`.
   subroutine crank_face(face, name, rc, error)
      type(interface_input_t), intent(out) :: face
      character(len=*), intent(in) :: name, rc
      type(error_t), allocatable, intent(out) :: error
      face%body = 'crank'
      face%name = name
      face%rc = rc
      call parse_dofs(rc, face%rc_dofs, error)
   end subroutine crank_face

   !> Free-free modes of a mesh built in memory (steel, no interfaces), with its K and M.
   subroutine cube_modes(mesh, num_modes, eigensolver, body, error, K, M, interfaces)
      type(mesh_t), intent(in) :: mesh
      integer, intent(in) :: num_modes
      character(len=*), intent(in) :: eigensolver
      type(body_modes_t), intent(out) :: body
      type(error_t), allocatable, intent(out) :: error
      type(csr_t), intent(out), optional :: K, M
      type(interface_spec_t), intent(in), optional :: interfaces(:)
      type(body_spec_t) :: spec
      type(modes_spec_t) :: modes
      type(interface_spec_t) :: none(0)
      type(logger_t) :: log
      type(stage_times_t) :: times
      spec%name = 'cube'
      spec%volumes(1) = 'cube'
      modes%num_modes = num_modes
      modes%eigensolver = eigensolver
      modes%tolerance = 0.0_dp
      log%level = LOG_QUIET
      if (present(interfaces)) then
         call compute_body_modes(mesh, spec, interfaces, modes, log, times, body, error, &
            mass_matrix=M, stiffness_matrix=K)
      else
         call compute_body_modes(mesh, spec, none, modes, log, times, body, error, &
            mass_matrix=M, stiffness_matrix=K)
      end if
   end subroutine cube_modes

   !> Tet4 mesh of cubes of c x c x c cells (edge 1 cm), the cube b at cell offset corner(:, b):
   !> every cell cut into 24 tetrahedra (a face edge, the face centre, the cell centre), so each
   !> cube has the 48 symmetries of the cube. Nodes on a lattice of half cells, shared where
   !> cubes touch. Physical volume 'cube'.
   subroutine cube_mesh(corner, c, mesh)
      integer, intent(in) :: corner(:, :), c
      type(mesh_t), intent(out) :: mesh
      integer, allocatable :: id(:, :, :)
      integer(ip), allocatable :: tets(:, :)
      real(dp), allocatable :: xyz(:, :)
      real(dp), parameter :: h = 0.01_dp
      integer :: b, i, j, k, d, side, e, a, num_nodes, num_tets, lo(3), hi(3), base(3), &
         face(3), v(3, 4), e1, e2, cell(3), t(4)
      real(dp) :: centre(3), volume
      lo = 2 * minval(corner, dim=2)
      hi = 2 * (maxval(corner, dim=2) + c)
      allocate (id(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)), source=0)
      allocate (xyz(3, size(id)), tets(4, 24 * c**3 * size(corner, 2)))
      centre = 0.5_dp * (lo + hi)
      num_nodes = 0
      num_tets = 0
      do b = 1, size(corner, 2)
         do k = 0, c - 1
            do j = 0, c - 1
               do i = 0, c - 1
                  base = 2 * (corner(:, b) + [i, j, k])
                  cell = base + 1
                  do d = 1, 3
                     e1 = mod(d, 3) + 1
                     e2 = mod(d + 1, 3) + 1
                     do side = 0, 1
                        face = base
                        face(d) = base(d) + 2 * side
                        do a = 1, 4
                           v(:, a) = face
                        end do
                        v(e1, 2) = v(e1, 2) + 2
                        v(e1, 3) = v(e1, 3) + 2
                        v(e2, 3) = v(e2, 3) + 2
                        v(e2, 4) = v(e2, 4) + 2
                        face(e1) = face(e1) + 1
                        face(e2) = face(e2) + 1
                        do a = 1, 4
                           t = [node(v(:, a)), node(v(:, mod(a, 4) + 1)), node(face), node(cell)]
                           volume = signed_volume(xyz(:, t))
                           if (volume < 0.0_dp) t([1, 2]) = t([2, 1])
                           num_tets = num_tets + 1
                           tets(:, num_tets) = int(t, ip)
                        end do
                     end do
                  end do
               end do
            end do
         end do
      end do
      mesh%num_nodes = num_nodes
      mesh%xyz = xyz(:, 1:num_nodes)
      mesh%node_tags = [(int(e, i8), e=1, num_nodes)]
      mesh%nodes_per_tet = 4
      mesh%tets = tets(:, 1:num_tets)
      mesh%tet_tags = [(int(e, i8), e=1, num_tets)]
      mesh%tet_entity = [(1_ip, e=1, num_tets)]
      mesh%nodes_per_tri = 0
      allocate (mesh%tris(3, 0), mesh%tri_tags(0), mesh%tri_entity(0), mesh%groups(1))
      mesh%groups(1)%dim = 3
      mesh%groups(1)%tag = 1
      mesh%groups(1)%name = 'cube'
      mesh%groups(1)%entities = [1_ip]
      mesh%file_name = '(symmetric cubes built in test_modes_free_spectra)'
   contains
      integer function node(p)
         integer, intent(in) :: p(3)
         if (id(p(1), p(2), p(3)) == 0) then
            num_nodes = num_nodes + 1
            id(p(1), p(2), p(3)) = num_nodes
            xyz(:, num_nodes) = (real(p, dp) - centre) * 0.5_dp * h
         end if
         node = id(p(1), p(2), p(3))
      end function node
   end subroutine cube_mesh

   pure real(dp) function signed_volume(x)
      real(dp), intent(in) :: x(3, 4)
      real(dp) :: a(3), b(3), c(3)
      a = x(:, 2) - x(:, 1)
      b = x(:, 3) - x(:, 1)
      c = x(:, 4) - x(:, 1)
      signed_volume = dot_product(a, [b(2) * c(3) - b(3) * c(2), b(3) * c(1) - b(1) * c(3), &
         b(1) * c(2) - b(2) * c(1)]) / 6.0_dp
   end function signed_volume

   !> All eigenvalues of K x = lambda M x, ascending (LAPACK dsygv on the dense matrices).
   subroutine dense_spectrum(K, M, lambda, error)
      type(csr_t), intent(in) :: K, M
      real(dp), allocatable, intent(out) :: lambda(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: Kd(:, :), Md(:, :), work(:)
      integer(ip) :: n, info
      n = K%num_rows
      call csr_to_dense(K, Kd)
      call csr_to_dense(M, Md)
      allocate (lambda(n), work(64 * n))
      call dsygv(1_ip, 'N', 'U', n, Kd, n, Md, n, lambda, work, int(size(work), ip), info)
      if (info /= 0) call fatal_error(error, FFRF_NUMERIC_ERROR, 'dense reference: dsygv ' // &
         'info = ' // to_str(info))
   end subroutine dense_spectrum

   !> ||a -+ b||_M for M-normalised a and b, the sign that makes it smallest.
   real(dp) function m_distance(M, a, b) result(distance)
      type(csr_t), intent(in) :: M
      real(dp), intent(in) :: a(:), b(:)
      real(dp), allocatable :: d(:), md(:)
      real(dp) :: sign_ab
      allocate (md(size(b)))
      call csr_matvec(M, b, md)
      sign_ab = sign(1.0_dp, dot_product(a, md))
      d = a - sign_ab * b
      call csr_matvec(M, d, md)
      distance = sqrt(max(0.0_dp, dot_product(d, md)))
   end function m_distance

   !> Index of the last member of the multiplet holding values(j) (ascending values).
   pure integer function multiplet_end(values, j) result(last)
      real(dp), intent(in) :: values(:)
      integer, intent(in) :: j
      last = j
      do while (last < size(values))
         if (values(last + 1) - values(last) > MULTIPLET_RTOL * values(last + 1)) exit
         last = last + 1
      end do
   end function multiplet_end

   !> " 1 2 3 ..." the sizes of the multiplets of an ascending list.
   function multiplicities(values) result(text)
      real(dp), intent(in) :: values(:)
      character(len=:), allocatable :: text
      integer :: j, last
      text = ''
      j = 1
      do while (j <= size(values))
         last = multiplet_end(values, j)
         text = text // ' ' // to_str(last - j + 1)
         j = last + 1
      end do
   end function multiplicities

end module test_modes_free_spectra

program main_modes_free_spectra
   use ffrf_testing, only: unittest_t, run_suite
   use test_modes_free_spectra, only: collect_modes_free_spectra
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_modes_free_spectra(tests)
   call run_suite('test_modes_free_spectra', tests)
end program main_modes_free_spectra
