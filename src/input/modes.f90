!> The &modes group as read (strings, as the user wrote them; reader src/input/nml_modes.f90).
!> The model (ffrf_model_specs) turns it into a modes_spec_t of ffrf_modes_input.
module ffrf_input_modes
   use ffrf_core_kinds, only: dp
   use ffrf_core_choices, only: choice_t, formulation_choices, basis_choices
   use ffrf_modes_input, only: modes_spec_t
   implicit none
   private
   public :: modes_input_t, formulation_choices, basis_choices, eigensolver_choices

   !> The &modes choice tables: words, kinds, names in messages (docs/developer.md "One table
   !> per choice"); the key specs (modes_keys) take their words from here, the model
   !> (ffrf_model_specs) their kinds. formulation_choices and basis_choices are those of
   !> ffrf_core_choices (the numerics name their kinds with them); the eigensolver word travels
   !> as text to ffrf_modes (eigen_options_t%eigensolver), so its kinds only number the rows.
   type(choice_t), parameter :: eigensolver_choices(*) = [choice_t('auto', 1), &
      choice_t('arpack', 2), choice_t('block', 3)]

   !> The numerics' defaults (modes_spec_t), the ones of &modes where a key has the same meaning
   type(modes_spec_t), parameter :: spec = modes_spec_t()

   !> Constrained normal modes (&modes).
   type :: modes_input_t
      !> Number of flexible modes per body (free-free bodies: the six rigid modes come on top)
      integer :: num_modes = 12
      !> Shift of the shift-invert Lanczos, as a frequency (Hz); its sign, and the automatic
      !> shift of the default 0: modes_spec_t%shift_hz
      real(dp) :: shift_hz = spec%shift_hz
      !> 'multipliers' (scalable, default) or 'null_space' (explicit LAPACK null spaces)
      character(len=16) :: formulation = 'multipliers'
      !> Label of the reference-condition set, e.g. 'RC set 1', for tables and plots
      character(len=64) :: rc_label = ''
      !> Relative tolerance of the Ritz values (0: machine precision); the default and why:
      !> modes_spec_t%tolerance
      real(dp) :: tolerance = spec%tolerance
      !> Lanczos basis size (ARPACK ncv); 0 = automatic, max(2 num_modes + 1, 20)
      integer :: lanczos_vectors = spec%lanczos_vectors
      !> Mode basis: 'rc_normal' (the constrained normal modes of the RC set, the paper's) or
      !> 'craig_bampton' (static constraint modes of the non-RC virtual-node dofs plus num_modes
      !> fixed-interface modes, orthonormalised by Rayleigh-Ritz: src/modes/craig_bampton.f90)
      character(len=16) :: basis = 'rc_normal'
      !> Out-of-core factorisation: MUMPS writes the factors to files (ICNTL(22) = 1)
      logical :: out_of_core = .false.
      !> Folder of the out-of-core files; blank: TMPDIR, else the output folder
      character(len=256) :: ooc_tmpdir = ''
      !> Memory limit per process in MB: -1 automatic (MemAvailable), 0 none, > 0 the limit
      integer :: memory_limit_mb = -1
      !> Block low-rank dropping tolerance (MUMPS CNTL(7)); 0 = full-rank factors
      real(dp) :: compression_tolerance = 0.0_dp
      !> Eigensolver: 'auto' (default: 'block' from AUTO_BLOCK_MIN_DOFS dofs on, else 'arpack'),
      !> 'arpack' (shift-invert Lanczos, one right-hand side per solve) or 'block' (block
      !> shift-invert Lanczos, many right-hand sides per solve: src/modes/block_krylov.f90)
      character(len=16) :: eigensolver = 'auto'
      !> Every mode below this frequency (Hz), at most num_modes (the smaller set wins); 0: off.
      !> Given without num_modes, num_modes becomes 10000 (no cap in practice)
      real(dp) :: max_frequency_hz = 0.0_dp
      !> Sturm check after convergence: the inertia of K - s M just above the highest mode
      !> proves that none is missing (one more factorisation); always made with max_frequency_hz
      logical :: sturm_check = .true.
   end type modes_input_t

end module ffrf_input_modes
