!> ffrf_la_mumps: memory options (out-of-core, block low-rank compression, limit; issue 12) and
!> the check of a factorisation's predicted memory against the limit.
submodule (ffrf_la_mumps) ffrf_la_mumps_memory
   implicit none

contains

   module procedure mumps_solver_set_memory_options
      character(len=:), allocatable :: folder
      character(len=4096) :: env
      integer :: length, stat

      if (self%phase /= phase_initialised) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'MUMPS set_memory_options: call it after ' // &
            'init and before analyse')
         return
      end if
      if (present(compression_tolerance)) then
         if (.not. (compression_tolerance >= 0.0_dp .and. compression_tolerance < 1.0_dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'MUMPS: compression tolerance ' // &
               to_str(compression_tolerance) // ' must lie in [0, 1) (0 = no compression)')
            return
         end if
         self%compression_tolerance = compression_tolerance
      end if
      if (present(memory_limit_mb)) then
         if (memory_limit_mb < -1) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'MUMPS: memory limit ' // &
               to_str(memory_limit_mb) // ' MB; give -1 (automatic), 0 (none) or a size in MB')
            return
         end if
         self%memory_limit_mb = memory_limit_mb
      end if
      if (present(out_of_core)) self%out_of_core = out_of_core
      folder = ''
      if (present(ooc_directory)) folder = trim(ooc_directory)
      if (len(folder) == 0) then
         call get_environment_variable('TMPDIR', env, length, stat)
         if (stat == 0 .and. length > 0) then
            folder = env(:length)
         else
            folder = '.'
         end if
      end if
      if (len(folder) > len(self%id%ooc_tmpdir)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'MUMPS: out-of-core folder "' // folder // &
            '" is ' // to_str(len(folder)) // ' characters long; MUMPS takes at most ' // &
            to_str(len(self%id%ooc_tmpdir)))
         return
      end if
      self%ooc_directory = folder
      associate (id => self%id)
         if (self%out_of_core) then
            id%icntl(22) = 1
            id%ooc_tmpdir = folder
            id%ooc_prefix = 'ffrf_ooc_'
         else
            id%icntl(22) = 0
         end if
         if (self%compression_tolerance > 0.0_dp) then
            ! BLR factorisation, low-rank factors kept for the solves (user guide: ICNTL(35)),
            ! and a fixed number of iterative-refinement steps with the exact matrix in each
            ! solve (ICNTL(10) < 0): without them the approximate inverse leaves eigen residuals
            ! of 2e-6 (CNTL(7) = 1e-10) to 3.5e-4 (1e-8) on the crank at lc = 3 mm
            id%icntl(35) = 2
            id%cntl(7) = self%compression_tolerance
            id%icntl(10) = -BLR_REFINEMENT_STEPS
         else
            id%icntl(35) = 0
            id%cntl(7) = 0.0_dp
         end if
      end associate
   end procedure mumps_solver_set_memory_options

   module procedure mumps_solver_check_memory
      integer(i8) :: resident, available, limit
      character(len=:), allocatable :: limit_text

      if (self%memory_checked .or. self%memory_limit_mb == 0) return
      self%memory_checked = .true.
      resident = max(resident_memory_mb(), 0_i8)
      if (self%memory_limit_mb < 0) then
         available = available_memory_mb()
         if (available < 0) return
         ! the ranks of one node share its free memory
         available = available / max(self%parallel%ranks_on_node, 1)
         limit = resident + available
         limit_text = 'the automatic limit ' // to_str(limit) // ' MB (resident ' // &
            to_str(resident) // ' MB + MemAvailable of /proc/meminfo'
         if (self%parallel%ranks_on_node > 1) limit_text = limit_text // ' / ' // &
            to_str(self%parallel%ranks_on_node) // ' ranks on this node'
         limit_text = limit_text // ': ' // to_str(available) // ' MB)'
      else
         limit = self%memory_limit_mb
         limit_text = 'the memory limit ' // to_str(limit) // ' MB (&modes memory_limit_mb)'
      end if
      self%resident_memory_mb = resident
      self%checked_limit_mb = limit
      if (resident + self%predicted_memory_mb + self%workspace_mb > limit) then
         self%status = MUMPS_STATUS_MEMORY_LIMIT
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'MUMPS factorisation (n = ' // &
            to_str(self%n) // ') would not fit: predicted ' // &
            to_str(resident + self%predicted_memory_mb + self%workspace_mb) // &
            ' MB (MUMPS analysis: ' // to_str(self%predicted_memory_mb) // ' MB for the ' // &
            self%memory_options_text() // ' factorisation, ' // &
            to_str(real(self%estimated_factor_entries, dp) / 1.0e6_dp, 4) // &
            ' M factor entries; + ' // to_str(resident) // ' MB resident + ' // &
            to_str(self%workspace_mb) // ' MB of eigensolver vectors) exceeds ' // &
            limit_text // '; remedies: ' // self%memory_remedies() // &
            ' (memory_limit_mb = 0 turns the check off)')
      end if
   end procedure mumps_solver_check_memory

end submodule ffrf_la_mumps_memory
