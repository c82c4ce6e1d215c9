!> ffrf_la_mumps: the symbolic analysis (serial or distributed input, METIS ordering) and the
!> numerical factorisation with its retries, and the analysis's memory estimates.
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

end submodule ffrf_la_mumps_factorise
