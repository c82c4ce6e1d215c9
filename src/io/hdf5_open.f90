!> ffrf_io_hdf5: files (create, open, close, flush, what exists), attributes and the run status.
submodule (ffrf_io_hdf5:ffrf_io_hdf5_internals) ffrf_io_hdf5_open
   implicit none

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

   ! ------------------------------------------------------------------ attributes

   module procedure set_attribute_string
      call enter_serial_section(SECTION_HDF5)
      section: block
         character(kind=c_char, len=1), allocatable, target :: bytes(:)
         integer(hid_t) :: string_type
         integer :: hdferr
         call packed_strings([value], len(value), .false., bytes, string_type, hdferr)
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

end submodule ffrf_io_hdf5_open
