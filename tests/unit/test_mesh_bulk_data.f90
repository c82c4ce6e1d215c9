!> Nastran bulk-data reader (ffrf_mesh_bulk_data). Reference: the hand-written deck
!> tests/data/bdf/corners.bdf (and its INCLUDE), whose every value is known by construction: one
!> Tet10 of corners (0,0,0) (0.2,0,0) (0,0.2,0) (0,0,0.2) with its mid-side nodes at the edge
!> midpoints, a grid given in a CORD2R system at basic (3, 3, 1), MAT1 by E and G (NU = 0.25), an
!> RBE3 and an RBE2. Coordinates are single decimal values read correctly rounded, so they must
!> equal the Fortran literals exactly (0 tolerance); the CORD2R grid goes through one rotation
!> (entries 0 or 1) and an offset: 4 eps.
module test_mesh_bulk_data
   use ffrf_core_kinds, only: dp, ip, i8
   use ffrf_core_error, only: error_t, fatal_error, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_choices, only: MPC_RBE2, MPC_RBE3
   use ffrf_mesh_mesh, only: mesh_t, extract_body
   use ffrf_mesh_bulk_data, only: read_mesh_file, is_bulk_data_file
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, test_data_dir
   implicit none
   private
   public :: collect_mesh_bulk_data

contains

   subroutine collect_mesh_bulk_data(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [new_unittest('corner_deck_values', test_corner_deck_values), &
         new_unittest('tet10_order_geometric', test_tet10_order_geometric), &
         new_unittest('interfaces_and_material', test_interfaces_and_material), &
         new_unittest('body_keeps_interfaces', test_body_keeps_interfaces), &
         new_unittest('suffixes', test_suffixes)]
   end subroutine collect_mesh_bulk_data

   function deck(name) result(path)
      character(len=*), intent(in) :: name
      character(len=:), allocatable :: path
      path = test_data_dir() // '/bdf/' // name
   end function deck

   !> Grids in card order (the INCLUDE read where it stands), their coordinates from small,
   !> free, large, tab-separated and CORD2R fields, and the grid after ENDDATA not read.
   subroutine test_corner_deck_values(error)
      type(error_t), allocatable, intent(out) :: error
      type(mesh_t) :: mesh
      real(dp) :: expected(3, 12)
      integer(i8), parameter :: tags(12) = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 51, 50]
      integer :: k, j
      call read_mesh_file(deck('corners.bdf'), mesh, error)
      if (allocated(error)) return
      call check(error, 'nodes: ' // to_str(mesh%num_nodes) // &
         ', expected 12 (grid 999 after ENDDATA is not read)', &
            mesh%num_nodes == 12)
      if (allocated(error)) return
      call check(error, 'grid ids in card order', &
            all(mesh%node_tags == tags))
      if (allocated(error)) return
      expected = reshape([0.0_dp, 0.0_dp, 0.0_dp, 0.2_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.2_dp, &
         0.0_dp, 0.0_dp, 0.0_dp, 0.2_dp, 0.1_dp, 0.0_dp, 0.0_dp, 0.1_dp, 0.1_dp, 0.0_dp, &
         0.0_dp, 0.1_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.1_dp, 0.1_dp, 0.0_dp, 0.1_dp, 0.0_dp, &
         0.1_dp, 0.1_dp, 0.5_dp, 0.5_dp, 0.5_dp, 3.0_dp, 3.0_dp, 1.0_dp], [3, 12])
      do k = 1, 12
         do j = 1, 3
            call check_close(error, 'grid ' // to_str(tags(k)) // ' x' // to_str(j), &
               mesh%xyz(j, k), expected(j, k), atol=merge(4.0_dp * epsilon(1.0_dp) * 3.0_dp, &
               0.0_dp, k == 12))
            if (allocated(error)) return
         end do
      end do
      call check(error, 'cards not read: ' // mesh%ignored_cards, &
            index(mesh%ignored_cards, 'PARAM (1)') > 0 .and. &
         index(mesh%ignored_cards, 'EIGRL (1)') > 0 .and. &
         index(mesh%ignored_cards, 'SPC1 (1)') > 0)
   end subroutine test_corner_deck_values

   !> Nastran's G9 (2,4) and G10 (3,4) land in Gmsh's order: every mid-side node of the Tet10 is
   !> the midpoint of the edge Gmsh's numbering gives it (src/mesh/gmsh.f90), exactly.
   subroutine test_tet10_order_geometric(error)
      type(error_t), allocatable, intent(out) :: error
      type(mesh_t) :: mesh
      integer, parameter :: edges(2, 5:10) = reshape([1, 2, 2, 3, 1, 3, 1, 4, 3, 4, 2, 4], [2, 6])
      integer :: m
      call read_mesh_file(deck('corners.bdf'), mesh, error)
      if (allocated(error)) return
      call check(error, 'one Tet10, EID 1, PSOLID 3', &
            mesh%nodes_per_tet == 10 .and. mesh%num_tets() == 1 .and. &
         mesh%tet_tags(1) == 1 .and. mesh%tet_entity(1) == 3)
      if (allocated(error)) return
      do m = 5, 10
         call check(error, &
            'node ' // to_str(m) // ' of the Tet10 is not the midpoint of its Gmsh edge', &
            all(mesh%xyz(:, mesh%tets(m, 1)) == 0.5_dp * &
            (mesh%xyz(:, mesh%tets(edges(1, m), 1)) + mesh%xyz(:, mesh%tets(edges(2, m), 1)))))
         if (allocated(error)) return
      end do
   end subroutine test_tet10_order_geometric

   !> RBE3 101: grids 1 2 (weight 1.0) and 3 (2.5), reference grid 50; RBE2 102: grids 1 THRU 4,
   !> independent 51; PSOLID 3 -> MAT1 17: E 2e11, NU = E / (2 G) - 1 = 0.25, RHO 7.8D3.
   subroutine test_interfaces_and_material(error)
      type(error_t), allocatable, intent(out) :: error
      type(mesh_t) :: mesh
      call read_mesh_file(deck('corners.bdf'), mesh, error)
      if (allocated(error)) return
      call check(error, 'two RBE elements', &
            size(mesh%node_sets) == 2)
      if (allocated(error)) return
      associate (r3 => mesh%node_sets(1), r2 => mesh%node_sets(2))
         call check(error, &
            'RBE3 101 nodes and weights', &
            r3%name == '101' .and. r3%rbe == MPC_RBE3 .and. &
            all(r3%nodes == [1, 2, 3]) .and. all(r3%weights == [1.0_dp, 1.0_dp, 2.5_dp]))
         if (.not. allocated(error)) call check_close(error, 'RBE3 reference x', &
            r3%reference(1), 3.0_dp, atol=12.0_dp * epsilon(1.0_dp))
         if (.not. allocated(error)) call check(error, &
            'RBE2 102: grids 1 THRU 4, reference grid 51', &
            r2%name == '102' .and. &
            r2%rbe == MPC_RBE2 .and. all(r2%nodes == [1, 2, 3, 4]) .and. &
            all(r2%reference == 0.5_dp))
      end associate
      if (allocated(error)) return
      call check(error, 'one physical volume named 3', &
            size(mesh%groups) == 1 .and. mesh%groups(1)%name == '3' .and. &
         mesh%groups(1)%dim == 3)
      if (allocated(error)) return
      call check_close(error, 'E', mesh%materials(1)%young, 2.0e11_dp, rtol=0.0_dp)
      if (.not. allocated(error)) call check_close(error, 'NU from E and G', &
         mesh%materials(1)%poisson, 0.25_dp, rtol=4.0_dp * epsilon(1.0_dp))
      if (.not. allocated(error)) call check_close(error, 'RHO', mesh%materials(1)%density, &
         7800.0_dp, rtol=0.0_dp)
   end subroutine test_interfaces_and_material

   !> extract_body drops the reference grids (no element) and renumbers the interface nodes.
   subroutine test_body_keeps_interfaces(error)
      type(error_t), allocatable, intent(out) :: error
      type(mesh_t) :: mesh, body
      call read_mesh_file(deck('corners.bdf'), mesh, error)
      if (allocated(error)) return
      call extract_body(mesh, ['3'], body, error)
      if (allocated(error)) return
      call check(error, &
         'body of 10 nodes with its two interfaces', &
            body%num_nodes == 10 .and. size(body%node_sets) == 2)
      if (allocated(error)) return
      call check(error, 'interface grids', &
            all(body%node_tags(body%node_sets(1)%nodes) == [1, 2, 3]) .and. &
         all(body%node_tags(body%node_sets(2)%nodes) == [1, 2, 3, 4]))
   end subroutine test_body_keeps_interfaces

   subroutine test_suffixes(error)
      type(error_t), allocatable, intent(out) :: error
      call check(error, &
         'suffixes .bdf .dat .nas .blk (any case)', &
            is_bulk_data_file('a.bdf') .and. is_bulk_data_file('b/c.DAT') .and. &
         is_bulk_data_file('x.nas') .and. is_bulk_data_file('y.blk') .and. &
         .not. is_bulk_data_file('crank.msh') .and. .not. is_bulk_data_file('.bdf'))
   end subroutine test_suffixes

end module test_mesh_bulk_data

program main_mesh_bulk_data
   use ffrf_testing, only: unittest_t, run_suite
   use test_mesh_bulk_data, only: collect_mesh_bulk_data
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_mesh_bulk_data(tests)
   call run_suite('test_mesh_bulk_data', tests)
end program main_mesh_bulk_data
