!> A thin, safe wrapper over the HDF5 Fortran API: the rest of ffrf writes and reads results
!> through `h5_file_t` and never sees an HDF5 handle.
!>
!> - Paths are absolute, '/bodies/crank/modes/frequency'; missing intermediate groups are created
!>   on write. Writing to a path that holds a dataset replaces it; a group there is an error.
!> - Every dataset of physical values carries a string attribute `units` (SI, '1' when
!>   dimensionless): `write_real` and `create_series` require it.
!> - Strings are fixed-length, NUL-padded (h5py reads them as `bytes`: `.decode()` them).
!> - Array order: HDF5's Fortran API reverses the dimensions, so a Fortran array `(n, m)` appears
!>   in h5py/C as `(m, n)` with the same bytes: `xyz(3, num_nodes)` reads as `(num_nodes, 3)`.
!>   Time series grow along the last Fortran dimension, i.e. the first h5py axis.
!> - Every h5* call is checked; a failure (hdferr < 0) becomes an `error_t` (FFRF_IO_ERROR) naming
!>   the file and the path. HDF5's own error printing is switched off (`h5eset_auto_f(0)`) when
!>   the library is initialised, lazily, by the first `create` or `open`.
module ffrf_io_hdf5
   use ffrf_core_kinds, only: dp, i8
   use ffrf_core_error, only: error_t
   use hdf5, only: hid_t
   implicit none
   private
   public :: h5_file_t, H5_READ_ONLY, H5_READ_WRITE

   integer, parameter :: H5_READ_ONLY = 1   !< h5_file_t%open: read only
   integer, parameter :: H5_READ_WRITE = 2  !< h5_file_t%open: read and write

   !> One HDF5 file, open or closed. Components are private: use the type-bound procedures.
   type :: h5_file_t
      private
      !> HDF5 file identifier, -1 when closed
      integer(hid_t) :: id = -1
      !> File name, for messages
      character(len=:), allocatable :: name
      !> False when opened H5_READ_ONLY
      logical :: writable = .false.
   contains
      procedure :: create => h5_file_create
      procedure :: open => h5_file_open
      procedure :: close => h5_file_close
      procedure :: flush => h5_file_flush
      procedure :: is_open => h5_file_is_open
      procedure :: exists => h5_file_exists
      procedure :: attribute_exists => h5_file_attribute_exists
      generic :: write_real => write_real_0d, write_real_1d, write_real_2d
      generic :: write_int => write_int_0d, write_int_1d, write_int_2d, write_long_0d, &
         write_long_1d, write_long_2d
      procedure :: write_string => h5_file_write_string
      procedure :: write_string_list => h5_file_write_string_list
      generic :: read_real => read_real_0d, read_real_1d, read_real_2d
      generic :: read_int => read_int_0d, read_int_1d, read_int_2d, read_long_0d, read_long_1d, &
         read_long_2d
      procedure :: read_string => h5_file_read_string
      procedure :: read_string_list => h5_file_read_string_list
      generic :: set_attribute => set_attribute_string, set_attribute_real, set_attribute_int
      generic :: read_attribute => read_attribute_string, read_attribute_real, &
         read_attribute_int
      procedure :: set_status => h5_file_set_status
      procedure :: get_status => h5_file_get_status
      procedure :: create_series => h5_file_create_series
      generic :: append => append_real_0d, append_real_1d, append_real_2d
      procedure :: series_length => h5_file_series_length
      procedure, private :: write_real_0d, write_real_1d, write_real_2d
      procedure, private :: write_int_0d, write_int_1d, write_int_2d
      procedure, private :: write_long_0d, write_long_1d, write_long_2d
      procedure, private :: read_real_0d, read_real_1d, read_real_2d
      procedure, private :: read_int_0d, read_int_1d, read_int_2d
      procedure, private :: read_long_0d, read_long_1d, read_long_2d
      procedure, private :: set_attribute_string, set_attribute_real, set_attribute_int
      procedure, private :: read_attribute_string, read_attribute_real, read_attribute_int
      procedure, private :: append_real_0d, append_real_1d, append_real_2d
   end type h5_file_t

   interface

      ! ------------------------------------------------------------------ file

      !> Create `file_name`, truncating an existing file, open for reading and writing.
      module subroutine h5_file_create(self, file_name, error)
         class(h5_file_t), intent(inout) :: self
         !> File to create
         character(len=*), intent(in) :: file_name
         type(error_t), allocatable, intent(out) :: error
      end subroutine h5_file_create

      !> Open an existing file: `mode` H5_READ_ONLY or H5_READ_WRITE.
      module subroutine h5_file_open(self, file_name, mode, error)
         class(h5_file_t), intent(inout) :: self
         !> File to open
         character(len=*), intent(in) :: file_name
         !> H5_READ_ONLY or H5_READ_WRITE
         integer, intent(in) :: mode
         type(error_t), allocatable, intent(out) :: error
      end subroutine h5_file_open

      !> Close the file (nothing to do when it is not open).
      module subroutine h5_file_close(self, error)
         class(h5_file_t), intent(inout) :: self
         type(error_t), allocatable, intent(out) :: error
      end subroutine h5_file_close

      !> Write buffered data to disk, so that a reader sees it while the run goes on.
      module subroutine h5_file_flush(self, error)
         class(h5_file_t), intent(inout) :: self
         type(error_t), allocatable, intent(out) :: error
      end subroutine h5_file_flush

      !> True while a file is open.
      module logical function h5_file_is_open(self) result(is_open)
         class(h5_file_t), intent(in) :: self
      end function h5_file_is_open

      !> True if `path` names a group or dataset ('/' is the root group); false if the file is
      !> closed or the path is malformed.
      module logical function h5_file_exists(self, path) result(found)
         class(h5_file_t), intent(in) :: self
         !> Absolute path
         character(len=*), intent(in) :: path
      end function h5_file_exists

      !> True if the object at `path` has an attribute `name`.
      module logical function h5_file_attribute_exists(self, path, name) result(found)
         class(h5_file_t), intent(in) :: self
         !> Absolute path of a group or dataset
         character(len=*), intent(in) :: path
         !> Attribute name
         character(len=*), intent(in) :: name
      end function h5_file_attribute_exists

      ! ------------------------------------------------------------------ writers

      !> Write a real scalar dataset with its `units` attribute.
      module subroutine write_real_0d(self, path, value, units, error)
         class(h5_file_t), intent(inout) :: self
         !> Absolute dataset path
         character(len=*), intent(in) :: path
         !> Value (SI)
         real(dp), intent(in), target :: value
         !> Units attribute, e.g. 'Hz', 'kg m^2', '1'
         character(len=*), intent(in) :: units
         type(error_t), allocatable, intent(out) :: error
      end subroutine write_real_0d

      !> Write a real 1D dataset with its `units` attribute.
      module subroutine write_real_1d(self, path, value, units, error)
         class(h5_file_t), intent(inout) :: self
         !> Absolute dataset path
         character(len=*), intent(in) :: path
         !> Values (SI)
         real(dp), intent(in), target, contiguous :: value(:)
         !> Units attribute
         character(len=*), intent(in) :: units
         type(error_t), allocatable, intent(out) :: error
      end subroutine write_real_1d

      !> Write a real 2D dataset (h5py sees the transposed shape) with its `units` attribute.
      module subroutine write_real_2d(self, path, value, units, error)
         class(h5_file_t), intent(inout) :: self
         !> Absolute dataset path
         character(len=*), intent(in) :: path
         !> Values (SI), Fortran (n, m) = h5py (m, n)
         real(dp), intent(in), target, contiguous :: value(:, :)
         !> Units attribute
         character(len=*), intent(in) :: units
         type(error_t), allocatable, intent(out) :: error
      end subroutine write_real_2d

      !> Write a default-integer scalar dataset (no units: counts, indices, tags).
      module subroutine write_int_0d(self, path, value, error)
         class(h5_file_t), intent(inout) :: self
         !> Absolute dataset path
         character(len=*), intent(in) :: path
         !> Value
         integer, intent(in), target :: value
         type(error_t), allocatable, intent(out) :: error
      end subroutine write_int_0d

      !> Write a default-integer 1D dataset.
      module subroutine write_int_1d(self, path, value, error)
         class(h5_file_t), intent(inout) :: self
         !> Absolute dataset path
         character(len=*), intent(in) :: path
         !> Values
         integer, intent(in), target, contiguous :: value(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine write_int_1d

      !> Write a default-integer 2D dataset (h5py sees the transposed shape).
      module subroutine write_int_2d(self, path, value, error)
         class(h5_file_t), intent(inout) :: self
         !> Absolute dataset path
         character(len=*), intent(in) :: path
         !> Values, Fortran (n, m) = h5py (m, n)
         integer, intent(in), target, contiguous :: value(:, :)
         type(error_t), allocatable, intent(out) :: error
      end subroutine write_int_2d

      !> Write a 64-bit integer scalar dataset.
      module subroutine write_long_0d(self, path, value, error)
         class(h5_file_t), intent(inout) :: self
         !> Absolute dataset path
         character(len=*), intent(in) :: path
         !> Value
         integer(i8), intent(in), target :: value
         type(error_t), allocatable, intent(out) :: error
      end subroutine write_long_0d

      !> Write a 64-bit integer 1D dataset.
      module subroutine write_long_1d(self, path, value, error)
         class(h5_file_t), intent(inout) :: self
         !> Absolute dataset path
         character(len=*), intent(in) :: path
         !> Values
         integer(i8), intent(in), target, contiguous :: value(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine write_long_1d

      !> Write a 64-bit integer 2D dataset (h5py sees the transposed shape).
      module subroutine write_long_2d(self, path, value, error)
         class(h5_file_t), intent(inout) :: self
         !> Absolute dataset path
         character(len=*), intent(in) :: path
         !> Values, Fortran (n, m) = h5py (m, n)
         integer(i8), intent(in), target, contiguous :: value(:, :)
         type(error_t), allocatable, intent(out) :: error
      end subroutine write_long_2d

      !> Write a scalar string dataset holding `text` exactly (trailing blanks included).
      module subroutine h5_file_write_string(self, path, text, error)
         class(h5_file_t), intent(inout) :: self
         !> Absolute dataset path
         character(len=*), intent(in) :: path
         !> Text (may hold newlines, may be empty)
         character(len=*), intent(in) :: text
         type(error_t), allocatable, intent(out) :: error
      end subroutine h5_file_write_string

      !> Write a 1D dataset of strings, each with its trailing blanks removed.
      module subroutine h5_file_write_string_list(self, path, strings, error)
         class(h5_file_t), intent(inout) :: self
         !> Absolute dataset path
         character(len=*), intent(in) :: path
         !> Strings (may be an empty list)
         character(len=*), intent(in) :: strings(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine h5_file_write_string_list

      ! ------------------------------------------------------------------ readers

      !> Read a scalar real dataset (integer data are converted).
      module subroutine read_real_0d(self, path, value, error)
         class(h5_file_t), intent(in) :: self
         !> Absolute dataset path
         character(len=*), intent(in) :: path
         !> Value read
         real(dp), intent(out), target :: value
         type(error_t), allocatable, intent(out) :: error
      end subroutine read_real_0d

      !> Read a 1D real dataset.
      module subroutine read_real_1d(self, path, value, error)
         class(h5_file_t), intent(in) :: self
         !> Absolute dataset path
         character(len=*), intent(in) :: path
         !> Values read, allocated to the dataset's size
         real(dp), allocatable, target, intent(out) :: value(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine read_real_1d

      !> Read a 2D real dataset into its Fortran shape (h5py's shape reversed).
      module subroutine read_real_2d(self, path, value, error)
         class(h5_file_t), intent(in) :: self
         !> Absolute dataset path
         character(len=*), intent(in) :: path
         !> Values read, allocated to the dataset's Fortran shape
         real(dp), allocatable, target, intent(out) :: value(:, :)
         type(error_t), allocatable, intent(out) :: error
      end subroutine read_real_2d

      !> Read a scalar default-integer dataset.
      module subroutine read_int_0d(self, path, value, error)
         class(h5_file_t), intent(in) :: self
         !> Absolute dataset path
         character(len=*), intent(in) :: path
         !> Value read
         integer, intent(out), target :: value
         type(error_t), allocatable, intent(out) :: error
      end subroutine read_int_0d

      !> Read a 1D default-integer dataset.
      module subroutine read_int_1d(self, path, value, error)
         class(h5_file_t), intent(in) :: self
         !> Absolute dataset path
         character(len=*), intent(in) :: path
         !> Values read
         integer, allocatable, target, intent(out) :: value(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine read_int_1d

      !> Read a 2D default-integer dataset into its Fortran shape.
      module subroutine read_int_2d(self, path, value, error)
         class(h5_file_t), intent(in) :: self
         !> Absolute dataset path
         character(len=*), intent(in) :: path
         !> Values read
         integer, allocatable, target, intent(out) :: value(:, :)
         type(error_t), allocatable, intent(out) :: error
      end subroutine read_int_2d

      !> Read a scalar 64-bit integer dataset.
      module subroutine read_long_0d(self, path, value, error)
         class(h5_file_t), intent(in) :: self
         !> Absolute dataset path
         character(len=*), intent(in) :: path
         !> Value read
         integer(i8), intent(out), target :: value
         type(error_t), allocatable, intent(out) :: error
      end subroutine read_long_0d

      !> Read a 1D 64-bit integer dataset.
      module subroutine read_long_1d(self, path, value, error)
         class(h5_file_t), intent(in) :: self
         !> Absolute dataset path
         character(len=*), intent(in) :: path
         !> Values read
         integer(i8), allocatable, target, intent(out) :: value(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine read_long_1d

      !> Read a 2D 64-bit integer dataset into its Fortran shape.
      module subroutine read_long_2d(self, path, value, error)
         class(h5_file_t), intent(in) :: self
         !> Absolute dataset path
         character(len=*), intent(in) :: path
         !> Values read
         integer(i8), allocatable, target, intent(out) :: value(:, :)
         type(error_t), allocatable, intent(out) :: error
      end subroutine read_long_2d

      !> Read a scalar string dataset (fixed-length; padding removed).
      module subroutine h5_file_read_string(self, path, text, error)
         class(h5_file_t), intent(in) :: self
         !> Absolute dataset path
         character(len=*), intent(in) :: path
         !> Text read
         character(len=:), allocatable, intent(out) :: text
         type(error_t), allocatable, intent(out) :: error
      end subroutine h5_file_read_string

      !> Read a 1D string dataset; every string has the dataset's width, blank-padded.
      module subroutine h5_file_read_string_list(self, path, strings, error)
         class(h5_file_t), intent(in) :: self
         !> Absolute dataset path
         character(len=*), intent(in) :: path
         !> Strings read (`trim` each)
         character(len=:), allocatable, intent(out) :: strings(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine h5_file_read_string_list

      ! ------------------------------------------------------------------ attributes

      !> Set (or replace) a string attribute of the group or dataset at `path` ('/' = root).
      module subroutine set_attribute_string(self, path, name, value, error)
         class(h5_file_t), intent(inout) :: self
         !> Absolute path of an existing group or dataset
         character(len=*), intent(in) :: path
         !> Attribute name
         character(len=*), intent(in) :: name
         !> Text
         character(len=*), intent(in) :: value
         type(error_t), allocatable, intent(out) :: error
      end subroutine set_attribute_string

      !> Set (or replace) a real scalar attribute.
      module subroutine set_attribute_real(self, path, name, value, error)
         class(h5_file_t), intent(inout) :: self
         !> Absolute path of an existing group or dataset
         character(len=*), intent(in) :: path
         !> Attribute name
         character(len=*), intent(in) :: name
         !> Value
         real(dp), intent(in), target :: value
         type(error_t), allocatable, intent(out) :: error
      end subroutine set_attribute_real

      !> Set (or replace) a default-integer scalar attribute.
      module subroutine set_attribute_int(self, path, name, value, error)
         class(h5_file_t), intent(inout) :: self
         !> Absolute path of an existing group or dataset
         character(len=*), intent(in) :: path
         !> Attribute name
         character(len=*), intent(in) :: name
         !> Value
         integer, intent(in), target :: value
         type(error_t), allocatable, intent(out) :: error
      end subroutine set_attribute_int

      !> Read a scalar string attribute.
      module subroutine read_attribute_string(self, path, name, value, error)
         class(h5_file_t), intent(in) :: self
         !> Absolute path of the group or dataset
         character(len=*), intent(in) :: path
         !> Attribute name
         character(len=*), intent(in) :: name
         !> Text read
         character(len=:), allocatable, intent(out) :: value
         type(error_t), allocatable, intent(out) :: error
      end subroutine read_attribute_string

      !> Read a real scalar attribute (integer attributes are converted).
      module subroutine read_attribute_real(self, path, name, value, error)
         class(h5_file_t), intent(in) :: self
         !> Absolute path of the group or dataset
         character(len=*), intent(in) :: path
         !> Attribute name
         character(len=*), intent(in) :: name
         !> Value read
         real(dp), intent(out), target :: value
         type(error_t), allocatable, intent(out) :: error
      end subroutine read_attribute_real

      !> Read a default-integer scalar attribute.
      module subroutine read_attribute_int(self, path, name, value, error)
         class(h5_file_t), intent(in) :: self
         !> Absolute path of the group or dataset
         character(len=*), intent(in) :: path
         !> Attribute name
         character(len=*), intent(in) :: name
         !> Value read
         integer, intent(out), target :: value
         type(error_t), allocatable, intent(out) :: error
      end subroutine read_attribute_int

      !> Set the root attribute `status`: 'running', 'complete' or the error message of a failed
      !> run.
      module subroutine h5_file_set_status(self, status, error)
         class(h5_file_t), intent(inout) :: self
         !> New status
         character(len=*), intent(in) :: status
         type(error_t), allocatable, intent(out) :: error
      end subroutine h5_file_set_status

      !> Read the root attribute `status`.
      module subroutine h5_file_get_status(self, status, error)
         class(h5_file_t), intent(in) :: self
         !> Status read
         character(len=:), allocatable, intent(out) :: status
         type(error_t), allocatable, intent(out) :: error
      end subroutine h5_file_get_status

      ! ------------------------------------------------------------------ time series

      !> Create an empty, growing real dataset for time-integration output. `num_rows = 0`: a 1D
      !> series of scalars, Fortran (num_steps) = h5py (num_steps,); `num_rows > 0`: one column
      !> per step, Fortran (num_rows, num_steps) = h5py (num_steps, num_rows). Chunked, unlimited
      !> along the step dimension; an existing dataset at `path` is replaced.
      module subroutine h5_file_create_series(self, path, num_rows, units, error)
         class(h5_file_t), intent(inout) :: self
         !> Absolute dataset path
         character(len=*), intent(in) :: path
         !> Values per step (0 for a scalar series)
         integer, intent(in) :: num_rows
         !> Units attribute
         character(len=*), intent(in) :: units
         type(error_t), allocatable, intent(out) :: error
      end subroutine h5_file_create_series

      !> Append one step to a 1D (scalar) series.
      module subroutine append_real_0d(self, path, value, error)
         class(h5_file_t), intent(inout) :: self
         !> Series path (made by create_series with num_rows = 0)
         character(len=*), intent(in) :: path
         !> Value of this step
         real(dp), intent(in), target :: value
         type(error_t), allocatable, intent(out) :: error
      end subroutine append_real_0d

      !> Append to a series: to a 1D series, `size(values)` steps; to a 2D series, one step, a
      !> column of num_rows values.
      module subroutine append_real_1d(self, path, values, error)
         class(h5_file_t), intent(inout) :: self
         !> Series path
         character(len=*), intent(in) :: path
         !> Values (see above)
         real(dp), intent(in), target, contiguous :: values(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine append_real_1d

      !> Append `size(values, 2)` steps to a 2D series; `size(values, 1)` must equal its num_rows.
      module subroutine append_real_2d(self, path, values, error)
         class(h5_file_t), intent(inout) :: self
         !> Series path (made by create_series with num_rows > 0)
         character(len=*), intent(in) :: path
         !> One column per step
         real(dp), intent(in), target, contiguous :: values(:, :)
         type(error_t), allocatable, intent(out) :: error
      end subroutine append_real_2d

      !> Number of steps stored in a series (its last Fortran dimension).
      module subroutine h5_file_series_length(self, path, num_steps, error)
         class(h5_file_t), intent(in) :: self
         !> Series path
         character(len=*), intent(in) :: path
         !> Steps stored
         integer(i8), intent(out) :: num_steps
         type(error_t), allocatable, intent(out) :: error
      end subroutine h5_file_series_length

   end interface

end module ffrf_io_hdf5

!> Bodies of ffrf_io_hdf5 (a submodule, as the house style asks of long modules) and the
!> helpers they share; only this submodule touches HDF5 handles.
submodule (ffrf_io_hdf5) ffrf_io_hdf5_impl
   use, intrinsic :: iso_c_binding, only: c_ptr, c_loc, c_null_ptr, c_associated, c_char
   use ffrf_core_error, only: fatal_error, FFRF_IO_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_serial_section, only: enter_serial_section, leave_serial_section, SECTION_HDF5
   use ffrf_core_posix, only: remove_file
   use hdf5, only: hsize_t, size_t, h5open_f, h5dont_atexit_f, h5eset_auto_f, h5kind_to_type, &
      H5_INTEGER_KIND, h5fcreate_f, h5fopen_f, h5fclose_f, h5fflush_f, H5F_ACC_EXCL_F, &
      H5F_ACC_RDWR_F, H5F_ACC_RDONLY_F, H5F_SCOPE_GLOBAL_F, h5gcreate_f, h5gclose_f, &
      h5lexists_f, h5ldelete_f, h5oopen_f, h5oclose_f, h5iget_type_f, H5I_DATASET_F, &
      H5I_GROUP_F, h5screate_f, h5screate_simple_f, h5sclose_f, H5S_SCALAR_F, &
      h5sget_simple_extent_ndims_f, h5sget_simple_extent_dims_f, h5sselect_hyperslab_f, &
      H5S_SELECT_SET_F, H5S_UNLIMITED_F, h5dcreate_f, h5dopen_f, h5dclose_f, h5dwrite_f, &
      h5dread_f, h5dget_space_f, h5dget_type_f, h5dset_extent_f, h5pcreate_f, h5pset_chunk_f, &
      h5pclose_f, H5P_DATASET_CREATE_F, h5tcopy_f, h5tset_size_f, h5tget_size_f, &
      h5tset_strpad_f, h5tclose_f, h5tget_class_f, h5tis_variable_str_f, &
      H5T_STRING_F, H5T_FORTRAN_S1, H5T_STR_NULLPAD_F, H5T_NATIVE_DOUBLE, &
      H5T_NATIVE_INTEGER, h5acreate_f, h5aopen_f, h5aclose_f, h5awrite_f, h5aread_f, &
      h5aexists_f, h5adelete_f, h5aget_type_f
   implicit none

   !> Steps per chunk of a 1D time series; a 2D series holds about this many values per chunk.
   integer, parameter :: series_chunk = 8192

   !> True once h5open_f has run (and automatic error printing is off).
   logical, save :: library_ready = .false.

contains

   ! ------------------------------------------------------------------ file

   module procedure h5_file_create
      call enter_serial_section(SECTION_HDF5)
      section: block
         integer :: hdferr
         call prepare_open(self, file_name, error)
         if (allocated(error)) exit section
         ! a new file, never written through a link left at its name (issue 23): the name is
         ! removed first (a link itself, never its target), and H5F_ACC_EXCL creates with
         ! O_CREAT | O_EXCL, which refuses a link that reappears in between
         call remove_file(file_name, error)
         if (allocated(error)) exit section
         call h5fcreate_f(file_name, H5F_ACC_EXCL_F, self%id, hdferr)
         self%writable = .true.
         if (hdferr < 0) then
            self%id = -1
            call fatal_error(error, FFRF_IO_ERROR, 'cannot create HDF5 file "' // file_name // &
               '": check that its folder exists and is writable')
         end if
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure h5_file_create

   module procedure h5_file_open
      call enter_serial_section(SECTION_HDF5)
      section: block
         integer :: hdferr, flags
         select case (mode)
         case (H5_READ_ONLY)
            flags = H5F_ACC_RDONLY_F
         case (H5_READ_WRITE)
            flags = H5F_ACC_RDWR_F
         case default
            call fatal_error(error, FFRF_IO_ERROR, 'HDF5 file "' // file_name // '": open mode ' &
               // to_str(mode) // ' is not H5_READ_ONLY or H5_READ_WRITE')
            exit section
         end select
         call prepare_open(self, file_name, error)
         if (allocated(error)) exit section
         call h5fopen_f(file_name, flags, self%id, hdferr)
         self%writable = mode == H5_READ_WRITE
         if (hdferr < 0) then
            self%id = -1
            call fatal_error(error, FFRF_IO_ERROR, 'cannot open HDF5 file "' // file_name // &
               '" (' // trim(merge('read only ', 'read-write', mode == H5_READ_ONLY)) // &
               '): check that it exists, is readable and is an HDF5 file')
         end if
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure h5_file_open

   module procedure h5_file_close
      call enter_serial_section(SECTION_HDF5)
      section: block
         integer :: hdferr
         if (self%id < 0) exit section
         call h5fclose_f(self%id, hdferr)
         self%id = -1
         if (hdferr < 0) call fatal_error(error, FFRF_IO_ERROR, 'HDF5 file "' // self%name // &
            '": closing failed (disk full, quota or file size limit?)')
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure h5_file_close

   module procedure h5_file_flush
      call enter_serial_section(SECTION_HDF5)
      section: block
         integer :: hdferr
         call require_open(self, '/', error)
         if (allocated(error)) exit section
         call h5fflush_f(self%id, H5F_SCOPE_GLOBAL_F, hdferr)
         if (hdferr < 0) call fail(self, error, '/', 'flush failed (disk full, quota or file ' // &
            'size limit?)')
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure h5_file_flush

   module procedure h5_file_is_open
      call enter_serial_section(SECTION_HDF5)
      section: block
         is_open = self%id >= 0
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure h5_file_is_open

   module procedure h5_file_exists
      call enter_serial_section(SECTION_HDF5)
      section: block
         integer :: i, hdferr
         found = .false.
         if (self%id < 0) exit section
         if (path == '/') then
            found = .true.
            exit section
         end if
         if (.not. valid_path(path)) exit section
         ! h5lexists_f needs every parent to exist: test the prefixes one by one
         do i = 2, len(path)
            if (path(i:i) == '/' .or. i == len(path)) then
               if (path(i:i) == '/') then
                  call h5lexists_f(self%id, path(1:i - 1), found, hdferr)
               else
                  call h5lexists_f(self%id, path, found, hdferr)
               end if
               if (hdferr < 0) found = .false.
               if (.not. found) exit section
            end if
         end do
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure h5_file_exists

   module procedure h5_file_attribute_exists
      call enter_serial_section(SECTION_HDF5)
      section: block
         integer(hid_t) :: obj
         integer :: hdferr
         found = .false.
         if (.not. self%exists(path)) exit section
         call h5oopen_f(self%id, path, obj, hdferr)
         if (hdferr < 0) exit section
         call h5aexists_f(obj, name, found, hdferr)
         if (hdferr < 0) found = .false.
         call h5oclose_f(obj, hdferr)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure h5_file_attribute_exists

   ! ------------------------------------------------------------------ writers

   module procedure write_real_0d
      call enter_serial_section(SECTION_HDF5)
      section: block
         call write_dataset(self, path, H5T_NATIVE_DOUBLE, [integer(hsize_t) ::], c_loc(value), &
            units, error)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure write_real_0d

   module procedure write_real_1d
      call enter_serial_section(SECTION_HDF5)
      section: block
         type(c_ptr) :: buffer
         buffer = c_null_ptr
         if (size(value) > 0) buffer = c_loc(value)
         call write_dataset(self, path, H5T_NATIVE_DOUBLE, shape(value, hsize_t), buffer, units, &
            error)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure write_real_1d

   module procedure write_real_2d
      call enter_serial_section(SECTION_HDF5)
      section: block
         type(c_ptr) :: buffer
         buffer = c_null_ptr
         if (size(value) > 0) buffer = c_loc(value)
         call write_dataset(self, path, H5T_NATIVE_DOUBLE, shape(value, hsize_t), buffer, units, &
            error)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure write_real_2d

   module procedure write_int_0d
      call enter_serial_section(SECTION_HDF5)
      section: block
         call write_dataset(self, path, H5T_NATIVE_INTEGER, [integer(hsize_t) ::], c_loc(value), &
            error=error)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure write_int_0d

   module procedure write_int_1d
      call enter_serial_section(SECTION_HDF5)
      section: block
         type(c_ptr) :: buffer
         buffer = c_null_ptr
         if (size(value) > 0) buffer = c_loc(value)
         call write_dataset(self, path, H5T_NATIVE_INTEGER, shape(value, hsize_t), buffer, &
            error=error)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure write_int_1d

   module procedure write_int_2d
      call enter_serial_section(SECTION_HDF5)
      section: block
         type(c_ptr) :: buffer
         buffer = c_null_ptr
         if (size(value) > 0) buffer = c_loc(value)
         call write_dataset(self, path, H5T_NATIVE_INTEGER, shape(value, hsize_t), buffer, &
            error=error)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure write_int_2d

   module procedure write_long_0d
      call enter_serial_section(SECTION_HDF5)
      section: block
         call write_dataset(self, path, h5kind_to_type(i8, H5_INTEGER_KIND), &
            [integer(hsize_t) ::], c_loc(value), error=error)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure write_long_0d

   module procedure write_long_1d
      call enter_serial_section(SECTION_HDF5)
      section: block
         type(c_ptr) :: buffer
         buffer = c_null_ptr
         if (size(value) > 0) buffer = c_loc(value)
         call write_dataset(self, path, h5kind_to_type(i8, H5_INTEGER_KIND), &
            shape(value, hsize_t), buffer, error=error)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure write_long_1d

   module procedure write_long_2d
      call enter_serial_section(SECTION_HDF5)
      section: block
         type(c_ptr) :: buffer
         buffer = c_null_ptr
         if (size(value) > 0) buffer = c_loc(value)
         call write_dataset(self, path, h5kind_to_type(i8, H5_INTEGER_KIND), &
            shape(value, hsize_t), buffer, error=error)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure write_long_2d

   module procedure h5_file_write_string
      call enter_serial_section(SECTION_HDF5)
      section: block
         character(kind=c_char, len=1), allocatable, target :: bytes(:)
         integer(hid_t) :: string_type
         integer :: hdferr
         call pack_strings([text], len(text), .false., bytes)
         call make_string_type(size(bytes), string_type, hdferr)
         if (hdferr < 0) then
            call fail(self, error, path, 'cannot make a string type of length ' // &
               to_str(size(bytes)))
            exit section
         end if
         call write_dataset(self, path, string_type, [integer(hsize_t) ::], c_loc(bytes), &
            error=error)
         call h5tclose_f(string_type, hdferr)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure h5_file_write_string

   module procedure h5_file_write_string_list
      call enter_serial_section(SECTION_HDF5)
      section: block
         character(kind=c_char, len=1), allocatable, target :: bytes(:)
         integer(hid_t) :: string_type
         integer :: hdferr, width, i
         type(c_ptr) :: buffer
         width = 1
         do i = 1, size(strings)
            width = max(width, len_trim(strings(i)))
         end do
         call pack_strings(strings, width, .true., bytes)
         call make_string_type(width, string_type, hdferr)
         if (hdferr < 0) then
            call fail(self, error, path, 'cannot make a string type of length ' // to_str(width))
            exit section
         end if
         buffer = c_null_ptr
         if (size(bytes) > 0) buffer = c_loc(bytes)
         call write_dataset(self, path, string_type, shape(strings, hsize_t), buffer, error=error)
         call h5tclose_f(string_type, hdferr)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure h5_file_write_string_list

   ! ------------------------------------------------------------------ readers

   module procedure read_real_0d
      call enter_serial_section(SECTION_HDF5)
      section: block
         integer(hid_t) :: dset
         integer(hsize_t) :: dims(0)
         value = 0.0_dp
         call open_dataset(self, path, 0, dset, dims, error)
         if (allocated(error)) exit section
         call read_and_close(self, path, dset, H5T_NATIVE_DOUBLE, c_loc(value), error)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure read_real_0d

   module procedure read_real_1d
      call enter_serial_section(SECTION_HDF5)
      section: block
         integer(hid_t) :: dset
         integer(hsize_t) :: dims(1)
         type(c_ptr) :: buffer
         call open_dataset(self, path, 1, dset, dims, error)
         if (allocated(error)) exit section
         allocate (value(dims(1)))
         buffer = c_null_ptr
         if (size(value) > 0) buffer = c_loc(value)
         call read_and_close(self, path, dset, H5T_NATIVE_DOUBLE, buffer, error)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure read_real_1d

   module procedure read_real_2d
      call enter_serial_section(SECTION_HDF5)
      section: block
         integer(hid_t) :: dset
         integer(hsize_t) :: dims(2)
         type(c_ptr) :: buffer
         call open_dataset(self, path, 2, dset, dims, error)
         if (allocated(error)) exit section
         allocate (value(dims(1), dims(2)))
         buffer = c_null_ptr
         if (size(value) > 0) buffer = c_loc(value)
         call read_and_close(self, path, dset, H5T_NATIVE_DOUBLE, buffer, error)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure read_real_2d

   module procedure read_int_0d
      call enter_serial_section(SECTION_HDF5)
      section: block
         integer(hid_t) :: dset
         integer(hsize_t) :: dims(0)
         value = 0
         call open_dataset(self, path, 0, dset, dims, error)
         if (allocated(error)) exit section
         call read_and_close(self, path, dset, H5T_NATIVE_INTEGER, c_loc(value), error)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure read_int_0d

   module procedure read_int_1d
      call enter_serial_section(SECTION_HDF5)
      section: block
         integer(hid_t) :: dset
         integer(hsize_t) :: dims(1)
         type(c_ptr) :: buffer
         call open_dataset(self, path, 1, dset, dims, error)
         if (allocated(error)) exit section
         allocate (value(dims(1)))
         buffer = c_null_ptr
         if (size(value) > 0) buffer = c_loc(value)
         call read_and_close(self, path, dset, H5T_NATIVE_INTEGER, buffer, error)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure read_int_1d

   module procedure read_int_2d
      call enter_serial_section(SECTION_HDF5)
      section: block
         integer(hid_t) :: dset
         integer(hsize_t) :: dims(2)
         type(c_ptr) :: buffer
         call open_dataset(self, path, 2, dset, dims, error)
         if (allocated(error)) exit section
         allocate (value(dims(1), dims(2)))
         buffer = c_null_ptr
         if (size(value) > 0) buffer = c_loc(value)
         call read_and_close(self, path, dset, H5T_NATIVE_INTEGER, buffer, error)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure read_int_2d

   module procedure read_long_0d
      call enter_serial_section(SECTION_HDF5)
      section: block
         integer(hid_t) :: dset
         integer(hsize_t) :: dims(0)
         value = 0_i8
         call open_dataset(self, path, 0, dset, dims, error)
         if (allocated(error)) exit section
         call read_and_close(self, path, dset, h5kind_to_type(i8, H5_INTEGER_KIND), c_loc(value), &
            error)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure read_long_0d

   module procedure read_long_1d
      call enter_serial_section(SECTION_HDF5)
      section: block
         integer(hid_t) :: dset
         integer(hsize_t) :: dims(1)
         type(c_ptr) :: buffer
         call open_dataset(self, path, 1, dset, dims, error)
         if (allocated(error)) exit section
         allocate (value(dims(1)))
         buffer = c_null_ptr
         if (size(value) > 0) buffer = c_loc(value)
         call read_and_close(self, path, dset, h5kind_to_type(i8, H5_INTEGER_KIND), buffer, error)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure read_long_1d

   module procedure read_long_2d
      call enter_serial_section(SECTION_HDF5)
      section: block
         integer(hid_t) :: dset
         integer(hsize_t) :: dims(2)
         type(c_ptr) :: buffer
         call open_dataset(self, path, 2, dset, dims, error)
         if (allocated(error)) exit section
         allocate (value(dims(1), dims(2)))
         buffer = c_null_ptr
         if (size(value) > 0) buffer = c_loc(value)
         call read_and_close(self, path, dset, h5kind_to_type(i8, H5_INTEGER_KIND), buffer, error)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure read_long_2d

   module procedure h5_file_read_string
      call enter_serial_section(SECTION_HDF5)
      section: block
         character(len=:), allocatable :: strings(:)
         call read_strings(self, path, 0, strings, error)
         if (allocated(error)) exit section
         text = trim_padding(strings(1))
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure h5_file_read_string

   module procedure h5_file_read_string_list
      call enter_serial_section(SECTION_HDF5)
      section: block
         integer :: i
         call read_strings(self, path, 1, strings, error)
         if (allocated(error)) exit section
         do i = 1, size(strings)
            strings(i) = trim_padding(strings(i))
         end do
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure h5_file_read_string_list

   ! ------------------------------------------------------------------ attributes

   module procedure set_attribute_string
      call enter_serial_section(SECTION_HDF5)
      section: block
         character(kind=c_char, len=1), allocatable, target :: bytes(:)
         integer(hid_t) :: string_type
         integer :: hdferr
         call pack_strings([value], len(value), .false., bytes)
         call make_string_type(size(bytes), string_type, hdferr)
         if (hdferr < 0) then
            call fail(self, error, path, 'cannot make a string type for attribute ' // name)
            exit section
         end if
         call put_attribute(self, path, name, string_type, c_loc(bytes), error)
         call h5tclose_f(string_type, hdferr)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure set_attribute_string

   module procedure set_attribute_real
      call enter_serial_section(SECTION_HDF5)
      section: block
         call put_attribute(self, path, name, H5T_NATIVE_DOUBLE, c_loc(value), error)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure set_attribute_real

   module procedure set_attribute_int
      call enter_serial_section(SECTION_HDF5)
      section: block
         call put_attribute(self, path, name, H5T_NATIVE_INTEGER, c_loc(value), error)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure set_attribute_int

   module procedure read_attribute_string
      call enter_serial_section(SECTION_HDF5)
      section: block
         character(kind=c_char, len=1), allocatable, target :: bytes(:)
         integer(hid_t) :: obj, attr, file_type
         integer(size_t) :: width
         integer :: hdferr, type_class, i
         logical :: variable
         type(c_ptr) :: pointer
         type_class = -1
         variable = .false.
         obj = -1
         attr = -1
         file_type = -1
         call open_attribute(self, path, name, obj, attr, error)
         steps: block
            if (allocated(error)) exit steps
            call h5aget_type_f(attr, file_type, hdferr)
            if (hdferr >= 0) call h5tget_class_f(file_type, type_class, hdferr)
            if (hdferr >= 0) call h5tis_variable_str_f(file_type, variable, hdferr)
            if (hdferr < 0 .or. type_class /= H5T_STRING_F) then
               call fail(self, error, path, 'attribute "' // name // '" is not a string')
               exit steps
            end if
            if (variable) then
               call fail(self, error, path, 'attribute "' // name // '" is a variable-length ' // &
                  'string; only fixed-length strings are read')
               exit steps
            end if
            call h5tget_size_f(file_type, width, hdferr)
            allocate (bytes(width))
            pointer = c_loc(bytes)
            call h5aread_f(attr, file_type, pointer, hdferr)
            if (hdferr < 0) then
               call fail(self, error, path, 'cannot read attribute "' // name // '"')
               exit steps
            end if
            allocate (character(len=size(bytes)) :: value)
            do i = 1, size(bytes)
               value(i:i) = bytes(i)
            end do
            value = trim_padding(value)
         end block steps
         if (.not. allocated(value)) value = ''
         call release(type=file_type, attr=attr, obj=obj)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure read_attribute_string

   module procedure read_attribute_real
      call enter_serial_section(SECTION_HDF5)
      section: block
         value = 0.0_dp
         call get_attribute(self, path, name, H5T_NATIVE_DOUBLE, c_loc(value), error)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure read_attribute_real

   module procedure read_attribute_int
      call enter_serial_section(SECTION_HDF5)
      section: block
         value = 0
         call get_attribute(self, path, name, H5T_NATIVE_INTEGER, c_loc(value), error)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure read_attribute_int

   module procedure h5_file_set_status
      call enter_serial_section(SECTION_HDF5)
      section: block
         call self%set_attribute('/', 'status', status, error)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure h5_file_set_status

   module procedure h5_file_get_status
      call enter_serial_section(SECTION_HDF5)
      section: block
         call self%read_attribute('/', 'status', status, error)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure h5_file_get_status

   ! ------------------------------------------------------------------ time series

   module procedure h5_file_create_series
      call enter_serial_section(SECTION_HDF5)
      section: block
         integer(hid_t) :: space, plist, dset
         integer(hsize_t), allocatable :: dims(:), max_dims(:), chunk(:)
         integer :: hdferr
         if (num_rows < 0) then
            call fail(self, error, path, 'time series with num_rows = ' // to_str(num_rows) // &
               ', must be >= 0')
            exit section
         end if
         if (num_rows == 0) then
            dims = [0_hsize_t]
            max_dims = [H5S_UNLIMITED_F]
            chunk = [int(series_chunk, hsize_t)]
         else
            dims = [int(num_rows, hsize_t), 0_hsize_t]
            max_dims = [int(num_rows, hsize_t), H5S_UNLIMITED_F]
            chunk = [int(num_rows, hsize_t), int(max(1, series_chunk / num_rows), hsize_t)]
         end if
         call prepare_dataset(self, path, error)
         if (allocated(error)) exit section
         space = -1
         plist = -1
         dset = -1
         steps: block
            call h5screate_simple_f(size(dims), dims, space, hdferr, max_dims)
            if (hdferr < 0) exit steps
            call h5pcreate_f(H5P_DATASET_CREATE_F, plist, hdferr)
            if (hdferr < 0) exit steps
            call h5pset_chunk_f(plist, size(chunk), chunk, hdferr)
            if (hdferr < 0) exit steps
            call h5dcreate_f(self%id, path, H5T_NATIVE_DOUBLE, space, dset, hdferr, plist)
            if (hdferr < 0) exit steps
            call put_units(dset, units, hdferr)
         end block steps
         if (hdferr < 0) call fail(self, error, path, 'cannot create the time series dataset')
         call release(dset=dset, space=space, plist=plist)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure h5_file_create_series

   module procedure append_real_0d
      call enter_serial_section(SECTION_HDF5)
      section: block
         call append_steps(self, path, 1, [0_hsize_t], 1_hsize_t, c_loc(value), error)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure append_real_0d

   module procedure append_real_1d
      call enter_serial_section(SECTION_HDF5)
      section: block
         integer :: rank
         if (size(values) == 0) exit section
         call series_rank(self, path, rank, error)
         if (allocated(error)) exit section
         if (rank == 1) then
            call append_steps(self, path, 1, [0_hsize_t], size(values, kind=hsize_t), &
               c_loc(values), error)
         else
            call append_steps(self, path, 2, [size(values, kind=hsize_t)], 1_hsize_t, &
               c_loc(values), error)
         end if
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure append_real_1d

   module procedure append_real_2d
      call enter_serial_section(SECTION_HDF5)
      section: block
         if (size(values) == 0) exit section
         call append_steps(self, path, 2, [size(values, 1, kind=hsize_t)], &
            size(values, 2, kind=hsize_t), c_loc(values), error)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure append_real_2d

   module procedure h5_file_series_length
      call enter_serial_section(SECTION_HDF5)
      section: block
         integer(hid_t) :: dset
         integer(hsize_t) :: dims(2)
         integer :: rank, hdferr
         num_steps = 0
         call series_rank(self, path, rank, error)
         if (allocated(error)) exit section
         call open_dataset(self, path, rank, dset, dims(1:rank), error)
         if (allocated(error)) exit section
         num_steps = int(dims(rank), i8)
         call h5dclose_f(dset, hdferr)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure h5_file_series_length

   ! ------------------------------------------------------------------ internals

   !> Initialise the HDF5 library once and switch off its automatic error printing. HDF5's own
   !> clean-up at exit is switched off first (h5dont_atexit_f): after a close that failed on a
   !> full disk, HDF5 1.10 keeps the file's identifier with a half-destroyed file structure,
   !> and its exit handler (H5_term_library -> H5F_term_package -> H5F__close_cb) then ends
   !> the process with SIGSEGV. ffrf closes every file it opens itself.
   subroutine ensure_library(ok)
      logical, intent(out) :: ok
      integer :: hdferr
      ok = library_ready
      if (library_ready) return
      call h5dont_atexit_f(hdferr)
      call h5open_f(hdferr)
      if (hdferr < 0) return
      call h5eset_auto_f(0, hdferr)
      library_ready = hdferr >= 0
      ok = library_ready
   end subroutine ensure_library

   !> Common start of create/open: library ready, this handle not already in use.
   subroutine prepare_open(self, file_name, error)
      class(h5_file_t), intent(inout) :: self
      character(len=*), intent(in) :: file_name
      type(error_t), allocatable, intent(out) :: error
      logical :: ok
      if (self%id >= 0) then
         call fatal_error(error, FFRF_IO_ERROR, 'HDF5 file "' // file_name // '": this ' // &
            'h5_file_t still has "' // self%name // '" open; close it first')
         return
      end if
      call ensure_library(ok)
      if (.not. ok) then
         call fatal_error(error, FFRF_IO_ERROR, 'HDF5 file "' // file_name // &
            '": the HDF5 library failed to initialise (h5open_f)')
         return
      end if
      self%name = file_name
   end subroutine prepare_open

   !> Error unless a file is open.
   subroutine require_open(self, path, error)
      class(h5_file_t), intent(in) :: self
      character(len=*), intent(in) :: path
      type(error_t), allocatable, intent(out) :: error
      if (self%id < 0) then
         if (allocated(self%name)) then
            call fatal_error(error, FFRF_IO_ERROR, 'HDF5 file "' // self%name // '", "' // &
               path // '": the file is not open')
         else
            call fatal_error(error, FFRF_IO_ERROR, 'HDF5 "' // path // '": no file is open; ' &
               // 'call create or open first')
         end if
      end if
   end subroutine require_open

   !> Error unless a file is open for writing.
   subroutine require_writable(self, path, error)
      class(h5_file_t), intent(in) :: self
      character(len=*), intent(in) :: path
      type(error_t), allocatable, intent(out) :: error
      call require_open(self, path, error)
      if (allocated(error)) return
      if (.not. self%writable) call fail(self, error, path, 'cannot write: the file is open ' &
         // 'read-only (mode r); open it with mode rw')
   end subroutine require_writable

   !> HDF5 identifier type (H5I_GROUP_F, H5I_DATASET_F) of the object at an existing `path`;
   !> -1 if it cannot be opened.
   integer function object_type(self, path)
      class(h5_file_t), intent(in) :: self
      character(len=*), intent(in) :: path
      integer(hid_t) :: obj
      integer :: hdferr, close_status
      object_type = -1
      call h5oopen_f(self%id, path, obj, hdferr)
      if (hdferr < 0) return
      call h5iget_type_f(obj, object_type, hdferr)
      if (hdferr < 0) object_type = -1
      call h5oclose_f(obj, close_status)
   end function object_type

   !> An FFRF_IO_ERROR naming the file and the path.
   subroutine fail(self, error, path, what)
      class(h5_file_t), intent(in) :: self
      type(error_t), allocatable, intent(out) :: error
      character(len=*), intent(in) :: path, what
      character(len=:), allocatable :: name
      name = '?'
      if (allocated(self%name)) name = self%name
      call fatal_error(error, FFRF_IO_ERROR, 'HDF5 file "' // name // '", "' // path // '": ' &
         // what)
   end subroutine fail

   !> An absolute path with non-empty components: '/a/b', not 'a', '/a/', '/a//b' or '/'.
   pure logical function valid_path(path)
      character(len=*), intent(in) :: path
      valid_path = len(path) >= 2
      if (.not. valid_path) return
      valid_path = path(1:1) == '/' .and. path(len(path):len(path)) /= '/' .and. &
         index(path, '//') == 0
   end function valid_path

   !> Before writing a dataset: file open, path valid, parent groups made, an old dataset at
   !> `path` removed (a group there is an error).
   subroutine prepare_dataset(self, path, error)
      class(h5_file_t), intent(inout) :: self
      character(len=*), intent(in) :: path
      type(error_t), allocatable, intent(out) :: error
      integer(hid_t) :: group
      integer :: i, hdferr
      call require_writable(self, path, error)
      if (allocated(error)) return
      if (.not. valid_path(path)) then
         call fail(self, error, path, 'not a valid dataset path (absolute, like /group/name, ' &
            // 'without empty parts)')
         return
      end if
      do i = 2, len(path)
         if (path(i:i) /= '/') cycle
         if (self%exists(path(1:i - 1))) then
            if (object_type(self, path(1:i - 1)) == H5I_GROUP_F) cycle
            call fail(self, error, path, '"' // path(1:i - 1) // '" is a dataset, not a ' // &
               'group: it cannot hold others')
            return
         end if
         call h5gcreate_f(self%id, path(1:i - 1), group, hdferr)
         if (hdferr < 0) then
            call fail(self, error, path, 'cannot create group "' // path(1:i - 1) // '"')
            return
         end if
         call h5gclose_f(group, hdferr)
      end do
      if (.not. self%exists(path)) return
      if (object_type(self, path) /= H5I_DATASET_F) then
         call fail(self, error, path, 'a group (not a dataset) is there already; pick ' // &
            'another name')
         return
      end if
      call h5ldelete_f(self%id, path, hdferr)
      if (hdferr < 0) call fail(self, error, path, 'cannot replace the existing dataset')
   end subroutine prepare_dataset

   !> Create the dataset `path` of `dims` (rank 0: scalar) and type `type_id` (used in memory
   !> and in the file), write `buffer` unless it is null (no elements), set `units` if present.
   subroutine write_dataset(self, path, type_id, dims, buffer, units, error)
      class(h5_file_t), intent(inout) :: self
      character(len=*), intent(in) :: path
      integer(hid_t), intent(in) :: type_id
      integer(hsize_t), intent(in) :: dims(:)
      type(c_ptr), intent(in) :: buffer
      character(len=*), intent(in), optional :: units
      type(error_t), allocatable, intent(out) :: error
      integer(hid_t) :: space, dset
      integer :: hdferr
      call prepare_dataset(self, path, error)
      if (allocated(error)) return
      space = -1
      dset = -1
      steps: block
         if (size(dims) == 0) then
            call h5screate_f(H5S_SCALAR_F, space, hdferr)
         else
            call h5screate_simple_f(size(dims), dims, space, hdferr)
         end if
         if (hdferr < 0) then
            call fail(self, error, path, 'cannot create a dataspace of shape ' // &
               shape_text(dims))
            exit steps
         end if
         call h5dcreate_f(self%id, path, type_id, space, dset, hdferr)
         if (hdferr < 0) then
            call fail(self, error, path, 'cannot create the dataset')
            exit steps
         end if
         if (c_associated(buffer)) then
            call h5dwrite_f(dset, type_id, buffer, hdferr)
            if (hdferr < 0) then
               call fail(self, error, path, 'cannot write ' // shape_text(dims) // &
                  ' values (disk full, quota or file size limit?)')
               exit steps
            end if
         end if
         if (present(units)) then
            call put_units(dset, units, hdferr)
            if (hdferr < 0) call fail(self, error, path, 'cannot set its units attribute')
         end if
      end block steps
      call close_written(self, path, dset, error)
      call release(dset=dset, space=space)
   end subroutine write_dataset

   !> Close a dataset that was written to, reporting a failure (closing writes the data HDF5
   !> still holds in its chunk cache: a full disk shows here) unless an error is already set.
   subroutine close_written(self, path, dset, error)
      class(h5_file_t), intent(in) :: self
      character(len=*), intent(in) :: path
      integer(hid_t), intent(inout) :: dset
      type(error_t), allocatable, intent(inout) :: error
      integer :: hdferr
      if (dset < 0) return
      call h5dclose_f(dset, hdferr)
      dset = -1
      if (hdferr < 0 .and. .not. allocated(error)) call fail(self, error, path, &
         'cannot write the values (disk full, quota or file size limit?)')
   end subroutine close_written

   !> Open dataset `path`, check it has `rank` dimensions, return its Fortran dims. On error the
   !> dataset is closed.
   subroutine open_dataset(self, path, rank, dset, dims, error)
      class(h5_file_t), intent(in) :: self
      character(len=*), intent(in) :: path
      integer, intent(in) :: rank
      integer(hid_t), intent(out) :: dset
      integer(hsize_t), intent(out) :: dims(:)
      type(error_t), allocatable, intent(out) :: error
      integer(hid_t) :: space
      integer(hsize_t) :: all_dims(8), max_dims(8)
      integer :: hdferr, close_status, file_rank
      dset = -1
      dims = 0
      call require_open(self, path, error)
      if (allocated(error)) return
      if (.not. self%exists(path)) then
         call fail(self, error, path, 'no such dataset')
         return
      end if
      call h5dopen_f(self%id, path, dset, hdferr)
      if (hdferr < 0) then
         dset = -1
         call fail(self, error, path, 'not a dataset (a group?)')
         return
      end if
      call h5dget_space_f(dset, space, hdferr)
      if (hdferr >= 0) then
         call h5sget_simple_extent_ndims_f(space, file_rank, hdferr)
         if (hdferr >= 0 .and. file_rank <= size(all_dims) .and. file_rank > 0) then
            ! this call returns the rank in hdferr, -1 on failure
            call h5sget_simple_extent_dims_f(space, all_dims(1:file_rank), &
               max_dims(1:file_rank), hdferr)
         end if
         call h5sclose_f(space, close_status)
      end if
      if (hdferr < 0) then
         call fail(self, error, path, 'cannot read the dataset shape')
      else if (file_rank /= rank) then
         call fail(self, error, path, 'has ' // to_str(file_rank) // ' dimensions, the ' // &
            'reader expects ' // to_str(rank))
      else
         dims = all_dims(1:rank)
         return
      end if
      call release(dset=dset)
   end subroutine open_dataset

   !> Read the whole dataset into `buffer` (skipped if null) with memory type `mem_type`, then
   !> close it.
   subroutine read_and_close(self, path, dset, mem_type, buffer, error)
      class(h5_file_t), intent(in) :: self
      character(len=*), intent(in) :: path
      integer(hid_t), intent(inout) :: dset
      integer(hid_t), intent(in) :: mem_type
      type(c_ptr), intent(in) :: buffer
      type(error_t), allocatable, intent(out) :: error
      integer :: hdferr
      type(c_ptr) :: pointer
      if (c_associated(buffer)) then
         pointer = buffer  ! h5dread_f wants a variable (intent inout)
         call h5dread_f(dset, mem_type, pointer, hdferr)
         if (hdferr < 0) call fail(self, error, path, 'cannot read the values (wrong type?)')
      end if
      call release(dset=dset)
   end subroutine read_and_close

   !> Read a scalar (rank 0) or 1D (rank 1) fixed-length string dataset, blank-padded.
   subroutine read_strings(self, path, rank, strings, error)
      class(h5_file_t), intent(in) :: self
      character(len=*), intent(in) :: path
      integer, intent(in) :: rank
      character(len=:), allocatable, intent(out) :: strings(:)
      type(error_t), allocatable, intent(out) :: error
      character(kind=c_char, len=1), allocatable, target :: bytes(:)
      integer(hid_t) :: dset, file_type
      integer(hsize_t) :: dims(1)
      integer(size_t) :: width
      integer :: hdferr, type_class, count, i, j
      logical :: variable
      type(c_ptr) :: pointer
      type_class = -1
      variable = .false.
      file_type = -1
      call open_dataset(self, path, rank, dset, dims(1:rank), error)
      if (allocated(error)) then
         allocate (character(len=0) :: strings(0))
         return
      end if
      count = 1
      if (rank == 1) count = int(dims(1))
      steps: block
         call h5dget_type_f(dset, file_type, hdferr)
         if (hdferr >= 0) call h5tget_class_f(file_type, type_class, hdferr)
         if (hdferr >= 0) call h5tis_variable_str_f(file_type, variable, hdferr)
         if (hdferr < 0 .or. type_class /= H5T_STRING_F) then
            call fail(self, error, path, 'not a string dataset')
            exit steps
         end if
         if (variable) then
            call fail(self, error, path, 'variable-length strings are not read; ffrf writes ' &
               // 'fixed-length strings')
            exit steps
         end if
         call h5tget_size_f(file_type, width, hdferr)
         allocate (bytes(width * count))
         if (size(bytes) > 0) then
            pointer = c_loc(bytes)
            call h5dread_f(dset, file_type, pointer, hdferr)
            if (hdferr < 0) then
               call fail(self, error, path, 'cannot read the strings')
               exit steps
            end if
         end if
         allocate (character(len=width) :: strings(count))
         do i = 1, count
            do j = 1, int(width)
               strings(i)(j:j) = bytes((i - 1) * width + j)
            end do
         end do
      end block steps
      if (.not. allocated(strings)) allocate (character(len=0) :: strings(0))
      call release(type=file_type, dset=dset)
   end subroutine read_strings

   !> Check `path` is a series and return its rank (1 or 2).
   subroutine series_rank(self, path, rank, error)
      class(h5_file_t), intent(in) :: self
      character(len=*), intent(in) :: path
      integer, intent(out) :: rank
      type(error_t), allocatable, intent(out) :: error
      integer(hid_t) :: dset, space
      integer :: hdferr, close_status
      rank = 0
      call require_open(self, path, error)
      if (allocated(error)) return
      if (.not. self%exists(path)) then
         call fail(self, error, path, 'no such time series; make it with create_series first')
         return
      end if
      call h5dopen_f(self%id, path, dset, hdferr)
      if (hdferr < 0) then
         call fail(self, error, path, 'not a dataset')
         return
      end if
      call h5dget_space_f(dset, space, hdferr)
      if (hdferr >= 0) then
         call h5sget_simple_extent_ndims_f(space, rank, hdferr)
         call h5sclose_f(space, close_status)
      end if
      call h5dclose_f(dset, close_status)
      if (rank /= 1 .and. rank /= 2) call fail(self, error, path, 'has rank ' // to_str(rank) &
         // '; a time series has rank 1 or 2')
   end subroutine series_rank

   !> Grow the series at `path` (rank `rank`) by `num_steps` steps of `rows` (empty for rank 1)
   !> values each, taken from `buffer`.
   subroutine append_steps(self, path, rank, rows, num_steps, buffer, error)
      class(h5_file_t), intent(inout) :: self
      character(len=*), intent(in) :: path
      integer, intent(in) :: rank
      integer(hsize_t), intent(in) :: rows(:)
      integer(hsize_t), intent(in) :: num_steps
      type(c_ptr), intent(in) :: buffer
      type(error_t), allocatable, intent(out) :: error
      integer(hid_t) :: dset, file_space, mem_space
      integer(hsize_t) :: dims(2), start(2), count(2)
      integer :: hdferr
      call require_writable(self, path, error)
      if (allocated(error)) return
      call open_dataset(self, path, rank, dset, dims(1:rank), error)
      if (allocated(error)) then
         call add_series_hint(error)
         return
      end if
      file_space = -1
      mem_space = -1
      steps: block
         if (rank == 2) then
            if (dims(1) /= rows(1)) then
               call fail(self, error, path, 'a step has ' // to_str(int(rows(1), i8)) // &
                  ' values, the series has ' // to_str(int(dims(1), i8)) // ' rows')
               exit steps
            end if
            start(1:2) = [0_hsize_t, dims(2)]
            count(1:2) = [rows(1), num_steps]
         else
            start(1) = dims(1)
            count(1) = num_steps
         end if
         dims(rank) = dims(rank) + num_steps
         call h5dset_extent_f(dset, dims(1:rank), hdferr)
         if (hdferr < 0) then
            call fail(self, error, path, 'cannot extend: not a time series made by ' // &
               'create_series')
            exit steps
         end if
         call h5dget_space_f(dset, file_space, hdferr)
         if (hdferr >= 0) call h5sselect_hyperslab_f(file_space, H5S_SELECT_SET_F, &
            start(1:rank), count(1:rank), hdferr)
         if (hdferr >= 0) call h5screate_simple_f(rank, count(1:rank), mem_space, hdferr)
         if (hdferr >= 0) call h5dwrite_f(dset, H5T_NATIVE_DOUBLE, buffer, hdferr, mem_space, &
            file_space)
         if (hdferr < 0) call fail(self, error, path, 'cannot write the appended steps ' // &
            '(disk full, quota or file size limit?)')
      end block steps
      call close_written(self, path, dset, error)
      call release(dset=dset, space=file_space, mem_space=mem_space)
   end subroutine append_steps

   !> Point a reader of an append error to the series API.
   subroutine add_series_hint(error)
      type(error_t), intent(inout) :: error
      error%message = error%message // ' (appending to a time series)'
   end subroutine add_series_hint

   !> Write a scalar attribute `name` of type `type_id` on the object at `path`, replacing one.
   subroutine put_attribute(self, path, name, type_id, buffer, error)
      class(h5_file_t), intent(inout) :: self
      character(len=*), intent(in) :: path, name
      integer(hid_t), intent(in) :: type_id
      type(c_ptr), intent(in) :: buffer
      type(error_t), allocatable, intent(out) :: error
      integer(hid_t) :: obj
      integer :: hdferr
      call require_writable(self, path, error)
      if (allocated(error)) return
      if (.not. self%exists(path)) then
         call fail(self, error, path, 'no such group or dataset to set attribute "' // name // &
            '" on')
         return
      end if
      call h5oopen_f(self%id, path, obj, hdferr)
      if (hdferr >= 0) then
         call put_scalar_attribute(obj, name, type_id, buffer, hdferr)
         call release(obj=obj)
      end if
      if (hdferr < 0) call fail(self, error, path, 'cannot set attribute "' // name // '"')
   end subroutine put_attribute

   !> Write a scalar attribute on an open object, replacing an existing one.
   subroutine put_scalar_attribute(obj, name, type_id, buffer, hdferr)
      integer(hid_t), intent(in) :: obj
      character(len=*), intent(in) :: name
      integer(hid_t), intent(in) :: type_id
      type(c_ptr), intent(in) :: buffer
      integer, intent(out) :: hdferr
      integer(hid_t) :: space, attr
      logical :: found
      call h5aexists_f(obj, name, found, hdferr)
      if (hdferr < 0) return
      if (found) then
         call h5adelete_f(obj, name, hdferr)
         if (hdferr < 0) return
      end if
      call h5screate_f(H5S_SCALAR_F, space, hdferr)
      if (hdferr < 0) return
      call h5acreate_f(obj, name, type_id, space, attr, hdferr)
      if (hdferr >= 0) then
         call h5awrite_f(attr, type_id, buffer, hdferr)
         call release(attr=attr)
      end if
      call release(space=space)
   end subroutine put_scalar_attribute

   !> Set the string attribute `units` on an open dataset.
   subroutine put_units(dset, units, hdferr)
      integer(hid_t), intent(in) :: dset
      character(len=*), intent(in) :: units
      integer, intent(out) :: hdferr
      character(kind=c_char, len=1), allocatable, target :: bytes(:)
      integer(hid_t) :: string_type
      call pack_strings([units], len(units), .false., bytes)
      call make_string_type(size(bytes), string_type, hdferr)
      if (hdferr < 0) return
      call put_scalar_attribute(dset, 'units', string_type, c_loc(bytes), hdferr)
      call release(type=string_type)
   end subroutine put_units

   !> Open attribute `name` of the object at `path`.
   subroutine open_attribute(self, path, name, obj, attr, error)
      class(h5_file_t), intent(in) :: self
      character(len=*), intent(in) :: path, name
      integer(hid_t), intent(out) :: obj, attr
      type(error_t), allocatable, intent(out) :: error
      integer :: hdferr
      obj = -1
      attr = -1
      call require_open(self, path, error)
      if (allocated(error)) return
      if (.not. self%attribute_exists(path, name)) then
         call fail(self, error, path, 'no attribute "' // name // '"')
         return
      end if
      call h5oopen_f(self%id, path, obj, hdferr)
      if (hdferr >= 0) call h5aopen_f(obj, name, attr, hdferr)
      if (hdferr < 0) then
         call fail(self, error, path, 'cannot open attribute "' // name // '"')
         call release(attr=attr, obj=obj)
      end if
   end subroutine open_attribute

   !> Read a scalar numeric attribute with memory type `mem_type`.
   subroutine get_attribute(self, path, name, mem_type, buffer, error)
      class(h5_file_t), intent(in) :: self
      character(len=*), intent(in) :: path, name
      integer(hid_t), intent(in) :: mem_type
      type(c_ptr), intent(in) :: buffer
      type(error_t), allocatable, intent(out) :: error
      integer(hid_t) :: obj, attr
      integer :: hdferr
      type(c_ptr) :: pointer
      call open_attribute(self, path, name, obj, attr, error)
      if (allocated(error)) return
      pointer = buffer  ! h5aread_f wants a variable (intent inout)
      call h5aread_f(attr, mem_type, pointer, hdferr)
      if (hdferr < 0) call fail(self, error, path, 'cannot read attribute "' // name // &
         '" as a number')
      call release(attr=attr, obj=obj)
   end subroutine get_attribute

   !> A fixed-length, NUL-padded string type of `width` bytes (at least 1).
   subroutine make_string_type(width, string_type, hdferr)
      integer, intent(in) :: width
      integer(hid_t), intent(out) :: string_type
      integer, intent(out) :: hdferr
      call h5tcopy_f(H5T_FORTRAN_S1, string_type, hdferr)
      if (hdferr < 0) return
      call h5tset_size_f(string_type, int(max(1, width), size_t), hdferr)
      if (hdferr >= 0) call h5tset_strpad_f(string_type, H5T_STR_NULLPAD_F, hdferr)
      if (hdferr < 0) call release(type=string_type)
   end subroutine make_string_type

   !> Bytes of `strings`, each NUL-padded to `width` (at least 1) characters; `trim_each`
   !> drops trailing blanks first (a list), else the text is kept exactly (a scalar).
   pure subroutine pack_strings(strings, width, trim_each, bytes)
      character(len=*), intent(in) :: strings(:)
      integer, intent(in) :: width
      logical, intent(in) :: trim_each
      character(kind=c_char, len=1), allocatable, intent(out) :: bytes(:)
      integer :: w, i, j, last
      w = max(1, width)
      allocate (bytes(w * size(strings)))
      bytes = achar(0, kind=c_char)
      do i = 1, size(strings)
         last = min(w, len(strings(i)))
         if (trim_each) last = min(last, len_trim(strings(i)))
         do j = 1, last
            bytes((i - 1) * w + j) = strings(i)(j:j)
         end do
      end do
   end subroutine pack_strings

   !> `text` up to its first NUL, trailing blanks kept (they belong to the text); a
   !> space-padded string from another writer cannot be told apart and keeps its blanks too.
   pure function trim_padding(text) result(trimmed)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: trimmed
      integer :: nul
      nul = index(text, achar(0))
      if (nul > 0) then
         trimmed = text(1:nul - 1)
      else
         trimmed = text
      end if
   end function trim_padding

   !> "(3, 10)" for messages.
   function shape_text(dims) result(text)
      integer(hsize_t), intent(in) :: dims(:)
      character(len=:), allocatable :: text
      integer :: i
      text = '('
      do i = 1, size(dims)
         if (i > 1) text = text // ', '
         text = text // to_str(int(dims(i), i8))
      end do
      text = text // ')'
   end function shape_text

   !> Close whichever handles are open (>= 0), ignoring secondary errors.
   subroutine release(dset, space, mem_space, plist, type, attr, obj)
      integer(hid_t), intent(inout), optional :: dset, space, mem_space, plist, type, attr, obj
      integer :: hdferr
      if (present(dset)) then
         if (dset >= 0) call h5dclose_f(dset, hdferr)
         dset = -1
      end if
      if (present(space)) then
         if (space >= 0) call h5sclose_f(space, hdferr)
         space = -1
      end if
      if (present(mem_space)) then
         if (mem_space >= 0) call h5sclose_f(mem_space, hdferr)
         mem_space = -1
      end if
      if (present(plist)) then
         if (plist >= 0) call h5pclose_f(plist, hdferr)
         plist = -1
      end if
      if (present(type)) then
         if (type >= 0) call h5tclose_f(type, hdferr)
         type = -1
      end if
      if (present(attr)) then
         if (attr >= 0) call h5aclose_f(attr, hdferr)
         attr = -1
      end if
      if (present(obj)) then
         if (obj >= 0) call h5oclose_f(obj, hdferr)
         obj = -1
      end if
   end subroutine release

end submodule ffrf_io_hdf5_impl
