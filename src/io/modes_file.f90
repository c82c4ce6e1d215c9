!> Modes stored in a results file, for reuse by a later run (&body modes_file; docs/mode_reuse.md):
!> the fingerprint datasets every results file with modes holds (modal and mechanism runs),
!>
!>   /bodies/<body>/modes/fingerprint/{mesh, material, interfaces, modes}   `label=value` lists
!>   /bodies/<body>/modes/fingerprint/hash      'mesh <hex>', ..., 'modes <hex>', 'total <hex>'
!>
!> and the reader of a body's stored modes (frequencies, shapes, virtual-node rows, basis,
!> fingerprint). A file that cannot be opened as HDF5 or whose datasets cannot be read is
!> FFRF_IO_ERROR; a readable file without the body's modes or fingerprint, or with inconsistent
!> sizes, FFRF_INPUT_ERROR.
module ffrf_io_modes_file
   use ffrf_core_kinds, only: dp, i8
   use ffrf_core_error, only: error_t, fatal_error, add_context, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_posix, only: check_input_file
   use ffrf_io_hdf5, only: h5_file_t, H5_READ_ONLY
   use ffrf_io_schema, only: check_schema_version
   use ffrf_modes_fingerprint, only: modes_fingerprint_t, COMPONENT_NAMES, NUM_COMPONENTS
   implicit none
   private
   public :: stored_modes_t, fingerprint_dataset, write_fingerprint, read_stored_modes, &
      NUM_FINGERPRINT_DATASETS

   !> Datasets of a fingerprint: its four components and the hash list
   integer, parameter :: NUM_FINGERPRINT_DATASETS = NUM_COMPONENTS + 1
   !> Largest results file read for its modes (bytes): 1 TiB, i.e. no practical limit
   integer(i8), parameter :: MAX_MODES_FILE_BYTES = 1024_i8**4

   !> A body's modes as stored.
   type :: stored_modes_t
      real(dp), allocatable :: frequency_hz(:)
      !> (3 num_nodes, num_modes)
      real(dp), allocatable :: shape(:, :)
      !> (6 num_interfaces, num_modes)
      real(dp), allocatable :: virtual_node_shape(:, :)
      !> Craig-Bampton static modes in the basis (0 for rc_normal)
      integer :: num_static = 0
      type(modes_fingerprint_t) :: fingerprint
   end type stored_modes_t

contains

   !> Dataset k (1..NUM_FINGERPRINT_DATASETS) of a fingerprint: its name under
   !> /bodies/<body>/modes/fingerprint/ and its strings.
   subroutine fingerprint_dataset(fingerprint, k, name, values)
      type(modes_fingerprint_t), intent(in) :: fingerprint
      integer, intent(in) :: k
      character(len=:), allocatable, intent(out) :: name
      character(len=:), allocatable, intent(out) :: values(:)
      integer :: c
      if (k <= NUM_COMPONENTS) then
         name = trim(COMPONENT_NAMES(k))
         values = fingerprint%components(k)%entries
      else
         name = 'hash'
         allocate (character(len=32) :: values(NUM_COMPONENTS + 1))
         do c = 1, NUM_COMPONENTS
            values(c) = trim(COMPONENT_NAMES(c)) // ' ' // fingerprint%component_hash(c)
         end do
         values(NUM_COMPONENTS + 1) = 'total ' // fingerprint%total_hash()
      end if
   end subroutine fingerprint_dataset

   !> Write the fingerprint of body `body_name` (nothing when it is not set).
   subroutine write_fingerprint(h5, body_name, fingerprint, error)
      type(h5_file_t), intent(inout) :: h5
      character(len=*), intent(in) :: body_name
      type(modes_fingerprint_t), intent(in) :: fingerprint
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: name
      character(len=:), allocatable :: values(:)
      integer :: k
      if (.not. fingerprint%is_set()) return
      do k = 1, NUM_FINGERPRINT_DATASETS
         call fingerprint_dataset(fingerprint, k, name, values)
         call h5%write_string_list('/bodies/' // body_name // '/modes/fingerprint/' // name, &
            values, error)
         if (allocated(error)) return
      end do
   end subroutine write_fingerprint

   !> Read the modes of body `body_name` from the results file `file_name` (module header for
   !> the error codes). `what` names the file's role in messages ('modes_file').
   subroutine read_stored_modes(file_name, body_name, what, stored, error)
      character(len=*), intent(in) :: file_name, body_name, what
      type(stored_modes_t), intent(out) :: stored
      type(error_t), allocatable, intent(out) :: error
      type(h5_file_t) :: h5
      type(error_t), allocatable :: ignored
      character(len=:), allocatable :: root, where
      character(len=:), allocatable :: entries(:), bodies(:)
      integer :: k

      where = what // ' "' // file_name // '"'
      call check_input_file(file_name, what, MAX_MODES_FILE_BYTES, error)
      if (allocated(error)) return
      call h5%open(file_name, H5_READ_ONLY, error)
      if (allocated(error)) then
         error%message = where // ': not readable as HDF5 (' // error%message // &
            '); give the results file (.h5) of an earlier run that computed the modes'
         return
      end if
      root = '/bodies/' // body_name // '/modes'
      section: block
         call check_schema_version(h5, where, error)
         if (allocated(error)) exit section
         if (.not. h5%exists(root // '/shape')) then
            bodies = stored_bodies(h5)
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': no mode shapes of body "' // &
               body_name // '" in it (' // trim(stored_list(bodies)) // '); give the ' // &
               'results file of a run that computed this body''s modes')
            exit section
         end if
         if (.not. h5%exists(root // '/fingerprint/modes')) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': body "' // body_name // &
               '" has modes but no fingerprint (/bodies/' // body_name // '/modes/' // &
               'fingerprint): the file comes from an ffrf before mode reuse; compute the ' // &
               'modes again (a run without modes_file) to get a file that can be reused')
            exit section
         end if
         call h5%read_real(root // '/frequency', stored%frequency_hz, error)
         if (.not. allocated(error)) call h5%read_real(root // '/shape', stored%shape, error)
         if (.not. allocated(error)) call h5%read_real(root // '/virtual_node_shape', &
            stored%virtual_node_shape, error)
         do k = 1, NUM_COMPONENTS
            if (allocated(error)) exit
            call h5%read_string_list(root // '/fingerprint/' // trim(COMPONENT_NAMES(k)), &
               entries, error)
            if (.not. allocated(error)) stored%fingerprint%components(k)%entries = entries
         end do
         ! the number of static modes: an attribute in mechanism files, a dataset in modal ones
         if (.not. allocated(error)) then
            if (h5%attribute_exists(root, 'num_static_modes')) then
               call h5%read_attribute(root, 'num_static_modes', stored%num_static, error)
            else if (h5%exists(root // '/num_static_modes')) then
               call h5%read_int(root // '/num_static_modes', stored%num_static, error)
            end if
         end if
         if (allocated(error)) then
            ! a dataset that cannot be read: a damaged file (FFRF_IO_ERROR as HDF5 gave it)
            call add_context(error, where // ', body "' // body_name // '"')
            exit section
         end if
         if (size(stored%shape, 2) /= size(stored%frequency_hz) .or. &
            size(stored%virtual_node_shape, 2) /= size(stored%frequency_hz)) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // ', body "' // body_name // &
               '": ' // to_str(size(stored%frequency_hz)) // ' frequencies but ' // &
               to_str(size(stored%shape, 2)) // ' shapes and ' // &
               to_str(size(stored%virtual_node_shape, 2)) // ' virtual-node columns; the ' // &
               'file is damaged')
         end if
      end block section
      call h5%close(ignored)
   end subroutine read_stored_modes

   !> Names of the bodies with mode shapes in an open results file (the &body names of its
   !> input echo, /input/namelist, that have /bodies/<name>/modes/shape).
   function stored_bodies(h5) result(names)
      type(h5_file_t), intent(in) :: h5
      character(len=:), allocatable :: names(:)
      character(len=*), parameter :: key = '&body name = '''
      character(len=:), allocatable :: echo, rest, name
      type(error_t), allocatable :: error
      integer :: k, last
      allocate (character(len=64) :: names(0))
      if (.not. h5%exists('/input/namelist')) return
      call h5%read_string('/input/namelist', echo, error)
      if (allocated(error)) return
      rest = echo
      do
         k = index(rest, key)
         if (k == 0) exit
         rest = rest(k + len(key):)
         last = index(rest, '''')
         if (last <= 1) exit
         name = rest(:last - 1)
         if (h5%exists('/bodies/' // name // '/modes/shape')) &
            names = [character(len=64) :: names, name]
      end do
   end function stored_bodies

   function stored_list(bodies) result(text)
      character(len=*), intent(in) :: bodies(:)
      character(len=:), allocatable :: text
      integer :: k
      if (size(bodies) == 0) then
         text = 'no body with mode shapes found'
         return
      end if
      text = 'it holds the modes of'
      do k = 1, size(bodies)
         text = text // ' "' // trim(bodies(k)) // '"'
      end do
   end function stored_list

end module ffrf_io_modes_file
