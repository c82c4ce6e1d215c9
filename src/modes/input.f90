!> Plain types of the modal pipeline: a body to cut from a mesh (its volume group names and
!> material; no file names: the mesh comes as an object) and the resolved modes specification
!> (no strings for choices: the model maps &body and &modes onto them, ffrf_model_model).
module ffrf_modes_input
   use ffrf_core_kinds, only: dp
   use ffrf_mpc_reduction, only: FORMULATION_MULTIPLIERS
   !> Mode basis: none (no modes asked), the constrained normal modes of the RC set, or
   !> Craig-Bampton (src/modes/craig_bampton.f90); their words in basis_choices
   use ffrf_core_choices, only: BASIS_NONE, BASIS_RC_NORMAL, BASIS_CRAIG_BAMPTON, basis_choices, &
      choice_name
   implicit none
   private
   public :: body_spec_t, modes_spec_t, MAX_VOLUMES, BASIS_NONE, BASIS_RC_NORMAL, &
      BASIS_CRAIG_BAMPTON, basis_name

   integer, parameter :: MAX_VOLUMES = 16

   !> A body to cut from a mesh (compute_body_modes): its name, the physical volumes that make
   !> it up and its isotropic material.
   type :: body_spec_t
      !> Body name, for the log and the results
      character(len=64) :: name = ''
      !> Physical volume names that make up the body (blank entries unused)
      character(len=64) :: volumes(MAX_VOLUMES) = ''
      !> Young's modulus (Pa)
      real(dp) :: young = 210.0e9_dp
      !> Poisson's ratio
      real(dp) :: poisson = 0.3_dp
      !> Density (kg/m^3)
      real(dp) :: density = 7850.0_dp
   end type body_spec_t

   !> Constrained normal modes of a body, as the model resolved them (from &modes, the body's
   !> num_modes and the automatic model: ffrf_model_specs).
   type :: modes_spec_t
      !> Number of flexible modes (free-free bodies: the six rigid modes come on top); 0: none,
      !> the body gets its mesh, mass properties and interfaces only
      integer :: num_modes = 12
      !> Shift of the shift-invert Lanczos, as a frequency (Hz); negative means sigma < 0:
      !> sigma = sign(shift_hz) (2 pi shift_hz)^2. 0 (default) = automatic: a negative shift at
      !> 1 % of the body's wave frequency sqrt(E/rho)/L, below its modes and far enough from
      !> zero that a free-free factorisation stays well conditioned.
      real(dp) :: shift_hz = 0.0_dp
      !> FORMULATION_MULTIPLIERS (scalable, default) or FORMULATION_NULL_SPACE (explicit LAPACK
      !> null spaces), of ffrf_mpc_reduction
      integer :: formulation = FORMULATION_MULTIPLIERS
      !> Label of the reference-condition set, e.g. 'RC set 1', for the log
      character(len=64) :: rc_label = ''
      !> Relative tolerance of the Ritz values (0: machine precision). Default 1e-9: eigen
      !> residuals ~1e-10 on the reference crank with fewer solves than machine precision; the
      !> frequencies (Rayleigh quotients) are accurate to about the residual squared (docs/method.md
      !> "Modes: spectra you can trust", measured)
      real(dp) :: tolerance = 1.0e-9_dp
      !> Lanczos basis size (ARPACK ncv); 0 = automatic, max(2 num_modes + 1, 20)
      integer :: lanczos_vectors = 0
      !> Mode basis: BASIS_RC_NORMAL (the constrained normal modes of the RC set, the paper's) or
      !> BASIS_CRAIG_BAMPTON (static constraint modes of the non-RC virtual-node dofs plus
      !> num_modes fixed-interface modes, orthonormalised by Rayleigh-Ritz:
      !> src/modes/craig_bampton.f90)
      integer :: basis = BASIS_RC_NORMAL
      !> Out-of-core MUMPS factorisation (factors in files in ooc_directory)
      logical :: out_of_core = .false.
      !> Folder of the out-of-core files; blank: TMPDIR, else the current folder
      character(len=256) :: ooc_directory = ''
      !> Memory limit per process in MB: -1 automatic (MemAvailable), 0 none, > 0 the limit
      integer :: memory_limit_mb = -1
      !> Block low-rank dropping tolerance of the factors (MUMPS CNTL(7)); 0 = full rank
      real(dp) :: compression_tolerance = 0.0_dp
      !> 'auto', 'arpack' or 'block' (eigen_options_t%eigensolver)
      character(len=16) :: eigensolver = 'auto'
      !> Not input: the run stops the eigen solve at its next solve on a signal
      !> (eigen_options_t%stop_on_signal); set by the modal run, not by mechanism runs
      logical :: stop_on_signal = .false.
      !> Every mode below this frequency (Hz; Nastran EIGRL's upper bound), at most num_modes
      !> (the smaller set wins), by shift windows; 0 (default): the num_modes lowest
      real(dp) :: max_frequency_hz = 0.0_dp
      !> Sturm check after convergence (one more factorisation, theory.md 5.7); always made with
      !> max_frequency_hz
      logical :: sturm_check = .true.
   end type modes_spec_t

contains

   !> 'none', 'rc_normal' or 'craig_bampton' (the &modes key's words), for logs and results.
   pure function basis_name(basis) result(name)
      !> BASIS_NONE, BASIS_RC_NORMAL or BASIS_CRAIG_BAMPTON
      integer, intent(in) :: basis
      character(len=:), allocatable :: name
      name = choice_name(basis_choices, basis, 'none')
   end function basis_name

end module ffrf_modes_input
