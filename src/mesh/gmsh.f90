!> Native reader of Gmsh mesh files: MSH 4.1 ASCII, MSH 4.1 binary and MSH 2.2 ASCII
!> (Gmsh reference manual, section "MSH file format"). The format is detected from $MeshFormat.
!>
!> Read: $MeshFormat, $PhysicalNames, $Entities (4.1: the physical tags of every entity),
!> $Nodes, $Elements. Kept element types: 4 Tet4, 11 Tet10, 2 Tri3, 9 Tri6; other known types
!> (15 points, 1 and 8 lines, quads, ...) are skipped, and so are unknown sections ($NodeData,
!> $Periodic, $Comments ...). Volume elements that are not Tet4/Tet10 (hexahedra, prisms,
!> pyramids, higher-order tetrahedra) are counted per entity in `mesh_t%other_volume_elements`:
!> `extract_body` refuses a body whose volumes hold any. An element type number the reader does
!> not know is an error (its node count is unknown). In MSH 2.2 the physical groups come from the
!> (physical, elementary) tags of each element; an element Gmsh wrote once per physical group
!> is kept once. Node tags may have gaps: they map to indices 1..num_nodes (file order) through
!> a direct table when dense, else sorted tags and a binary search.
!>
!> The whole file is read into memory with one stream read and parsed by hand (integers by a
!> digit loop; reals by Clinger's exact fast path, mantissa <= 2**53 and |exponent| <= 22, which
!> is correctly rounded like strtod, else by C strtod, with an internal read as fallback), so
!> ASCII and binary copies of a mesh agree to the 16 digits (%.16g) Gmsh prints. Peak memory is
!> about the file size plus the mesh arrays (~60 MB for a 30 MB Tet10 file).
!>
!> Node order is Gmsh's, unchanged (checked by meshing one tetrahedron with gmsh 4.8.4 -order 2,
!> and as drawn in the Gmsh manual, section "Node ordering"; 1-based here):
!>
!>     Tet10                                    Tri6
!>                 4                             3
!>               ,/|`\                           |`\         edge nodes, Tet10:
!>             ,/  |  `\                         |  `\          5 (1,2)   8 (1,4)
!>           ,8    '.   `10                      6    `5        6 (2,3)   9 (3,4)
!>         ,/       9     `\                     |      `\      7 (1,3)  10 (2,4)
!>       ,/         |       `\                   |        `\    Tri6:
!>      1--------5--'.--------2                  1-----4----2     4 (1,2), 5 (2,3), 6 (1,3)
!>       `\.         |      ,/
!>          `\.      |    ,6
!>             `7.   '. ,/
!>                `\. |/
!>                   `3
!>
!> (CalculiX/Abaqus C3D10 swap nodes 9 and 10 against this: toolchain pitfall 12.)
!> Every message names the file, the section and the line (ASCII) or byte offset (binary).
!>
!> File-level checks (each an FFRF_INPUT_ERROR naming the file and the tag or line): the file is a
!> regular file of at most MAX_MESH_BYTES (else FFRF_IO_ERROR, before it is opened: a FIFO would
!> block); its first bytes are $MeshFormat (checked before it is read whole: a 2 GB file of zeros
!> is refused at once); only its content is read, up to the last byte that is not NUL or blank
!> when that ends a $End... line (NUL padding after it is refused, blanks are not read); every
!> count (nodes, elements, blocks, entities, names) is checked against the bytes left in the
!> content before anything is allocated for it, so that memory stays within a multiple of the
!> content (docs/input.md "Input rules": at most 5x, measured 3.9x for the worst files);
!> header counts and tag ranges must match the data; node and element tags
!> are >= 1; coordinates are finite; ASCII coordinates and element nodes stay on their line (a
!> missing value is reported where it is missing); a physical name appears once per dimension;
!> an element block's type matches its entity's dimension.
module ffrf_mesh_gmsh
   use ffrf_core_whole_file, only: read_whole_file, READ_OPEN_FAILED, READ_NO_MEMORY, &
      READ_FAILED, read_file_head, content_end
   use ffrf_core_error, only: error_t
   use ffrf_mesh_mesh, only: mesh_t
   implicit none
   private
   public :: read_gmsh

   interface
      !> Read the Gmsh mesh `file_name` (MSH 4.1 ASCII or binary, MSH 2.2 ASCII) into `mesh`.
      !> A file without tetrahedra, mixed Tet4/Tet10, an element naming a node that $Nodes does not
      !> list, an unsupported version or any failed file-level check (see above) give an error;
      !> a path that is no regular file or is over MAX_MESH_BYTES gives FFRF_IO_ERROR.
      module subroutine read_gmsh(file_name, mesh, error)
         !> Path of the .msh file
         character(len=*), intent(in) :: file_name
         !> The mesh read
         type(mesh_t), intent(out) :: mesh
         type(error_t), allocatable, intent(out) :: error
      end subroutine read_gmsh
   end interface

end module ffrf_mesh_gmsh
