!> ffrf_io_hdf5: time series, chunked datasets that grow along their last dimension.
submodule (ffrf_io_hdf5:ffrf_io_hdf5_internals) ffrf_io_hdf5_series
   use hdf5, only: h5pset_shuffle_f, h5pset_deflate_f
   implicit none

contains

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
            chunk = [int(chunk_steps(0, self%max_chunk_steps), hsize_t)]
         else
            dims = [int(num_rows, hsize_t), 0_hsize_t]
            max_dims = [int(num_rows, hsize_t), H5S_UNLIMITED_F]
            chunk = [int(num_rows, hsize_t), int(chunk_steps(num_rows, self%max_chunk_steps), &
               hsize_t)]
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
            if (self%deflate_level > 0) then
               call h5pset_shuffle_f(plist, hdferr)
               if (hdferr < 0) exit steps
               call h5pset_deflate_f(plist, self%deflate_level, hdferr)
               if (hdferr < 0) exit steps
            end if
            call h5dcreate_f(self%id, path, H5T_NATIVE_DOUBLE, space, dset, hdferr, plist)
            if (hdferr < 0) exit steps
            call put_units(dset, units, hdferr)
         end block steps
         if (hdferr < 0) call fail(self, error, path, 'cannot create the time series dataset')
         call release(dset=dset, space=space, plist=plist)
      end block section
      call leave_serial_section(SECTION_HDF5)
   end procedure h5_file_create_series

   module procedure h5_file_set_compression
      self%deflate_level = max(0, min(9, level))
      self%max_chunk_steps = 0
      if (present(max_chunk_steps)) self%max_chunk_steps = max(0, max_chunk_steps)
   end procedure h5_file_set_compression

   !> Steps per chunk of a series of num_rows values per step (0: scalar): about series_chunk
   !> values, at most `cap` steps when cap > 0.
   pure integer function chunk_steps(num_rows, cap) result(steps)
      integer, intent(in) :: num_rows, cap
      steps = max(1, series_chunk / max(1, num_rows))
      if (cap > 0) steps = min(steps, cap)
   end function chunk_steps

   module procedure series_storage_bytes
      integer(i8) :: rows, steps_per_chunk, chunks, leaves, node
      rows = max(1_i8, int(num_rows, i8))
      steps_per_chunk = int(chunk_steps(num_rows, max_chunk_steps), i8)
      chunks = (num_steps + steps_per_chunk - 1_i8) / steps_per_chunk
      bytes = chunks * steps_per_chunk * rows * 8_i8
      ! the chunk index: version-1 B-tree nodes of 64 chunks (HDF5's default K = 32), a header
      ! of 24 bytes, 65 keys (chunk size, filter mask, one offset per dimension and one more)
      ! and 64 addresses, allocated once the first chunk is written
      if (chunks == 0_i8) return
      node = 24_i8 + 65_i8 * (8_i8 + 8_i8 * merge(3_i8, 2_i8, num_rows > 0)) + 64_i8 * 8_i8
      leaves = (chunks + 63_i8) / 64_i8
      bytes = bytes + (leaves + (leaves + 62_i8) / 63_i8 - merge(1_i8, 0_i8, leaves == 1_i8)) &
         * node
   end procedure series_storage_bytes

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

   !> Check `path` is a series and return its rank (1 or 2).
   subroutine series_rank(self, path, rank, error)
      class(h5_file_t), intent(in) :: self
      character(len=*), intent(in) :: path
      integer, intent(out) :: rank
      type(error_t), allocatable, intent(out) :: error
      integer(hid_t) :: dset, space
      integer :: hdferr, close_status
      rank = 0
      call open_existing(self, path, 'no such time series; make it with create_series first', &
         'not a dataset', dset, error)
      if (allocated(error)) return
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

end submodule ffrf_io_hdf5_series
