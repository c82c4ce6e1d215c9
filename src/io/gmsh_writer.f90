!> Mode shapes for Gmsh: a Gmsh MSH 2.2 ASCII file (format described in the Gmsh reference
!> manual, "MSH file format version 2") holding the tetrahedral mesh and one `$NodeData` view per
!> mode, plus the option file `<file>.opt` that Gmsh merges on its own when it opens or merges
!> `<file>`.
!>
!> - Nodes get tags 1..num_nodes (the column of `xyz`), tetrahedra tags 1..num_tets, physical and
!>   elementary tag 1; element type 4 (4-node) or 11 (10-node), node order as Gmsh's own (the
!>   order the mesh reader keeps), so a mesh read from Gmsh goes back unchanged.
!> - View k is named "mode k: 812.4 Hz", has 3 components per node (the displacement of mode k,
!>   rows 3i-2..3i of `shapes` for node i) and one time step whose time value is the frequency.
!> - The .opt file shows each view as a displaced mesh (`View[k].VectorType = 5`, displacement)
!>   with a `DisplacementFactor` that makes the largest displacement 10% of the mesh's bounding
!>   box diagonal, shows only mode 1, and sets `PostProcessing.AnimationCycle = 1` so that
!>   Gmsh's play button steps through the modes. To see one mode oscillate, apply
!>   Tools > Plugins > HarmonicToTime (RealPart 0, ImaginaryPart 0) to its view: the result
!>   sqrt(2) cos(w t + pi/4) times the shape animates over its time steps.
!> `write_displacement_frames_msh` writes, in the same format, ONE view "elastic displacement"
!> with one time step per frame (time value = the frame's time in s), e.g. the elastic
!> deformation of a flexible body over an engine cycle in its body frame; its .opt file uses one
!> displacement factor for all frames and Gmsh's play button animates them; frame values are
!> written with 7 significant digits (for viewing, not for reading back).
!> Numbers are written with 17 significant digits, so they read back as the same doubles.
!> The .msh text is that of the formatted writes '(i0, 3(1x, es24.16e3))' (nodes, mode values;
!> es14.6e3 for frame values), '(*(i0, :, 1x))' (elements) and '(a)', byte for byte, but it is
!> formatted in memory and written in 1 MiB chunks (ffrf_io_text_stream, number_text.c): about
!> six to ten times faster than one WRITE per line (the engine's two animations, 8,100 nodes x
!> 24 frames, took 0.7 to 1.1 s of a 4 to 5 s run with reused modes that way).
!> Both files are written under `<file>.part`, checked to be whole on disk (a formatted write
!> does not report a full disk: the size on disk is compared with the size written), forced to
!> the device and renamed over their final names (an existing file is replaced only by a
!> complete one); on failure the `.part` files are removed and FFRF_IO_ERROR names the file.
module ffrf_io_gmsh_writer
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_kinds, only: dp, i8
   use ffrf_core_posix, only: file_kind, remove_file, commit_durably
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR, FFRF_IO_ERROR, &
      FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_io_text_stream, only: text_stream_t
   implicit none
   private
   public :: write_mode_shapes_msh, write_displacement_frames_msh, open_part, close_part

   !> Largest displacement drawn, as a fraction of the bounding-box diagonal
   real(dp), parameter :: shown_amplitude = 0.1_dp

contains

   !> Write `file_name` (MSH 2.2 ASCII) with the mesh and one displacement view per mode, and
   !> `file_name // '.opt'` with the display options (see the module notes).
   subroutine write_mode_shapes_msh(file_name, xyz, tets, shapes, frequencies_hz, error)
      !> Output file, e.g. 'crank_modes.msh'
      character(len=*), intent(in) :: file_name
      !> Node coordinates (3, num_nodes), m
      real(dp), intent(in) :: xyz(:, :)
      !> Tetrahedra (4 or 10, num_tets), 1-based node numbers, Gmsh node order
      integer, intent(in) :: tets(:, :)
      !> Mode shapes (3*num_nodes, num_modes): ux, uy, uz of node 1, then node 2, ...
      real(dp), intent(in) :: shapes(:, :)
      !> Natural frequencies (num_modes), Hz
      real(dp), intent(in) :: frequencies_hz(:)
      type(error_t), allocatable, intent(out) :: error
      call write_views(file_name, xyz, tets, shapes, frequencies_hz, .false., error)
   end subroutine write_mode_shapes_msh

   !> Write `file_name` (MSH 2.2 ASCII) with the mesh and one view of num_frames time steps, and
   !> its .opt file (module notes).
   subroutine write_displacement_frames_msh(file_name, xyz, tets, displacements, times, error)
      !> Output file, e.g. 'engine_rc1_crank_animation.msh'
      character(len=*), intent(in) :: file_name
      !> Node coordinates (3, num_nodes), m
      real(dp), intent(in) :: xyz(:, :)
      !> Tetrahedra (4 or 10, num_tets), 1-based node numbers, Gmsh node order
      integer, intent(in) :: tets(:, :)
      !> Displacements (3*num_nodes, num_frames): ux, uy, uz of node 1, then node 2, ...
      real(dp), intent(in) :: displacements(:, :)
      !> Time of each frame (s)
      real(dp), intent(in) :: times(:)
      type(error_t), allocatable, intent(out) :: error
      call write_views(file_name, xyz, tets, displacements, times, .true., error)
   end subroutine write_displacement_frames_msh

   !> The mesh and the views: one per column of `fields` (modes), or one view with a time step
   !> per column (`frames`).
   subroutine write_views(file_name, xyz, tets, shapes, frequencies_hz, frames, error)
      character(len=*), intent(in) :: file_name
      real(dp), intent(in) :: xyz(:, :)
      integer, intent(in) :: tets(:, :)
      real(dp), intent(in) :: shapes(:, :)
      !> Frequency of each mode (Hz), or time of each frame (s)
      real(dp), intent(in) :: frequencies_hz(:)
      logical, intent(in) :: frames
      type(error_t), allocatable, intent(out) :: error
      type(text_stream_t) :: file
      integer :: num_nodes, num_modes, mode, i, step, digits
      character(len=:), allocatable :: name
      integer :: element_type
      !> Significant digits of the values: 17 (read back as the same doubles, '(es24.16e3)');
      !> frames are for viewing: 7 digits ('(es14.6e3)') keep the files a third of the size
      integer, parameter :: exact_digits = 17, frame_digits = 7

      call check_input(file_name, xyz, tets, shapes, frequencies_hz, element_type, error)
      if (allocated(error)) return
      num_nodes = size(xyz, 2)
      num_modes = size(shapes, 2)

      ! The text is that of the formatted writes '(i0, 3(1x, es24.16e3))' (nodes, values),
      ! '(*(i0, :, 1x))' (elements) and '(a)', byte for byte, formatted in memory (text_stream)
      call open_part(file, file_name, 'Gmsh file', error)
      if (allocated(error)) return
      call file%put_line('$MeshFormat')
      call file%put_line('2.2 0 8')
      call file%put_line('$EndMeshFormat')
      call file%put_line('$Nodes')
      call file%put_integers([num_nodes])
      call file%put_tagged_es_lines(1, reshape(xyz, [3 * num_nodes]), exact_digits)
      call file%put_line('$EndNodes')
      call file%put_line('$Elements')
      call file%put_integers([size(tets, 2)])
      do i = 1, size(tets, 2)
         if (file%stat /= 0) exit
         ! tag, type, 2 tags (physical 1, elementary 1), nodes
         call file%put_integers([i, element_type, 2, 1, 1, tets(:, i)])
      end do
      call file%put_line('$EndElements')
      digits = exact_digits
      do mode = 1, num_modes
         if (file%stat /= 0) exit
         ! 1 string tag (name), 1 real tag (time = frequency), 3 integer tags (time step,
         ! components, entities)
         if (frames) then
            name = 'elastic displacement'
            step = mode - 1
         else
            name = view_name(mode, frequencies_hz(mode))
            step = 0
         end if
         call file%put_line('$NodeData')
         call file%put_integers([1])
         call file%put_line('"' // name // '"')
         call file%put_integers([1])
         call file%put_es(frequencies_hz(mode), exact_digits)
         call file%put_integers([3])
         call file%put_integers([step])
         call file%put_integers([3])
         call file%put_integers([num_nodes])
         if (frames) digits = frame_digits
         call file%put_tagged_es_lines(1, shapes(:, mode), digits)
         call file%put_line('$EndNodeData')
      end do
      call close_part(file, file_name, 'Gmsh file', error)
      if (allocated(error)) return
      call write_options(file_name // '.opt', xyz, shapes, frames, error)
      if (.not. allocated(error)) call commit_durably(file_name // '.part', file_name, 'Gmsh file', &
         error)
      if (.not. allocated(error)) call commit_durably(file_name // '.opt.part', file_name // '.opt', &
         'Gmsh option file', error)
      if (allocated(error)) then
         call remove_quietly(file_name // '.part')
         call remove_quietly(file_name // '.opt.part')
      end if
   end subroutine write_views

   !> Open `<file_name>.part` as the text stream `file` (`file_name`: its final name);
   !> FFRF_IO_ERROR "cannot write <what> ..." when it cannot be created.
   subroutine open_part(file, file_name, what, error)
      type(text_stream_t), intent(inout) :: file
      !> Final name, and what the file is ('Gmsh file'), for the message
      character(len=*), intent(in) :: file_name, what
      type(error_t), allocatable, intent(out) :: error
      call file%open(file_name // '.part')
      if (file%stat /= 0) call fatal_error(error, FFRF_IO_ERROR, 'cannot write ' // what // &
         ' "' // file_name // '": ' // trim(file%msg) // '; check that its folder exists and ' &
         // 'is writable')
   end subroutine open_part

   !> Flush the text stream `file` of `<file_name>.part`, close it and check that it is whole on
   !> disk (close_whole); on failure it is removed and FFRF_IO_ERROR names `what`.
   subroutine close_part(file, file_name, what, error)
      type(text_stream_t), intent(inout) :: file
      !> Final name, and what the file is ('Gmsh file'), for the message
      character(len=*), intent(in) :: file_name, what
      type(error_t), allocatable, intent(out) :: error
      call file%flush()
      if (file%stat /= 0) then
         close (file%unit, status='delete')
         call fatal_error(error, FFRF_IO_ERROR, 'writing ' // what // ' "' // file_name // &
            '" failed: ' // trim(file%msg) // ' (disk full, quota or file size limit?)')
         return
      end if
      call close_whole(file%unit, file_name // '.part', what // ' "' // file_name // '"', error)
   end subroutine close_part

   !> Close `unit` (the file `path`) and check that all it was written reached the file: the
   !> size on disk must equal the size the runtime wrote (a full disk or a file size limit
   !> truncates it silently). The file is removed on failure.
   subroutine close_whole(unit, path, what, error)
      integer, intent(in) :: unit
      character(len=*), intent(in) :: path, what
      type(error_t), allocatable, intent(out) :: error
      integer(i8) :: written, on_disk
      integer :: stat, kind
      character(len=512) :: msg
      written = -1
      inquire (unit=unit, size=written)
      flush (unit, iostat=stat, iomsg=msg)
      if (stat == 0) close (unit, iostat=stat, iomsg=msg)
      if (stat /= 0) then
         close (unit, iostat=stat)
         call remove_quietly(path)
         call fatal_error(error, FFRF_IO_ERROR, what // ' not written: closing "' // path // &
            '" failed: ' // trim(msg))
         return
      end if
      call file_kind(path, kind, on_disk, error)
      if (allocated(error)) return
      if (on_disk /= written .or. written < 0) then
         call remove_quietly(path)
         call fatal_error(error, FFRF_IO_ERROR, what // ' not written: only ' // &
            to_str(on_disk) // ' of its ' // to_str(written) // ' bytes reached "' // path // &
            '" (disk full, quota or file size limit?)')
      end if
   end subroutine close_whole

   !> Remove a file, ignoring errors (a missing file is fine).
   subroutine remove_quietly(path)
      character(len=*), intent(in) :: path
      type(error_t), allocatable :: ignored
      call remove_file(path, ignored)
   end subroutine remove_quietly

   !> Sizes, node numbers and finiteness of the input.
   subroutine check_input(file_name, xyz, tets, shapes, frequencies_hz, element_type, error)
      character(len=*), intent(in) :: file_name
      real(dp), intent(in) :: xyz(:, :)
      integer, intent(in) :: tets(:, :)
      real(dp), intent(in) :: shapes(:, :)
      real(dp), intent(in) :: frequencies_hz(:)
      !> Gmsh element type, 4 (tet4) or 11 (tet10)
      integer, intent(out) :: element_type
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: where
      integer :: num_nodes
      where = 'Gmsh file "' // file_name // '": '
      element_type = 0
      num_nodes = size(xyz, 2)
      if (size(xyz, 1) /= 3) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // 'xyz has ' // to_str(size(xyz, 1)) &
            // ' rows, must be 3 (x, y, z of each node)')
         return
      end if
      select case (size(tets, 1))
      case (4)
         element_type = 4
      case (10)
         element_type = 11
      case default
         call fatal_error(error, FFRF_INPUT_ERROR, where // 'tets has ' // &
            to_str(size(tets, 1)) // ' nodes per element, must be 4 or 10')
         return
      end select
      if (size(tets) > 0) then
         if (minval(tets) < 1 .or. maxval(tets) > num_nodes) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // 'tets use node numbers ' // &
               to_str(minval(tets)) // ' .. ' // to_str(maxval(tets)) // ', must lie in 1 .. ' &
               // to_str(num_nodes))
            return
         end if
      end if
      if (size(shapes, 1) /= 3 * num_nodes) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // 'shapes has ' // &
            to_str(size(shapes, 1)) // ' rows, must be 3*num_nodes = ' // to_str(3 * num_nodes))
         return
      end if
      if (size(frequencies_hz) /= size(shapes, 2)) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // to_str(size(frequencies_hz)) // &
            ' frequencies for ' // to_str(size(shapes, 2)) // ' mode shapes')
         return
      end if
      if (.not. (all(ieee_is_finite(xyz)) .and. all(ieee_is_finite(shapes)) .and. &
         all(ieee_is_finite(frequencies_hz)))) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, where // 'coordinates, shapes or ' // &
            'frequencies hold NaN or Inf')
      end if
   end subroutine check_input

   !> "mode 3: 812.4 Hz"
   function view_name(mode, frequency_hz) result(name)
      integer, intent(in) :: mode
      real(dp), intent(in) :: frequency_hz
      character(len=:), allocatable :: name
      name = 'mode ' // to_str(mode) // ': ' // to_str(frequency_hz, 6) // ' Hz'
   end function view_name

   !> The option file Gmsh merges after the mesh: displaced-mesh display of every view.
   subroutine write_options(file_name, xyz, shapes, frames, error)
      character(len=*), intent(in) :: file_name
      real(dp), intent(in) :: xyz(:, :)
      real(dp), intent(in) :: shapes(:, :)
      !> One view with a time step per column (one displacement factor for all)
      logical, intent(in) :: frames
      type(error_t), allocatable, intent(out) :: error
      character(len=512) :: msg
      character(len=:), allocatable :: view
      real(dp) :: diagonal, largest, factor
      integer :: unit, stat, mode, i
      diagonal = 0.0_dp
      if (size(xyz) > 0) diagonal = norm2(maxval(xyz, dim=2) - minval(xyz, dim=2))
      ! never through a link left at the name (issue 23; as text_stream_open)
      call remove_file(file_name // '.part', error)
      if (allocated(error)) return
      open (newunit=unit, file=file_name // '.part', status='new', action='write', &
         iostat=stat, iomsg=msg)
      if (stat /= 0) then
         call fatal_error(error, FFRF_IO_ERROR, 'cannot write Gmsh option file "' // &
            file_name // '": ' // trim(msg))
         return
      end if
      if (frames) then
         largest = 0.0_dp
         do i = 1, size(shapes, 1) / 3
            largest = max(largest, maxval(norm2(shapes(3 * i - 2:3 * i, :), dim=1)))
         end do
         factor = 1.0_dp
         if (largest > 0.0_dp .and. diagonal > 0.0_dp) factor = shown_amplitude * diagonal / &
            largest
         write (unit, '(a)', iostat=stat, iomsg=msg) &
            '// ffrf: elastic displacement frames, largest displacement 10% of the size', &
            'PostProcessing.AnimationCycle = 0; // the play button steps through the frames', &
            'View[0].VectorType = 5;', 'View[0].DisplacementFactor = ' // to_str(factor, 8) // ';'
      else
         write (unit, '(a)', iostat=stat, iomsg=msg) &
            '// ffrf: show each mode as a displaced mesh, largest displacement 10% of the size', &
            'PostProcessing.AnimationCycle = 1; // the play button steps through the modes'
      end if
      do mode = 1, merge(0, size(shapes, 2), frames)
         if (stat /= 0) exit
         largest = 0.0_dp
         do i = 1, size(shapes, 1) / 3
            largest = max(largest, norm2(shapes(3 * i - 2:3 * i, mode)))
         end do
         factor = 1.0_dp
         if (largest > 0.0_dp .and. diagonal > 0.0_dp) factor = shown_amplitude * diagonal / &
            largest
         view = 'View[' // to_str(mode - 1) // ']'
         write (unit, '(a)', iostat=stat, iomsg=msg) view // '.VectorType = 5;', &
            view // '.DisplacementFactor = ' // to_str(factor, 8) // ';', &
            view // '.Visible = ' // trim(merge('1', '0', mode == 1)) // ';'
      end do
      if (stat /= 0) then
         close (unit, status='delete')
         call fatal_error(error, FFRF_IO_ERROR, 'writing Gmsh option file "' // file_name // &
            '" failed: ' // trim(msg))
         return
      end if
      call close_whole(unit, file_name // '.part', 'Gmsh option file "' // file_name // '"', &
         error)
   end subroutine write_options

end module ffrf_io_gmsh_writer
