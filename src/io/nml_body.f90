!> Namelist group &body (required, repeatable): a flexible body meshed in Gmsh.
!>   name       body name (unique), used by &interface
!>   mesh_file  Gmsh MSH 4.1/2.2 file; relative to the mesh directory (ffrf --mesh-dir)
!>   volumes    physical volume name(s) of the body (default: the body name)
!>   young [Pa], poisson [-], density [kg/m^3]   isotropic linear elastic material
!>   geometric_stiffness  mechanism runs, flexible bodies: centrifugal stress stiffening (.false.)
!>   coarse_meshes  mechanism runs, flexible bodies, &model selection = 'auto': up to 4 coarser
!>                  meshes of the same geometry, coarse to fine, to choose the mesh from
module ffrf_io_nml_body
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str, to_lower
   use ffrf_modes_input, only: body_input_t, MAX_VOLUMES
   use ffrf_mbs_mechanism_input, only: body_motion_input_t
   use ffrf_io_nml_common, only: namelist_read_error
   implicit none
   private
   public :: read_body_groups, inertia_tensor

contains

   !> Read every &body group; at least one is required. motions(k) holds body k's mechanism keys.
   subroutine read_body_groups(unit, bodies, motions, error)
      integer, intent(in) :: unit
      type(body_input_t), allocatable, intent(out) :: bodies(:)
      type(body_motion_input_t), allocatable, intent(out) :: motions(:)
      type(error_t), allocatable, intent(out) :: error
      type(body_input_t) :: defaults
      type(body_motion_input_t) :: motion_defaults, motion
      character(len=64) :: name
      character(len=256) :: mesh_file
      character(len=64) :: volumes(MAX_VOLUMES)
      character(len=16) :: type
      real(dp) :: young, poisson, density, modal_damping, mass, center_of_mass(3), inertia(6)
      real(dp) :: position(3)
      integer :: num_modes
      logical :: geometric_stiffness
      character(len=256) :: coarse_meshes(4)
      character(len=512) :: msg
      integer :: stat, k
      namelist /body/ name, mesh_file, volumes, young, poisson, density, type, num_modes, &
         modal_damping, mass, center_of_mass, inertia, position, geometric_stiffness, coarse_meshes
      allocate (bodies(0), motions(0))
      rewind (unit)
      do
         name = defaults%name
         mesh_file = defaults%mesh_file
         volumes = defaults%volumes
         young = defaults%young
         poisson = defaults%poisson
         density = defaults%density
         geometric_stiffness = defaults%geometric_stiffness
         type = motion_defaults%type
         num_modes = motion_defaults%num_modes
         modal_damping = motion_defaults%modal_damping
         mass = motion_defaults%mass
         center_of_mass = motion_defaults%center_of_mass
         inertia = motion_defaults%inertia
         position = motion_defaults%position
         coarse_meshes = motion_defaults%coarse_meshes
         read (unit, nml=body, iostat=stat, iomsg=msg)
         if (is_iostat_end(stat)) exit
         if (stat /= 0) then
            call namelist_read_error(error, 'body', size(bodies) + 1, msg, &
               'name, mesh_file, volumes, young, poisson, density, type, num_modes, ' // &
               'modal_damping, mass, center_of_mass, inertia, position, geometric_stiffness, ' // &
               'coarse_meshes')
            return
         end if
         if (len_trim(volumes(1)) == 0) volumes(1) = name
         motion = body_motion_input_t(to_lower(type), num_modes, modal_damping, mass, &
            center_of_mass, inertia, position, coarse_meshes)
         bodies = [bodies, body_input_t(name, mesh_file, volumes, young, poisson, density, &
            geometric_stiffness)]
         motions = [motions, motion]
         call check_body(bodies(size(bodies)), motion, size(bodies), error)
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

   subroutine check_body(body, motion, occurrence, error)
      type(body_input_t), intent(in) :: body
      type(body_motion_input_t), intent(in) :: motion
      integer, intent(in) :: occurrence
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: where
      where = '&body #' // to_str(occurrence)
      if (len_trim(body%name) == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': name is missing')
      else if (to_lower(trim(body%name)) == 'ground') then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': the name "ground" is reserved ' &
            // 'for the fixed frame (it needs no &body group)')
      else if (motion%type /= 'flexible' .and. motion%type /= 'rigid') then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ' "' // trim(body%name) // &
            '": type = ''' // trim(motion%type) // ''', must be ''flexible'' or ''rigid''')
      else if (motion%type == 'rigid' .and. body%geometric_stiffness) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ' "' // trim(body%name) // &
            '": geometric_stiffness = .true. needs a flexible body (type = ''flexible''); a ' // &
            'rigid body does not deform')
      else if (motion%type == 'rigid') then
         call check_rigid_body(body, motion, where, error)
      else if (motion%num_modes < -1) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ' "' // trim(body%name) // &
            '": num_modes = ' // to_str(motion%num_modes) // ', must be >= 0 (0: rigid ' // &
            'with the mass of its mesh; default: &modes num_modes)')
      else if (.not. (motion%modal_damping >= 0.0_dp .and. motion%modal_damping < 1.0_dp)) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ' "' // trim(body%name) // &
            '": modal_damping = ' // to_str(motion%modal_damping) // ', must lie in [0, 1)')
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

   !> A rigid body needs a positive mass and a positive-definite inertia (checked by Cholesky
   !> of the symmetric 3 x 3 tensor); a mesh is not used for it.
   subroutine check_rigid_body(body, motion, where, error)
      type(body_input_t), intent(in) :: body
      type(body_motion_input_t), intent(in) :: motion
      character(len=*), intent(in) :: where
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: J(3, 3)
      if (len_trim(body%mesh_file) > 0) then
         if (motion%mass /= 0.0_dp .or. any(motion%inertia /= 0.0_dp) .or. &
            any(motion%center_of_mass /= 0.0_dp)) call fatal_error(error, FFRF_INPUT_ERROR, &
            where // ' "' // trim(body%name) // '": a rigid body takes its mass from ' // &
            'mesh_file or from mass, center_of_mass and inertia, not both')
      else if (.not. (motion%mass > 0.0_dp)) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ' "' // trim(body%name) // &
            '": rigid body mass = ' // to_str(motion%mass) // ' kg, must be > 0')
      else
         J = inertia_tensor(motion%inertia)
         if (.not. positive_definite(J)) call fatal_error(error, FFRF_INPUT_ERROR, where // &
            ' "' // trim(body%name) // '": the inertia (Jxx Jyy Jzz Jxy Jyz Jxz) = ' // &
            to_str(motion%inertia(1)) // ' ' // to_str(motion%inertia(2)) // ' ' // &
            to_str(motion%inertia(3)) // ' ' // to_str(motion%inertia(4)) // ' ' // &
            to_str(motion%inertia(5)) // ' ' // to_str(motion%inertia(6)) // &
            ' kg m^2 is not positive definite (every principal moment must be > 0)')
      end if
   end subroutine check_rigid_body

   !> The symmetric tensor of Jxx Jyy Jzz Jxy Jyz Jxz.
   pure function inertia_tensor(j6) result(J)
      real(dp), intent(in) :: j6(6)
      real(dp) :: J(3, 3)
      J = reshape([j6(1), j6(4), j6(6), j6(4), j6(2), j6(5), j6(6), j6(5), j6(3)], [3, 3])
   end function inertia_tensor

   !> Cholesky of a symmetric 3 x 3 matrix succeeds (all pivots > 0).
   pure logical function positive_definite(A) result(ok)
      real(dp), intent(in) :: A(3, 3)
      real(dp) :: d1, d2, d3, l21, l31, l32
      ok = .false.
      d1 = A(1, 1)
      if (.not. (d1 > 0.0_dp)) return
      l21 = A(2, 1) / sqrt(d1)
      l31 = A(3, 1) / sqrt(d1)
      d2 = A(2, 2) - l21**2
      if (.not. (d2 > 0.0_dp)) return
      l32 = (A(3, 2) - l31 * l21) / sqrt(d2)
      d3 = A(3, 3) - l31**2 - l32**2
      ok = d3 > 0.0_dp
   end function positive_definite

end module ffrf_io_nml_body
