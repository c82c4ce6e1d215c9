!> The datasets of an engine results file written once (a submodule of
!> ffrf_app_engine_results): run information, matrices, strings, a body's modal data.
submodule (ffrf_app_engine_results) ffrf_app_engine_results_data
   use ffrf_core_error, only: fatal_error, add_context, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_io_xdmf, only: write_xdmf_body
   implicit none

contains

   module procedure engine_results_write_real
      call self%h5%write_real(path, values, unit, error)
   end procedure engine_results_write_real

   module procedure engine_results_write_matrix
      call self%h5%write_real(path, values, unit, error)
   end procedure engine_results_write_matrix

   module procedure engine_results_write_int
      call self%h5%write_int(path, values, error)
   end procedure engine_results_write_int

   module procedure engine_results_write_strings
      call self%h5%write_string_list(path, values, error)
   end procedure engine_results_write_strings

   module procedure engine_results_write_modes
      character(len=:), allocatable :: root
      integer :: k
      if (size(virtual_node_shape, 1) /= 6 * size(interface_names) .or. &
         size(virtual_node_shape, 2) /= size(frequency_hz) .or. &
         size(virtual_xyz, 2) /= size(interface_names)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'engine results "' // self%file_name // &
            '", body "' // body_name // '": ' // to_str(size(frequency_hz)) // ' modes, ' // &
            to_str(size(interface_names)) // ' interfaces, virtual-node rows ' // &
            to_str(size(virtual_node_shape, 1)) // ' x ' // to_str(size(virtual_node_shape, 2)) &
            // '; need 6 rows per interface and one column per mode')
         return
      end if
      root = '/bodies/' // body_name
      call self%h5%write_real(root // '/modes/frequency', frequency_hz, 'Hz', error)
      if (.not. allocated(error)) call self%h5%write_real(root // '/modes/virtual_node_shape', &
         virtual_node_shape, 'm kg^-1/2 (u), rad kg^-1/2 (theta)', error)
      if (.not. allocated(error)) call self%h5%set_attribute(root // '/modes', 'basis', basis, &
         error)
      if (.not. allocated(error)) call self%h5%set_attribute(root // '/modes', &
         'num_static_modes', num_static, error)
      if (.not. allocated(error) .and. size(interface_names) > 0) call &
         self%h5%write_string_list(root // '/interfaces/order', interface_names, error)
      do k = 1, size(interface_names)
         if (allocated(error)) exit
         call self%h5%write_real(root // '/interfaces/' // trim(interface_names(k)) // &
            '/virtual_node', virtual_xyz(:, k), 'm', error)
      end do
      if (allocated(error)) call add_context(error, 'engine results "' // self%file_name // '"')
   end procedure engine_results_write_modes

   module procedure engine_results_write_xdmf_body
      call write_xdmf_body(self%h5, name, xyz, tets, fields, times, .true., body, error)
   end procedure engine_results_write_xdmf_body

   module procedure engine_results_write_long
      call self%h5%write_int(path, values, error)
   end procedure engine_results_write_long

end submodule ffrf_app_engine_results_data
