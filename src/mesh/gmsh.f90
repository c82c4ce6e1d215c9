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

!> Bodies of ffrf_mesh_gmsh: file loading, tokenizer, section parsers, group building.
submodule(ffrf_mesh_gmsh) ffrf_mesh_gmsh_parse
   use, intrinsic :: iso_fortran_env, only: int32
   use, intrinsic :: iso_c_binding, only: c_char, c_double, c_ptr, c_null_char, c_loc, &
      c_associated
   use ffrf_core_kinds, only: dp, ip, i8
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_error, only: fatal_error, FFRF_INPUT_ERROR, FFRF_IO_ERROR
   use ffrf_core_strings, only: to_str, to_lower
   use ffrf_core_posix, only: file_kind, check_input_file, FILE_MISSING
   use ffrf_mesh_mesh, only: physical_group_t, dimension_word, element_type_name
   implicit none

   !> Largest mesh file read, bytes (4 GiB; the lc = 3 mm Tet10 crank, 10^5 nodes, is 11 MB)
   integer(i8), parameter :: MAX_MESH_BYTES = 4_i8 * 1024_i8**3

   !> Exact powers of ten for the fast real parser (10**22 < 2**53 * 2**22 is still exact).
   real(dp), parameter :: powers_of_ten(0:22) = [1.0e0_dp, 1.0e1_dp, 1.0e2_dp, 1.0e3_dp, &
      1.0e4_dp, 1.0e5_dp, 1.0e6_dp, 1.0e7_dp, 1.0e8_dp, 1.0e9_dp, 1.0e10_dp, 1.0e11_dp, &
      1.0e12_dp, 1.0e13_dp, 1.0e14_dp, 1.0e15_dp, 1.0e16_dp, 1.0e17_dp, 1.0e18_dp, 1.0e19_dp, &
      1.0e20_dp, 1.0e21_dp, 1.0e22_dp]
   !> Largest integer every smaller one of which a double holds exactly, 2**53
   integer(i8), parameter :: exact_mantissa = 9007199254740992_i8

   interface
      !> C strtod: correctly rounded, the conversion libgfortran's list-directed read ends in;
      !> `end` points after the last character used.
      function c_strtod(text, end) result(value) bind(c, name='strtod')
         import :: c_char, c_ptr, c_double
         character(kind=c_char), intent(in) :: text(*)
         type(c_ptr), intent(out) :: end
         real(c_double) :: value
      end function c_strtod
   end interface

   !> The whole file in memory and the read position in it.
   type :: cursor_t
      !> File contents
      character(len=:), allocatable :: text
      !> Next byte to read
      integer(i8) :: pos = 1
      !> Line of `pos` (meaningful in ASCII parts)
      integer(i8) :: line = 1
      !> Inside binary data (messages give byte offsets, not lines)
      logical :: binary = .false.
      !> For messages
      character(len=:), allocatable :: file_name
      !> Section being read, for messages ("$Nodes")
      character(len=:), allocatable :: section
   end type cursor_t

   !> Node tag -> node index: a direct table when the tags are dense, else sorted tags.
   type :: tag_map_t
      !> Direct table in use
      logical :: dense = .true.
      !> Smallest tag
      integer(i8) :: min_tag = 0
      !> Largest tag
      integer(i8) :: max_tag = -1
      !> Index of tag min_tag + k - 1, 0 if absent (dense)
      integer(ip), allocatable :: direct(:)
      !> Tags ascending (sparse)
      integer(i8), allocatable :: sorted_tags(:)
      !> Node index of sorted_tags(k) (sparse)
      integer(ip), allocatable :: sorted_index(:)
   end type tag_map_t

   !> Elements of one kind (tetrahedra or triangles) while reading; grown by doubling.
   type :: element_list_t
      !> "Tet" or "Tri", for messages
      character(len=3) :: kind = ''
      !> 4/10 or 3/6 once the first element is seen, 0 before
      integer(ip) :: nodes_per_element = 0
      !> Elements stored
      integer(ip) :: count = 0
      !> (nodes_per_element, capacity) node indices
      integer(ip), allocatable :: nodes(:, :)
      !> Gmsh element tags
      integer(i8), allocatable :: tags(:)
      !> Entity tag of each element
      integer(ip), allocatable :: entity(:)
   end type element_list_t

   !> Everything gathered while reading one file.
   type :: reader_t
      type(cursor_t) :: c
      !> "4.1" or "2.2"
      character(len=3) :: version = ''
      !> Binary file (MSH 4.1 file type 1)
      logical :: binary_file = .false.
      !> $Nodes and $Elements seen
      logical :: have_nodes = .false., have_elements = .false.
      !> $PhysicalNames: dim, tag, name of each (entities unused)
      type(physical_group_t), allocatable :: names(:)
      !> (dim, physical tag, entity tag) triples, consecutive repeats dropped
      integer(ip), allocatable :: links(:, :)
      !> Triples stored in `links`
      integer(ip) :: num_links = 0
      !> Number of nodes
      integer(ip) :: num_nodes = 0
      !> (3, num_nodes) coordinates
      real(dp), allocatable :: xyz(:, :)
      !> Gmsh tag of each node
      integer(i8), allocatable :: node_tags(:)
      type(tag_map_t) :: map
      type(element_list_t) :: tets, tris
      !> Elements of the skipped types
      integer(i8) :: num_skipped = 0
      !> Skipped volume elements: (entity, type, count, first element tag) per run of a block
      integer(i8), allocatable :: other_volume(:, :)
      !> Columns stored in `other_volume`
      integer(ip) :: num_other_volume = 0
      !> Smallest and largest element tag seen (MSH 4.1 header check)
      integer(i8) :: min_element_tag = 0, max_element_tag = 0
   end type reader_t

contains

   module subroutine read_gmsh(file_name, mesh, error)
      character(len=*), intent(in) :: file_name
      type(mesh_t), intent(out) :: mesh
      type(error_t), allocatable, intent(out) :: error
      type(reader_t) :: r
      character(len=:), allocatable :: word
      logical :: seen_entities

      seen_entities = .false.
      r%tets%kind = 'Tet'
      r%tris%kind = 'Tri'
      call load_file(file_name, r%c, error)
      if (allocated(error)) return
      call read_mesh_format(r, error)
      if (allocated(error)) return
      do
         call skip_space(r%c%text, r%c%pos, r%c%line)
         if (r%c%pos > len(r%c%text, kind=i8)) exit
         r%c%section = 'after the last section'
         word = next_word(r%c)
         if (word(1:1) /= '$') then
            call syntax_error(r%c, 'expected a section header such as $Nodes', error)
            return
         end if
         r%c%section = word
         select case (word)
         case ('$PhysicalNames')
            if (allocated(r%names)) then
               call location_error(r%c, 'a second $PhysicalNames section; ffrf reads one', &
                  error)
            else
               call read_physical_names(r, error)
            end if
         case ('$Entities')
            if (seen_entities) then
               call location_error(r%c, 'a second $Entities section; ffrf reads one', error)
            else if (r%version == '4.1') then
               seen_entities = .true.
               call read_entities(r, error)
            else
               call skip_section(r%c, error)
            end if
         case ('$Nodes')
            if (r%have_nodes) then
               call location_error(r%c, 'a second $Nodes section; ffrf reads one', error)
            else if (r%version == '4.1') then
               call read_nodes_41(r, error)
            else
               call read_nodes_22(r, error)
            end if
         case ('$Elements')
            if (r%have_elements) then
               call location_error(r%c, 'a second $Elements section; ffrf reads one', error)
            else if (.not. r%have_nodes) then
               call location_error(r%c, '$Elements comes before $Nodes', error)
            else if (r%version == '4.1') then
               call read_elements_41(r, error)
            else
               call read_elements_22(r, error)
            end if
         case ('$PartitionedEntities')
            call location_error(r%c, 'partitioned meshes are not supported: save the mesh ' // &
               'without partitioning (no -part)', error)
         case ('$MeshFormat')
            call location_error(r%c, 'a second $MeshFormat section', error)
         case default
            call skip_section(r%c, error)
         end select
         if (allocated(error)) return
      end do
      r%c%section = 'end of file'
      if (.not. (r%have_nodes .and. r%have_elements)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // file_name // ''': no $Nodes ' // &
            'or no $Elements section; is it a mesh (gmsh -3) and not a geometry only?')
         return
      end if
      call build_mesh(r, mesh, error)
   end subroutine read_gmsh

   ! ------------------------------------------------------------------------------------------
   ! Sections
   ! ------------------------------------------------------------------------------------------

   !> $MeshFormat: "4.1 0 8" (ASCII) or "4.1 1 8" plus the int 1 in this machine's byte order.
   subroutine read_mesh_format(r, error)
      type(reader_t), intent(inout) :: r
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: word
      integer(i8) :: file_type, data_size, one

      r%c%section = 'start of file'
      word = next_word(r%c)
      if (word /= '$MeshFormat') then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // r%c%file_name // ''' is not ' // &
            'a Gmsh MSH file: it does not start with $MeshFormat')
         return
      end if
      r%c%section = '$MeshFormat'
      word = next_word(r%c)
      if (word /= '4.1' .and. word /= '2.2') then
         call location_error(r%c, 'MSH version ' // word // ' is not supported; ffrf reads ' // &
            'MSH 4.1 (ASCII or binary) and MSH 2.2 (ASCII): re-save with gmsh -format msh41', error)
         return
      end if
      r%version = word
      call read_int(r%c, 'file type', file_type, error)
      if (allocated(error)) return
      call read_int(r%c, 'data size', data_size, error)
      if (allocated(error)) return
      if (data_size /= 8) then
         call location_error(r%c, 'data size ' // to_str(data_size) // ' (sizeof(size_t)) ' // &
            'is not supported, only 8', error)
         return
      end if
      select case (file_type)
      case (0)
      case (1)
         if (r%version /= '4.1') then
            call location_error(r%c, 'binary MSH ' // r%version // ' is not supported: save ' // &
               'it as ASCII (-format msh22) or as MSH 4.1 (-format msh41 [-bin])', error)
            return
         end if
         call start_binary(r%c, error)
         if (allocated(error)) return
         call binary_int(r%c, 'the endianness check int 1', one, error)
         if (allocated(error)) return
         r%c%binary = .false.
         r%binary_file = .true.
         if (one /= 1) then
            call location_error(r%c, 'binary file written with the other byte order (the ' // &
               'int 1 reads as ' // to_str(one) // '); re-save it on this machine or as ASCII', &
               error)
            return
         end if
      case default
         call location_error(r%c, 'file type ' // to_str(file_type) // ' is neither 0 (ASCII) ' // &
            'nor 1 (binary)', error)
         return
      end select
      call expect_end(r%c, error)
   end subroutine read_mesh_format

   !> $PhysicalNames (ASCII also in binary files): count, then "dim tag "name"" lines.
   subroutine read_physical_names(r, error)
      type(reader_t), intent(inout) :: r
      type(error_t), allocatable, intent(out) :: error
      integer(ip) :: num, i, j
      integer(i8) :: value, closing
      character(len=:), allocatable :: problem

      call read_count(r%c, 'number of physical names', num, error)
      if (allocated(error)) return
      ! dim, blank, tag, blank, two quotes, line end: 7 bytes at least
      call check_count_fits(r%c, 'number of physical names', int(num, i8), 7_i8, error)
      if (allocated(error)) return
      allocate (r%names(num))
      do i = 1, num
         call read_int(r%c, 'dimension of a physical name', value, error)
         if (allocated(error)) return
         r%names(i)%dim = int(value, ip)
         call read_int(r%c, 'tag of a physical name', value, error)
         if (allocated(error)) return
         r%names(i)%tag = int(value, ip)
         call skip_space(r%c%text, r%c%pos, r%c%line)
         closing = 0
         if (r%c%pos <= len(r%c%text, kind=i8)) then
            if (r%c%text(r%c%pos:r%c%pos) == '"') closing = index(r%c%text(r%c%pos + 1:), '"', &
               kind=i8)
         end if
         if (closing == 0) then
            call syntax_error(r%c, 'expected a quoted physical name', error)
            return
         end if
         r%names(i)%name = r%c%text(r%c%pos + 1:r%c%pos + closing - 1)
         if (scan(r%names(i)%name, achar(10) // achar(13) // achar(9)) > 0) then
            call location_error(r%c, 'the name of physical group ' // to_str(r%names(i)%tag) // &
               ' holds a line break or tab; write it on one line', error)
            return
         end if
         r%c%pos = r%c%pos + closing + 1
      end do
      call expect_end(r%c, error)
      if (allocated(error)) return
      ! One name per (dimension, tag) and one tag per (dimension, name): of two groups with one
      ! name, the first one found would be used silently wherever the name is given.
      do i = 2, num
         do j = 1, i - 1
            if (r%names(i)%dim /= r%names(j)%dim) cycle
            ! names are compared exactly, but a case's names are blank-padded strings: two
            ! names equal up to trailing blanks could not be told apart from a case
            if (r%names(i)%name == r%names(j)%name) then
               if (len(r%names(i)%name) == len(r%names(j)%name)) then
                  problem = 'are named ''' // r%names(i)%name // ''''
               else
                  problem = 'are named ''' // r%names(j)%name // ''' and ''' // &
                     r%names(i)%name // ''', equal up to trailing blanks'
               end if
               call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // r%c%file_name // &
                  ''': $PhysicalNames: two physical ' // dimension_word(r%names(i)%dim) // &
                  's ' // problem // ' (tags ' // to_str(r%names(j)%tag) // ' and ' // &
                  to_str(r%names(i)%tag) // '); give each physical group its own name in ' // &
                  'the .geo')
               return
            else if (r%names(i)%tag == r%names(j)%tag) then
               call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // r%c%file_name // &
                  ''': $PhysicalNames: physical ' // dimension_word(r%names(i)%dim) // ' ' // &
                  to_str(r%names(i)%tag) // ' has two names, ''' // r%names(j)%name // &
                  ''' and ''' // r%names(i)%name // '''')
               return
            end if
         end do
      end do
   end subroutine read_physical_names

   !> $Entities (4.1): points, curves, surfaces, volumes, each with its physical tags.
   subroutine read_entities(r, error)
      type(reader_t), intent(inout) :: r
      type(error_t), allocatable, intent(out) :: error
      integer(i8) :: counts(0:3), tag, num_physical, physical, num_bounding, k, j
      integer(ip) :: dim
      logical :: binary
      real(dp) :: ignored

      binary = r%binary_file
      if (binary) call start_binary(r%c, error)
      if (allocated(error)) return
      do dim = 0, 3
         call read_size(r%c, binary, 'number of ' // dimension_word(dim) // ' entities', &
            counts(dim), error)
         if (allocated(error)) return
         ! an entity takes a tag, 3 or 6 coordinates and a count: 5 tokens of 2 bytes at least
         ! (ASCII), 4 + 3 * 8 + 8 bytes (binary)
         call check_count_fits(r%c, 'number of ' // dimension_word(dim) // ' entities', &
            counts(dim), merge(36_i8, 10_i8, binary), error)
         if (allocated(error)) return
      end do
      call check_count_fits(r%c, 'number of entities', sum(counts), merge(36_i8, 10_i8, binary), &
         error)
      if (allocated(error)) return
      do dim = 0, 3
         do k = 1, counts(dim)
            call read_tag(r%c, binary, dimension_word(dim) // ' entity tag', tag, error)
            if (allocated(error)) return
            ! Points: x y z; curves, surfaces, volumes: bounding box min x y z, max x y z.
            do j = 1, merge(3, 6, dim == 0)
               call read_real(r%c, binary, 'entity coordinate', ignored, error)
               if (allocated(error)) return
            end do
            call read_size(r%c, binary, 'number of physical tags', num_physical, error)
            if (allocated(error)) return
            do j = 1, num_physical
               call read_tag(r%c, binary, 'physical tag', physical, error)
               if (allocated(error)) return
               call add_link(r, dim, int(physical, ip), int(tag, ip))
            end do
            if (dim == 0) cycle
            call read_size(r%c, binary, 'number of bounding entities', num_bounding, error)
            if (allocated(error)) return
            do j = 1, num_bounding
               call read_tag(r%c, binary, 'bounding entity tag', physical, error)
               if (allocated(error)) return
            end do
         end do
      end do
      r%c%binary = .false.
      call expect_end(r%c, error)
   end subroutine read_entities

   !> $Nodes (4.1): blocks of (entityDim, entityTag, parametric, count), tags, coordinates.
   !> The header's node count and tag range must match the blocks.
   subroutine read_nodes_41(r, error)
      type(reader_t), intent(inout) :: r
      type(error_t), allocatable, intent(out) :: error
      integer(i8) :: num_blocks, num_nodes, block, dim, entity, parametric, n, first, k, i
      integer(i8) :: values_per_node, min_tag, max_tag
      real(dp), allocatable :: values(:)
      logical :: binary

      binary = r%binary_file
      if (binary) call start_binary(r%c, error)
      if (allocated(error)) return
      call read_size(r%c, binary, 'number of node blocks', num_blocks, error)
      if (.not. allocated(error)) call read_size(r%c, binary, 'number of nodes', num_nodes, error)
      if (.not. allocated(error)) call read_size(r%c, binary, 'smallest node tag', min_tag, error)
      if (.not. allocated(error)) call read_size(r%c, binary, 'largest node tag', max_tag, error)
      if (allocated(error)) return
      ! A node takes a tag and three coordinates: 4 tokens of 2 bytes at least (ASCII), 8 + 3 * 8
      ! bytes (binary); a block header 4 tokens (ASCII), 3 ints and a size_t (binary).
      call check_count_fits(r%c, 'number of nodes', num_nodes, merge(32_i8, 8_i8, binary), error)
      if (allocated(error)) return
      call check_count_fits(r%c, 'number of node blocks', num_blocks, merge(20_i8, 8_i8, binary), &
         error)
      if (allocated(error)) return
      call allocate_nodes(r, num_nodes, error)
      if (allocated(error)) return
      first = 0
      do block = 1, num_blocks
         call read_tag(r%c, binary, 'entity dimension of a node block', dim, error)
         if (.not. allocated(error)) call read_tag(r%c, binary, 'entity tag', entity, error)
         if (.not. allocated(error)) call read_tag(r%c, binary, 'parametric flag', parametric, &
            error)
         if (.not. allocated(error)) call read_size(r%c, binary, 'nodes in block', n, error)
         if (allocated(error)) return
         if (first + n > num_nodes) then
            call location_error(r%c, 'node blocks hold more nodes than the ' // &
               to_str(num_nodes) // ' announced in the section header', error)
            return
         end if
         values_per_node = 3
         if (parametric /= 0) values_per_node = 3 + max(0_i8, min(3_i8, dim))
         if (binary) then
            call binary_take(r%c, 8 * n, 'node tags', k, error)
            if (allocated(error)) return
            if (n > 0) r%node_tags(first + 1:first + n) = transfer(r%c%text(k:k + 8 * n - 1), &
               0_i8, int(n))
            do i = first + 1, first + n
               if (r%node_tags(i) < 1) then
                  r%c%pos = k + 8 * (i - first - 1)
                  call node_tag_error(r%c, r%node_tags(i), error)
                  return
               end if
            end do
            call binary_take(r%c, 8 * n * values_per_node, 'node coordinates', k, error)
            if (allocated(error)) return
            if (n > 0) then
               values = transfer(r%c%text(k:k + 8 * n * values_per_node - 1), 0.0_dp, &
                  int(n * values_per_node))
               do i = 1, n
                  r%xyz(:, first + i) = values((i - 1) * values_per_node + 1: &
                     (i - 1) * values_per_node + 3)
               end do
            end if
         else
            call read_node_block_ascii(r, first, n, values_per_node, error)
            if (allocated(error)) return
         end if
         first = first + n
      end do
      if (first /= num_nodes) then
         call location_error(r%c, 'node blocks hold ' // to_str(first) // ' nodes, the ' // &
            'header announced ' // to_str(num_nodes), error)
         return
      end if
      r%c%binary = .false.
      call check_coordinates(r, error)
      if (allocated(error)) return
      call build_tag_map(r, error)
      if (allocated(error)) return
      if (num_nodes > 0 .and. (r%map%min_tag /= min_tag .or. r%map%max_tag /= max_tag)) then
         call location_error(r%c, 'the header gives node tags ' // to_str(min_tag) // '..' // &
            to_str(max_tag) // ', the nodes have tags ' // to_str(r%map%min_tag) // '..' // &
            to_str(r%map%max_tag), error)
         return
      end if
      r%have_nodes = .true.
      call expect_end(r%c, error)
   end subroutine read_nodes_41

   !> Nodes first+1 .. first+n of an ASCII 4.1 block: n tags, then n lines of coordinates
   !> (x y z and, for parametric nodes, the parametric coordinates). A value missing from a
   !> line is reported on that line, not where the shifted values run out.
   subroutine read_node_block_ascii(r, first, n, values_per_node, error)
      type(reader_t), intent(inout) :: r
      integer(i8), intent(in) :: first, n, values_per_node
      type(error_t), allocatable, intent(out) :: error
      integer(i8) :: i, j, line
      real(dp) :: value
      logical :: ok
      do i = first + 1, first + n
         call scan_int(r%c%text, r%c%pos, r%c%line, r%node_tags(i), ok)
         if (.not. ok) then
            call missing_item_error(r%c, 'a node tag', 'a node block announces ' // to_str(n) // &
               ' nodes, the section ends after ' // to_str(i - first - 1), error)
            return
         end if
         if (r%node_tags(i) < 1) then
            call node_tag_error(r%c, r%node_tags(i), error)
            return
         end if
      end do
      do i = first + 1, first + n
         line = -1
         do j = 1, values_per_node
            call scan_real(r%c%text, r%c%pos, r%c%line, value, ok)
            if (j == 1) then
               line = r%c%line
            else if (r%c%line /= line) then
               call line_error(r%c, line, 'node ' // to_str(r%node_tags(i)) // ': the line ' // &
                  'holds ' // to_str(j - 1) // ' of the node''s ' // to_str(values_per_node) // &
                  ' coordinates; one is missing', error)
               return
            end if
            if (.not. ok) then
               call coordinate_error(r%c, r%node_tags(i), error)
               return
            end if
            if (j <= 3) r%xyz(j, i) = value
         end do
         call skip_line_end(r%c%text, r%c%pos, r%c%line, ok)
         if (.not. ok) then
            call syntax_error(r%c, 'expected the end of the line after the ' // &
               to_str(values_per_node) // ' coordinates of node ' // to_str(r%node_tags(i)), error)
            return
         end if
      end do
   end subroutine read_node_block_ascii

   !> $Nodes (2.2): count, then "tag x y z" lines.
   subroutine read_nodes_22(r, error)
      type(reader_t), intent(inout) :: r
      type(error_t), allocatable, intent(out) :: error
      integer(ip) :: num_nodes, i, j
      integer(i8) :: line
      logical :: ok

      call read_count(r%c, 'number of nodes', num_nodes, error)
      if (allocated(error)) return
      call check_count_fits(r%c, 'number of nodes', int(num_nodes, i8), 8_i8, error)
      if (allocated(error)) return
      call allocate_nodes(r, int(num_nodes, i8), error)
      if (allocated(error)) return
      do i = 1, num_nodes
         call scan_int(r%c%text, r%c%pos, r%c%line, r%node_tags(i), ok)
         if (.not. ok) then
            call missing_item_error(r%c, 'a node tag', '$Nodes announces ' // &
               to_str(num_nodes) // ' nodes, the section ends after ' // to_str(i - 1), error)
            return
         end if
         if (r%node_tags(i) < 1) then
            call node_tag_error(r%c, r%node_tags(i), error)
            return
         end if
         line = r%c%line
         do j = 1, 3
            call scan_real(r%c%text, r%c%pos, r%c%line, r%xyz(j, i), ok)
            if (r%c%line /= line) then
               call line_error(r%c, line, 'node ' // to_str(r%node_tags(i)) // ': the line ' // &
                  'holds ' // to_str(j - 1) // ' of the node''s 3 coordinates; one is missing', &
                  error)
               return
            end if
            if (.not. ok) then
               call coordinate_error(r%c, r%node_tags(i), error)
               return
            end if
         end do
         call skip_line_end(r%c%text, r%c%pos, r%c%line, ok)
         if (.not. ok) then
            call syntax_error(r%c, 'expected the end of the line after the coordinates of ' // &
               'node ' // to_str(r%node_tags(i)), error)
            return
         end if
      end do
      call check_coordinates(r, error)
      if (allocated(error)) return
      call build_tag_map(r, error)
      if (allocated(error)) return
      r%have_nodes = .true.
      call expect_end(r%c, error)
   end subroutine read_nodes_22

   !> $Elements (4.1): blocks of (entityDim, entityTag, type, count), then per element its tag
   !> and node tags (one line each in ASCII). The header's element count and tag range must
   !> match the blocks, every type must be known and of its entity's dimension.
   subroutine read_elements_41(r, error)
      type(reader_t), intent(inout) :: r
      type(error_t), allocatable, intent(out) :: error
      integer(i8) :: num_blocks, num_elements, block, dim, entity, element_type, n, k, e, j
      integer(i8), allocatable :: values(:)
      integer(i8) :: node_tag, min_tag, max_tag, total, tag, first_tag, data_start
      integer(ip) :: nodes_per_element, index
      logical :: binary, ok

      binary = r%binary_file
      if (binary) call start_binary(r%c, error)
      if (allocated(error)) return
      call read_size(r%c, binary, 'number of element blocks', num_blocks, error)
      if (.not. allocated(error)) call read_size(r%c, binary, 'number of elements', &
         num_elements, error)
      if (.not. allocated(error)) call read_size(r%c, binary, 'smallest element tag', min_tag, &
         error)
      if (.not. allocated(error)) call read_size(r%c, binary, 'largest element tag', max_tag, &
         error)
      if (allocated(error)) return
      call check_count_fits(r%c, 'number of elements', num_elements, merge(16_i8, 4_i8, binary), &
         error)
      if (allocated(error)) return
      call check_count_fits(r%c, 'number of element blocks', num_blocks, &
         merge(20_i8, 8_i8, binary), error)
      if (allocated(error)) return
      total = 0
      r%min_element_tag = huge(0_i8)
      r%max_element_tag = -huge(0_i8)
      do block = 1, num_blocks
         call read_tag(r%c, binary, 'entity dimension of an element block', dim, error)
         if (.not. allocated(error)) call read_tag(r%c, binary, 'entity tag', entity, error)
         if (.not. allocated(error)) call read_tag(r%c, binary, 'element type', element_type, &
            error)
         if (.not. allocated(error)) call read_size(r%c, binary, 'elements in block', n, error)
         if (allocated(error)) return
         if (n > huge(0_ip)) then
            call location_error(r%c, to_str(n) // ' elements in one block: more than ffrf''s ' // &
               '32-bit indices hold', error)
            return
         end if
         if (element_type < 1 .or. element_type > huge(0_ip)) then
            nodes_per_element = -1
         else
            nodes_per_element = nodes_of_type(int(element_type, ip))
         end if
         if (nodes_per_element < 0) then
            call unknown_type_error(r%c, element_type, 'the element block of ' // &
               dimension_word(int(max(0_i8, min(3_i8, dim)), ip)) // ' entity ' // &
               to_str(entity), error)
            return
         end if
         if (dim_of_type(int(element_type, ip)) /= dim) then
            call location_error(r%c, 'an element block of entity dimension ' // to_str(dim) // &
               ' (entity ' // to_str(entity) // ') holds ' // type_name(element_type) // &
               ' elements, which have dimension ' // &
               to_str(dim_of_type(int(element_type, ip))), error)
            return
         end if
         call check_count_fits(r%c, 'elements in block', n, &
            merge(8_i8, 2_i8, binary) * (nodes_per_element + 1), error)
         if (allocated(error)) return
         total = total + n
         if (total > num_elements) then
            call location_error(r%c, 'element blocks hold more elements than the ' // &
               to_str(num_elements) // ' announced in the section header', error)
            return
         end if
         if (.not. binary) then
            call skip_line_end(r%c%text, r%c%pos, r%c%line, ok)
            if (.not. ok) then
               call syntax_error(r%c, 'expected the end of the line after the element block ' // &
                  'header', error)
               return
            end if
         end if
         select case (element_type)
         case (4, 11, 2, 9)
            if (binary) then
               call binary_take(r%c, 8 * n * (nodes_per_element + 1), 'element data', k, error)
               if (allocated(error)) return
               if (n == 0) cycle
               values = transfer(r%c%text(k:k + 8 * n * (nodes_per_element + 1) - 1), 0_i8, &
                  int(n * (nodes_per_element + 1)))
               data_start = k
            end if
            do e = 1, n
               if (element_type == 4 .or. element_type == 11) then
                  call start_element(r%c, r%tets, nodes_per_element, int(n - e + 1, ip), error)
               else
                  call start_element(r%c, r%tris, nodes_per_element, int(n - e + 1, ip), error)
               end if
               if (allocated(error)) return
               if (binary) then
                  k = (e - 1) * (nodes_per_element + 1)
                  if (values(k + 1) < 1) then
                     r%c%pos = data_start + 8 * k
                     call element_tag_error(r%c, values(k + 1), error)
                     return
                  end if
                  do j = 1, nodes_per_element
                     node_tag = values(k + 1 + j)
                     index = node_index(r%map, node_tag)
                     if (index == 0) then
                        call missing_node_error(r%c, values(k + 1), element_type, node_tag, error)
                        return
                     end if
                     call store_node(r, element_type, int(j, ip), index)
                  end do
                  call finish_element(r, element_type, values(k + 1), int(entity, ip))
               else
                  call read_element_record(r, element_type, nodes_per_element, int(entity, ip), &
                     -1_i8, error)
                  if (allocated(error)) return
               end if
            end do
         case default
            r%num_skipped = r%num_skipped + n
            first_tag = 0
            if (binary) then
               call binary_take(r%c, 8 * n * (nodes_per_element + 1), 'element data', k, error)
               if (allocated(error)) return
            end if
            do e = 1, n
               if (binary) then
                  j = k + 8 * (e - 1) * (nodes_per_element + 1)
                  tag = transfer(r%c%text(j:j + 7), 0_i8)
                  if (tag < 1) r%c%pos = j
               else
                  call scan_int(r%c%text, r%c%pos, r%c%line, tag, ok)
                  if (.not. ok) then
                     call missing_item_error(r%c, 'an element tag', 'the block announces ' // &
                        to_str(n) // ' elements, the section ends after ' // to_str(e - 1), &
                        error)
                     return
                  end if
                  call skip_line(r%c)
               end if
               if (tag < 1) then
                  call element_tag_error(r%c, tag, error)
                  return
               end if
               if (e == 1) first_tag = tag
               r%min_element_tag = min(r%min_element_tag, tag)
               r%max_element_tag = max(r%max_element_tag, tag)
            end do
            if (dim == 3 .and. n > 0) call add_other_volume(r, entity, element_type, n, first_tag)
         end select
      end do
      if (total /= num_elements) then
         call location_error(r%c, 'element blocks hold ' // to_str(total) // ' elements, the ' // &
            'header announced ' // to_str(num_elements), error)
         return
      end if
      if (total > 0 .and. (r%min_element_tag /= min_tag .or. r%max_element_tag /= max_tag)) then
         call location_error(r%c, 'the header gives element tags ' // to_str(min_tag) // '..' // &
            to_str(max_tag) // ', the elements have tags ' // to_str(r%min_element_tag) // &
            '..' // to_str(r%max_element_tag), error)
         return
      end if
      r%c%binary = .false.
      r%have_elements = .true.
      call expect_end(r%c, error)
   end subroutine read_elements_41

   !> $Elements (2.2): count, then "tag type num_tags tags... nodes..." lines; the first tag is
   !> the physical group (0: none), the second the elementary entity.
   subroutine read_elements_22(r, error)
      type(reader_t), intent(inout) :: r
      type(error_t), allocatable, intent(out) :: error
      integer(ip) :: num_elements, e, nodes_per_element, dim
      integer(i8) :: tag, element_type, num_tags, value, physical, elementary, j
      logical :: ok

      call read_count(r%c, 'number of elements', num_elements, error)
      if (allocated(error)) return
      call check_count_fits(r%c, 'number of elements', int(num_elements, i8), 8_i8, error)
      if (allocated(error)) return
      do e = 1, num_elements
         call skip_space(r%c%text, r%c%pos, r%c%line)
         if (at_section_end(r%c)) then
            call location_error(r%c, '$Elements announces ' // to_str(num_elements) // &
               ' elements, the section ends after ' // to_str(e - 1), error)
            return
         end if
         call read_int(r%c, 'element tag', tag, error)
         if (.not. allocated(error)) call read_int(r%c, 'element type', element_type, error)
         if (.not. allocated(error)) call read_int(r%c, 'number of tags', num_tags, error)
         if (allocated(error)) return
         if (tag < 1) then
            call element_tag_error(r%c, tag, error)
            return
         end if
         physical = 0
         elementary = 0
         do j = 1, num_tags
            call scan_int(r%c%text, r%c%pos, r%c%line, value, ok)
            if (.not. ok) then
               call syntax_error(r%c, 'expected a tag of element ' // to_str(tag), error)
               return
            end if
            if (j == 1) physical = value
            if (j == 2) elementary = value
         end do
         if (element_type < 1 .or. element_type > huge(0_ip)) then
            nodes_per_element = -1
         else
            nodes_per_element = nodes_of_type(int(element_type, ip))
         end if
         if (nodes_per_element < 0) then
            call unknown_type_error(r%c, element_type, 'element ' // to_str(tag), error)
            return
         end if
         dim = dim_of_type(int(element_type, ip))
         if (physical /= 0) call add_link(r, dim, int(physical, ip), int(elementary, ip))
         select case (element_type)
         case (4, 11, 2, 9)
            if (element_type == 4 .or. element_type == 11) then
               call start_element(r%c, r%tets, nodes_per_element, 1_ip, error)
            else
               call start_element(r%c, r%tris, nodes_per_element, 1_ip, error)
            end if
            if (allocated(error)) return
            call read_element_record(r, element_type, nodes_per_element, int(elementary, ip), &
               tag, error)
            if (allocated(error)) return
         case default
            r%num_skipped = r%num_skipped + 1
            if (dim == 3) call add_other_volume(r, elementary, element_type, 1_i8, tag)
            call skip_line(r%c)
         end select
      end do
      r%have_elements = .true.
      call expect_end(r%c, error)
   end subroutine read_elements_22

   !> Skip an unknown section up to its $End line.
   subroutine skip_section(c, error)
      type(cursor_t), intent(inout) :: c
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: marker
      integer(i8) :: found, p
      marker = '$End' // c%section(2:)
      found = index(c%text(c%pos:), marker, kind=i8)
      if (found == 0) then
         call location_error(c, 'no ' // marker // ' closes the section', error)
         return
      end if
      do p = c%pos, c%pos + found - 2
         if (c%text(p:p) == achar(10)) c%line = c%line + 1
      end do
      c%pos = c%pos + found - 1 + len(marker)
   end subroutine skip_section

   ! ------------------------------------------------------------------------------------------
   ! Nodes, elements, groups
   ! ------------------------------------------------------------------------------------------

   !> Room for `num_nodes` nodes.
   subroutine allocate_nodes(r, num_nodes, error)
      type(reader_t), intent(inout) :: r
      integer(i8), intent(in) :: num_nodes
      type(error_t), allocatable, intent(out) :: error
      integer :: stat
      if (num_nodes < 0 .or. num_nodes > huge(0_ip)) then
         call location_error(r%c, 'number of nodes ' // to_str(num_nodes) // ' out of range', &
            error)
         return
      end if
      r%num_nodes = int(num_nodes, ip)
      allocate (r%xyz(3, r%num_nodes), r%node_tags(r%num_nodes), stat=stat)
      if (stat /= 0) call location_error(r%c, 'out of memory for ' // to_str(num_nodes) // &
         ' nodes', error)
   end subroutine allocate_nodes

   !> Map node tags to indices: a direct table when max - min + 1 <= 2 n + 1024, else sorted
   !> tags for a binary search. Duplicate tags are an error.
   subroutine build_tag_map(r, error)
      type(reader_t), intent(inout) :: r
      type(error_t), allocatable, intent(out) :: error
      integer(ip), allocatable :: perm(:)
      integer(i8) :: span
      integer(ip) :: i, stat
      type(tag_map_t) :: map

      if (r%num_nodes == 0) then
         r%map = map
         allocate (r%map%direct(0))
         return
      end if
      map%min_tag = minval(r%node_tags)
      map%max_tag = maxval(r%node_tags)
      span = map%max_tag - map%min_tag + 1
      map%dense = span <= 2_i8 * r%num_nodes + 1024_i8
      if (map%dense) then
         allocate (map%direct(span), stat=stat)
         if (stat /= 0) then
            call location_error(r%c, 'out of memory for the node tag table', error)
            return
         end if
         map%direct = 0
         do i = 1, r%num_nodes
            if (map%direct(r%node_tags(i) - map%min_tag + 1) /= 0) then
               call duplicate_tag_error(r%c, r%node_tags(i), error)
               return
            end if
            map%direct(r%node_tags(i) - map%min_tag + 1) = i
         end do
      else
         if (all(r%node_tags(2:) > r%node_tags(:r%num_nodes - 1))) then
            perm = [(i, i=1, r%num_nodes)]
         else
            call sort_tags(r%node_tags, perm)
         end if
         map%sorted_tags = r%node_tags(perm)
         map%sorted_index = perm
         do i = 2, r%num_nodes
            if (map%sorted_tags(i) == map%sorted_tags(i - 1)) then
               call duplicate_tag_error(r%c, map%sorted_tags(i), error)
               return
            end if
         end do
      end if
      r%map = map
   end subroutine build_tag_map

   !> Index of node `tag`, 0 if no node has it.
   pure function node_index(map, tag) result(index)
      type(tag_map_t), intent(in) :: map
      integer(i8), intent(in) :: tag
      integer(ip) :: index
      integer(ip) :: low, high, mid
      index = 0
      if (tag < map%min_tag .or. tag > map%max_tag) return
      if (map%dense) then
         index = map%direct(tag - map%min_tag + 1)
         return
      end if
      low = 1
      high = size(map%sorted_tags, kind=ip)
      do while (low <= high)
         mid = low + (high - low) / 2
         if (map%sorted_tags(mid) == tag) then
            index = map%sorted_index(mid)
            return
         else if (map%sorted_tags(mid) < tag) then
            low = mid + 1
         else
            high = mid - 1
         end if
      end do
   end function node_index

   !> Check the element order of `list` (no Tet4 with Tet10) and make room for `remaining` more.
   subroutine start_element(c, list, nodes_per_element, remaining, error)
      type(cursor_t), intent(in) :: c
      type(element_list_t), intent(inout) :: list
      integer(ip), intent(in) :: nodes_per_element
      !> Elements still to come in this block (room is made for all at once)
      integer(ip), intent(in) :: remaining
      type(error_t), allocatable, intent(out) :: error
      integer(ip), allocatable :: nodes(:, :), entity(:)
      integer(i8), allocatable :: tags(:)
      integer(i8) :: capacity
      integer :: stat

      if (list%nodes_per_element == 0) then
         list%nodes_per_element = nodes_per_element
      else if (list%nodes_per_element /= nodes_per_element) then
         call location_error(c, 'the mesh mixes ' // list%kind // &
            to_str(list%nodes_per_element) // ' and ' // list%kind // to_str(nodes_per_element) // &
            ' elements; ffrf needs one element order per mesh: mesh all volumes with the same ' // &
            '-order', error)
         return
      end if
      if (allocated(list%tags)) then
         if (size(list%tags, kind=i8) > list%count) return
         capacity = max(int(list%count, i8) + remaining, 2_i8 * size(list%tags, kind=i8))
      else
         capacity = max(int(remaining, i8), 1024_i8)
      end if
      capacity = min(capacity, int(huge(0_ip), i8))
      allocate (nodes(nodes_per_element, capacity), tags(capacity), entity(capacity), stat=stat)
      if (stat /= 0) then
         call location_error(c, 'out of memory for ' // to_str(capacity) // ' elements', error)
         return
      end if
      if (list%count > 0) then
         nodes(:, :list%count) = list%nodes(:, :list%count)
         tags(:list%count) = list%tags(:list%count)
         entity(:list%count) = list%entity(:list%count)
      end if
      call move_alloc(nodes, list%nodes)
      call move_alloc(tags, list%tags)
      call move_alloc(entity, list%entity)
   end subroutine start_element

   !> Node j of the element being added.
   pure subroutine store_node(r, element_type, j, index)
      type(reader_t), intent(inout) :: r
      integer(i8), intent(in) :: element_type
      integer(ip), intent(in) :: j, index
      if (element_type == 4 .or. element_type == 11) then
         r%tets%nodes(j, r%tets%count + 1) = index
      else
         r%tris%nodes(j, r%tris%count + 1) = index
      end if
   end subroutine store_node

   !> Close the element being added: its tag and entity.
   pure subroutine finish_element(r, element_type, tag, entity)
      type(reader_t), intent(inout) :: r
      integer(i8), intent(in) :: element_type, tag
      integer(ip), intent(in) :: entity
      r%min_element_tag = min(r%min_element_tag, tag)
      r%max_element_tag = max(r%max_element_tag, tag)
      if (element_type == 4 .or. element_type == 11) then
         r%tets%count = r%tets%count + 1
         r%tets%tags(r%tets%count) = tag
         r%tets%entity(r%tets%count) = entity
      else
         r%tris%count = r%tris%count + 1
         r%tris%tags(r%tris%count) = tag
         r%tris%entity(r%tris%count) = entity
      end if
   end subroutine finish_element

   !> One ASCII element line (from the element tag on if `tag` < 0, else from the node tags on):
   !> node tags mapped to indices, then the end of the line.
   subroutine read_element_record(r, element_type, nodes_per_element, entity, tag, error)
      type(reader_t), intent(inout) :: r
      integer(i8), intent(in) :: element_type
      integer(ip), intent(in) :: nodes_per_element, entity
      !> Element tag already read (2.2), or -1 to read it here (4.1)
      integer(i8), intent(in) :: tag
      type(error_t), allocatable, intent(out) :: error
      integer(i8) :: element_tag, node_tag, line, n, p
      integer(ip) :: j, index
      integer :: digit, digits
      logical :: ok

      element_tag = tag
      if (tag < 0) then
         call scan_int(r%c%text, r%c%pos, r%c%line, element_tag, ok)
         if (.not. ok) then
            call missing_item_error(r%c, 'an element tag', 'the element block holds fewer ' // &
               'elements than its header announces', error)
            return
         end if
         if (element_tag < 1) then
            call element_tag_error(r%c, element_tag, error)
            return
         end if
      end if
      line = r%c%line
      n = len(r%c%text, kind=i8)
      do j = 1, nodes_per_element
         ! Fast path for the common "blanks, digits, separator" on this line; anything else
         ! (signs, tabs, line ends, errors) goes through scan_int
         p = r%c%pos
         do while (p <= n)
            if (iachar(r%c%text(p:p)) /= 32) exit  ! not a blank (no len_trim call)
            p = p + 1
         end do
         node_tag = 0
         digits = 0
         do while (p <= n .and. digits < 18)
            digit = iachar(r%c%text(p:p)) - 48
            if (digit < 0 .or. digit > 9) exit
            node_tag = 10 * node_tag + digit
            digits = digits + 1
            p = p + 1
         end do
         ok = digits > 0 .and. digits < 18
         if (ok .and. p <= n) ok = is_separator(r%c%text(p:p))
         if (ok) then
            r%c%pos = p
         else
            call scan_int(r%c%text, r%c%pos, r%c%line, node_tag, ok)
         end if
         if (r%c%line /= line) then
            call line_error(r%c, line, 'element ' // to_str(element_tag) // ' (' // &
               type_name(element_type) // ') lists ' // to_str(j - 1) // ' of its ' // &
               to_str(nodes_per_element) // ' nodes; a node is missing', error)
            return
         end if
         if (.not. ok) then
            call syntax_error(r%c, 'expected node ' // to_str(j) // ' of element ' // &
               to_str(element_tag) // ' (' // type_name(element_type) // ')', error)
            return
         end if
         ! The direct table inline (this loop reads every node of every element)
         index = 0
         if (r%map%dense) then
            if (node_tag >= r%map%min_tag .and. node_tag <= r%map%max_tag) &
               index = r%map%direct(node_tag - r%map%min_tag + 1)
         else
            index = node_index(r%map, node_tag)
         end if
         if (index == 0) then
            call missing_node_error(r%c, element_tag, element_type, node_tag, error)
            return
         end if
         call store_node(r, element_type, j, index)
      end do
      call skip_line_end(r%c%text, r%c%pos, r%c%line, ok)
      if (.not. ok) then
         call syntax_error(r%c, 'expected the end of the line after the ' // &
            to_str(nodes_per_element) // ' nodes of element ' // to_str(element_tag) // &
            ' (' // type_name(element_type) // ')', error)
         return
      end if
      call finish_element(r, element_type, element_tag, entity)
   end subroutine read_element_record

   !> Record that `entity` of dimension `dim` is in physical group `physical`.
   subroutine add_link(r, dim, physical, entity)
      type(reader_t), intent(inout) :: r
      integer(ip), intent(in) :: dim, physical, entity
      integer(ip), allocatable :: grown(:, :)
      if (r%num_links > 0) then
         if (all(r%links(:, r%num_links) == [dim, physical, entity])) return
      end if
      if (.not. allocated(r%links)) allocate (r%links(3, 64))
      if (r%num_links == size(r%links, 2)) then
         allocate (grown(3, 2 * r%num_links))
         grown(:, :r%num_links) = r%links
         call move_alloc(grown, r%links)
      end if
      r%num_links = r%num_links + 1
      r%links(:, r%num_links) = [dim, physical, entity]
   end subroutine add_link

   !> Move what was read into `mesh`: elements (duplicates of MSH 2.2 removed), groups.
   subroutine build_mesh(r, mesh, error)
      type(reader_t), intent(inout) :: r
      type(mesh_t), intent(out) :: mesh
      type(error_t), allocatable, intent(out) :: error
      integer(ip), allocatable :: links(:, :), perm(:)
      logical :: shared(0:3)
      integer(ip) :: i

      if (r%tets%count == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // r%c%file_name // ''' has no ' // &
            'tetrahedra (Tet4 or Tet10; ' // to_str(r%tris%count) // ' triangles and ' // &
            to_str(r%num_skipped) // ' other elements). Gmsh saves only the elements of ' // &
            'physical groups once any group exists (toolchain pitfall 13): add a Physical ' // &
            'Volume for the body''s volumes to the .geo and mesh it in 3D (gmsh -3)')
         return
      end if

      ! Unique (dim, physical, entity) triples.
      if (r%num_links > 0) then
         links = unique_columns(r%links(:, :r%num_links))
      else
         allocate (links(3, 0))
      end if

      ! MSH 2.2 repeats an element once per physical group of its entity: drop the copies.
      shared = .false.
      if (r%version == '2.2' .and. size(links, 2) > 1) then
         call sort_columns(links([1, 3], :), perm)
         do i = 2, size(perm, kind=ip)
            if (all(links([1, 3], perm(i)) == links([1, 3], perm(i - 1)))) &
               shared(links(1, perm(i))) = .true.
         end do
      end if
      if (shared(3)) call drop_repeated(r%tets)
      if (shared(2)) call drop_repeated(r%tris)

      mesh%file_name = r%c%file_name
      mesh%num_nodes = r%num_nodes
      call move_alloc(r%xyz, mesh%xyz)
      call move_alloc(r%node_tags, mesh%node_tags)
      mesh%nodes_per_tet = r%tets%nodes_per_element
      if (size(r%tets%tags) == r%tets%count) then
         ! Filled to capacity (one block, the usual case): hand the arrays over, no copy
         call move_alloc(r%tets%nodes, mesh%tets)
         call move_alloc(r%tets%tags, mesh%tet_tags)
         call move_alloc(r%tets%entity, mesh%tet_entity)
      else
         mesh%tets = r%tets%nodes(:, :r%tets%count)
         mesh%tet_tags = r%tets%tags(:r%tets%count)
         mesh%tet_entity = r%tets%entity(:r%tets%count)
      end if
      mesh%nodes_per_tri = r%tris%nodes_per_element
      if (r%tris%count > 0) then
         mesh%tris = r%tris%nodes(:, :r%tris%count)
         mesh%tri_tags = r%tris%tags(:r%tris%count)
         mesh%tri_entity = r%tris%entity(:r%tris%count)
      else
         allocate (mesh%tris(0, 0), mesh%tri_tags(0), mesh%tri_entity(0))
      end if
      call build_groups(r, links, mesh%groups)
      if (r%num_other_volume > 0) then
         mesh%other_volume_elements = r%other_volume(:, :r%num_other_volume)
      else
         allocate (mesh%other_volume_elements(4, 0))
      end if
   end subroutine build_mesh

   !> Record `count` skipped volume elements of `element_type` in `entity` (a run continues the
   !> previous column when entity and type are the same).
   subroutine add_other_volume(r, entity, element_type, count, first_tag)
      type(reader_t), intent(inout) :: r
      integer(i8), intent(in) :: entity, element_type, count, first_tag
      integer(i8), allocatable :: grown(:, :)
      integer(ip) :: n
      n = r%num_other_volume
      if (n > 0) then
         if (r%other_volume(1, n) == entity .and. r%other_volume(2, n) == element_type) then
            r%other_volume(3, n) = r%other_volume(3, n) + count
            return
         end if
      end if
      if (.not. allocated(r%other_volume)) allocate (r%other_volume(4, 16))
      if (n == size(r%other_volume, 2)) then
         allocate (grown(4, 2 * n))
         grown(:, :n) = r%other_volume
         call move_alloc(grown, r%other_volume)
      end if
      r%num_other_volume = n + 1
      r%other_volume(:, n + 1) = [entity, element_type, count, first_tag]
   end subroutine add_other_volume

   !> Every coordinate finite: a NaN or Inf would surface later as a degenerate element or a
   !> failed factorisation far from its cause.
   subroutine check_coordinates(r, error)
      type(reader_t), intent(in) :: r
      type(error_t), allocatable, intent(out) :: error
      integer(ip) :: i
      do i = 1, r%num_nodes
         if (ieee_is_finite(r%xyz(1, i)) .and. ieee_is_finite(r%xyz(2, i)) .and. &
            ieee_is_finite(r%xyz(3, i))) cycle
         call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // r%c%file_name // ''': ' // &
            r%c%section // ': node ' // to_str(r%node_tags(i)) // ' has a non-finite ' // &
            'coordinate, (x, y, z) = (' // to_str(r%xyz(1, i)) // ', ' // to_str(r%xyz(2, i)) // &
            ', ' // to_str(r%xyz(3, i)) // '); every coordinate must be a finite number')
         return
      end do
   end subroutine check_coordinates

   !> Keep the first of elements with the same entity and the same nodes in the same order.
   subroutine drop_repeated(list)
      type(element_list_t), intent(inout) :: list
      integer(ip), allocatable :: keys(:, :), perm(:)
      logical, allocatable :: keep(:)
      integer(ip) :: i, n, k
      n = list%count
      if (n < 2) return
      allocate (keys(list%nodes_per_element + 1, n))
      keys(1, :) = list%entity(:n)
      keys(2:, :) = list%nodes(:, :n)
      call sort_columns(keys, perm)
      allocate (keep(n))
      keep = .true.
      do i = 2, n
         ! The sort is stable: the earlier copy comes first and stays.
         if (all(keys(:, perm(i)) == keys(:, perm(i - 1)))) keep(perm(i)) = .false.
      end do
      k = 0
      do i = 1, n
         if (.not. keep(i)) cycle
         k = k + 1
         list%nodes(:, k) = list%nodes(:, i)
         list%tags(k) = list%tags(i)
         list%entity(k) = list%entity(i)
      end do
      list%count = k
   end subroutine drop_repeated

   !> Physical groups from the unique sorted (dim, physical, entity) triples and the names,
   !> sorted by dimension and tag.
   subroutine build_groups(r, links, groups)
      type(reader_t), intent(in) :: r
      integer(ip), intent(in) :: links(:, :)
      type(physical_group_t), allocatable, intent(out) :: groups(:)
      integer(ip), allocatable :: keys(:, :)
      integer(ip) :: num_names, i, k
      num_names = 0
      if (allocated(r%names)) num_names = size(r%names, kind=ip)
      allocate (keys(2, size(links, 2) + num_names))
      keys(:, :size(links, 2)) = links(1:2, :)
      do i = 1, num_names
         keys(:, size(links, 2) + i) = [r%names(i)%dim, r%names(i)%tag]
      end do
      keys = unique_columns(keys)
      allocate (groups(size(keys, 2)))
      do k = 1, size(groups, kind=ip)
         groups(k)%dim = keys(1, k)
         groups(k)%tag = keys(2, k)
         groups(k)%name = ''
         do i = 1, num_names
            if (r%names(i)%dim == keys(1, k) .and. r%names(i)%tag == keys(2, k)) &
               groups(k)%name = r%names(i)%name
         end do
         groups(k)%entities = pack(links(3, :), links(1, :) == keys(1, k) .and. &
            links(2, :) == keys(2, k))
      end do
   end subroutine build_groups

   !> Nodes per element of Gmsh element `element_type`, -1 if unknown to ffrf.
   pure function nodes_of_type(element_type) result(n)
      integer(ip), intent(in) :: element_type
      integer(ip) :: n
      integer(ip), parameter :: table(31) = [2, 3, 4, 4, 8, 6, 5, 3, 6, 9, 10, 27, 18, 14, 1, &
         8, 20, 15, 13, 9, 10, 12, 15, 15, 21, 4, 5, 6, 20, 35, 56]
      select case (element_type)
      case (1:31)
         n = table(element_type)
      case (92)
         n = 64
      case (93)
         n = 125
      case default
         n = -1
      end select
   end function nodes_of_type

   !> Dimension of Gmsh element `element_type`, -1 if unknown to ffrf.
   pure function dim_of_type(element_type) result(dim)
      integer(ip), intent(in) :: element_type
      integer(ip) :: dim
      integer(ip), parameter :: table(31) = [1, 2, 2, 3, 3, 3, 3, 1, 2, 2, 3, 3, 3, 3, 0, &
         2, 3, 3, 3, 2, 2, 2, 2, 2, 2, 1, 1, 1, 3, 3, 3]
      select case (element_type)
      case (1:31)
         dim = table(element_type)
      case (92, 93)
         dim = 3
      case default
         dim = -1
      end select
   end function dim_of_type

   !> "Tet10", "Tri3" ... for messages.
   function type_name(element_type) result(name)
      integer(i8), intent(in) :: element_type
      character(len=:), allocatable :: name
      name = element_type_name(element_type)
   end function type_name

   ! ------------------------------------------------------------------------------------------
   ! Sorting (stable bottom-up merge sorts of a permutation)
   ! ------------------------------------------------------------------------------------------

   !> Permutation putting the columns of `keys` in lexicographic order (stable).
   subroutine sort_columns(keys, perm)
      integer(ip), intent(in) :: keys(:, :)
      integer(ip), allocatable, intent(out) :: perm(:)
      integer(ip), allocatable :: work(:)
      integer(ip) :: n, width, left, mid, right, i, a, b
      n = size(keys, 2, kind=ip)
      perm = [(i, i=1, n)]
      allocate (work(n))
      width = 1
      do while (width < n)
         do left = 1, n, 2 * width
            mid = min(left + width - 1, n)
            right = min(left + 2 * width - 1, n)
            a = left
            b = mid + 1
            do i = left, right
               if (b > right) then
                  work(i) = perm(a)
                  a = a + 1
               else if (a > mid) then
                  work(i) = perm(b)
                  b = b + 1
               else if (column_less(keys(:, perm(b)), keys(:, perm(a)))) then
                  work(i) = perm(b)
                  b = b + 1
               else
                  work(i) = perm(a)
                  a = a + 1
               end if
            end do
         end do
         perm = work
         width = 2 * width
      end do
   end subroutine sort_columns

   !> The distinct columns of `keys`, in lexicographic order.
   function unique_columns(keys) result(unique)
      integer(ip), intent(in) :: keys(:, :)
      integer(ip), allocatable :: unique(:, :)
      integer(ip), allocatable :: perm(:)
      logical, allocatable :: first(:)
      integer(ip) :: i, n
      n = size(keys, 2, kind=ip)
      call sort_columns(keys, perm)
      allocate (first(n))
      do i = 1, n
         first(i) = .true.
         if (i > 1) first(i) = any(keys(:, perm(i)) /= keys(:, perm(i - 1)))
      end do
      unique = keys(:, pack(perm, first))
   end function unique_columns

   !> Whether column `x` comes strictly before column `y` lexicographically.
   pure function column_less(x, y) result(less)
      integer(ip), intent(in) :: x(:), y(:)
      logical :: less
      integer :: k
      less = .false.
      do k = 1, size(x)
         if (x(k) /= y(k)) then
            less = x(k) < y(k)
            return
         end if
      end do
   end function column_less

   !> Permutation putting `tags` in ascending order (stable).
   subroutine sort_tags(tags, perm)
      integer(i8), intent(in) :: tags(:)
      integer(ip), allocatable, intent(out) :: perm(:)
      integer(ip), allocatable :: work(:)
      integer(ip) :: n, width, left, mid, right, i, a, b
      n = size(tags, kind=ip)
      perm = [(i, i=1, n)]
      allocate (work(n))
      width = 1
      do while (width < n)
         do left = 1, n, 2 * width
            mid = min(left + width - 1, n)
            right = min(left + 2 * width - 1, n)
            a = left
            b = mid + 1
            do i = left, right
               if (b > right) then
                  work(i) = perm(a)
                  a = a + 1
               else if (a > mid) then
                  work(i) = perm(b)
                  b = b + 1
               else if (tags(perm(b)) < tags(perm(a))) then
                  work(i) = perm(b)
                  b = b + 1
               else
                  work(i) = perm(a)
                  a = a + 1
               end if
            end do
         end do
         perm = work
         width = 2 * width
      end do
   end subroutine sort_tags

   ! ------------------------------------------------------------------------------------------
   ! File and tokens
   ! ------------------------------------------------------------------------------------------

   !> The whole file into `c%text` with one stream read.
   subroutine load_file(file_name, c, error)
      character(len=*), intent(in) :: file_name
      type(cursor_t), intent(out) :: c
      type(error_t), allocatable, intent(out) :: error
      character(len=512) :: message
      character(len=64) :: head
      integer(i8) :: file_size, content_bytes
      integer :: step, kind, got, stat, first, last_line
      logical :: nul_after
      c%file_name = file_name
      content_bytes = huge(1_i8)
      c%section = 'start of file'
      ! A FIFO or device would block or never end, a folder cannot be read: only a regular file
      ! of bounded size is opened (a missing one gets the open error below, with its hint).
      call file_kind(file_name, kind, file_size, error)
      if (allocated(error)) then
         error%message = 'mesh ''' // file_name // ''': ' // error%message
         return
      end if
      if (kind /= FILE_MISSING) then
         call check_input_file(file_name, 'mesh file', MAX_MESH_BYTES, error)
         if (allocated(error)) return
         ! bounded reads (docs/input.md "Input rules"): the first bytes say whether it is a mesh at
         ! all, and only its content (up to the last byte that is not NUL or blank) is read
         call read_file_head(file_name, 1_i8, head, got, stat, message)
         if (stat == 0) then
            first = verify(head(:got), ' ' // achar(9) // achar(10) // achar(13))
            if (first == 0 .or. index(head(max(first, 1):got), '$MeshFormat') /= 1) then
               call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // file_name // ''' (' // &
                  to_str(file_size) // ' bytes) is not a Gmsh MSH file: it does not start ' // &
                  'with $MeshFormat (first bytes: "' // printable(head(:min(got, 24))) // '")')
               return
            end if
            call content_end(file_name, content_bytes, nul_after, stat)
            if (stat /= 0) content_bytes = huge(1_i8)
         end if
         ! only after a complete last section ($End... line) is the rest padding: a file cut in
         ! binary data may end in zero bytes of that data, and is read whole (the parser then
         ! says where it ends)
         if (stat == 0) call read_file_head(file_name, max(1_i8, content_bytes - 63_i8), head, &
            got, stat, message)
         if (stat == 0) then
            ! the tail of the content only (the padding after it is not looked at)
            got = int(min(int(got, i8), content_bytes - max(1_i8, content_bytes - 63_i8) + 1))
            last_line = index(head(:got), achar(10), back=.true.) + 1
            if (index(head(last_line:got), '$End') /= 1) content_bytes = huge(1_i8)
            if (index(head(last_line:got), '$End') /= 1) nul_after = .false.
         end if
         if (stat == 0 .and. nul_after) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // file_name // ''': ' // &
               to_str(file_size - content_bytes) // ' bytes of NUL padding after its last ' // &
               'section (content ends at byte ' // to_str(content_bytes) // ' of ' // &
               to_str(file_size) // '); a mesh file ends with its last $End... line: was ' // &
               'it cut short or padded? write it again with gmsh')
            return
         end if
         ! the content and the line end after it (a trailing blank run is not read)
         if (stat == 0) content_bytes = min(content_bytes, huge(1_i8) - 1) + 1
      end if
      call read_whole_file(file_name, c%text, step, file_size, message, &
         content_bytes=content_bytes)
      select case (step)
      case (READ_OPEN_FAILED)
         call fatal_error(error, FFRF_IO_ERROR, 'mesh ''' // file_name // ''': cannot open: ' // &
            trim(message) // '; build the mesh first (gmsh -3 ... -o ' // file_name // ')')
      case (READ_NO_MEMORY)
         call fatal_error(error, FFRF_IO_ERROR, 'mesh ''' // file_name // ''': out of memory ' // &
            'for ' // to_str(file_size) // ' bytes')
      case (READ_FAILED)
         call fatal_error(error, FFRF_IO_ERROR, 'mesh ''' // file_name // ''': cannot ' // &
            'read: ' // trim(message))
      end select
   end subroutine load_file

   !> `text` with control characters and bytes above 126 as '?', for a one-line message.
   pure function printable(text) result(shown)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: shown
      integer :: k
      shown = text
      do k = 1, len(shown)
         if (iachar(shown(k:k)) < 32 .or. iachar(shown(k:k)) > 126) shown(k:k) = '?'
      end do
   end function printable

   !> Skip blanks and line ends, counting lines.
   pure subroutine skip_space(text, pos, line)
      character(len=*), intent(in) :: text
      integer(i8), intent(inout) :: pos, line
      integer(i8) :: n
      n = len(text, kind=i8)
      do while (pos <= n)
         select case (iachar(text(pos:pos)))
         case (10)
            line = line + 1
         case (9, 13, 32)
         case default
            return
         end select
         pos = pos + 1
      end do
   end subroutine skip_space

   !> Whether `ch` separates tokens (blank, tab, CR, LF).
   elemental function is_separator(ch) result(yes)
      character, intent(in) :: ch
      logical :: yes
      select case (iachar(ch))
      case (9, 10, 13, 32)
         yes = .true.
      case default
         yes = .false.
      end select
   end function is_separator

   !> Integer token after white space. On failure `ok` is false and `pos` stays at the token.
   pure subroutine scan_int(text, pos, line, value, ok)
      character(len=*), intent(in) :: text
      integer(i8), intent(inout) :: pos, line
      integer(i8), intent(out) :: value
      logical, intent(out) :: ok
      integer(i8) :: n, p
      integer :: digit, digits
      logical :: negative
      call skip_space(text, pos, line)
      n = len(text, kind=i8)
      p = pos
      negative = .false.
      value = 0
      ok = .false.
      if (p > n) return
      if (text(p:p) == '-') then
         negative = .true.
         p = p + 1
      else if (text(p:p) == '+') then
         p = p + 1
      end if
      digits = 0
      do while (p <= n)
         digit = iachar(text(p:p)) - 48
         if (digit < 0 .or. digit > 9) exit
         if (digits == 18) return
         value = 10 * value + digit
         digits = digits + 1
         p = p + 1
      end do
      if (digits == 0) return
      if (p <= n) then
         if (.not. is_separator(text(p:p))) return
      end if
      if (negative) value = -value
      ok = .true.
      pos = p
   end subroutine scan_int

   !> Real token after white space, correctly rounded: exact fast path (mantissa <= 2**53,
   !> |decimal exponent| <= 22: one IEEE multiply or divide of exact operands), else C strtod
   !> (strtod_token) or an internal read. On failure `ok` is false and `pos` stays at the token.
   subroutine scan_real(text, pos, line, value, ok)
      character(len=*), intent(in) :: text
      integer(i8), intent(inout) :: pos, line
      real(dp), intent(out) :: value
      logical, intent(out) :: ok
      integer(i8) :: n, p, mantissa
      integer :: digit, significant, exponent, exponent_part, exponent_digits, stat
      logical :: negative, exact, any_digit, negative_exponent, converted
      call skip_space(text, pos, line)
      n = len(text, kind=i8)
      p = pos
      value = 0.0_dp
      ok = .false.
      if (p > n) return
      negative = .false.
      if (text(p:p) == '-') then
         negative = .true.
         p = p + 1
      else if (text(p:p) == '+') then
         p = p + 1
      end if
      mantissa = 0
      significant = 0
      exponent = 0
      exact = .true.
      any_digit = .false.
      ! Integer part
      do while (p <= n)
         digit = iachar(text(p:p)) - 48
         if (digit < 0 .or. digit > 9) exit
         any_digit = .true.
         if (mantissa > 0 .or. digit > 0) then
            if (significant < 18) then
               mantissa = 10 * mantissa + digit
               significant = significant + 1
            else
               exponent = exponent + 1
               if (digit /= 0) exact = .false.
            end if
         end if
         p = p + 1
      end do
      ! Fraction
      if (p <= n) then
         if (text(p:p) == '.') then
            p = p + 1
            do while (p <= n)
               digit = iachar(text(p:p)) - 48
               if (digit < 0 .or. digit > 9) exit
               any_digit = .true.
               if (mantissa == 0 .and. digit == 0) then
                  exponent = exponent - 1
               else if (significant < 18) then
                  mantissa = 10 * mantissa + digit
                  significant = significant + 1
                  exponent = exponent - 1
               else if (digit /= 0) then
                  exact = .false.
               end if
               p = p + 1
            end do
         end if
      end if
      if (.not. any_digit) return
      ! Exponent
      if (p <= n) then
         if (text(p:p) == 'e' .or. text(p:p) == 'E' .or. text(p:p) == 'd' .or. &
             text(p:p) == 'D') then
            p = p + 1
            negative_exponent = .false.
            if (p <= n) then
               if (text(p:p) == '-' .or. text(p:p) == '+') then
                  negative_exponent = text(p:p) == '-'
                  p = p + 1
               end if
            end if
            exponent_part = 0
            exponent_digits = 0
            do while (p <= n)
               digit = iachar(text(p:p)) - 48
               if (digit < 0 .or. digit > 9) exit
               if (exponent_digits == 5) return
               exponent_part = 10 * exponent_part + digit
               exponent_digits = exponent_digits + 1
               p = p + 1
            end do
            if (exponent_digits == 0) return
            if (negative_exponent) exponent_part = -exponent_part
            exponent = exponent + exponent_part
         end if
      end if
      if (p <= n) then
         if (.not. is_separator(text(p:p))) return
      end if
      if (mantissa == 0) then
         value = 0.0_dp
      else if (exact .and. mantissa <= exact_mantissa .and. abs(exponent) <= 22) then
         if (exponent >= 0) then
            value = real(mantissa, dp) * powers_of_ten(exponent)
         else
            value = real(mantissa, dp) / powers_of_ten(-exponent)
         end if
      else
         call strtod_token(text(pos:p - 1), value, converted)
         if (.not. converted) then
            read (text(pos:p - 1), *, iostat=stat) value
            if (stat /= 0) return
         end if
         negative = .false.
      end if
      if (negative) value = -value
      ok = .true.
      pos = p
   end subroutine scan_real

   !> A real token already checked by scan_real (sign, digits, point, exponent with e, E, d or
   !> D), converted by C strtod, the correctly rounded conversion behind the internal read,
   !> without the cost of Fortran I/O. `ok` false (the caller does the internal read) for a
   !> long token, one strtod does not take whole (a locale with a decimal comma) and a result
   !> that is not finite or is zero.
   subroutine strtod_token(token, value, ok)
      character(len=*), intent(in) :: token
      real(dp), intent(out) :: value
      logical, intent(out) :: ok
      character(kind=c_char), target :: buffer(64)
      type(c_ptr) :: end
      integer :: k
      value = 0.0_dp
      ok = .false.
      if (len(token) >= size(buffer)) return
      do k = 1, len(token)
         select case (token(k:k))
         case ('d', 'D')
            buffer(k) = 'e'
         case default
            buffer(k) = token(k:k)
         end select
      end do
      buffer(len(token) + 1) = c_null_char
      value = c_strtod(buffer, end)
      ok = c_associated(end, c_loc(buffer(len(token) + 1))) .and. ieee_is_finite(value) .and. &
         value /= 0.0_dp
   end subroutine strtod_token

   !> Next white-space delimited word ('' at end of file).
   function next_word(c) result(word)
      type(cursor_t), intent(inout) :: c
      character(len=:), allocatable :: word
      integer(i8) :: start, n
      call skip_space(c%text, c%pos, c%line)
      n = len(c%text, kind=i8)
      start = c%pos
      do while (c%pos <= n)
         if (is_separator(c%text(c%pos:c%pos))) exit
         c%pos = c%pos + 1
      end do
      word = c%text(start:c%pos - 1)
   end function next_word

   !> Past the end of the current line, wherever in it the cursor is.
   subroutine skip_line(c)
      type(cursor_t), intent(inout) :: c
      integer(i8) :: found
      found = index(c%text(c%pos:), achar(10), kind=i8)
      if (found == 0) then
         c%pos = len(c%text, kind=i8) + 1
      else
         c%pos = c%pos + found
         c%line = c%line + 1
      end if
   end subroutine skip_line

   !> Only blanks may remain on the current line; step past its end (ok false, pos at the
   !> offending text, if something else comes first).
   pure subroutine skip_line_end(text, pos, line, ok)
      character(len=*), intent(in) :: text
      integer(i8), intent(inout) :: pos, line
      logical, intent(out) :: ok
      integer(i8) :: n
      n = len(text, kind=i8)
      ok = .true.
      do while (pos <= n)
         select case (iachar(text(pos:pos)))
         case (9, 13, 32)
            pos = pos + 1
         case (10)
            pos = pos + 1
            line = line + 1
            return
         case default
            ok = .false.
            return
         end select
      end do
   end subroutine skip_line_end

   !> "$EndX" closing the current section "$X".
   subroutine expect_end(c, error)
      type(cursor_t), intent(inout) :: c
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: word
      integer(i8) :: start
      call skip_space(c%text, c%pos, c%line)
      start = c%pos
      word = next_word(c)
      if (word /= '$End' // c%section(2:)) then
         c%pos = start
         call syntax_error(c, 'expected $End' // c%section(2:) // ' (the section holds ' // &
            'more or fewer items than its counts announce)', error)
      end if
   end subroutine expect_end

   !> Integer with a message on failure.
   subroutine read_int(c, what, value, error)
      type(cursor_t), intent(inout) :: c
      character(len=*), intent(in) :: what
      integer(i8), intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      logical :: ok
      call scan_int(c%text, c%pos, c%line, value, ok)
      if (.not. ok) call syntax_error(c, 'expected an integer (' // what // ')', error)
   end subroutine read_int

   !> Non-negative integer that fits `ip`.
   subroutine read_count(c, what, value, error)
      type(cursor_t), intent(inout) :: c
      character(len=*), intent(in) :: what
      integer(ip), intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      integer(i8) :: long
      value = 0
      call read_int(c, what, long, error)
      if (allocated(error)) return
      if (long < 0 .or. long > huge(0_ip)) then
         call location_error(c, what // ' = ' // to_str(long) // ' is out of range', error)
         return
      end if
      value = int(long, ip)
   end subroutine read_count

   !> A size_t (binary) or a non-negative integer (ASCII); counts that must fit `ip` are
   !> checked where they are used.
   subroutine read_size(c, binary, what, value, error)
      type(cursor_t), intent(inout) :: c
      logical, intent(in) :: binary
      character(len=*), intent(in) :: what
      integer(i8), intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      integer(i8) :: p
      if (binary) then
         call binary_take(c, 8_i8, what, p, error)
         if (allocated(error)) return
         value = transfer(c%text(p:p + 7), 0_i8)
      else
         call read_int(c, what, value, error)
         if (allocated(error)) return
      end if
      if (value < 0) then
         call location_error(c, what // ' = ' // to_str(value) // ' is negative', error)
      end if
   end subroutine read_size

   !> An int (binary, 4 bytes) or an integer (ASCII).
   subroutine read_tag(c, binary, what, value, error)
      type(cursor_t), intent(inout) :: c
      logical, intent(in) :: binary
      character(len=*), intent(in) :: what
      integer(i8), intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      if (binary) then
         call binary_int(c, what, value, error)
      else
         call read_int(c, what, value, error)
      end if
   end subroutine read_tag

   !> A double (binary) or a real (ASCII).
   subroutine read_real(c, binary, what, value, error)
      type(cursor_t), intent(inout) :: c
      logical, intent(in) :: binary
      character(len=*), intent(in) :: what
      real(dp), intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      integer(i8) :: p
      logical :: ok
      if (binary) then
         call binary_take(c, 8_i8, what, p, error)
         if (allocated(error)) return
         value = transfer(c%text(p:p + 7), 0.0_dp)
      else
         call scan_real(c%text, c%pos, c%line, value, ok)
         if (.not. ok) call syntax_error(c, 'expected a real (' // what // ')', error)
      end if
   end subroutine read_real

   !> Step over the line end after a section header: binary data starts right after it.
   subroutine start_binary(c, error)
      type(cursor_t), intent(inout) :: c
      type(error_t), allocatable, intent(out) :: error
      integer(i8) :: n
      n = len(c%text, kind=i8)
      do while (c%pos <= n)
         if (c%text(c%pos:c%pos) /= ' ' .and. c%text(c%pos:c%pos) /= achar(13)) exit
         c%pos = c%pos + 1
      end do
      if (c%pos > n) then
         call location_error(c, 'file ends before the binary data', error)
         return
      end if
      if (c%text(c%pos:c%pos) /= achar(10)) then
         call syntax_error(c, 'expected the end of the line before binary data', error)
         return
      end if
      c%pos = c%pos + 1
      c%line = c%line + 1
      c%binary = .true.
   end subroutine start_binary

   !> Reserve `bytes` of binary data: `first` is where they start.
   subroutine binary_take(c, bytes, what, first, error)
      type(cursor_t), intent(inout) :: c
      integer(i8), intent(in) :: bytes
      character(len=*), intent(in) :: what
      integer(i8), intent(out) :: first
      type(error_t), allocatable, intent(out) :: error
      first = c%pos
      if (bytes < 0 .or. c%pos + bytes - 1 > len(c%text, kind=i8)) then
         call location_error(c, 'file ends inside the ' // what // ' (truncated file?)', error)
         return
      end if
      c%pos = c%pos + bytes
   end subroutine binary_take

   !> A 4-byte int of binary data.
   subroutine binary_int(c, what, value, error)
      type(cursor_t), intent(inout) :: c
      character(len=*), intent(in) :: what
      integer(i8), intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      integer(i8) :: p
      value = 0
      call binary_take(c, 4_i8, what, p, error)
      if (allocated(error)) return
      value = transfer(c%text(p:p + 3), 0_int32)
   end subroutine binary_int

   ! ------------------------------------------------------------------------------------------
   ! Messages
   ! ------------------------------------------------------------------------------------------

   !> "mesh 'box.msh': $Nodes, line 12" or "..., byte 1234".
   function location(c) result(text)
      type(cursor_t), intent(in) :: c
      character(len=:), allocatable :: text
      text = 'mesh ''' // c%file_name // ''': ' // c%section
      if (c%binary) then
         text = text // ', byte ' // to_str(c%pos - 1)
      else
         text = text // ', line ' // to_str(c%line)
      end if
   end function location

   !> Error at the cursor.
   subroutine location_error(c, message, error)
      type(cursor_t), intent(in) :: c
      character(len=*), intent(in) :: message
      type(error_t), allocatable, intent(out) :: error
      call fatal_error(error, FFRF_INPUT_ERROR, location(c) // ': ' // message)
   end subroutine location_error

   !> Error at the cursor quoting the text found there.
   subroutine syntax_error(c, message, error)
      type(cursor_t), intent(in) :: c
      character(len=*), intent(in) :: message
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: found
      integer(i8) :: last, n
      n = len(c%text, kind=i8)
      if (c%pos > n) then
         found = 'end of file'
      else
         last = c%pos
         do while (last < n .and. last < c%pos + 39)
            if (is_separator(c%text(last + 1:last + 1))) exit
            last = last + 1
         end do
         found = '''' // c%text(c%pos:last) // ''''
      end if
      call location_error(c, message // ', found ' // found, error)
   end subroutine syntax_error

   subroutine missing_node_error(c, element_tag, element_type, node_tag, error)
      type(cursor_t), intent(in) :: c
      integer(i8), intent(in) :: element_tag, element_type, node_tag
      type(error_t), allocatable, intent(out) :: error
      call location_error(c, 'element ' // to_str(element_tag) // ' (' // &
         type_name(element_type) // ') refers to node ' // to_str(node_tag) // &
         ', which $Nodes does not list', error)
   end subroutine missing_node_error

   subroutine duplicate_tag_error(c, tag, error)
      type(cursor_t), intent(in) :: c
      integer(i8), intent(in) :: tag
      type(error_t), allocatable, intent(out) :: error
      call location_error(c, 'node tag ' // to_str(tag) // ' appears twice', error)
   end subroutine duplicate_tag_error

   subroutine node_tag_error(c, tag, error)
      type(cursor_t), intent(in) :: c
      integer(i8), intent(in) :: tag
      type(error_t), allocatable, intent(out) :: error
      call location_error(c, 'node tag ' // to_str(tag) // ' is not allowed: Gmsh node ' // &
         'tags are 1 or more', error)
   end subroutine node_tag_error

   subroutine element_tag_error(c, tag, error)
      type(cursor_t), intent(in) :: c
      integer(i8), intent(in) :: tag
      type(error_t), allocatable, intent(out) :: error
      call location_error(c, 'element tag ' // to_str(tag) // ' is not allowed: Gmsh ' // &
         'element tags are 1 or more', error)
   end subroutine element_tag_error

   !> An element type the reader does not know: its node count, and so the file layout, is
   !> unknown, wherever the element lies.
   subroutine unknown_type_error(c, element_type, where, error)
      type(cursor_t), intent(in) :: c
      integer(i8), intent(in) :: element_type
      character(len=*), intent(in) :: where
      type(error_t), allocatable, intent(out) :: error
      call location_error(c, where // ' has element type ' // to_str(element_type) // &
         ', which ffrf does not know (it knows Gmsh types 1-31, 92 and 93 and uses Tet4 and ' // &
         'Tet10 volumes with Tri3 and Tri6 surfaces); re-mesh with gmsh -3 and ' // &
         'Mesh.ElementOrder 1 or 2', error)
   end subroutine unknown_type_error

   !> A coordinate could not be read: a NaN or Inf token is named as such.
   subroutine coordinate_error(c, tag, error)
      type(cursor_t), intent(in) :: c
      integer(i8), intent(in) :: tag
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: token
      integer(i8) :: last, n
      n = len(c%text, kind=i8)
      last = c%pos - 1
      do while (last < n .and. last < c%pos + 39)
         if (is_separator(c%text(last + 1:last + 1))) exit
         last = last + 1
      end do
      token = to_lower(c%text(c%pos:last))
      if (len(token) > 0) then
         if (token(1:1) == '+' .or. token(1:1) == '-') token = token(2:)
      end if
      if (index(token, 'nan') == 1 .or. index(token, 'inf') == 1) then
         call location_error(c, 'node ' // to_str(tag) // ' has the coordinate ''' // &
            c%text(c%pos:last) // ''', which is not a finite number', error)
      else
         call syntax_error(c, 'expected a coordinate of node ' // to_str(tag), error)
      end if
   end subroutine coordinate_error

   !> Whether the cursor stands at a "$End..." line.
   pure function at_section_end(c) result(yes)
      type(cursor_t), intent(in) :: c
      logical :: yes
      yes = .false.
      if (c%pos + 3 <= len(c%text, kind=i8)) yes = c%text(c%pos:c%pos + 3) == '$End'
   end function at_section_end

   !> `what` was expected: where the section ends instead, its counts announced more items than
   !> it holds (`announced` says which); else a syntax error quoting what is there.
   subroutine missing_item_error(c, what, announced, error)
      type(cursor_t), intent(in) :: c
      character(len=*), intent(in) :: what, announced
      type(error_t), allocatable, intent(out) :: error
      if (at_section_end(c)) then
         call location_error(c, announced, error)
      else
         call syntax_error(c, 'expected ' // what, error)
      end if
   end subroutine missing_item_error

   !> Error on ASCII line `line` of the current section (a value missing from that line).
   subroutine line_error(c, line, message, error)
      type(cursor_t), intent(in) :: c
      integer(i8), intent(in) :: line
      character(len=*), intent(in) :: message
      type(error_t), allocatable, intent(out) :: error
      call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // c%file_name // ''': ' // &
         c%section // ', line ' // to_str(line) // ': ' // message)
   end subroutine line_error

   !> A count read from the file must fit the bytes left in it, each item taking `min_bytes` at
   !> least; checked before anything is allocated for the items, so a corrupt count cannot make
   !> the reader allocate more than a small multiple of the file size.
   subroutine check_count_fits(c, what, count, min_bytes, error)
      type(cursor_t), intent(in) :: c
      character(len=*), intent(in) :: what
      integer(i8), intent(in) :: count, min_bytes
      type(error_t), allocatable, intent(out) :: error
      integer(i8) :: left
      left = max(0_i8, len(c%text, kind=i8) - c%pos + 1)
      if (count > left / min_bytes) then
         call location_error(c, what // ' = ' // to_str(count) // ' cannot be right: the ' // &
            to_str(left) // ' bytes left in the file hold at most ' // to_str(left / min_bytes) // &
            ' (truncated or corrupt file?)', error)
      end if
   end subroutine check_count_fits

end submodule ffrf_mesh_gmsh_parse
