!> Assembly of the body stiffness K and consistent mass M (both triangles stored, CSR) from Tet4
!> or Tet10 elements, and the rigid-body mass properties of the body from M.
!>
!> Dof numbering: dof = 3 (node - 1) + c, c = 1, 2, 3 for x, y, z. The sparsity pattern is built
!> once from the node graph G = E^T E (E the element-node incidence, Gustavson product with
!> sorted columns): K stores the full 3x3 block of every connected node pair, M = Ms (x) I3 only
!> its diagonal entries c = d, so the pattern of M is a subset of the pattern of K. Element
!> matrices are then scattered straight into the values (binary search of the node in the sorted
!> node row; no COO list, no sort of the entries). assemble_matrices without K: M alone.
!> With several ranks (MPI build) each rank integrates a contiguous block of the elements into
!> the same pattern and the values are summed over the ranks (the same on every rank).
module ffrf_fe_assembly
   use ffrf_core_kinds, only: dp, ip, i8
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_la_sparse, only: csr_t, csr_transpose, csr_matmul, csr_find
   use ffrf_fe_material, only: material_t, check_material
   use ffrf_fe_tet, only: tet_stiffness_mass, tet_mass
   use ffrf_core_parallel, only: parallel_t
   implicit none
   private
   public :: assemble_stiffness_mass, assemble_matrices, body_mass_properties, node_graph

contains

   !> Assemble K (N/m) and M (kg), each 3 num_nodes square, both triangles stored. Checks the
   !> material, the element node indices and every element's det J (tetrahedron tag in the
   !> message).
   subroutine assemble_stiffness_mass(xyz, tets, tet_tags, material, K, M, error, parallel)
      !> Node coordinates (3, num_nodes) (m)
      real(dp), intent(in) :: xyz(:, :)
      !> Element node indices (nen, num_tets), nen = 4 or 10, 1..num_nodes, Gmsh node order
      integer(ip), intent(in) :: tets(:, :)
      !> Gmsh element tag of each tetrahedron (for messages)
      integer(i8), intent(in) :: tet_tags(:)
      !> Isotropic material of the body
      type(material_t), intent(in) :: material
      !> Stiffness matrix, 3 num_nodes square
      type(csr_t), intent(out) :: K
      !> Consistent mass matrix, 3 num_nodes square (entries only where c = d)
      type(csr_t), intent(out) :: M
      !> Bad material, node index out of range, inverted element, too many entries
      type(error_t), allocatable, intent(out) :: error
      !> The ranks sharing the element loop (MPI build); default one process
      type(parallel_t), intent(in), optional :: parallel
      call assemble_matrices(xyz, tets, tet_tags, material, M, error, parallel, K)
   end subroutine assemble_stiffness_mass

   !> Assemble M (kg) and, when K is present, K (N/m): the one element loop of the body
   !> matrices. Without K it serves a body whose modes are not computed but taken from a file
   !> (&body modes_file: the inertia invariants of FFRF need M, not K), in about a third of the
   !> time. M receives the same element masses (ffrf_fe_tet's mass kernel) in the same order
   !> either way: it is bitwise the same with or without K. The checks of
   !> assemble_stiffness_mass.
   subroutine assemble_matrices(xyz, tets, tet_tags, material, M, error, parallel, K)
      !> Node coordinates (3, num_nodes) (m)
      real(dp), intent(in) :: xyz(:, :)
      !> Element node indices (nen, num_tets), nen = 4 or 10, 1..num_nodes, Gmsh node order
      integer(ip), intent(in) :: tets(:, :)
      !> Gmsh element tag of each tetrahedron (for messages)
      integer(i8), intent(in) :: tet_tags(:)
      !> Isotropic material of the body
      type(material_t), intent(in) :: material
      !> Consistent mass matrix, 3 num_nodes square (entries only where c = d)
      type(csr_t), intent(out) :: M
      !> Bad material, node index out of range, inverted element, too many entries
      type(error_t), allocatable, intent(out) :: error
      !> The ranks sharing the element loop (MPI build); default one process
      type(parallel_t), intent(in), optional :: parallel
      !> Stiffness matrix, 3 num_nodes square; absent: M only
      type(csr_t), intent(out), optional :: K
      type(csr_t) :: G
      type(parallel_t) :: ranks
      real(dp), allocatable :: ke(:, :), me(:, :), xe(:, :)
      integer(ip), allocatable :: offset(:, :)
      integer(ip) :: nen, num_nodes, num_tets, e, a, b, c, d, i, rk, rm, kb, deg, off, stat
      integer(i8) :: nnz_k, nnz_m
      logical :: stiffness

      stiffness = present(K)
      call check_material(material, error)
      if (allocated(error)) return
      nen = size(tets, 1, kind=ip)
      num_tets = size(tets, 2, kind=ip)
      num_nodes = size(xyz, 2, kind=ip)
      if (nen /= 4 .and. nen /= 10) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'assembly: elements have ' // to_str(nen) // &
            ' nodes; only Tet4 (4) and Tet10 (10) are supported')
         return
      end if
      if (size(tet_tags) /= num_tets) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'assembly: ' // to_str(num_tets) // &
            ' tetrahedra but ' // to_str(size(tet_tags, kind=ip)) // ' tags; pass one tag each')
         return
      end if
      do e = 1, num_tets
         do a = 1, nen
            if (tets(a, e) < 1 .or. tets(a, e) > num_nodes) then
               call fatal_error(error, FFRF_INPUT_ERROR, 'tetrahedron ' // &
                  to_str(tet_tags(e)) // ': node index ' // to_str(tets(a, e)) // &
                  ' is outside 1..' // to_str(num_nodes) // '; check the mesh')
               return
            end if
         end do
      end do

      call node_graph(tets, num_nodes, G, error)
      if (allocated(error)) return
      nnz_m = 3_i8*int(G%row_ptr(num_nodes + 1) - 1, i8)
      nnz_k = 0
      if (stiffness) nnz_k = 3_i8*nnz_m
      if (max(nnz_k, nnz_m) > int(huge(0_ip), i8) - 1 .or. &
         3_i8*num_nodes > int(huge(0_ip), i8)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'assembly: ' // merge('K', 'M', stiffness) // &
            ' would have ' // to_str(max(nnz_k, nnz_m)) // ' entries, more than 32-bit ' // &
            'indices allow; use a coarser mesh')
         return
      end if

      ! patterns: node row i, neighbour number p (0-based) -> K entries 3p + (1..3) of the
      ! three dof rows of node i, M entry p of each
      M%num_rows = 3*num_nodes
      M%num_cols = 3*num_nodes
      allocate (M%row_ptr(3*num_nodes + 1))
      allocate (M%col(nnz_m), M%val(nnz_m), stat=stat)
      if (stiffness .and. stat == 0) then
         K%num_rows = 3*num_nodes
         K%num_cols = 3*num_nodes
         allocate (K%row_ptr(3*num_nodes + 1))
         allocate (K%col(nnz_k), K%val(nnz_k), stat=stat)
      end if
      if (stat /= 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'assembly: cannot allocate ' // &
            to_str(nnz_k + nnz_m) // ' matrix entries; use a coarser mesh or more memory')
         return
      end if
      do i = 1, num_nodes
         off = G%row_ptr(i) - 1
         deg = G%row_ptr(i + 1) - G%row_ptr(i)
         do c = 1, 3
            rm = 3*off + (c - 1)*deg + 1
            M%row_ptr(3*(i - 1) + c) = rm
            do kb = 0, deg - 1
               M%col(rm + kb) = 3*(G%col(off + 1 + kb) - 1) + c
            end do
            if (.not. stiffness) cycle
            rk = 9*off + 3*(c - 1)*deg + 1
            K%row_ptr(3*(i - 1) + c) = rk
            do kb = 0, deg - 1
               b = G%col(off + 1 + kb)
               K%col(rk + 3*kb:rk + 3*kb + 2) = 3*(b - 1) + [1, 2, 3]
            end do
         end do
      end do
      M%row_ptr(3*num_nodes + 1) = int(nnz_m, ip) + 1
      M%val = 0.0_dp
      if (stiffness) then
         K%row_ptr(3*num_nodes + 1) = int(nnz_k, ip) + 1
         K%val = 0.0_dp
         allocate (ke(3*nen, 3*nen))
      end if

      allocate (me(nen, nen), xe(3, nen), offset(nen, nen))
      if (present(parallel)) ranks = parallel
      do e = int(int(num_tets, i8)*ranks%rank/ranks%num_ranks, ip) + 1, &
            int(int(num_tets, i8)*(ranks%rank + 1)/ranks%num_ranks, ip)
         xe = xyz(:, tets(:, e))
         if (stiffness) then
            call tet_stiffness_mass(xe, material, tet_tags(e), ke, me, error)
         else
            call tet_mass(xe, material%density, tet_tags(e), me, error)
         end if
         if (allocated(error)) exit
         ! offset(a, b): position (0-based) of node b in the sorted node row of node a (G holds
         ! every pair of nodes of an element)
         do a = 1, nen
            i = tets(a, e)
            do b = 1, nen
               offset(a, b) = csr_find(G, i, tets(b, e)) - G%row_ptr(i)
            end do
         end do
         do a = 1, nen
            i = tets(a, e)
            do c = 1, 3
               rm = M%row_ptr(3*(i - 1) + c)
               do b = 1, nen
                  M%val(rm + offset(a, b)) = M%val(rm + offset(a, b)) + me(a, b)
               end do
               if (.not. stiffness) cycle
               rk = K%row_ptr(3*(i - 1) + c)
               do b = 1, nen
                  kb = rk + 3*offset(a, b)
                  ! ke is exactly symmetric: read its column (contiguous) for row 3(a-1)+c
                  do d = 1, 3
                     K%val(kb + d - 1) = K%val(kb + d - 1) + ke(3*(b - 1) + d, 3*(a - 1) + c)
                  end do
               end do
            end do
         end do
      end do
      if (ranks%num_ranks > 1) then
         ! an inverted element found by one rank stops every rank
         call ranks%agree(error)
         if (allocated(error)) return
         if (stiffness) call ranks%sum_reals(K%val)
         call ranks%sum_reals(M%val)
      end if
   end subroutine assemble_matrices

   !> Node graph G (num_nodes square, sorted columns, diagonal included): G(i, j) /= 0 iff nodes
   !> i and j share an element. G = E^T E with E(e, node) = 1; G's values count shared elements.
   subroutine node_graph(elements, num_nodes, G, error)
      !> Element node indices (nodes per element, num_elements), 1..num_nodes
      integer(ip), intent(in) :: elements(:, :)
      !> Number of nodes
      integer(ip), intent(in) :: num_nodes
      !> Node graph
      type(csr_t), intent(out) :: G
      !> Too many entries
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: E, Et
      integer(ip) :: nen, num_elements, k
      nen = size(elements, 1, kind=ip)
      num_elements = size(elements, 2, kind=ip)
      E%num_rows = num_elements
      E%num_cols = num_nodes
      ! rows hold an element's nodes unsorted: fine for the product, whose rows are sorted
      E%row_ptr = [(1 + nen*k, k=0, num_elements)]
      E%col = reshape(elements, [size(elements)])
      allocate (E%val(size(elements)))
      E%val = 1.0_dp
      call csr_transpose(E, Et)
      call csr_matmul(Et, E, G, error)
   end subroutine node_graph

   !> Rigid-body mass properties from the consistent mass (Zwoelfer & Gerstmayr 2020; theory.md
   !> section 3.2). With the scalar mass Ms (the x-dof entries of M = Ms (x) I3):
   !>     m = Phi_t^T M Phi_t = sum_ab Ms_ab,   chi = Phi_t^T M x / m = sum_ab Ms_ab x_b / m,
   !>     S = sum_ab Ms_ab r_a r_b^T (r = x - chi),   J = tr(S) I3 - S = int rho (r.r I - r r^T) dV.
   !> Sign: with a~ b~ = b a^T - (a.b) I, Theta_u = r~^T M r~ = -sum_ab Ms_ab r~_a r~_b
   !> = tr(S) I - S = +J: theory.md's Theta_u is the inertia tensor itself about the origin of the
   !> positions it is built from (here the centre of mass).
   !> Exact for the consistent mass of straight elements, where x is interpolated exactly.
   subroutine body_mass_properties(M, xyz, mass, center, inertia)
      !> Consistent mass matrix (3 num_nodes square)
      type(csr_t), intent(in) :: M
      !> Node coordinates (3, num_nodes) (m)
      real(dp), intent(in) :: xyz(:, :)
      !> Total mass m (kg)
      real(dp), intent(out) :: mass
      !> Centre of mass chi (m)
      real(dp), intent(out) :: center(3)
      !> Inertia tensor about the centre of mass (kg m^2)
      real(dp), intent(out) :: inertia(3, 3)
      real(dp) :: S(3, 3), first(3), ra(3), rb(3), trace
      integer(ip) :: a, b, k, row, j
      mass = 0.0_dp
      first = 0.0_dp
      do a = 1, size(xyz, 2, kind=ip)
         row = 3*(a - 1) + 1
         do k = M%row_ptr(row), M%row_ptr(row + 1) - 1
            if (mod(M%col(k) - 1, 3) /= 0) cycle
            b = (M%col(k) - 1)/3 + 1
            mass = mass + M%val(k)
            first = first + M%val(k)*xyz(:, b)
         end do
      end do
      center = 0.0_dp
      if (mass /= 0.0_dp) center = first/mass
      S = 0.0_dp
      do a = 1, size(xyz, 2, kind=ip)
         row = 3*(a - 1) + 1
         ra = xyz(:, a) - center
         do k = M%row_ptr(row), M%row_ptr(row + 1) - 1
            if (mod(M%col(k) - 1, 3) /= 0) cycle
            b = (M%col(k) - 1)/3 + 1
            rb = xyz(:, b) - center
            do j = 1, 3
               S(:, j) = S(:, j) + (M%val(k)*rb(j))*ra
            end do
         end do
      end do
      S = 0.5_dp*(S + transpose(S))
      trace = S(1, 1) + S(2, 2) + S(3, 3)
      inertia = -S
      do k = 1, 3
         inertia(k, k) = inertia(k, k) + trace
      end do
   end subroutine body_mass_properties

end module ffrf_fe_assembly
