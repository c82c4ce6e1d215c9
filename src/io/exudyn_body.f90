!> A reduced flexible body as a file that Exudyn's `FEMinterface.LoadFromFile` loads as it is
!> (&run export = 'exudyn'; layout: docs/results.md "Exudyn export"). Exudyn (1.13) stores a
!> FEMinterface with `SaveDictToHDF5` (exudyn/advancedUtilities.py): every dictionary a group
!> with the attribute datatype = 'dict', a list a group 'list' of items item_0, item_1, ...,
!> a scipy CSR matrix a group 'csr_matrix' of data, indices, indptr, shape, an array a dataset
!> 'ndarray', a string a dataset 'str', an integer a dataset 'int'; `LoadDictFromHDF5` compares
!> those attributes with Python strings, so they are variable-length UTF-8 strings
!> (h5_file_t%set_attribute, variable = .true.). The file holds ffrf's own matrices and modes:
!> the mesh nodes, the tetrahedra in Exudyn's Tet10 order (Abaqus C3D10: the last two
!> mid-side nodes of Gmsh's order swapped, GMSH_TO_C3D10 of ffrf_fe_tet), the assembled M and
!> K of the mesh dofs (x, y, z per node), the body's surface (outward triangles; Tet10: also
!> the 6-node triangles), one node set per interface (RBE3 weights normalised to sum 1), the
!> mode basis (RC normal 'NormalModes' or Craig-Bampton 'HCBmodes'; ffrf's basis word in
!> /metaData) and omega^2 of each mode. Written as `<file>.part`, renamed when complete.
module ffrf_io_exudyn_body
   use ffrf_core_kinds, only: dp, ip, i8, pi
   use ffrf_core_error, only: error_t, add_context
   use ffrf_core_strings, only: to_str
   use ffrf_core_posix, only: commit_durably, remove_file
   use ffrf_core_choices, only: BASIS_CRAIG_BAMPTON, basis_choices, choice_name, mpc_choices
   use ffrf_la_sparse, only: csr_t
   use ffrf_mesh_mesh, only: boundary_faces
   use ffrf_mpc_interface, only: dofs_text
   use ffrf_fe_tet, only: GMSH_TO_C3D10, TET10_EDGES
   use ffrf_modes_modal_analysis, only: body_modes_t
   use ffrf_mbs_rotation, only: cross3
   use ffrf_io_hdf5, only: h5_file_t
   implicit none
   private
   public :: write_exudyn_body

   interface put_array
      module procedure put_vector, put_matrix
   end interface put_array

   !> The FEMinterface file version Exudyn 1.13's SaveToFile writes by default
   integer, parameter :: FEM_FILE_VERSION = 4

contains

   !> Write `body` (modes computed) with its mass and stiffness matrices M and K (CSR, both
   !> triangles, dofs 3 (node - 1) + component) to `file_name`, through `<file_name>.part`.
   subroutine write_exudyn_body(file_name, body, M, K, error)
      !> File to write (an Exudyn FEMinterface file must end in .hdf5)
      character(len=*), intent(in) :: file_name
      !> The body: mesh, interfaces, modes
      type(body_modes_t), intent(in) :: body
      !> Consistent mass matrix (kg) and stiffness matrix (N/m) of the body's mesh dofs
      type(csr_t), intent(in) :: M, K
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: close_error
      type(h5_file_t) :: h5
      character(len=:), allocatable :: temp
      type(error_t), allocatable :: ignored

      temp = file_name // '.part'
      call h5%create(temp, error)
      if (.not. allocated(error)) call write_content(h5, body, M, K, error)
      call h5%close(close_error)
      if (.not. allocated(error) .and. allocated(close_error)) call move_alloc(close_error, error)
      if (.not. allocated(error)) call commit_durably(temp, file_name, 'Exudyn body file', error)
      if (allocated(error)) then
         call remove_file(temp, ignored)
         call add_context(error, 'body "' // body%name // '", Exudyn file "' // file_name // '"')
      end if
   end subroutine write_exudyn_body

   !> The FEMinterface dictionary (GetDictionary of exudyn/FEM.py) written into `h5`.
   subroutine write_content(h5, body, M, K, error)
      type(h5_file_t), intent(inout) :: h5
      type(body_modes_t), intent(in) :: body
      type(csr_t), intent(in) :: M, K
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: element_type, g
      integer(ip), allocatable :: tets(:, :)
      integer :: i_if

      call put_string(h5, '/type', 'FEMinterface', error)
      if (.not. allocated(error)) call h5%write_int('/fileVersion', FEM_FILE_VERSION, error)
      if (.not. allocated(error)) call mark(h5, '/fileVersion', 'int', error)
      ! metaData: what Exudyn does not hold itself
      if (.not. allocated(error)) call mark(h5, '/metaData', 'dict', error)
      if (.not. allocated(error)) call put_string(h5, '/metaData/source', 'ffrf', error)
      if (.not. allocated(error)) call put_string(h5, '/metaData/body', body%name, error)
      if (.not. allocated(error)) call put_string(h5, '/metaData/basis', &
         choice_name(basis_choices, body%basis, missing='none'), error)
      if (allocated(error)) return
      ! nodes (metres) and elements (0-based, Exudyn's order)
      call mark(h5, '/nodes', 'dict', error)
      if (.not. allocated(error)) call put_array(h5, '/nodes/Position', body%mesh%xyz, 'm', error)
      if (allocated(error)) return
      if (body%mesh%nodes_per_tet == 10) then
         element_type = 'Tet10'
         tets = body%mesh%tets(GMSH_TO_C3D10, :) - 1_ip
      else
         element_type = 'Tet4'
         tets = body%mesh%tets(1:4, :) - 1_ip
      end if
      call mark(h5, '/elements', 'list', error)
      if (.not. allocated(error)) call mark(h5, '/elements/item_0', 'dict', error)
      if (.not. allocated(error)) call put_string(h5, '/elements/item_0/Name', body%name, error)
      if (.not. allocated(error)) call h5%write_int('/elements/item_0/' // element_type, tets, &
         error)
      if (.not. allocated(error)) call mark(h5, '/elements/item_0/' // element_type, &
         'ndarray', error)
      if (.not. allocated(error)) call put_csr(h5, '/massMatrix', M, 'kg', error)
      if (.not. allocated(error)) call put_csr(h5, '/stiffnessMatrix', K, 'N/m', error)
      if (.not. allocated(error)) call put_surface(h5, body, error)
      if (allocated(error)) return
      ! one node set per interface, in the body's interface order
      call mark(h5, '/nodeSets', 'list', error)
      do i_if = 1, size(body%interfaces)
         if (allocated(error)) return
         associate (f => body%interfaces(i_if))
            g = '/nodeSets/item_' // to_str(i_if - 1)
            call mark(h5, g, 'dict', error)
            if (.not. allocated(error)) call put_string(h5, g // '/Name', f%name, error)
            if (.not. allocated(error)) call h5%write_int(g // '/NodeNumbers', f%nodes - 1_ip, &
               error)
            if (.not. allocated(error)) call mark(h5, g // '/NodeNumbers', 'ndarray', error)
            if (.not. allocated(error)) call put_array(h5, g // '/NodeWeights', &
               f%weights / sum(f%weights), '1', error)
            if (.not. allocated(error)) call put_string(h5, g // '/type', 'boundary', error)
            if (.not. allocated(error)) call put_string(h5, g // '/MPC', &
               choice_name(mpc_choices, f%mpc), error)
            if (.not. allocated(error)) call put_array(h5, g // '/VirtualNode', f%virtual_xyz, &
               'm', error)
            if (.not. allocated(error)) call put_string(h5, g // '/RC', dofs_text(f%rc), error)
         end associate
      end do
      if (allocated(error)) return
      call mark(h5, '/elementSets', 'list', error)
      if (.not. allocated(error)) call mark(h5, '/postProcessingModes', 'dict', error)
      ! the mode basis (3 num_nodes, num_modes) and omega^2 (1/s^2)
      if (.not. allocated(error)) call mark(h5, '/modeBasis', 'dict', error)
      if (.not. allocated(error)) call put_array(h5, '/modeBasis/matrix', &
         transpose(body%shape), '1', error)
      if (allocated(error)) return
      if (body%basis == BASIS_CRAIG_BAMPTON) then
         call put_string(h5, '/modeBasis/type', 'HCBmodes', error)
      else
         call put_string(h5, '/modeBasis/type', 'NormalModes', error)
      end if
      if (.not. allocated(error)) call put_array(h5, '/eigenValues', &
         (2.0_dp * pi * body%frequency_hz)**2, '1/s^2', error)
   end subroutine write_content

   !> The body's surface: /surface item_0 'meshSurface' with Trigs (outward, 0-based corners)
   !> and, for Tet10, Trigs6 (corners, then the mid-side nodes of edges 1-2, 2-3, 3-1).
   subroutine put_surface(h5, body, error)
      type(h5_file_t), intent(inout) :: h5
      type(body_modes_t), intent(in) :: body
      type(error_t), allocatable, intent(out) :: error
      integer(ip), allocatable :: faces(:, :), trigs(:, :), trigs6(:, :)
      integer(ip) :: i, e, corner(3), opposite, mids(3)
      integer(ip), parameter :: face_corners(3, 4) = reshape([2, 3, 4, 1, 3, 4, 1, 2, 4, 1, 2, &
         3], [3, 4])
      real(dp) :: a(3), b(3), c(3), d(3)
      integer :: j

      call boundary_faces(body%mesh, faces)
      allocate (trigs(3, size(faces, 2)), trigs6(6, size(faces, 2)))
      do i = 1, size(faces, 2, kind=ip)
         e = faces(1, i)
         opposite = faces(2, i)
         corner = face_corners(:, opposite)
         associate (xyz => body%mesh%xyz, tet => body%mesh%tets(:, e))
            a = xyz(:, tet(corner(1)))
            b = xyz(:, tet(corner(2)))
            c = xyz(:, tet(corner(3)))
            d = xyz(:, tet(opposite))
            ! outward: the face normal (b - a) x (c - a) points away from the opposite corner
            if (dot_product(cross3(b - a, c - a), d - a) > 0.0_dp) corner = corner([1, 3, 2])
            trigs(:, i) = tet(corner) - 1_ip
            if (body%mesh%nodes_per_tet == 10) then
               do j = 1, 3
                  mids(j) = tet(4 + edge_of(corner(j), corner(mod(j, 3) + 1)))
               end do
               trigs6(:, i) = [tet(corner), mids] - 1_ip
            end if
         end associate
      end do
      call mark(h5, '/surface', 'list', error)
      if (.not. allocated(error)) call mark(h5, '/surface/item_0', 'dict', error)
      if (.not. allocated(error)) call put_string(h5, '/surface/item_0/Name', 'meshSurface', &
         error)
      if (.not. allocated(error)) call h5%write_int('/surface/item_0/Trigs', trigs, error)
      if (.not. allocated(error)) call mark(h5, '/surface/item_0/Trigs', 'ndarray', error)
      if (allocated(error) .or. body%mesh%nodes_per_tet /= 10) return
      call h5%write_int('/surface/item_0/Trigs6', trigs6, error)
      if (.not. allocated(error)) call mark(h5, '/surface/item_0/Trigs6', 'ndarray', error)
   end subroutine put_surface

   !> The Gmsh Tet10 edge (1..6, mid-side node 4 + edge) joining corners p and q.
   pure integer(ip) function edge_of(p, q) result(edge)
      integer(ip), intent(in) :: p, q
      integer(ip) :: k
      edge = 0
      do k = 1, 6
         if ((TET10_EDGES(1, k) == p .and. TET10_EDGES(2, k) == q) .or. &
             (TET10_EDGES(1, k) == q .and. TET10_EDGES(2, k) == p)) edge = k
      end do
   end function edge_of

   !> A CSR matrix as scipy's csr_matrix dictionary (0-based indices and pointers).
   subroutine put_csr(h5, path, A, units, error)
      type(h5_file_t), intent(inout) :: h5
      character(len=*), intent(in) :: path, units
      type(csr_t), intent(in) :: A
      type(error_t), allocatable, intent(out) :: error
      integer(ip) :: nnz
      nnz = A%row_ptr(A%num_rows + 1) - 1
      call mark(h5, path, 'csr_matrix', error)
      if (.not. allocated(error)) call h5%write_real(path // '/data', A%val(1:nnz), units, error)
      if (.not. allocated(error)) call h5%write_int(path // '/indices', A%col(1:nnz) - 1_ip, &
         error)
      if (.not. allocated(error)) call h5%write_int(path // '/indptr', A%row_ptr - 1_ip, error)
      if (.not. allocated(error)) call h5%write_int(path // '/shape', &
         [int(A%num_rows, i8), int(A%num_cols, i8)], error)
   end subroutine put_csr

   !> The attribute datatype = `kind` of the group or dataset at `path` (a missing path becomes a
   !> group), as a variable-length string: Exudyn's loader compares it with Python strings.
   subroutine mark(h5, path, kind, error)
      type(h5_file_t), intent(inout) :: h5
      character(len=*), intent(in) :: path, kind
      type(error_t), allocatable, intent(out) :: error
      call h5%set_attribute(path, 'datatype', kind, error, variable=.true.)
   end subroutine mark

   !> A string dataset as Exudyn stores a str (datatype 'str').
   subroutine put_string(h5, path, text, error)
      type(h5_file_t), intent(inout) :: h5
      character(len=*), intent(in) :: path, text
      type(error_t), allocatable, intent(out) :: error
      call h5%write_string(path, text, error)
      if (.not. allocated(error)) call mark(h5, path, 'str', error)
   end subroutine put_string

   !> A real vector as Exudyn stores a numpy array (datatype 'ndarray').
   subroutine put_vector(h5, path, values, units, error)
      type(h5_file_t), intent(inout) :: h5
      character(len=*), intent(in) :: path, units
      real(dp), intent(in) :: values(:)
      type(error_t), allocatable, intent(out) :: error
      call h5%write_real(path, values, units, error)
      if (.not. allocated(error)) call mark(h5, path, 'ndarray', error)
   end subroutine put_vector

   !> A real matrix as Exudyn stores a numpy array (h5py sees the transposed shape).
   subroutine put_matrix(h5, path, values, units, error)
      type(h5_file_t), intent(inout) :: h5
      character(len=*), intent(in) :: path, units
      real(dp), intent(in) :: values(:, :)
      type(error_t), allocatable, intent(out) :: error
      call h5%write_real(path, values, units, error)
      if (.not. allocated(error)) call mark(h5, path, 'ndarray', error)
   end subroutine put_matrix

end module ffrf_io_exudyn_body
