!> Bodies of ffrf_io_hdf5, first of its submodules: the helpers the others share (library
!> start, open checks, dataset create/write/open/read, attribute writes, release of handles);
!> only ffrf_io_hdf5's submodules touch HDF5 handles. Its children: hdf5_open.f90,
!> hdf5_datasets.f90, hdf5_series.f90.
submodule (ffrf_io_hdf5) ffrf_io_hdf5_internals
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

   abstract interface
      !> The close of one kind of HDF5 handle (h5dclose_f, h5sclose_f, h5pclose_f, ...)
      subroutine h5_close(id, hdferr)
         import :: hid_t
         integer(hid_t), intent(in) :: id
         integer, intent(out) :: hdferr
      end subroutine h5_close
   end interface

contains

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

   !> Open the dataset `path` of an open file (dset = -1 if that fails, the error worded by
   !> `missing` when there is no such object and by `not_dataset` when it is no dataset).
   subroutine open_existing(self, path, missing, not_dataset, dset, error)
      class(h5_file_t), intent(in) :: self
      character(len=*), intent(in) :: path, missing, not_dataset
      integer(hid_t), intent(out) :: dset
      type(error_t), allocatable, intent(out) :: error
      integer :: hdferr
      dset = -1
      call require_open(self, path, error)
      if (allocated(error)) return
      if (.not. self%exists(path)) then
         call fail(self, error, path, missing)
         return
      end if
      call h5dopen_f(self%id, path, dset, hdferr)
      if (hdferr < 0) then
         dset = -1
         call fail(self, error, path, not_dataset)
      end if
   end subroutine open_existing

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
      dims = 0
      call open_existing(self, path, 'no such dataset', 'not a dataset (a group?)', dset, error)
      if (allocated(error)) return
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
      call packed_strings([units], len(units), .false., bytes, string_type, hdferr)
      if (hdferr < 0) return
      call put_scalar_attribute(dset, 'units', string_type, c_loc(bytes), hdferr)
      call release(type=string_type)
   end subroutine put_units

   !> `strings` packed into `bytes` (pack_strings) and the fixed-length, NUL-padded string type
   !> of their `width` (at least 1) bytes, for the caller to close.
   subroutine packed_strings(strings, width, trim_each, bytes, string_type, hdferr)
      character(len=*), intent(in) :: strings(:)
      integer, intent(in) :: width
      logical, intent(in) :: trim_each
      character(kind=c_char, len=1), allocatable, intent(out) :: bytes(:)
      integer(hid_t), intent(out) :: string_type
      integer, intent(out) :: hdferr
      call pack_strings(strings, width, trim_each, bytes)
      call h5tcopy_f(H5T_FORTRAN_S1, string_type, hdferr)
      if (hdferr < 0) return
      call h5tset_size_f(string_type, int(max(1, width), size_t), hdferr)
      if (hdferr >= 0) call h5tset_strpad_f(string_type, H5T_STR_NULLPAD_F, hdferr)
      if (hdferr < 0) call release(type=string_type)
   end subroutine packed_strings

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
      call release_one(dset, h5dclose_f)
      call release_one(space, h5sclose_f)
      call release_one(mem_space, h5sclose_f)
      call release_one(plist, h5pclose_f)
      call release_one(type, h5tclose_f)
      call release_one(attr, h5aclose_f)
      call release_one(obj, h5oclose_f)
   end subroutine release

   !> Close `id` with `close` when it is present and open (>= 0), then mark it closed (-1).
   subroutine release_one(id, close)
      integer(hid_t), intent(inout), optional :: id
      !> The HDF5 close of the handle's kind (h5dclose_f, h5sclose_f, ...)
      procedure(h5_close) :: close
      integer :: hdferr
      if (.not. present(id)) return
      if (id >= 0) call close(id, hdferr)
      id = -1
   end subroutine release_one

end submodule ffrf_io_hdf5_internals
