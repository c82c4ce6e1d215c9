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
   public :: h5_file_t, H5_READ_ONLY, H5_READ_WRITE, series_storage_bytes

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
      !> Deflate level (1-9) of the series created from now on, after a byte shuffle; 0: none
      integer :: deflate_level = 0
      !> At most this many steps per chunk of the series created from now on (0: no limit)
      integer :: max_chunk_steps = 0
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
      procedure :: set_compression => h5_file_set_compression
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
      module subroutine set_attribute_string(self, path, name, value, error, variable)
         class(h5_file_t), intent(inout) :: self
         !> Absolute path of an existing group or dataset
         character(len=*), intent(in) :: path
         !> Attribute name
         character(len=*), intent(in) :: name
         !> Text
         character(len=*), intent(in) :: value
         type(error_t), allocatable, intent(out) :: error
         !> .true.: a variable-length UTF-8 string (what h5py writes for a Python str and reads
         !> back as str, for readers that compare it with one: Exudyn's LoadDictFromHDF5,
         !> docs/results.md "Exudyn export"), and a missing `path` becomes a group (with its
         !> parents); default .false.: fixed-length, NUL-padded
         logical, intent(in), optional :: variable
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
      !> along the step dimension; an existing dataset at `path` is replaced. A chunk holds whole
      !> steps and about 8192 values (64 kB): appending touches the last chunk only, and reading
      !> one history whole reads its own chunks, contiguous in time. With set_compression, each
      !> chunk is shuffled and deflated.
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

      !> Compress the series created from now on (create_series): shuffle + deflate at `level`
      !> (1 fastest .. 9 smallest; 0: none, the default). `max_chunk_steps` > 0 caps the steps
      !> of a chunk (a series expected to hold few steps: a chunk is allocated whole).
      module subroutine h5_file_set_compression(self, level, max_chunk_steps)
         class(h5_file_t), intent(inout) :: self
         !> Deflate level, 0..9 (clipped)
         integer, intent(in) :: level
         !> Steps per chunk at most (0, default: no cap)
         integer, intent(in), optional :: max_chunk_steps
      end subroutine h5_file_set_compression

      !> Bytes a series of `num_rows` values per step (0: scalar) takes in the file after
      !> `num_steps` steps without compression: whole chunks of create_series (the last one
      !> allocated whole) and the nodes of their chunk index, without the few hundred bytes of
      !> its header (written when the series is created).
      module pure integer(i8) function series_storage_bytes(num_rows, num_steps, &
            max_chunk_steps) result(bytes)
         integer, intent(in) :: num_rows
         integer(i8), intent(in) :: num_steps
         !> The cap of set_compression (0: none)
         integer, intent(in) :: max_chunk_steps
      end function series_storage_bytes

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
