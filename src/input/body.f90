!> Plain input type of a &body group's mesh and material (reader: src/input/nml_body.f90; its
!> motion keys are body_motion_input_t of ffrf_input_mechanism). The model turns it into the
!> numerics' body_spec_t (ffrf_model_model body_spec_of) and resolves its mesh file.
module ffrf_input_body
   use ffrf_core_kinds, only: dp
   use ffrf_modes_input, only: MAX_VOLUMES, body_spec_t
   implicit none
   private
   public :: body_input_t, MAX_VOLUMES

   !> The numerics' material defaults (body_spec_t: steel), those of &body
   type(body_spec_t), parameter :: spec = body_spec_t()

   !> A body: mesh file, physical volumes and material (&body).
   type :: body_input_t
      !> Body name, used by &interface and in the results
      character(len=64) :: name = ''
      !> Mesh file: Gmsh (MSH 4.1 or 2.2) or Nastran bulk data (.bdf .dat .nas .blk); relative
      !> paths are taken from the mesh directory
      character(len=256) :: mesh_file = ''
      !> Physical volume names that make up the body
      character(len=64) :: volumes(MAX_VOLUMES) = ''
      !> Young's modulus (Pa)
      real(dp) :: young = spec%young
      !> Poisson's ratio
      real(dp) :: poisson = spec%poisson
      !> Density (kg/m^3)
      real(dp) :: density = spec%density
      !> young, poisson, density written in &body (a Nastran deck's MAT1 gives those not written)
      logical :: material_given(3) = .false.
      !> Mechanism runs, flexible bodies: add the modal geometric stiffness of the centrifugal
      !> load cases (stress stiffening of a spinning body, ffrf_modes_modal_geometric_stiffness)
      logical :: geometric_stiffness = .false.
      !> Mechanism runs, flexible bodies: results file of an earlier run whose modes of this body
      !> are taken instead of computed (checked against their fingerprint); '' = compute them
      character(len=256) :: modes_file = ''
   end type body_input_t

end module ffrf_input_body
