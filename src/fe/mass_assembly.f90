!> assemble_mass: the mass matrix alone (&body modes_file), under the name its callers use
!> (ffrf_modes_reused_modes). It is ffrf_fe_assembly's assemble_matrices without K, the one
!> element loop of K and M (M bitwise that of assemble_stiffness_mass); new code uses
!> ffrf_fe_assembly, and this module goes once no caller names it.
module ffrf_fe_mass_assembly
   use ffrf_fe_assembly, only: assemble_mass => assemble_matrices
   implicit none
   private
   public :: assemble_mass
end module ffrf_fe_mass_assembly
