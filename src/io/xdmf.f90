!> XDMF 3 export (&run export = 'xdmf'; docs/results.md "XDMF export"): `<stem>.xdmf` beside
!> the results file `<stem>.h5`, a small XML file that points into the HDF5 file, so that
!> ParaView (and meshio) show every flexible body's mesh with its mode shapes (modal run) or its
!> elastic deformation over time (mechanism run, the frames of the Gmsh animation).
!>
!> - The datasets it needs are written into the results file under `/xdmf/<body>/`:
!>   `geometry` (h5py (num_nodes, 3), m), `topology` (h5py (num_tets, 4 or 10), 0-based node
!>   numbers in VTK's order), and one dataset per mode `mode_<k>` (h5py (num_nodes, 3), the
!>   mass-normalised shape, m kg^-1/2) or per frame `frame_<k>` (h5py (num_nodes, 3), m): whole
!>   datasets, so that readers without hyperslab support (meshio) read them.
!> - Node order: VTK's quadratic tetra (VTK_QUADRATIC_TETRA = XDMF's Tetrahedron_10) has the
!>   mid-edge nodes on the edges (0,1), (1,2), (2,0), (0,3), (1,3), (2,3) (VTK's
!>   vtkQuadraticTetra documentation); Gmsh's 10-node tetrahedron has them on (0,1), (1,2),
!>   (2,0), (3,0), (3,2), (3,1) (Gmsh reference manual, "Node ordering"; src/fe/tet.f90 draws
!>   it): the last two are swapped (GMSH_TO_VTK_TET10). Tet4 is the same in both.
!> - The XML: one Domain; per body a Uniform grid (modes as point vector attributes
!>   "mode k, f Hz") or a Temporal collection of Uniform grids, one per frame with its Time and
!>   the attribute "elastic displacement" (each grid names the same topology and geometry).
!>   A mechanism run without frames (animation_frames = 0) gives each body's mesh alone, as a
!>   Uniform grid. The HDF5 file is named relative to the .xdmf file (its file name only: both
!>   sit in one folder). Written under `<file>.part`, checked whole on disk and renamed over
!>   `<file>` (ffrf_io_gmsh_writer open_part, close_part; ffrf_core_posix commit_durably), as
!>   the results are.
module ffrf_io_xdmf
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_posix, only: commit_durably, remove_file
   use ffrf_io_hdf5, only: h5_file_t
   use ffrf_io_text_stream, only: text_stream_t
   use ffrf_io_gmsh_writer, only: open_part, close_part
   implicit none
   private
   public :: xdmf_body_t, write_xdmf_body, write_xdmf_file, xdmf_name, GMSH_TO_VTK_TET10

   !> Gmsh Tet10 -> VTK quadratic tetra: node k of VTK's order is node GMSH_TO_VTK_TET10(k) of
   !> Gmsh's (module notes)
   integer, parameter :: GMSH_TO_VTK_TET10(10) = [1, 2, 3, 4, 5, 6, 7, 8, 10, 9]

   !> What the XML says of one body whose datasets are in the results file.
   type :: xdmf_body_t
      character(len=:), allocatable :: name
      integer :: num_nodes = 0, num_tets = 0, nodes_per_tet = 0
      !> Frames over time (mechanism) rather than modes
      logical :: frames = .false.
      !> The frequency of each mode (Hz) or the time of each frame (s)
      real(dp), allocatable :: values(:)
   end type xdmf_body_t

contains

   !> `<stem>.xdmf` of a results file `<stem>.h5` (the suffix after the last '.' replaced).
   pure function xdmf_name(results_file) result(name)
      character(len=*), intent(in) :: results_file
      character(len=:), allocatable :: name
      integer :: dot, slash
      dot = index(results_file, '.', back=.true.)
      slash = index(results_file, '/', back=.true.)
      if (dot > slash + 1) then
         name = results_file(:dot) // 'xdmf'
      else
         name = results_file // '.xdmf'
      end if
   end function xdmf_name

   !> Write body `name`'s XDMF datasets into the open results file `h5` (module notes): its
   !> mesh and one dataset per column of `fields`; `body` describes them for write_xdmf_file.
   subroutine write_xdmf_body(h5, name, xyz, tets, fields, values, frames, body, error)
      type(h5_file_t), intent(inout) :: h5
      !> Body name (the group /xdmf/<name>)
      character(len=*), intent(in) :: name
      !> Node coordinates (3, num_nodes), m
      real(dp), intent(in) :: xyz(:, :)
      !> Tetrahedra (4 or 10, num_tets), 1-based node numbers, Gmsh node order
      integer, intent(in) :: tets(:, :)
      !> Mode shapes or frames (3*num_nodes, num_fields): ux, uy, uz of node 1, then node 2, ...
      real(dp), intent(in) :: fields(:, :)
      !> Frequency of each mode (Hz) or time of each frame (s), (num_fields)
      real(dp), intent(in) :: values(:)
      !> Frames over time (units m) rather than modes (m kg^-1/2)
      logical, intent(in) :: frames
      type(xdmf_body_t), intent(out) :: body
      type(error_t), allocatable, intent(out) :: error
      integer, allocatable :: topology(:, :)
      real(dp), allocatable :: field(:, :)
      character(len=:), allocatable :: root
      integer :: k, num_nodes
      num_nodes = size(xyz, 2)
      if (size(tets, 1) /= 4 .and. size(tets, 1) /= 10 .or. size(fields, 1) /= 3 * num_nodes &
         .or. size(fields, 2) /= size(values)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'XDMF export of body "' // name // '": ' // &
            to_str(size(tets, 1)) // '-node elements, ' // to_str(size(fields, 1)) // ' x ' // &
            to_str(size(fields, 2)) // ' fields for ' // to_str(num_nodes) // ' nodes and ' // &
            to_str(size(values)) // ' values; give Tet4 or Tet10 and 3 rows per node')
         return
      end if
      root = '/xdmf/' // name
      if (size(tets, 1) == 10) then
         topology = tets(GMSH_TO_VTK_TET10, :) - 1
      else
         topology = tets - 1
      end if
      call h5%write_real(root // '/geometry', xyz, 'm', error)
      if (.not. allocated(error)) call h5%write_int(root // '/topology', topology, error)
      allocate (field(3, num_nodes))
      do k = 1, size(fields, 2)
         if (allocated(error)) exit
         field = reshape(fields(:, k), [3, num_nodes])
         if (frames) then
            call h5%write_real(root // '/frame_' // to_str(k), field, 'm', error)
         else
            call h5%write_real(root // '/mode_' // to_str(k), field, 'm kg^-1/2', error)
         end if
      end do
      if (allocated(error)) return
      body%name = name
      body%num_nodes = num_nodes
      body%num_tets = size(tets, 2)
      body%nodes_per_tet = size(tets, 1)
      body%frames = frames
      body%values = values
   end subroutine write_xdmf_body

   !> Write the XDMF file `file_name` for the bodies whose datasets are in the results file
   !> `h5_name` (a file name in the folder of `file_name`), through `<file_name>.part`.
   subroutine write_xdmf_file(file_name, h5_name, bodies, error)
      character(len=*), intent(in) :: file_name, h5_name
      type(xdmf_body_t), intent(in) :: bodies(:)
      type(error_t), allocatable, intent(out) :: error
      type(text_stream_t) :: file
      type(error_t), allocatable :: ignored
      integer :: b, k
      !> The lines before the grids
      character(len=*), parameter :: header(*) = [character(len=72) :: &
         '<?xml version="1.0" ?>', &
         '<!-- ffrf results for ParaView (docs/results.md, "XDMF export") -->', &
         '<Xdmf Version="3.0">', '  <Domain>']
      call open_part(file, file_name, 'XDMF file', error)
      if (allocated(error)) return
      do k = 1, size(header)
         call file%put_line(trim(header(k)))
      end do
      do b = 1, size(bodies)
         associate (body => bodies(b))
            if (body%frames .and. size(body%values) > 0) then
               call file%put_line('    <Grid Name="' // xml_escaped(body%name) // &
                  '" GridType="Collection" CollectionType="Temporal">')
               do k = 1, size(body%values)
                  call file%put_line('      <Grid Name="' // xml_escaped(body%name) // &
                     ' frame ' // to_str(k) // '" GridType="Uniform">')
                  call file%put_line('        <Time Value="' // to_str(body%values(k), 17) // &
                     '"/>')
                  call put_mesh(body, '        ')
                  call put_field(body, 'elastic displacement', 'frame_' // to_str(k), &
                     '        ')
                  call file%put_line('      </Grid>')
               end do
            else
               call file%put_line('    <Grid Name="' // xml_escaped(body%name) // &
                  '" GridType="Uniform">')
               call put_mesh(body, '      ')
               do k = 1, size(body%values)
                  call put_field(body, 'mode ' // to_str(k) // ', ' // &
                     to_str(body%values(k), 7) // ' Hz', 'mode_' // to_str(k), '      ')
               end do
            end if
            call file%put_line('    </Grid>')
         end associate
      end do
      call file%put_line('  </Domain>')
      call file%put_line('</Xdmf>')
      call close_part(file, file_name, 'XDMF file', error)
      if (.not. allocated(error)) call commit_durably(file_name // '.part', file_name, &
         'XDMF file', error)
      if (allocated(error)) call remove_file(file_name // '.part', ignored)
   contains
      !> The Topology and Geometry of `body`, lines indented by `indent`.
      subroutine put_mesh(body, indent)
         type(xdmf_body_t), intent(in) :: body
         character(len=*), intent(in) :: indent
         character(len=*), parameter :: topology_types(2) = [character(len=14) :: &
            'Tetrahedron', 'Tetrahedron_10']
         call file%put_line(indent // '<Topology TopologyType="' // &
            trim(topology_types(merge(2, 1, body%nodes_per_tet == 10))) // &
            '" NumberOfElements="' // to_str(body%num_tets) // '">')
         call file%put_line(indent // '  ' // data_item(to_str(body%num_tets) // ' ' // &
            to_str(body%nodes_per_tet), 'Int" Precision="4', body%name, 'topology'))
         call file%put_line(indent // '</Topology>')
         call file%put_line(indent // '<Geometry GeometryType="XYZ">')
         call file%put_line(indent // '  ' // data_item(to_str(body%num_nodes) // ' 3', &
            'Float" Precision="8', body%name, 'geometry'))
         call file%put_line(indent // '</Geometry>')
      end subroutine put_mesh

      !> A point vector attribute `attribute` of `body` from its dataset `dataset`.
      subroutine put_field(body, attribute, dataset, indent)
         type(xdmf_body_t), intent(in) :: body
         character(len=*), intent(in) :: attribute, dataset, indent
         call file%put_line(indent // '<Attribute Name="' // attribute // &
            '" AttributeType="Vector" Center="Node">')
         call file%put_line(indent // '  ' // data_item(to_str(body%num_nodes) // ' 3', &
            'Float" Precision="8', body%name, dataset))
         call file%put_line(indent // '</Attribute>')
      end subroutine put_field

      !> A DataItem element naming dataset /xdmf/<body>/<dataset> of the results file.
      function data_item(dimensions, number_type, body_name, dataset) result(line)
         character(len=*), intent(in) :: dimensions, number_type, body_name, dataset
         character(len=:), allocatable :: line
         line = '<DataItem Dimensions="' // dimensions // '" NumberType="' // number_type // &
            '" Format="HDF">' // xml_escaped(h5_name // ':/xdmf/' // body_name // '/' // &
            dataset) // '</DataItem>'
      end function data_item
   end subroutine write_xdmf_file

   !> `text` with XML's special characters as entities (&amp; &lt; &gt; &quot;), for names in
   !> attribute values and element text.
   pure function xml_escaped(text) result(escaped)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: escaped
      !> The special characters and their entities, in the same order
      character(len=*), parameter :: special = '&<>"'
      character(len=6), parameter :: entities(4) = [character(len=6) :: '&amp;', '&lt;', &
         '&gt;', '&quot;']
      integer :: i, e
      escaped = ''
      do i = 1, len(text)
         e = index(special, text(i:i))
         if (e > 0) then
            escaped = escaped // trim(entities(e))
         else
            escaped = escaped // text(i:i)
         end if
      end do
   end function xml_escaped

end module ffrf_io_xdmf
