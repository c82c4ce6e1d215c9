!> ffrf_io_hdf5: files (create, open, close, flush, what exists) and the run status.
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

end submodule ffrf_io_hdf5_open
