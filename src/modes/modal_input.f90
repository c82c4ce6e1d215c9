!> Plain input types of the modal pipeline, with their defaults (namelist groups &body and
!> &modes; readers in src/io/nml_*.f90).
module ffrf_modes_input
   use ffrf_core_kinds, only: dp
   implicit none
   private
   public :: body_input_t, modes_input_t, MAX_VOLUMES

   integer, parameter :: MAX_VOLUMES = 16

   !> A flexible body: mesh, physical volumes and material (&body).
   type :: body_input_t
      !> Body name, used by &interface and in the results
      character(len=64) :: name = ''
      !> Gmsh mesh file (MSH 4.1 or 2.2); relative paths are taken from the mesh directory
      character(len=256) :: mesh_file = ''
      !> Physical volume names that make up the body
      character(len=64) :: volumes(MAX_VOLUMES) = ''
      !> Young's modulus (Pa)
      real(dp) :: young = 210.0e9_dp
      !> Poisson's ratio
      real(dp) :: poisson = 0.3_dp
      !> Density (kg/m^3)
      real(dp) :: density = 7850.0_dp
      !> Mechanism runs, flexible bodies: add the modal geometric stiffness of the centrifugal
      !> load cases (stress stiffening of a spinning body, ffrf_modes_modal_geometric_stiffness)
      logical :: geometric_stiffness = .false.
   end type body_input_t

   !> Constrained normal modes (&modes).
   type :: modes_input_t
      !> Number of flexible modes per body (free-free bodies: the six rigid modes come on top)
      integer :: num_modes = 12
      !> Shift of the shift-invert Lanczos, as a frequency (Hz); negative means sigma < 0:
      !> sigma = sign(shift_hz) (2 pi shift_hz)^2. 0 (default) = automatic: a negative shift at
      !> 1 % of the body's wave frequency sqrt(E/rho)/L, below its modes and far enough from
      !> zero that a free-free factorisation stays well conditioned.
      real(dp) :: shift_hz = 0.0_dp
      !> 'multipliers' (scalable, default) or 'null_space' (explicit LAPACK null spaces)
      character(len=16) :: formulation = 'multipliers'
      !> Label of the reference-condition set, e.g. 'RC set 1', for tables and plots
      character(len=64) :: rc_label = ''
      !> Relative tolerance of ARPACK's Ritz values (0: machine precision). 1e-9 gives eigen
      !> residuals ~1e-10 on the reference crank with ~25 % fewer solves than machine precision;
      !> the frequencies (Rayleigh quotients) are accurate to about the residual squared.
      real(dp) :: tolerance = 1.0e-9_dp
      !> Lanczos basis size (ARPACK ncv); 0 = automatic, max(2 num_modes + 1, 20)
      integer :: lanczos_vectors = 0
      !> Mode basis: 'rc_normal' (the constrained normal modes of the RC set, the paper's) or
      !> 'craig_bampton' (static constraint modes of the non-RC virtual-node dofs plus num_modes
      !> fixed-interface modes, orthonormalised by Rayleigh-Ritz: src/modes/craig_bampton.f90)
      character(len=16) :: basis = 'rc_normal'
   end type modes_input_t

end module ffrf_modes_input
