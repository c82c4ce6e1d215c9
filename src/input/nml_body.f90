!> Namelist group &body (required, repeatable): a flexible body meshed in Gmsh.
!>   name       body name (unique, not 'ground'), used by &interface; <= 64 characters
!>   mesh_file  Gmsh MSH 4.1/2.2 file, or Nastran bulk data (.bdf .dat .nas .blk); relative to
!>              the mesh directory (ffrf --mesh-dir), or absolute; <= 256 characters
!>   volumes    physical volume name(s) of the body (default: the body name); 1 to 16 names;
!>              of a Nastran deck: PSOLID ids ('1'), whose MAT1 gives the material keys not set
!>   young [Pa]        Young's modulus, in (0, 1e13] Pa
!>   poisson [-]       Poisson's ratio, in (-1, 0.5)
!>   density [kg/m^3]  in (0, 1e5] kg/m^3
!>   geometric_stiffness  mechanism runs, flexible bodies: centrifugal stress stiffening (.false.)
!>   coarse_meshes  mechanism runs, flexible bodies, &model selection = 'auto': up to 4 coarser
!>                  meshes of the same geometry, coarse to fine, to choose the mesh from
!>   modes_file     mechanism runs, flexible bodies: results file (.h5) of an earlier modal or
!>                  mechanism run to take this body's modes from, checked against what they
!>                  depend on (ffrf_modes_fingerprint); relative to the current folder; <= 256
!> Mechanism keys (ffrf_input_mechanism's body_motion_input_t):
!>   type           'flexible' (default) or 'rigid'
!>   num_modes      flexible bodies: modes kept, integer in 0..10000 (default: &modes num_modes);
!>                  modal runs take it too (ffrf_model_specs body_modes_spec)
!>   modal_damping  damping ratio of every mode, in [0, 1)
!>   mass [kg]      rigid bodies without a mesh: in [0, 1e9] kg, > 0 when it is used
!>   center_of_mass [m]    3 finite reals in [-1e4, 1e4] m
!>   inertia [kg m^2]      Jxx Jyy Jzz Jxy Jyz Jxz, 6 finite reals in [-1e12, 1e12], positive
!>                         definite when it is used
!>   position [m]   start position of the body frame, 3 finite reals in [-1e4, 1e4] m
!>   orientation [-]  start orientation, rigid and flexible bodies: the rotation matrix A
!>                  (body -> global, r = position + A x_bar) by rows, 9 reals A11 A12 A13 A21
!>                  A22 A23 A31 A32 A33 in [-1e6, 1e6]; its columns are the body x, y, z axes
!>                  in global coordinates. Must be a rotation: |A A^T - I| <= 1e-9 (largest
!>                  entry) and det A > 0 (default: the identity, body axes = global axes)
!>   velocity [m/s]         start velocity of the body-frame origin, global, 3 reals in
!>                          [-1e6, 1e6] (default 0)
!>   angular_velocity [rad/s]  start angular velocity, global axes, 3 reals in [-1e6, 1e6]
!>                          (default 0). The assembly makes position, orientation and the
!>                          velocities consistent with the joints (least-squares projection; the
!>                          log's [assembly] lines say how much each body moved)
!> Types, counts and ranges are checked by ffrf_input_nml_source from body_keys.
module ffrf_input_nml_body
   use ffrf_core_kinds, only: dp, i8
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str, to_lower
   use ffrf_input_body, only: body_input_t, MAX_VOLUMES
   use ffrf_input_mechanism, only: body_motion_input_t, body_type_choices
   use ffrf_core_choices, only: choice_words
   use ffrf_input_nml_common, only: read_status
   use ffrf_mbs_rotation, only: rotation_defect, determinant3, ROTATION_TOLERANCE
   use ffrf_input_nml_source, only: key_spec_t, real_key, integer_key, logical_key, string_key, &
      choice_key, nml_source_t
   implicit none
   private
   public :: read_body_groups, inertia_tensor, body_keys

contains

   !> Keys of &body, their types and ranges (module header).
   function body_keys() result(keys)
      type(key_spec_t), allocatable :: keys(:)
      keys = [string_key('name', 64), string_key('mesh_file', 256), &
         string_key('volumes', 64, MAX_VOLUMES), &
         real_key('young', 0.0_dp, 1.0e13_dp, 'Pa', lower_open=.true.), &
         real_key('poisson', -1.0_dp, 0.5_dp, '', lower_open=.true., upper_open=.true.), &
         real_key('density', 0.0_dp, 1.0e5_dp, 'kg/m^3', lower_open=.true.), &
         choice_key('type', 16, choice_words(body_type_choices)), &
         integer_key('num_modes', 0_i8, 10000_i8), &
         real_key('modal_damping', 0.0_dp, 1.0_dp, '', upper_open=.true.), &
         real_key('mass', 0.0_dp, 1.0e9_dp, 'kg'), &
         real_key('center_of_mass', -1.0e4_dp, 1.0e4_dp, 'm', count=3), &
         real_key('inertia', -1.0e12_dp, 1.0e12_dp, 'kg m^2', count=6), &
         real_key('position', -1.0e4_dp, 1.0e4_dp, 'm', count=3), &
         real_key('orientation', -1.0e6_dp, 1.0e6_dp, '', count=9), &
         real_key('velocity', -1.0e6_dp, 1.0e6_dp, 'm/s', count=3), &
         real_key('angular_velocity', -1.0e6_dp, 1.0e6_dp, 'rad/s', count=3), &
         logical_key('geometric_stiffness'), string_key('coarse_meshes', 256, 4), &
         string_key('modes_file', 256)]
   end function body_keys

   !> Read every &body group; at least one is required. motions(k) holds body k's mechanism keys.
   subroutine read_body_groups(unit, src, bodies, motions, error)
      integer, intent(in) :: unit
      !> The checked case text (FILE:LINE of the keys)
      type(nml_source_t), intent(in) :: src
      type(body_input_t), allocatable, intent(out) :: bodies(:)
      type(body_motion_input_t), allocatable, intent(out) :: motions(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: orientation(9)
      character(len=512) :: msg
      integer :: stat, k
      allocate (bodies(src%count('body')), motions(src%count('body')))
      rewind (unit)
      do k = 1, size(bodies)
         ! by rows in the input, the body axes its columns
         orientation = reshape(transpose(motions(k)%orientation), [9])
         associate (b => bodies(k), m => motions(k))
            call read_body(b%name, b%mesh_file, b%volumes, b%young, b%poisson, b%density, &
               m%type, m%num_modes, m%modal_damping, m%mass, m%center_of_mass, m%inertia, &
               m%position, b%geometric_stiffness, m%coarse_meshes, b%modes_file, &
               m%velocity, m%angular_velocity)
            call read_status(src, 'body', k, stat, msg, error)
            if (allocated(error)) return
            if (len_trim(b%volumes(1)) == 0) b%volumes(1) = b%name
            b%material_given = [src%has_key('body', k, 'young'), &
               src%has_key('body', k, 'poisson'), src%has_key('body', k, 'density')]
            m%type = to_lower(m%type)
            m%orientation = transpose(reshape(orientation, [3, 3]))
         end associate
         call check_body(src, bodies(k), motions(k), k, error)
         if (allocated(error)) return
      end do
      if (size(bodies) == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'no &body group: a case needs at least one ' // &
            'body (&body name=..., mesh_file=..., volumes=... /)')
         return
      end if
      do k = 2, size(bodies)
         if (any(bodies(:k - 1)%name == bodies(k)%name)) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('body', k, 'name') // &
               ': the name is used twice; body names must be unique')
            return
         end if
      end do
   contains
      !> The namelist read of &body k into its fields (absent keys keep their defaults; the
      !> orientation into that of the host).
      subroutine read_body(name, mesh_file, volumes, young, poisson, density, type, num_modes, &
            modal_damping, mass, center_of_mass, inertia, position, geometric_stiffness, &
            coarse_meshes, modes_file, velocity, angular_velocity)
         character(len=*), intent(inout) :: name, mesh_file, volumes(MAX_VOLUMES), type, &
            coarse_meshes(4), modes_file
         real(dp), intent(inout) :: young, poisson, density, modal_damping, mass, &
            center_of_mass(3), inertia(6), position(3), velocity(3), angular_velocity(3)
         integer, intent(inout) :: num_modes
         logical, intent(inout) :: geometric_stiffness
         namelist /body/ name, mesh_file, volumes, young, poisson, density, type, num_modes, &
            modal_damping, mass, center_of_mass, inertia, position, geometric_stiffness, &
            coarse_meshes, modes_file, orientation, velocity, angular_velocity
         read (unit, nml=body, iostat=stat, iomsg=msg)
      end subroutine read_body
   end subroutine read_body_groups

   !> Cross-key checks of one &body (single keys are checked by ffrf_input_nml_source).
   subroutine check_body(src, body, motion, occurrence, error)
      type(nml_source_t), intent(in) :: src
      type(body_input_t), intent(in) :: body
      type(body_motion_input_t), intent(in) :: motion
      integer, intent(in) :: occurrence
      type(error_t), allocatable, intent(out) :: error
      if (len_trim(body%name) == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, src%where('body', occurrence, '') // &
            ': name is missing; give every body a unique name')
      else if (to_lower(trim(body%name)) == 'ground') then
         call fatal_error(error, FFRF_INPUT_ERROR, src%where('body', occurrence, 'name') // &
            ': the name "ground" is reserved for the fixed frame (it needs no &body group)')
      else if (motion%type == 'rigid' .and. body%geometric_stiffness) then
         call fatal_error(error, FFRF_INPUT_ERROR, src%where('body', occurrence, &
            'geometric_stiffness') // ': "' // trim(body%name) // '": geometric_stiffness ' // &
            '= .true. needs a flexible body (type = ''flexible''); a rigid body does not deform')
      else if (motion%type == 'rigid' .and. len_trim(body%modes_file) > 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, src%where('body', occurrence, &
            'modes_file') // ': "' // trim(body%name) // '": a rigid body has no modes; ' // &
            'modes_file is for flexible bodies')
      else if (rotation_defect(motion%orientation) > ROTATION_TOLERANCE) then
         call fatal_error(error, FFRF_INPUT_ERROR, src%where('body', occurrence, &
            'orientation') // ': "' // trim(body%name) // '": the orientation is not ' // &
            'orthonormal: largest |A A^T - I| = ' // to_str(rotation_defect(motion%orientation)) &
            // ' > 1e-9 (give the rotation matrix by rows, 9 reals, its columns the body axes)')
      else if (.not. determinant3(motion%orientation) > 0.0_dp) then
         call fatal_error(error, FFRF_INPUT_ERROR, src%where('body', occurrence, &
            'orientation') // ': "' // trim(body%name) // '": the orientation has det = ' // &
            to_str(determinant3(motion%orientation)) // ', a reflection, not a rotation ' // &
            '(det must be +1: a right-handed set of body axes)')
      else if (motion%type == 'rigid') then
         call check_rigid_body(src, body, motion, occurrence, error)
      else if (len_trim(body%mesh_file) == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, src%where('body', occurrence, &
            'mesh_file') // ': "' // trim(body%name) // '": mesh_file is missing; a ' // &
            'flexible body needs its Gmsh mesh')
      end if
   end subroutine check_body

   !> A rigid body needs a positive mass and a positive-definite inertia (checked by Cholesky
   !> of the symmetric 3 x 3 tensor); a mesh is not used for it.
   subroutine check_rigid_body(src, body, motion, occurrence, error)
      type(nml_source_t), intent(in) :: src
      type(body_input_t), intent(in) :: body
      type(body_motion_input_t), intent(in) :: motion
      integer, intent(in) :: occurrence
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: J(3, 3)
      if (len_trim(body%mesh_file) > 0) then
         if (motion%mass /= 0.0_dp .or. any(motion%inertia /= 0.0_dp) .or. &
            any(motion%center_of_mass /= 0.0_dp)) call fatal_error(error, FFRF_INPUT_ERROR, &
            src%where('body', occurrence, 'mesh_file') // ': "' // trim(body%name) // &
            '": a rigid body takes its mass from mesh_file or from mass, center_of_mass and ' // &
            'inertia, not both')
      else if (.not. (motion%mass > 0.0_dp)) then
         call fatal_error(error, FFRF_INPUT_ERROR, src%where('body', occurrence, 'mass') // &
            ': "' // trim(body%name) // '": rigid body mass = ' // to_str(motion%mass) // &
            ' kg, must be > 0 (or give a mesh_file)')
      else
         J = inertia_tensor(motion%inertia)
         if (.not. positive_definite(J)) call fatal_error(error, FFRF_INPUT_ERROR, &
            src%where('body', occurrence, 'inertia') // ': "' // trim(body%name) // &
            '": the inertia (Jxx Jyy Jzz Jxy Jyz Jxz) = ' // &
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

end module ffrf_input_nml_body
