!> Namelist group &modes (optional, single): the constrained normal modes of every flexible body.
!>   num_modes    flexible modes per body (default 12), integer in 1..10000
!>   shift_hz     shift of the shift-invert Lanczos as a frequency [Hz]; negative: sigma < 0;
!>                0 (default): automatic, 1 % of the body's wave frequency sqrt(E/rho)/L, negative;
!>                a finite real in [-1e9, 1e9] Hz
!>   formulation  'multipliers' (default, scalable) or 'null_space' (explicit LAPACK null spaces)
!>   rc_label     label of the RC set for tables and plots (e.g. 'RC set 1'), <= 64 characters
!>   tolerance    ARPACK relative tolerance (default 1e-9; 0: machine precision), in [0, 1e-2)
!>   lanczos_vectors  Lanczos basis size, ARPACK's ncv (default 0: max(2 num_modes + 1, 20)),
!>                integer in 0..100000, > num_modes unless 0
!>   basis        'rc_normal' (default: constrained normal modes of the RC set) or
!>                'craig_bampton' (static constraint modes of the non-RC virtual-node dofs +
!>                num_modes fixed-interface modes, orthonormalised; Heirman & Desmet 2010)
!>   out_of_core  .true.: MUMPS writes the factors to files (out-of-core; default .false.)
!>   ooc_tmpdir   folder of the out-of-core files (default '': TMPDIR, else the output folder);
!>                with out_of_core = .true. an existing folder (else exit 3 here, not in MUMPS)
!>   memory_limit_mb  memory limit per process [MB]: -1 (default) MemAvailable, 0 no check;
!>                a factorisation predicted above it is refused (exit 4); integer >= -1
!>   compression_tolerance  block low-rank dropping tolerance of the factors (MUMPS CNTL(7)),
!>                in [0, 1); 0 (default): full-rank factors
!>   eigensolver  'auto' (default: 'block' for bodies of 200,000 dofs or more, else 'arpack'),
!>                'arpack' (ARPACK shift-invert Lanczos, one solve per vector) or 'block' (block
!>                shift-invert Lanczos: num_modes + 4 right-hand sides per solve)
!>   max_frequency_hz  every mode below this frequency [Hz] (Nastran EIGRL V2), by shift windows
!>                of at most 50 modes each proven by Sturm counts; with num_modes too the smaller
!>                set wins, without it num_modes becomes 10000; 0 (default): off; in [0, 1e9]
!>   sturm_check  .true. (default): after convergence the inertia of K - s M just above the
!>                highest mode proves that none is missing (one more factorisation; a short
!>                count triggers a recovery); .false. skips it (large meshes); needed with
!>                max_frequency_hz
module ffrf_input_nml_modes
   use ffrf_core_kinds, only: dp, i8
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR, FFRF_IO_ERROR
   use ffrf_core_posix, only: file_kind, file_kind_name, FILE_DIRECTORY, FILE_MISSING
   use ffrf_core_strings, only: to_str, to_lower
   use ffrf_core_choices, only: choice_words
   use ffrf_input_modes, only: modes_input_t, formulation_choices, basis_choices, &
      eigensolver_choices
   use ffrf_modes_shift_invert, only: DEFAULT_WINDOW_SIZE
   use ffrf_input_nml_common, only: read_status
   use ffrf_input_nml_source, only: key_spec_t, real_key, integer_key, string_key, choice_key, &
      nml_source_t, logical_key
   implicit none
   private
   public :: read_modes_group, modes_keys

contains

   !> Keys of &modes, their types and ranges (module header).
   function modes_keys() result(keys)
      type(key_spec_t), allocatable :: keys(:)
      keys = [integer_key('num_modes', 1_i8, 10000_i8), &
         real_key('shift_hz', -1.0e9_dp, 1.0e9_dp, 'Hz'), &
         choice_key('formulation', 16, choice_words(formulation_choices)), &
         string_key('rc_label', 64), &
         real_key('tolerance', 0.0_dp, 1.0e-2_dp, '', upper_open=.true.), &
         integer_key('lanczos_vectors', 0_i8, 100000_i8), &
         choice_key('basis', 16, choice_words(basis_choices)), logical_key('out_of_core'), &
         string_key('ooc_tmpdir', 256), integer_key('memory_limit_mb', -1_i8, 1000000000_i8), &
         real_key('compression_tolerance', 0.0_dp, 1.0_dp, '', upper_open=.true.), &
         choice_key('eigensolver', 16, choice_words(eigensolver_choices)), &
         real_key('max_frequency_hz', 0.0_dp, 1.0e9_dp, 'Hz'), logical_key('sturm_check')]
   end function modes_keys

   !> Read &modes (optional group; defaults from modes_input_t).
   subroutine read_modes_group(unit, src, input, error)
      integer, intent(in) :: unit
      !> The checked case text (FILE:LINE of the keys)
      type(nml_source_t), intent(in) :: src
      type(modes_input_t), intent(inout) :: input
      type(error_t), allocatable, intent(out) :: error
      type(modes_input_t) :: m
      character(len=512) :: msg
      integer :: stat, kind
      integer(i8) :: size_bytes
      m = input
      ! -1: not given (the strict pre-reader refuses it written), so that max_frequency_hz alone
      ! means every mode below it
      m%num_modes = -1
      rewind (unit)
      call read_modes(m%num_modes, m%shift_hz, m%formulation, m%rc_label, m%tolerance, &
         m%lanczos_vectors, m%basis, m%out_of_core, m%ooc_tmpdir, m%memory_limit_mb, &
         m%compression_tolerance, m%eigensolver, m%max_frequency_hz, m%sturm_check)
      if (is_iostat_end(stat)) return
      call read_status(src, 'modes', 0, stat, msg, error)
      if (allocated(error)) return
      if (m%num_modes == -1) then
         m%num_modes = input%num_modes
         if (m%max_frequency_hz > 0.0_dp) m%num_modes = 10000
      end if
      m%formulation = to_lower(m%formulation)
      m%basis = to_lower(m%basis)
      m%eigensolver = to_lower(m%eigensolver)
      ! the ranges, shift_hz's finiteness and the words of formulation, basis and eigensolver
      ! were checked by the key spec (modes_keys); here the rules between keys
      if (m%lanczos_vectors /= 0 .and. m%lanczos_vectors <= min(m%num_modes, &
               int(DEFAULT_WINDOW_SIZE))) then
         call fatal_error(error, FFRF_INPUT_ERROR, src%where('modes', 1, 'lanczos_vectors') // &
            ': must exceed num_modes = ' // to_str(m%num_modes) // ' (at most the ' // &
            to_str(DEFAULT_WINDOW_SIZE) // ' modes of one shift window; about twice that; ' // &
            '0 = automatic)')
      else if (m%max_frequency_hz > 0.0_dp .and. m%shift_hz > 0.0_dp) then
         call fatal_error(error, FFRF_INPUT_ERROR, src%where('modes', 1, 'shift_hz') // &
            ' Hz cannot go with max_frequency_hz = ' // to_str(m%max_frequency_hz) // ' Hz: ' // &
            'the shift windows run from the shift up to it; give shift_hz <= 0 (0: ' // &
            'automatic, below every mode)')
      else if (m%max_frequency_hz > 0.0_dp .and. .not. m%sturm_check) then
         call fatal_error(error, FFRF_INPUT_ERROR, src%where('modes', 1, 'sturm_check') // &
            ' cannot go with max_frequency_hz = ' // to_str(m%max_frequency_hz) // ' Hz: the ' // &
            'Sturm counts are how the shift windows find every mode below it; remove ' // &
            'sturm_check = .false. or max_frequency_hz')
      else if (m%compression_tolerance > 0.0_dp) then
         ! Measured on this toolchain (docs/performance.md "Large meshes"): about one BLR analysis
         ! in four ends with SIGSEGV inside SCOTCH, and the crank's fronts hardly compress.
         call fatal_error(error, FFRF_INPUT_ERROR, '&modes: compression_tolerance = ' // &
            to_str(m%compression_tolerance) // ': block low-rank factors are not offered: ' // &
            'Debian 12''s MUMPS 5.5.1 with SCOTCH 7.0.3 crashes (SIGSEGV in ' // &
            'SCOTCH_graphBuild) in about one block low-rank analysis in four, and on the ' // &
            'crank they store 90-95 % of the full factor; use out_of_core = .true. or more ' // &
            'ranks (the MPI build) for large meshes, and compression_tolerance = 0')
      end if
      if (allocated(error)) return
      if (m%out_of_core .and. len_trim(m%ooc_tmpdir) > 0) then
         ! MUMPS would only fail in the factorisation (INFOG(1) = -90)
         call file_kind(trim(m%ooc_tmpdir), kind, size_bytes, error)
         if (allocated(error)) return
         if (kind /= FILE_DIRECTORY) then
            if (kind == FILE_MISSING) then
               msg = 'does not exist'
            else
               msg = 'is ' // file_kind_name(kind) // ', not a folder'
            end if
            call fatal_error(error, FFRF_IO_ERROR, src%where('modes', 1, 'ooc_tmpdir') // &
               ': "' // trim(m%ooc_tmpdir) // '" ' // trim(msg) // '; out_of_core = .true. ' // &
               'writes the factors there: create the folder, or leave ooc_tmpdir out ' // &
               '(TMPDIR, else the output folder)')
            return
         end if
      end if
      input = m
   contains
      !> The namelist read of &modes into its fields (absent keys keep their values).
      subroutine read_modes(num_modes, shift_hz, formulation, rc_label, tolerance, &
            lanczos_vectors, basis, out_of_core, ooc_tmpdir, memory_limit_mb, &
            compression_tolerance, eigensolver, max_frequency_hz, sturm_check)
         integer, intent(inout) :: num_modes, lanczos_vectors, memory_limit_mb
         real(dp), intent(inout) :: shift_hz, tolerance, compression_tolerance, max_frequency_hz
         character(len=*), intent(inout) :: formulation, rc_label, basis, ooc_tmpdir, eigensolver
         logical, intent(inout) :: out_of_core, sturm_check
         namelist /modes/ num_modes, shift_hz, formulation, rc_label, tolerance, &
            lanczos_vectors, basis, out_of_core, ooc_tmpdir, memory_limit_mb, &
            compression_tolerance, eigensolver, max_frequency_hz, sturm_check
         read (unit, nml=modes, iostat=stat, iomsg=msg)
      end subroutine read_modes
   end subroutine read_modes_group

end module ffrf_input_nml_modes
