!> Namelist group &body (required, repeatable): a flexible body meshed in Gmsh.
!>   name       body name (unique), used by &interface
!>   mesh_file  Gmsh MSH 4.1/2.2 file; relative to the mesh directory (ffrf --mesh-dir)
!>   volumes    physical volume name(s) of the body (default: the body name)
!>   young [Pa], poisson [-], density [kg/m^3]   isotropic linear elastic material
module ffrf_io_nml_body
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_modes_input, only: body_input_t, MAX_VOLUMES
   use ffrf_io_nml_common, only: namelist_read_error
   implicit none
   private
   public :: read_body_groups

contains

   !> Read every &body group; at least one is required.
   subroutine read_body_groups(unit, bodies, error)
      integer, intent(in) :: unit
      type(body_input_t), allocatable, intent(out) :: bodies(:)
      type(error_t), allocatable, intent(out) :: error
      type(body_input_t) :: defaults
      character(len=64) :: name
      character(len=256) :: mesh_file
      character(len=64) :: volumes(MAX_VOLUMES)
      real(dp) :: young, poisson, density
      character(len=512) :: msg
      integer :: stat, k
      namelist /body/ name, mesh_file, volumes, young, poisson, density
      allocate (bodies(0))
      rewind (unit)
      do
         name = defaults%name
         mesh_file = defaults%mesh_file
         volumes = defaults%volumes
         young = defaults%young
         poisson = defaults%poisson
         density = defaults%density
         read (unit, nml=body, iostat=stat, iomsg=msg)
         if (is_iostat_end(stat)) exit
         if (stat /= 0) then
            call namelist_read_error(error, 'body', size(bodies) + 1, msg, &
               'name, mesh_file, volumes, young, poisson, density')
            return
         end if
         if (len_trim(volumes(1)) == 0) volumes(1) = name
         bodies = [bodies, body_input_t(name, mesh_file, volumes, young, poisson, density)]
         call check_body(bodies(size(bodies)), size(bodies), error)
         if (allocated(error)) return
      end do
      if (size(bodies) == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'no &body group: a case needs at least one ' // &
            'body (&body name=..., mesh_file=..., volumes=... /)')
         return
      end if
      do k = 2, size(bodies)
         if (any(bodies(:k - 1)%name == bodies(k)%name)) then
            call fatal_error(error, FFRF_INPUT_ERROR, '&body #' // to_str(k) // ': name "' // &
               trim(bodies(k)%name) // '" is used twice; body names must be unique')
            return
         end if
      end do
   end subroutine read_body_groups

   subroutine check_body(body, occurrence, error)
      type(body_input_t), intent(in) :: body
      integer, intent(in) :: occurrence
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: where
      where = '&body #' // to_str(occurrence)
      if (len_trim(body%name) == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': name is missing')
      else if (len_trim(body%mesh_file) == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ' "' // trim(body%name) // &
            '": mesh_file is missing')
      else if (.not. (body%young > 0.0_dp)) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ' "' // trim(body%name) // &
            '": young = ' // to_str(body%young) // ' Pa, must be > 0')
      else if (.not. (body%poisson > -1.0_dp .and. body%poisson < 0.5_dp)) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ' "' // trim(body%name) // &
            '": poisson = ' // to_str(body%poisson) // ', must lie in (-1, 0.5)')
      else if (.not. (body%density > 0.0_dp)) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ' "' // trim(body%name) // &
            '": density = ' // to_str(body%density) // ' kg/m^3, must be > 0')
      end if
   end subroutine check_body

end module ffrf_io_nml_body
