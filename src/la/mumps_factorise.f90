!> ffrf_la_mumps: the symbolic analysis (serial or distributed input, METIS ordering) and the
!> numerical factorisation with its retries, the analysis's memory estimates, and the helpers
!> the module shares (one MUMPS call at a time, status texts, release of the user arrays).
submodule (ffrf_la_mumps) ffrf_la_mumps_factorise
   implicit none

contains

   module procedure mumps_solver_analyse
      integer(ip), allocatable :: order(:), iperm(:)
      integer(i8) :: k
      integer :: stat
      real(dp) :: t0

      if (self%phase < phase_initialised) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'MUMPS analyse: solver not initialised; ' &
            // 'call init(sym, error) first')
         return
      end if
      if (n < 1 .or. size(irn) /= size(jcn) .or. size(irn) < 1) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'MUMPS analyse: n = ' // to_str(n) // &
            ', size(irn) = ' // to_str(size(irn)) // ', size(jcn) = ' // to_str(size(jcn)) // &
            '; need n >= 1 and equal, non-empty index arrays')
         return
      end if
      do k = 1, size(irn, kind=i8)
         if (irn(k) < 1 .or. irn(k) > n .or. jcn(k) < 1 .or. jcn(k) > n) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'MUMPS analyse: entry ' // to_str(k) // &
               ' at (' // to_str(irn(k)) // ', ' // to_str(jcn(k)) // ') lies outside the ' // &
               to_str(n) // ' x ' // to_str(n) // ' matrix')
            return
         end if
      end do

      allocate (iperm(n))
      self%time_ordering = 0.0_dp
      if (present(perm)) then
         if (.not. is_permutation(perm, n)) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'MUMPS analyse: perm (size ' // &
               to_str(size(perm)) // ') is not a permutation of 1..' // to_str(n))
            return
         end if
         iperm = perm
         self%metis_ordering = .false.
      else if (self%parallel%is_root()) then
         ! (more than one rank: only the host's PERM_IN is read)
         t0 = wall_time()
         allocate (order(n))
         call pattern_nested_dissection(n, irn, jcn, order, iperm, error)
         if (allocated(error)) then
            call add_context(error, 'MUMPS analyse, METIS ordering')
            call self%parallel%agree(error)
            return
         end if
         self%time_ordering = wall_time() - t0
         self%metis_ordering = .true.
      else
         self%metis_ordering = .true.
      end if
      if (self%parallel%num_ranks > 1) then
         call self%parallel%agree(error)
         if (allocated(error)) return
         call analyse_distributed(self, n, irn, jcn, iperm, error)
         return
      end if

      associate (id => self%id)
         call release_user_arrays(id)
         allocate (id%irn(size(irn)), id%jcn(size(jcn)), id%perm_in(n), stat=stat)
         if (stat /= 0) then
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'MUMPS analyse: cannot allocate the ' &
               // 'index arrays of ' // to_str(size(irn, kind=i8)) // ' entries')
            return
         end if
         id%irn = irn
         id%jcn = jcn
         id%perm_in = iperm
      end associate
      call run_analysis(self, n, size(irn, kind=i8), '', error)
   end procedure mumps_solver_analyse

   module procedure mumps_solver_factorise
      integer :: stat, attempt
      real(dp) :: t0

      if (self%phase < phase_analysed) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'MUMPS factorise: no analysed pattern; ' // &
            'call analyse(n, irn, jcn, error=error) first')
         return
      end if
      if (size(values, kind=i8) /= self%nnz) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'MUMPS factorise: ' // &
            to_str(size(values, kind=i8)) // ' values given for a pattern of ' // &
            to_str(self%nnz) // ' entries')
         return
      end if
      call self%check_memory(error)
      ! One rank's refusal is every rank's: the factorisation below is collective.
      if (self%parallel%num_ranks > 1) call self%parallel%agree(error)
      if (allocated(error)) return
      self%phase = phase_analysed
      associate (id => self%id)
         if (self%parallel%num_ranks > 1) call set_local_values(self, values, error)
         if (allocated(error)) return
         if (.not. associated(id%a) .and. self%parallel%num_ranks == 1) then
            allocate (id%a(self%nnz), stat=stat)
            if (stat /= 0) then
               call fatal_error(error, FFRF_NUMERIC_ERROR, 'MUMPS factorise: cannot allocate ' &
                  // to_str(self%nnz) // ' matrix values')
               return
            end if
         end if
         if (self%parallel%num_ranks == 1) id%a = values
         id%job = 2
         self%num_workspace_retries = 0
         t0 = wall_time()
         call signal_test_point('factorisation:before')
         call signal_test_point('factorisation:during')
         do attempt = 0, max_workspace_retries
            call serial_dmumps(id)
            if (id%infog(1) /= -8 .and. id%infog(1) /= -9) exit
            if (attempt == max_workspace_retries) exit
            id%icntl(14) = 2 * max(id%icntl(14), 10)
            self%num_workspace_retries = self%num_workspace_retries + 1
         end do
         call signal_test_point('factorisation:after')
         self%time_factorisation = wall_time() - t0
         self%workspace_percent = id%icntl(14)
         self%status = id%infog(1)
         if (id%infog(1) < 0) then
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'MUMPS factorisation (n = ' // &
               to_str(self%n) // ', ' // to_str(self%nnz) // ' entries, SYM = ' // &
               to_str(self%sym) // ', ICNTL(14) = ' // to_str(id%icntl(14)) // '): ' // &
               describe_status(id%infog(1), id%infog(2)))
            return
         end if
         self%num_negative_pivots = id%infog(12)
         self%num_delayed_pivots = id%infog(13)
         self%max_front_size = id%infog(11)
         if (id%icntl(24) == 1) then
            self%num_null_pivots = id%infog(28)
         else
            self%num_null_pivots = 0
         end if
         self%factor_entries = mumps_count(id%infog(29))
         self%factor_storage = mumps_count(id%infog(9))
         self%memory_allocated_mb = id%infog(18)
         self%memory_used_mb = id%infog(21)
         self%factor_flops = id%rinfog(3)
         self%compressed_factor_entries = mumps_count(id%infog(35))
         self%factor_flops_done = id%rinfog(14)
      end associate
      self%time_solve = 0.0_dp
      self%num_solves = 0
      self%phase = phase_factorised
   end procedure mumps_solver_factorise

   !> .true. if p holds each of 1..n exactly once.
   pure function is_permutation(p, n) result(valid)
      integer(ip), intent(in) :: p(:)
      integer(ip), intent(in) :: n
      logical :: valid
      logical, allocatable :: seen(:)
      integer(ip) :: i
      valid = size(p) == n
      if (.not. valid) return
      allocate (seen(n), source=.false.)
      do i = 1, n
         if (p(i) < 1 .or. p(i) > n) then
            valid = .false.
            return
         end if
         if (seen(p(i))) then
            valid = .false.
            return
         end if
         seen(p(i)) = .true.
      end do
   end function is_permutation

   !> Analysis (JOB = 1) with distributed assembled input (ICNTL(18) = 3) on more than one
   !> rank: this rank's contiguous slice of the entries; n and PERM_IN (ICNTL(7) = 1) on the
   !> host. Entries of one (i, j) on several ranks are summed by MUMPS, as within one rank.
   subroutine analyse_distributed(self, n, irn, jcn, iperm, error)
      type(mumps_solver_t), intent(inout) :: self
      integer(ip), intent(in) :: n, irn(:), jcn(:), iperm(:)
      type(error_t), allocatable, intent(out) :: error
      integer(i8) :: nnz
      integer :: stat
      nnz = size(irn, kind=i8)
      self%first_entry = nnz * self%parallel%rank / self%parallel%num_ranks + 1
      self%last_entry = nnz * (self%parallel%rank + 1) / self%parallel%num_ranks
      associate (id => self%id, first => self%first_entry, last => self%last_entry)
         call release_user_arrays(id)
         allocate (id%irn_loc(last - first + 1), id%jcn_loc(last - first + 1), stat=stat)
         if (stat == 0 .and. self%parallel%is_root()) allocate (id%perm_in(n), stat=stat)
         if (stat /= 0) call fatal_error(error, FFRF_NUMERIC_ERROR, 'MUMPS analyse: cannot ' &
            // 'allocate the index arrays of ' // to_str(last - first + 1) // ' entries')
         call self%parallel%agree(error)
         if (allocated(error)) return
         id%irn_loc = irn(first:last)
         id%jcn_loc = jcn(first:last)
         id%nnz_loc = last - first + 1
         if (self%parallel%is_root()) id%perm_in = iperm
         id%icntl(18) = 3
      end associate
      call run_analysis(self, n, nnz, ' on ' // to_str(self%parallel%num_ranks) // ' ranks', &
         error)
   end subroutine analyse_distributed

   !> JOB = 1 on the index arrays set in self%id, PERM_IN given (ICNTL(7) = 1): its time and
   !> status, the ordering used and the estimates (per-rank INFO(15)/(17) and the global
   !> INFOG/RINFOG ones, on every rank); the phase goes to analysed, or back to initialised.
   subroutine run_analysis(self, n, nnz, on_ranks, error)
      type(mumps_solver_t), intent(inout) :: self
      !> Matrix order and entries (all ranks)
      integer(ip), intent(in) :: n
      integer(i8), intent(in) :: nnz
      !> ' on N ranks' for the message, or ''
      character(len=*), intent(in) :: on_ranks
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: t0
      associate (id => self%id)
         id%n = n
         id%nnz = nnz
         id%icntl(7) = 1
         id%job = 1
         t0 = wall_time()
         call serial_dmumps(id)
         self%time_analysis = wall_time() - t0
         self%status = id%infog(1)
         if (id%infog(1) < 0) then
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'MUMPS analysis (n = ' // to_str(n) // &
               ', ' // to_str(nnz) // ' entries' // on_ranks // '): ' // &
               describe_status(id%infog(1), id%infog(2)))
            self%phase = phase_initialised
            return
         end if
         self%ordering_used = id%infog(7)
         self%estimated_factor_entries = mumps_count(id%infog(20))
         call record_estimates(self)
      end associate
      self%n = n
      self%nnz = nnz
      self%phase = phase_analysed
   end subroutine run_analysis

   !> Distributed input: this rank's slice of `values` as A_loc (ICNTL(18) = 3).
   subroutine set_local_values(self, values, error)
      type(mumps_solver_t), intent(inout) :: self
      real(dp), intent(in) :: values(:)
      type(error_t), allocatable, intent(out) :: error
      integer :: stat
      associate (id => self%id, first => self%first_entry, last => self%last_entry)
         stat = 0
         if (.not. associated(id%a_loc)) allocate (id%a_loc(last - first + 1), stat=stat)
         if (stat /= 0) call fatal_error(error, FFRF_NUMERIC_ERROR, 'MUMPS factorise: ' // &
            'cannot allocate ' // to_str(last - first + 1) // ' matrix values')
         call self%parallel%agree(error)
         if (allocated(error)) return
         id%a_loc = values(first:last)
      end associate
   end subroutine set_local_values

   !> The analysis's estimates (INFO(15), (17), INFOG(16), (17), (26), (27), (36)-(39),
   !> RINFOG(1), (15)) and the one for the chosen options, predicted_memory_mb.
   subroutine record_estimates(self)
      class(mumps_solver_t), intent(inout) :: self
      associate (id => self%id)
         self%estimated_memory_incore_mb = id%info(15)
         self%estimated_memory_incore_max_mb = id%infog(16)
         self%estimated_memory_incore_total_mb = id%infog(17)
         self%estimated_memory_ooc_mb = id%info(17)
         self%estimated_memory_ooc_max_mb = id%infog(26)
         self%estimated_memory_ooc_total_mb = id%infog(27)
         self%estimated_memory_blr_incore_mb = id%infog(36)
         self%estimated_memory_blr_incore_total_mb = id%infog(37)
         self%estimated_memory_blr_ooc_mb = id%infog(38)
         self%estimated_memory_blr_ooc_total_mb = id%infog(39)
         self%estimated_flops = id%rinfog(1)
         self%estimated_disk_mb = id%rinfog(15)
      end associate
      if (self%compression_tolerance > 0.0_dp) then
         self%predicted_memory_mb = merge(self%estimated_memory_blr_ooc_mb, &
            self%estimated_memory_blr_incore_mb, self%out_of_core)
      else
         self%predicted_memory_mb = merge(self%estimated_memory_ooc_mb, &
            self%estimated_memory_incore_mb, self%out_of_core)
      end if
      self%memory_checked = .false.
      self%checked_limit_mb = 0
   end subroutine record_estimates

   module procedure describe_status
      text = 'INFOG(1) = ' // to_str(info1) // ', INFOG(2) = ' // to_str(info2) // ': '
      select case (info1)
      case (-2)
         text = text // 'NNZ out of range; the matrix must have at least one entry'
      case (-5, -7, -13)
         text = text // 'memory allocation failed (' // memory_text(info2) // &
            '); free memory, or remedies: ' // MEMORY_REMEDIES
      case (-6)
         text = text // 'matrix is structurally singular (structural rank ' // &
            to_str(info2) // '); a row and column without entries, e.g. an unconstrained ' // &
            'dof with no stiffness, or dependent constraint rows'
      case (-8, -9)
         text = text // 'MUMPS workspace too small even after raising ICNTL(14) ' // &
            to_str(max_workspace_retries) // ' times; pass a larger workspace_percent to init' &
            // ', or remedies: ' // MEMORY_REMEDIES
      case (-10)
         text = text // 'matrix is singular (zero pivot): a dof without stiffness, a ' // &
            'rigid-body motion left free, dependent constraint rows, or an eigen shift equal ' &
            // 'to an eigenvalue'
      case (-11, -14, -15)
         text = text // 'workspace too small for the solution; pass a larger ' // &
            'workspace_percent to init'
      case (-16)
         text = text // 'N out of range; the matrix order must be at least 1'
      case (-22)
         text = text // 'an input array (IRN, JCN, A, RHS or PERM_IN) is not allocated or ' // &
            'too small (internal error of the wrapper)'
      case (-23)
         text = text // 'MPI not initialised (linked against the MPI MUMPS instead of ' // &
            'the sequential one?)'
      case (-40)
         text = text // 'SYM = 1 but the matrix is not positive definite; use SYM = 2'
      case default
         text = text // 'see the MUMPS 5.5 user guide, section 8 (error diagnostics)'
      end select
   end procedure describe_status

   module procedure mumps_count
      if (value < 0) then
         count = -int(value, i8) * 1000000_i8
      else
         count = int(value, i8)
      end if
   end procedure mumps_count

   module procedure release_user_arrays
      if (associated(id%irn)) deallocate (id%irn)
      if (associated(id%jcn)) deallocate (id%jcn)
      if (associated(id%a)) deallocate (id%a)
      if (associated(id%perm_in)) deallocate (id%perm_in)
      if (associated(id%rhs)) deallocate (id%rhs)
      if (associated(id%irn_loc)) deallocate (id%irn_loc)
      if (associated(id%jcn_loc)) deallocate (id%jcn_loc)
      if (associated(id%a_loc)) deallocate (id%a_loc)
   end procedure release_user_arrays

   module procedure serial_dmumps
      call enter_serial_section(SECTION_MUMPS)
      ! MUMPS 5.5 installs no signal handlers (it imports neither signal nor sigaction); the
      ! run signals' handlers are restored after it all the same (issue 23)
      call hold_signals(block=.false.)
      call dmumps(id)
      call release_signals()
      call leave_serial_section(SECTION_MUMPS)
   end procedure serial_dmumps

   !> INFO(2) of an allocation error: bytes, or millions of bytes when negative.
   function memory_text(info2) result(text)
      integer, intent(in) :: info2
      character(len=:), allocatable :: text
      if (info2 < 0) then
         text = to_str(-info2) // ' million bytes requested'
      else
         text = to_str(info2) // ' bytes requested'
      end if
   end function memory_text

end submodule ffrf_la_mumps_factorise
