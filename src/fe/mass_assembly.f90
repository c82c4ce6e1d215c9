!> Assembly of the consistent mass M alone (no stiffness), for a body whose modes are not computed
!> but taken from a file (&body modes_file): the inertia invariants of FFRF need M, not K. The
!> pattern and the scatter are those of ffrf_fe_assembly (M = Ms (x) I3, diagonal entries c = d
!> of each connected node pair) and the element masses those of ffrf_fe_tet, added in the same
!> order: M is bitwise the M of assemble_stiffness_mass, in about a third of its time.
module ffrf_fe_mass_assembly
   use ffrf_core_kinds, only: dp, ip, i8
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_la_sparse, only: csr_t
   use ffrf_fe_material, only: material_t, check_material
   use ffrf_fe_tet, only: tet_mass
   use ffrf_fe_assembly, only: node_graph, position_in_row
   implicit none
   private
   public :: assemble_mass

contains

   !> Assemble M (kg), 3 num_nodes square, both triangles stored; the checks of
   !> assemble_stiffness_mass (material, node indices, every element's det J).
   subroutine assemble_mass(xyz, tets, tet_tags, material, M, error)
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
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: G
      real(dp), allocatable :: me(:, :), xe(:, :)
      integer(ip), allocatable :: offset(:, :)
      integer(ip) :: nen, num_nodes, num_tets, e, a, b, c, i, rm, kb, deg, off, stat
      integer(i8) :: nnz_m

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
      if (size(tet_tags) /= num_tets .or. any(tets < 1 .or. tets > num_nodes)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'assembly: element tags or node indices ' // &
            'do not match the ' // to_str(num_nodes) // ' nodes; check the mesh')
         return
      end if
      call node_graph(tets, num_nodes, G, error)
      if (allocated(error)) return
      nnz_m = 3_i8*int(G%row_ptr(num_nodes + 1) - 1, i8)
      if (nnz_m > int(huge(0_ip), i8) - 1 .or. 3_i8*num_nodes > int(huge(0_ip), i8)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'assembly: M would have ' // to_str(nnz_m) // &
            ' entries, more than 32-bit indices allow; use a coarser mesh')
         return
      end if
      M%num_rows = 3*num_nodes
      M%num_cols = 3*num_nodes
      allocate (M%row_ptr(3*num_nodes + 1))
      allocate (M%col(nnz_m), M%val(nnz_m), stat=stat)
      if (stat /= 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'assembly: cannot allocate ' // &
            to_str(nnz_m) // ' mass entries; use a coarser mesh or more memory')
         return
      end if
      ! node row i, neighbour p (0-based) -> entry p of each of the three dof rows of node i
      do i = 1, num_nodes
         off = G%row_ptr(i) - 1
         deg = G%row_ptr(i + 1) - G%row_ptr(i)
         do c = 1, 3
            rm = 3*off + (c - 1)*deg + 1
            M%row_ptr(3*(i - 1) + c) = rm
            do kb = 0, deg - 1
               M%col(rm + kb) = 3*(G%col(off + 1 + kb) - 1) + c
            end do
         end do
      end do
      M%row_ptr(3*num_nodes + 1) = int(nnz_m, ip) + 1
      M%val = 0.0_dp

      allocate (me(nen, nen), xe(3, nen), offset(nen, nen))
      do e = 1, num_tets
         xe = xyz(:, tets(:, e))
         call tet_mass(xe, material%density, tet_tags(e), me, error)
         if (allocated(error)) return
         do a = 1, nen
            do b = 1, nen
               offset(a, b) = position_in_row(G, tets(a, e), tets(b, e))
            end do
         end do
         do a = 1, nen
            i = tets(a, e)
            do c = 1, 3
               rm = M%row_ptr(3*(i - 1) + c)
               do b = 1, nen
                  M%val(rm + offset(a, b)) = M%val(rm + offset(a, b)) + me(a, b)
               end do
            end do
         end do
      end do
   end subroutine assemble_mass

end module ffrf_fe_mass_assembly
