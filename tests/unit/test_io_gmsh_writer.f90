!> Tests of ffrf_io_gmsh_writer. The written file is read back by a small MSH 2.2 parser in this
!> file (independent of Gmsh and of the writer) and compared exactly: 17 significant digits
!> round-trip IEEE doubles. The real gmsh program (FFRF_GMSH, set by ctest) must load the file
!> and its .opt without error and find the same views and maxima, and must fail on a truncated
!> copy, which shows that the check can fail.
module test_io_gmsh_writer
   use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_positive_inf, ieee_negative_inf, &
      ieee_quiet_nan, ieee_is_nan
   use, intrinsic :: iso_fortran_env, only: int64
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR, FFRF_IO_ERROR, &
      FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_io_gmsh_writer, only: write_mode_shapes_msh, write_displacement_frames_msh
   use ffrf_io_text_stream, only: es_e3_text
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, report
   implicit none
   private
   public :: collect_io_gmsh_writer

   !> What the independent parser finds in a MSH 2.2 file.
   type :: msh_content_t
      character(len=:), allocatable :: version
      real(dp), allocatable :: xyz(:, :)
      integer, allocatable :: element_types(:)
      integer, allocatable :: elements(:, :)
      character(len=80), allocatable :: view_names(:)
      real(dp), allocatable :: view_times(:)
      !> (3*num_nodes, num_views)
      real(dp), allocatable :: values(:, :)
   end type msh_content_t

contains

   subroutine collect_io_gmsh_writer(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [ &
         new_unittest('tet4_read_back', test_tet4_read_back), &
         new_unittest('tet10_read_back', test_tet10_read_back), &
         new_unittest('gmsh_loads_file', test_gmsh_loads_file), &
         new_unittest('input_errors', test_input_errors), &
         new_unittest('number_text_as_formatted_write', test_number_text_as_formatted_write), &
         new_unittest('files_as_formatted_writes', test_files_as_formatted_writes)]
   end subroutine collect_io_gmsh_writer

   !> A unit cube cut into 6 tetrahedra (Kuhn triangulation around the diagonal 1-7), 8 nodes.
   subroutine cube_mesh(xyz, tets)
      real(dp), allocatable, intent(out) :: xyz(:, :)
      integer, allocatable, intent(out) :: tets(:, :)
      xyz = reshape([0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1] &
         * 1.0_dp, [3, 8])
      tets = reshape([1, 2, 3, 7, 1, 3, 4, 7, 1, 4, 8, 7, 1, 8, 5, 7, 1, 5, 6, 7, 1, 6, 2, 7], &
         [4, 6])
   end subroutine cube_mesh

   !> Analytic nodal fields: mode 1 u = (sin x, 0, z/3), mode 2 u = rotation about z, (-y, x, 0)
   !> times 1/7, mode 3 u = 0 (a zero view must still be written).
   subroutine analytic_shapes(xyz, shapes)
      real(dp), intent(in) :: xyz(:, :)
      real(dp), allocatable, intent(out) :: shapes(:, :)
      integer :: i
      allocate (shapes(3 * size(xyz, 2), 3))
      do i = 1, size(xyz, 2)
         shapes(3 * i - 2:3 * i, 1) = [sin(xyz(1, i) + 0.1_dp), 0.0_dp, xyz(3, i) / 3.0_dp]
         shapes(3 * i - 2:3 * i, 2) = [-xyz(2, i), xyz(1, i), 0.0_dp] / 7.0_dp
         shapes(3 * i - 2:3 * i, 3) = 0.0_dp
      end do
   end subroutine analytic_shapes

   !> Tet4 cube, 3 modes: nodes, elements (type 4), view names, times and values read back.
   subroutine test_tet4_read_back(error)
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: name
      real(dp), allocatable :: xyz(:, :), shapes(:, :)
      integer, allocatable :: tets(:, :)
      real(dp), parameter :: frequencies(3) = [812.4_dp, 1234.56789_dp, 20000.0_dp]
      type(msh_content_t) :: msh
      name = scratch('tet4.msh')
      call cube_mesh(xyz, tets)
      call analytic_shapes(xyz, shapes)
      call write_mode_shapes_msh(name, xyz, tets, shapes, frequencies, error)
      if (allocated(error)) return
      call read_msh(name, msh, error)
      if (allocated(error)) return
      call compare(msh, xyz, tets, 4, shapes, frequencies, error)
      if (allocated(error)) return
      call check(error, 'view names: "' // trim(msh%view_names(1)) // '", "' // &
         trim(msh%view_names(2)) // '", "' // trim(msh%view_names(3)) // '"', &
         msh%view_names(1) == 'mode 1: 812.4 Hz' .and. &
         msh%view_names(2) == 'mode 2: 1234.57 Hz' .and. &
         msh%view_names(3) == 'mode 3: 20000 Hz')
   end subroutine test_tet4_read_back

   !> One 10-node tetrahedron (corners then mid-edge nodes in Gmsh order: 0-1, 1-2, 2-0, 3-0,
   !> 3-2, 3-1), its node numbers deliberately not 1..10 in order, to catch a writer that
   !> renumbers.
   subroutine tet10_mesh(xyz, tets)
      real(dp), allocatable, intent(out) :: xyz(:, :)
      integer, allocatable, intent(out) :: tets(:, :)
      integer, parameter :: edges(2, 6) = reshape([1, 2, 2, 3, 3, 1, 4, 1, 4, 3, 4, 2], [2, 6])
      integer :: k
      allocate (xyz(3, 10), tets(10, 1))
      xyz(:, 1:4) = reshape([0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1] * 1.0_dp, [3, 4])
      do k = 1, 6
         xyz(:, 4 + k) = 0.5_dp * (xyz(:, edges(1, k)) + xyz(:, edges(2, k)))
      end do
      tets(:, 1) = [3, 1, 2, 4, 7, 5, 6, 10, 9, 8]
   end subroutine tet10_mesh

   !> Tet10: element type 11 with its 10 nodes in the given order.
   subroutine test_tet10_read_back(error)
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: name
      real(dp), allocatable :: xyz(:, :), shapes(:, :)
      integer, allocatable :: tets(:, :)
      type(msh_content_t) :: msh
      name = scratch('tet10.msh')
      call tet10_mesh(xyz, tets)
      call analytic_shapes(xyz, shapes)
      call write_mode_shapes_msh(name, xyz, tets, shapes, [100.0_dp, 200.0_dp, 300.0_dp], &
         error)
      if (allocated(error)) return
      call read_msh(name, msh, error)
      if (allocated(error)) return
      call compare(msh, xyz, tets, 11, shapes, [100.0_dp, 200.0_dp, 300.0_dp], error)
   end subroutine test_tet10_read_back

   !> gmsh (batch, `gmsh check.geo -`) merges the file, which also merges its .opt; the script
   !> checks the node and tetrahedron counts, the number of views, the largest displacement
   !> norm of each view (Gmsh's View.Max) against the one computed here (relative 1e-12: both
   !> come from the same 17-digit numbers) and that the .opt set displacement display; any
   !> Error makes gmsh exit 1. Done for the tet4 cube and the tet10; the same check on a copy
   !> missing its last lines must fail.
   subroutine test_gmsh_loads_file(error)
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: broken
      real(dp), allocatable :: xyz(:, :), shapes(:, :)
      integer, allocatable :: tets(:, :)
      character(len=:), allocatable :: name
      integer :: stat, mesh
      broken = scratch('broken.msh')
      do mesh = 1, 2
         if (mesh == 1) then
            call cube_mesh(xyz, tets)
            name = scratch('gmsh_tet4.msh')
         else
            call tet10_mesh(xyz, tets)
            name = scratch('gmsh_tet10.msh')
         end if
         call analytic_shapes(xyz, shapes)
         call write_mode_shapes_msh(name, xyz, tets, shapes, [1.0_dp, 2.0_dp, 3.0_dp], error)
         if (allocated(error)) return
         call write_check_script(name // '.geo', name, size(xyz, 2), size(tets, 2), shapes, &
            error)
         if (allocated(error)) return
         call run_gmsh(name // '.geo', name // '.log', stat, error)
         if (allocated(error)) return
         call check(error, 'gmsh loads ' // name // ' and its checks pass (exit status ' // &
            to_str(stat) // ', see ' // name // '.log)', stat == 0)
         if (allocated(error)) return
      end do

      ! the same options, the mesh file cut short: only the truncation can fail the check
      call copy_without_last_lines(name // '.opt', broken // '.opt', 0, error)
      if (allocated(error)) return
      call copy_without_last_lines(name, broken, 4, error)
      if (allocated(error)) return
      call write_check_script(broken // '.geo', broken, size(xyz, 2), size(tets, 2), shapes, &
         error)
      if (allocated(error)) return
      call run_gmsh(broken // '.geo', broken // '.log', stat, error)
      if (allocated(error)) return
      call check(error, 'gmsh fails on the truncated ' // broken // ' (exit status ' // &
         to_str(stat) // ')', stat /= 0)
   end subroutine test_gmsh_loads_file

   !> Wrong shapes, node numbers, element sizes, NaN and an unwritable folder: errors that name
   !> the file and the offending value.
   subroutine test_input_errors(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: xyz(:, :), shapes(:, :)
      integer, allocatable :: tets(:, :)
      type(error_t), allocatable :: e
      real(dp) :: f(3)
      integer :: bad_tets(8, 1)
      f = [1.0_dp, 2.0_dp, 3.0_dp]
      call cube_mesh(xyz, tets)
      call analytic_shapes(xyz, shapes)
      call write_mode_shapes_msh('no_such_folder_ffrf/modes.msh', xyz, tets, shapes, f, e)
      call expect(error, e, FFRF_IO_ERROR, 'missing folder', 'no_such_folder_ffrf/modes.msh')
      if (allocated(error)) return
      call write_mode_shapes_msh('bad.msh', xyz, tets, shapes(1:23, :), f, e)
      call expect(error, e, FFRF_INPUT_ERROR, 'short shapes', '3*num_nodes = 24')
      if (allocated(error)) return
      call write_mode_shapes_msh('bad.msh', xyz, tets, shapes, f(1:2), e)
      call expect(error, e, FFRF_INPUT_ERROR, 'frequency count', '2 frequencies for 3')
      if (allocated(error)) return
      bad_tets = 1
      call write_mode_shapes_msh('bad.msh', xyz, bad_tets, shapes, f, e)
      call expect(error, e, FFRF_INPUT_ERROR, '8-node elements', 'must be 4 or 10')
      if (allocated(error)) return
      tets(2, 3) = 9
      call write_mode_shapes_msh('bad.msh', xyz, tets, shapes, f, e)
      call expect(error, e, FFRF_INPUT_ERROR, 'node 9 of 8', 'must lie in 1 .. 8')
      if (allocated(error)) return
      tets(2, 3) = 3
      shapes(5, 2) = ieee_value(1.0_dp, ieee_positive_inf)
      call write_mode_shapes_msh('bad.msh', xyz, tets, shapes, f, e)
      call expect(error, e, FFRF_NUMERIC_ERROR, 'Inf in shapes', 'NaN or Inf')
   end subroutine test_input_errors

   !> Fails unless `actual` has `code` and its message holds `words`.
   subroutine expect(error, actual, code, what, words)
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable, intent(inout) :: actual
      integer, intent(in) :: code
      character(len=*), intent(in) :: what, words
      if (.not. allocated(actual)) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, what // ': expected an error, got none')
      else if (actual%code /= code .or. index(actual%message, words) == 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, what // ': expected code ' // &
            to_str(code) // ' and "' // words // '", got code ' // to_str(actual%code) // &
            ': ' // actual%message)
      else
         deallocate (actual)
      end if
   end subroutine expect

   !> Compare what was read with what was written, exactly.
   subroutine compare(msh, xyz, tets, element_type, shapes, frequencies, error)
      type(msh_content_t), intent(in) :: msh
      real(dp), intent(in) :: xyz(:, :), shapes(:, :), frequencies(:)
      integer, intent(in) :: tets(:, :), element_type
      type(error_t), allocatable, intent(out) :: error
      call check(error, 'format version "' // msh%version // '", expected "2.2 0 8"', &
         msh%version == '2.2 0 8')
      if (allocated(error)) return
      call check(error, to_str(size(msh%xyz, 2)) // ' nodes read, ' // to_str(size(xyz, 2)) &
         // ' written', all(shape(msh%xyz) == shape(xyz)))
      if (allocated(error)) return
      call check_close(error, 'max |xyz read - written|', maxval(abs(msh%xyz - xyz)), 0.0_dp, &
         atol=0.0_dp)
      if (allocated(error)) return
      call check(error, 'elements read equal those written', &
         all(shape(msh%elements) == shape(tets)) .and. all(msh%elements == tets))
      if (allocated(error)) return
      call check(error, 'all element types ' // to_str(element_type), &
         all(msh%element_types == element_type))
      if (allocated(error)) return
      call check(error, to_str(size(msh%values, 2)) // ' views read, ' // &
         to_str(size(shapes, 2)) // ' modes written', all(shape(msh%values) == shape(shapes)))
      if (allocated(error)) return
      call check_close(error, 'max |view values - shapes|', maxval(abs(msh%values - shapes)), &
         0.0_dp, atol=0.0_dp)
      if (allocated(error)) return
      call check_close(error, 'max |view time - frequency|', &
         maxval(abs(msh%view_times - frequencies)), 0.0_dp, atol=0.0_dp)
   end subroutine compare

   !> A minimal MSH 2.2 ASCII reader for this test: nodes (tags must be 1..n), elements with
   !> their tags skipped, and 3-component $NodeData blocks (one time step each).
   subroutine read_msh(file_name, msh, error)
      character(len=*), intent(in) :: file_name
      type(msh_content_t), intent(out) :: msh
      type(error_t), allocatable, intent(out) :: error
      character(len=256) :: line, msg
      integer :: unit, stat, n, i, tag, num_tags, num_views, ints(3), num_strings, num_reals
      integer :: fields(20)
      real(dp) :: time
      real(dp), allocatable :: values(:, :)
      character(len=80), allocatable :: names(:)
      real(dp), allocatable :: times(:)
      open (newunit=unit, file=file_name, status='old', action='read', iostat=stat, iomsg=msg)
      if (stat /= 0) then
         call fatal_error(error, FFRF_IO_ERROR, trim(msg))
         return
      end if
      num_views = 0
      allocate (names(0), times(0), msh%values(0, 0))
      do
         read (unit, '(a)', iostat=stat) line
         if (stat /= 0) exit
         select case (trim(line))
         case ('$MeshFormat')
            read (unit, '(a)', iostat=stat) line
            msh%version = trim(line)
         case ('$Nodes')
            read (unit, *, iostat=stat) n
            allocate (msh%xyz(3, n))
            do i = 1, n
               read (unit, *, iostat=stat) tag, msh%xyz(:, i)
               if (stat /= 0 .or. tag /= i) exit
            end do
         case ('$Elements')
            read (unit, *, iostat=stat) n
            allocate (msh%element_types(n))
            do i = 1, n
               read (unit, '(a)', iostat=stat) line
               read (line, *, iostat=stat) tag, msh%element_types(i), num_tags
               if (i == 1) then
                  select case (msh%element_types(1))
                  case (4)
                     allocate (msh%elements(4, n))
                  case (11)
                     allocate (msh%elements(10, n))
                  case default
                     exit
                  end select
               end if
               read (line, *, iostat=stat) fields(1:3 + num_tags + size(msh%elements, 1))
               msh%elements(:, i) = fields(4 + num_tags:3 + num_tags + size(msh%elements, 1))
            end do
         case ('$NodeData')
            read (unit, *, iostat=stat) num_strings
            read (unit, '(a)', iostat=stat) line
            read (unit, *, iostat=stat) num_reals
            read (unit, *, iostat=stat) time
            read (unit, *, iostat=stat) n
            read (unit, *, iostat=stat) ints
            if (stat /= 0 .or. num_strings /= 1 .or. num_reals /= 1 .or. n /= 3 .or. &
               ints(2) /= 3) exit
            allocate (values(3 * ints(3), num_views + 1))
            if (num_views > 0) values(:, 1:num_views) = msh%values
            do i = 1, ints(3)
               read (unit, *, iostat=stat) tag, values(3 * tag - 2:3 * tag, num_views + 1)
            end do
            call move_alloc(values, msh%values)
            num_views = num_views + 1
            line = adjustl(line)
            names = [character(len=80) :: names, line(2:index(line, '"', back=.true.) - 1)]
            times = [times, time]
         case default
            continue  ! other sections and end markers
         end select
         if (stat /= 0) exit
      end do
      close (unit)
      if (.not. is_iostat_end(stat)) then
         call fatal_error(error, FFRF_IO_ERROR, file_name // ': unexpected content near "' // &
            trim(line) // '"')
         return
      end if
      msh%view_names = names
      msh%view_times = times
      if (.not. (allocated(msh%xyz) .and. allocated(msh%elements))) then
         call fatal_error(error, FFRF_IO_ERROR, file_name // ': no $Nodes or no tetrahedra')
      end if
   end subroutine read_msh

   !> A Gmsh script that merges `msh_file` and raises an Error (exit status 1) unless it finds
   !> num_nodes nodes, num_tets tetrahedra, one view per column of `shapes` whose View.Max is
   !> the largest nodal displacement norm of that column, and displacement display from the .opt.
   subroutine write_check_script(script, msh_file, num_nodes, num_tets, shapes, error)
      character(len=*), intent(in) :: script, msh_file
      integer, intent(in) :: num_nodes, num_tets
      real(dp), intent(in) :: shapes(:, :)
      type(error_t), allocatable, intent(out) :: error
      integer :: unit, stat, k, i
      real(dp) :: largest
      character(len=256) :: msg
      character(len=:), allocatable :: view, expected
      open (newunit=unit, file=script, status='replace', action='write', iostat=stat, &
         iomsg=msg)
      if (stat /= 0) then
         call fatal_error(error, FFRF_IO_ERROR, trim(msg))
         return
      end if
      write (unit, '(a)') 'Merge "' // msh_file // '";', &
         'If (Mesh.NbNodes != ' // to_str(num_nodes) // ' || Mesh.NbTetrahedra != ' // &
         to_str(num_tets) // ')', &
         '  Error("found %g nodes and %g tetrahedra", Mesh.NbNodes, Mesh.NbTetrahedra);', &
         'EndIf', &
         'If (PostProcessing.NbViews != ' // to_str(size(shapes, 2)) // ')', &
         '  Error("expected ' // to_str(size(shapes, 2)) // ' views, found %g", ' // &
         'PostProcessing.NbViews);', 'EndIf'
      do k = 1, size(shapes, 2)
         largest = 0.0_dp
         do i = 1, num_nodes
            largest = max(largest, norm2(shapes(3 * i - 2:3 * i, k)))
         end do
         view = 'View[' // to_str(k - 1) // ']'
         expected = to_str(largest, 17)
         write (unit, '(a)') 'If (Fabs(' // view // '.Max - ' // expected // ') > 1e-12 * ' &
            // expected // ' + 1e-30)', &
            '  Error("' // view // '.Max = %.17g, expected ' // expected // '", ' // view // &
            '.Max);', 'EndIf', &
            'If (' // view // '.VectorType != 5)', &
            '  Error("' // view // ': displacement display not set by the .opt file");', 'EndIf'
      end do
      close (unit)
   end subroutine write_check_script

   !> Run the gmsh program on a check script in batch mode; `stat` is its exit status.
   subroutine run_gmsh(script, log_file, stat, error)
      character(len=*), intent(in) :: script, log_file
      integer, intent(out) :: stat
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: gmsh
      integer :: length, env_stat, command_stat
      character(len=256) :: msg
      call get_environment_variable('FFRF_GMSH', length=length, status=env_stat)
      if (env_stat == 0 .and. length > 0) then
         allocate (character(len=length) :: gmsh)
         call get_environment_variable('FFRF_GMSH', gmsh)
      else
         gmsh = 'gmsh'
      end if
      stat = -1
      msg = ''
      call execute_command_line(gmsh // ' ' // script // ' - > ' // log_file // ' 2>&1', &
         exitstat=stat, cmdstat=command_stat, cmdmsg=msg)
      if (command_stat /= 0) call fatal_error(error, FFRF_IO_ERROR, 'cannot run "' // gmsh // &
         '": ' // trim(msg))
   end subroutine run_gmsh

   !> Copy a text file without its last `drop` lines.
   subroutine copy_without_last_lines(source, target, drop, error)
      character(len=*), intent(in) :: source, target
      integer, intent(in) :: drop
      type(error_t), allocatable, intent(out) :: error
      character(len=256), allocatable :: lines(:)
      character(len=256) :: line
      integer :: in, out, stat, n, i
      open (newunit=in, file=source, status='old', action='read', iostat=stat)
      if (stat /= 0) then
         call fatal_error(error, FFRF_IO_ERROR, 'cannot read ' // source)
         return
      end if
      allocate (lines(0))
      do
         read (in, '(a)', iostat=stat) line
         if (stat /= 0) exit
         lines = [character(len=256) :: lines, line]
      end do
      close (in)
      n = size(lines) - drop
      open (newunit=out, file=target, status='replace', action='write', iostat=stat)
      if (stat /= 0) then
         call fatal_error(error, FFRF_IO_ERROR, 'cannot write ' // target)
         return
      end if
      do i = 1, n
         write (out, '(a)') trim(lines(i))
      end do
      close (out)
   end subroutine copy_without_last_lines

   !> Values whose text is awkward: zeros of both signs, the extremes of the exponent (subnormal,
   !> huge), roundings that carry into the exponent (the largest double below 1: 17 digits keep
   !> it, 7 round it to 1.000000E+000), exact ties at 7 digits (12345665 and 12345675: ties to
   !> even), numbers next to powers of ten, negative numbers.
   function awkward_values() result(values)
      real(dp), allocatable :: values(:)
      real(dp) :: zero
      zero = 0.0_dp
      values = [zero, -zero, 1.0e-300_dp, 1.0e+300_dp, -1.0e-300_dp, nearest(1.0_dp, -1.0_dp), &
         -nearest(1.0_dp, -1.0_dp), nearest(1.0_dp, 1.0_dp), 9.9999995e-1_dp, 0.99999995_dp, &
         12345665.0_dp, 12345675.0_dp, -12345675.0_dp, 0.5_dp, -1.5_dp, 1.0e22_dp, 1.0e23_dp, &
         nearest(1.0e23_dp, -1.0_dp), 1.0e-3_dp, 0.1_dp, 1.0_dp / 3.0_dp, -2.0_dp / 3.0_dp, &
         huge(1.0_dp), -huge(1.0_dp), tiny(1.0_dp), transfer(1_int64, 1.0_dp), &
         -transfer(1_int64, 1.0_dp), transfer(shiftr(huge(1_int64), 20), 1.0_dp), 812.4_dp, &
         1234.56789_dp, 2.0_dp**60, 123456789012345678.0_dp, 9.999999999999999e-5_dp]
   end function awkward_values

   !> The text of numbers made in memory (es_e3_text, number_text.c) against gfortran's own
   !> formatted WRITE of the same number with '(es24.16e3)' and '(es14.6e3)' (the independent
   !> reference: what the writer used before), exact bytes: the awkward values, NaN and +-Inf
   !> (the writer refuses them; the text is still gfortran's), and 20,000 pseudo-random bit
   !> patterns spread over the whole range of finite doubles.
   subroutine test_number_text_as_formatted_write(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: values(:)
      character(len=24) :: exact
      character(len=14) :: short
      integer(int64) :: state
      real(dp) :: x
      integer :: i, num_random, compared
      num_random = 20000
      values = [awkward_values(), ieee_value(1.0_dp, ieee_quiet_nan), &
         ieee_value(1.0_dp, ieee_positive_inf), ieee_value(1.0_dp, ieee_negative_inf)]
      state = 88172645463325252_int64
      compared = 0
      do i = 1, size(values) + num_random
         if (i <= size(values)) then
            x = values(i)
         else
            ! xorshift64: bit patterns of any sign and exponent; NaN and Inf skipped
            state = ieor(state, shiftl(state, 13))
            state = ieor(state, shiftr(state, 7))
            state = ieor(state, shiftl(state, 17))
            x = transfer(state, x)
            if (ieee_is_nan(x) .or. abs(x) > huge(x)) cycle
         end if
         write (exact, '(es24.16e3)') x
         write (short, '(es14.6e3)') x
         compared = compared + 1
         if (es_e3_text(x, 17) /= exact .or. es_e3_text(x, 7) /= short) then
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'value ' // to_str(i) // ': "' // &
               es_e3_text(x, 17) // '" / "' // es_e3_text(x, 7) // '", expected "' // exact // &
               '" / "' // short // '" (formatted write)')
            return
         end if
      end do
      call report('numbers compared with the formatted write, exact: ' // to_str(compared))
      call check(error, 'numbers compared: ' // to_str(compared), compared > size(values) + &
         num_random / 2)
   end subroutine test_number_text_as_formatted_write

   !> The files of write_mode_shapes_msh and write_displacement_frames_msh, byte for byte, against
   !> files written here by formatted WRITE statements in the MSH 2.2 layout (the writer's code
   !> before it formatted in memory): a Tet10 with the awkward values as coordinates and fields,
   !> and a mesh of 30,000 nodes (more than the writer's 1 MiB chunk holds: the chunk seams).
   subroutine test_files_as_formatted_writes(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: xyz(:, :), shapes(:, :), values(:)
      integer, allocatable :: tets(:, :)
      integer :: i, num_nodes
      call tet10_mesh(xyz, tets)
      values = awkward_values()
      allocate (shapes(3 * size(xyz, 2), 4))
      do i = 1, size(shapes)
         shapes(mod(i - 1, size(shapes, 1)) + 1, (i - 1) / size(shapes, 1) + 1) = &
            values(mod(7 * i, size(values)) + 1)
      end do
      xyz = reshape([(values(mod(i, size(values)) + 1), i = 1, size(xyz))], shape(xyz))
      call compare_with_formatted(xyz, tets, shapes, [812.4_dp, -0.0_dp, 1.0e-300_dp, &
         nearest(1.0_dp, -1.0_dp)], 'awkward', error)
      if (allocated(error)) return
      num_nodes = 30000
      deallocate (xyz, tets, shapes)
      allocate (xyz(3, num_nodes), shapes(3 * num_nodes, 2), tets(4, num_nodes - 3))
      do i = 1, num_nodes
         xyz(:, i) = [sin(real(i, dp)), cos(real(i, dp)) * 1.0e-3_dp, real(i, dp) / 7.0_dp]
      end do
      shapes(:, 1) = [(sin(0.1_dp * i) * 1.0e-5_dp, i = 1, 3 * num_nodes)]
      shapes(:, 2) = [(cos(0.1_dp * i) * 1.0e+5_dp, i = 1, 3 * num_nodes)]
      tets = reshape([(i, i + 1, i + 2, i + 3, i = 1, num_nodes - 3)], shape(tets))
      call compare_with_formatted(xyz, tets, shapes, [1.0_dp, 2.0_dp], 'large', error)
   end subroutine test_files_as_formatted_writes

   !> Both writers against the formatted reference (reference_msh), exact bytes.
   subroutine compare_with_formatted(xyz, tets, shapes, times, label, error)
      real(dp), intent(in) :: xyz(:, :)
      integer, intent(in) :: tets(:, :)
      real(dp), intent(in) :: shapes(:, :), times(:)
      character(len=*), intent(in) :: label
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: name, reference, written, expected
      logical :: frames
      integer :: pass, at
      do pass = 1, 2
         frames = pass == 2
         name = scratch(label // trim(merge('_frames', '_modes ', frames)) // '.msh')
         reference = scratch(label // trim(merge('_frames', '_modes ', frames)) // '_ref.msh')
         if (frames) then
            call write_displacement_frames_msh(name, xyz, tets, shapes, times, error)
         else
            call write_mode_shapes_msh(name, xyz, tets, shapes, times, error)
         end if
         if (allocated(error)) return
         call reference_msh(reference, xyz, tets, shapes, times, frames, error)
         if (allocated(error)) return
         call file_bytes(name, written, error)
         if (allocated(error)) return
         call file_bytes(reference, expected, error)
         if (allocated(error)) return
         if (written == expected) cycle
         do at = 1, min(len(written), len(expected))
            if (written(at:at) /= expected(at:at)) exit
         end do
         call fatal_error(error, FFRF_NUMERIC_ERROR, name // ' (' // to_str(len(written)) // &
            ' bytes) differs from its formatted reference (' // to_str(len(expected)) // &
            ' bytes) from byte ' // to_str(at) // ': "' // &
            written(max(1, at - 30):min(len(written), at + 30)) // '"')
         return
      end do
   end subroutine compare_with_formatted

   !> The MSH 2.2 file as formatted WRITE statements make it: the layout of the module notes of
   !> ffrf_io_gmsh_writer ('(i0, 3(1x, es24.16e3))' per node and mode value, es14.6e3 for frame
   !> values, '(*(i0, :, 1x))' per element).
   subroutine reference_msh(file_name, xyz, tets, shapes, times, frames, error)
      character(len=*), intent(in) :: file_name
      real(dp), intent(in) :: xyz(:, :)
      integer, intent(in) :: tets(:, :)
      real(dp), intent(in) :: shapes(:, :), times(:)
      logical, intent(in) :: frames
      type(error_t), allocatable, intent(out) :: error
      integer :: unit, stat, i, mode
      character(len=512) :: msg
      character(len=:), allocatable :: name, line
      open (newunit=unit, file=file_name, status='replace', action='write', iostat=stat, &
         iomsg=msg)
      if (stat == 0) write (unit, '(a / a / a / a / i0)', iostat=stat, iomsg=msg) &
         '$MeshFormat', '2.2 0 8', '$EndMeshFormat', '$Nodes', size(xyz, 2)
      do i = 1, size(xyz, 2)
         if (stat == 0) write (unit, '(i0, 3(1x, es24.16e3))', iostat=stat, iomsg=msg) i, &
            xyz(:, i)
      end do
      if (stat == 0) write (unit, '(a / a / i0)', iostat=stat, iomsg=msg) '$EndNodes', &
         '$Elements', size(tets, 2)
      do i = 1, size(tets, 2)
         if (stat == 0) write (unit, '(*(i0, :, 1x))', iostat=stat, iomsg=msg) i, &
            merge(4, 11, size(tets, 1) == 4), 2, 1, 1, tets(:, i)
      end do
      if (stat == 0) write (unit, '(a)', iostat=stat, iomsg=msg) '$EndElements'
      line = '(i0, 3(1x, es24.16e3))'
      if (frames) line = '(i0, 3(1x, es14.6e3))'
      do mode = 1, size(shapes, 2)
         name = 'elastic displacement'
         if (.not. frames) name = 'mode ' // to_str(mode) // ': ' // to_str(times(mode), 6) // &
            ' Hz'
         if (stat == 0) write (unit, '(a / i0 / a / i0 / es24.16e3 / i0 / i0 / i0 / i0)', &
            iostat=stat, iomsg=msg) '$NodeData', 1, '"' // name // '"', 1, times(mode), 3, &
            merge(mode - 1, 0, frames), 3, size(xyz, 2)
         do i = 1, size(xyz, 2)
            if (stat == 0) write (unit, line, iostat=stat, iomsg=msg) i, &
               shapes(3 * i - 2:3 * i, mode)
         end do
         if (stat == 0) write (unit, '(a)', iostat=stat, iomsg=msg) '$EndNodeData'
      end do
      if (stat == 0) close (unit, iostat=stat, iomsg=msg)
      if (stat /= 0) call fatal_error(error, FFRF_IO_ERROR, file_name // ': ' // trim(msg))
   end subroutine reference_msh

   !> The whole content of a file.
   subroutine file_bytes(file_name, content, error)
      character(len=*), intent(in) :: file_name
      character(len=:), allocatable, intent(out) :: content
      type(error_t), allocatable, intent(out) :: error
      integer :: unit, stat, size_bytes
      character(len=512) :: msg
      open (newunit=unit, file=file_name, access='stream', form='unformatted', status='old', &
         action='read', iostat=stat, iomsg=msg)
      if (stat == 0) inquire (unit=unit, size=size_bytes, iostat=stat, iomsg=msg)
      if (stat == 0) then
         allocate (character(len=size_bytes) :: content)
         read (unit, iostat=stat, iomsg=msg) content
         close (unit)
      end if
      if (stat /= 0) call fatal_error(error, FFRF_IO_ERROR, file_name // ': ' // trim(msg))
   end subroutine file_bytes

   !> `suffix` prefixed by this executable's name ("test_io_hdf5_real.h5"): the files of the
   !> plain and the _checked build of the suite never collide when ctest runs both at once.
   function scratch(suffix) result(name)
      character(len=*), intent(in) :: suffix
      character(len=:), allocatable :: name
      character(len=512) :: program
      call get_command_argument(0, program)
      name = trim(program(index(program, '/', back=.true.) + 1:)) // '_' // suffix
   end function scratch

end module test_io_gmsh_writer

program main_io_gmsh_writer
   use ffrf_testing, only: unittest_t, run_suite
   use test_io_gmsh_writer, only: collect_io_gmsh_writer
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_io_gmsh_writer(tests)
   call run_suite('test_io_gmsh_writer', tests)
end program main_io_gmsh_writer
