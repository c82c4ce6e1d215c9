!> ffrf_io_hdf5: whole datasets (reals, integers, strings; rank 0 to 2) and scalar attributes,
!> written and read.
submodule (ffrf_io_hdf5:ffrf_io_hdf5_internals) ffrf_io_hdf5_datasets
   use, intrinsic :: iso_c_binding, only: c_null_char
   use hdf5, only: H5T_STRING, h5tset_cset_f, H5T_CSET_UTF8_F
   implicit none

contains

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
         call packed_strings([text], len(text), .false., bytes, string_type, hdferr)
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
         call packed_strings(strings, width, .true., bytes, string_type, hdferr)
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

   ! ------------------------------------------------------------------ attributes

   module procedure set_attribute_string
      call enter_serial_section(SECTION_HDF5)
      section: block
         character(kind=c_char, len=1), allocatable, target :: bytes(:)
         character(kind=c_char, len=:), allocatable, target :: text
         type(c_ptr), target :: pointer
         type(c_ptr) :: buffer
         integer(hid_t) :: string_type, group
         integer :: hdferr
         logical :: vlen
         vlen = .false.
         if (present(variable)) vlen = variable
         if (vlen) then
            ! h5awrite_f of a variable-length string takes the address of a char* to the text
            if (.not. self%exists(path)) then
               call prepare_dataset(self, path, error)
               if (allocated(error)) exit section
               call h5gcreate_f(self%id, path, group, hdferr)
               if (hdferr < 0) then
                  call fail(self, error, path, 'cannot create the group')
                  exit section
               end if
               call h5gclose_f(group, hdferr)
            end if
            text = value // c_null_char
            pointer = c_loc(text)
            buffer = c_loc(pointer)
            call h5tcopy_f(H5T_STRING, string_type, hdferr)
            if (hdferr >= 0) call h5tset_cset_f(string_type, H5T_CSET_UTF8_F, hdferr)
         else
            call packed_strings([value], len(value), .false., bytes, string_type, hdferr)
            buffer = c_loc(bytes)
         end if
         if (hdferr < 0) then
            call fail(self, error, path, 'cannot make a string type for attribute ' // name)
            exit section
         end if
         call put_attribute(self, path, name, string_type, buffer, error)
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

end submodule ffrf_io_hdf5_datasets
