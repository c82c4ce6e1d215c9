!> Isotropic linear-elastic material: Young's modulus E, Poisson's ratio nu, density rho, and the
!> Lame constants lambda = E nu / ((1 + nu)(1 - 2 nu)), mu = E / (2 (1 + nu)) the element
!> stiffness uses (e.g. Zienkiewicz & Taylor, The Finite Element Method, vol. 1, ch. 6).
module ffrf_fe_material
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   implicit none
   private
   public :: material_t, check_material, lame_parameters

   !> An isotropic linear-elastic material.
   type :: material_t
      !> Young's modulus E (Pa)
      real(dp) :: young = 0.0_dp
      !> Poisson's ratio nu (-)
      real(dp) :: poisson = 0.0_dp
      !> Density rho (kg/m^3)
      real(dp) :: density = 0.0_dp
      !> Name for messages ("steel")
      character(len=64) :: name = ''
   end type material_t

contains

   !> Check E > 0, -1 < nu < 0.5 (positive definite strain energy) and rho > 0.
   subroutine check_material(material, error)
      !> Material to check
      type(material_t), intent(in) :: material
      !> The first property out of range, with its value and the allowed range
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: where
      where = 'material "' // trim(material%name) // '": '
      if (.not. (material%young > 0.0_dp)) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // 'E = ' // to_str(material%young) // &
            ' Pa, must be > 0')
         return
      end if
      if (.not. (material%poisson > -1.0_dp .and. material%poisson < 0.5_dp)) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // 'nu = ' // &
            to_str(material%poisson) // ', must lie in (-1, 0.5)')
         return
      end if
      if (.not. (material%density > 0.0_dp)) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // 'rho = ' // &
            to_str(material%density) // ' kg/m^3, must be > 0')
         return
      end if
   end subroutine check_material

   !> Lame constants of an isotropic material (call check_material first).
   pure subroutine lame_parameters(material, lambda, mu)
      !> Material (E, nu)
      type(material_t), intent(in) :: material
      !> lambda = E nu / ((1 + nu)(1 - 2 nu)) (Pa)
      real(dp), intent(out) :: lambda
      !> Shear modulus mu = E / (2 (1 + nu)) (Pa)
      real(dp), intent(out) :: mu
      lambda = material%young*material%poisson/ &
         ((1.0_dp + material%poisson)*(1.0_dp - 2.0_dp*material%poisson))
      mu = material%young/(2.0_dp*(1.0_dp + material%poisson))
   end subroutine lame_parameters

end module ffrf_fe_material
