!> Ranks of a run (MPI build, -DFFRF_MPI=ON; src/core/parallel_serial.f90 is the sequential
!> build's module of the same name). A `parallel_t` wraps the communicator the caller gives
!> (the driver: MPI_COMM_WORLD; a host code: any communicator, e.g. a split of it): rank, size,
!> and the few collective operations the library needs. The library never calls MPI_Init or
!> MPI_Finalize (the driver or the host does). Every rank runs the same code on the same data;
!> only the element assembly (ffrf_fe_assembly), MUMPS (ffrf_la_mumps) and the PARPACK Lanczos
!> loop (row-distributed vectors: row_block, allgather_rows) share work, and
!> rank 0 (the root) alone logs and writes files (docs/mpi.md "MPI build and runs").
module ffrf_core_parallel
   use, intrinsic :: iso_c_binding, only: c_int
   use mpi
   use ffrf_core_kinds, only: dp, i8
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   implicit none
   private
   public :: parallel_t, parallel_of_communicator, solver_communicator, check_solver_ready
   public :: FFRF_MPI_BUILD, NO_COMMUNICATOR, use_ranks, current_ranks

   !> .true. in the MPI build
   logical, parameter :: FFRF_MPI_BUILD = .true.
   !> A parallel_t without communicator: one process (MUMPS on MPI_COMM_SELF)
   integer, parameter :: NO_COMMUNICATOR = -987654
   !> Values per message of the collective operations on arrays (1 GiB of doubles)
   integer(i8), parameter :: CHUNK = 2_i8**27
   !> Microseconds a rank sleeps between tests while it waits for the others in `agree`
   integer(c_int), parameter :: WAIT_POLL_US = 200_c_int

   interface
      !> POSIX usleep: give the core away while waiting
      integer(c_int) function usleep(microseconds) bind(c, name='usleep')
         import :: c_int
         implicit none
         integer(c_int), value :: microseconds
      end function usleep
   end interface

   !> The ranks of a run: communicator (Fortran handle, MPI_Fint), this rank, their number.
   type :: parallel_t
      !> Fortran MPI communicator; NO_COMMUNICATOR: a single process
      integer :: comm = NO_COMMUNICATOR
      !> This process's rank, 0-based
      integer :: rank = 0
      !> Number of ranks
      integer :: num_ranks = 1
      !> Ranks of the communicator on this rank's node (sharing its memory)
      integer :: ranks_on_node = 1
   contains
      procedure :: is_root => parallel_is_root
      procedure :: sum_reals => parallel_sum_reals
      procedure :: broadcast_reals => parallel_broadcast_reals
      procedure :: max_int => parallel_max_int
      procedure :: gather_real => parallel_gather_real
      procedure :: agree => parallel_agree
      procedure :: row_block => parallel_row_block
      procedure :: allgather_rows => parallel_allgather_rows
   end type parallel_t

   !> The ranks of the run in progress in this process (use_ranks): what compute_body_modes and
   !> the solvers take when not given ranks explicitly. One run at a time per process in the MPI
   !> build (the sequential build keeps no state: its runs may go in threads).
   type(parallel_t), save :: ranks_in_use

contains

   !> Make `parallel` the ranks of the runs that follow in this process (run_modal,
   !> run_mechanism, the API's run and advance set the case's ranks).
   subroutine use_ranks(parallel)
      type(parallel_t), intent(in) :: parallel
      ranks_in_use = parallel
   end subroutine use_ranks

   !> The ranks set by use_ranks (one process when none).
   function current_ranks() result(parallel)
      type(parallel_t) :: parallel
      parallel = ranks_in_use
   end function current_ranks

   !> The ranks of communicator `comm` (a Fortran handle); MPI must be initialised.
   subroutine parallel_of_communicator(comm, parallel, error)
      integer, intent(in) :: comm
      type(parallel_t), intent(out) :: parallel
      type(error_t), allocatable, intent(out) :: error
      logical :: ready
      integer :: ierr, node_comm
      call MPI_Initialized(ready, ierr)
      if (.not. ready) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'communicator ' // to_str(comm) // &
            ' given before MPI_Init: initialise MPI in the host program first')
         return
      end if
      call MPI_Comm_rank(comm, parallel%rank, ierr)
      if (ierr == MPI_SUCCESS) call MPI_Comm_size(comm, parallel%num_ranks, ierr)
      if (ierr /= MPI_SUCCESS) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'communicator ' // to_str(comm) // &
            ' is not a valid MPI communicator (MPI error ' // to_str(ierr) // '); give a ' // &
            'Fortran handle, from C MPI_Comm_c2f (include/ffrf_mpi.h)')
         parallel = parallel_t()
         return
      end if
      parallel%comm = comm
      ! the ranks that share this node's memory (the automatic memory limit divides it)
      call MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, parallel%rank, MPI_INFO_NULL, &
         node_comm, ierr)
      if (ierr == MPI_SUCCESS) then
         call MPI_Comm_size(node_comm, parallel%ranks_on_node, ierr)
         call MPI_Comm_free(node_comm, ierr)
      end if
   end subroutine parallel_of_communicator

   !> The communicator MUMPS runs on: the run's, else MPI_COMM_SELF.
   pure integer function solver_communicator(parallel) result(comm)
      type(parallel_t), intent(in) :: parallel
      comm = parallel%comm
      if (comm == NO_COMMUNICATOR) comm = MPI_COMM_SELF
   end function solver_communicator

   !> MPI initialised (the MPI MUMPS needs it, also on one process)?
   subroutine check_solver_ready(error)
      type(error_t), allocatable, intent(out) :: error
      logical :: ready
      integer :: ierr
      call MPI_Initialized(ready, ierr)
      if (.not. ready) call fatal_error(error, FFRF_INPUT_ERROR, 'this is the MPI build of ' &
         // 'ffrf (-DFFRF_MPI=ON): its MUMPS needs MPI initialised; call MPI_Init in the ' // &
         'host program before using the library (or use the sequential build)')
   end subroutine check_solver_ready

   pure logical function parallel_is_root(self)
      class(parallel_t), intent(in) :: self
      parallel_is_root = self%rank == 0
   end function parallel_is_root

   !> x summed over the ranks, the same bits on every rank (reduced on the root in place,
   !> broadcast), in pieces of at most CHUNK values (no message above 1 GiB).
   subroutine parallel_sum_reals(self, x)
      class(parallel_t), intent(in) :: self
      real(dp), intent(inout) :: x(:)
      integer(i8) :: first, last
      integer :: ierr
      if (self%num_ranks == 1) return
      do first = 1, size(x, kind=i8), CHUNK
         last = min(first + CHUNK - 1, size(x, kind=i8))
         if (self%rank == 0) then
            call MPI_Reduce(MPI_IN_PLACE, x(first:last), int(last - first + 1), &
               MPI_DOUBLE_PRECISION, MPI_SUM, 0, self%comm, ierr)
         else
            call MPI_Reduce(x(first:last), x(first:last), int(last - first + 1), &
               MPI_DOUBLE_PRECISION, MPI_SUM, 0, self%comm, ierr)
         end if
      end do
      call self%broadcast_reals(x)
   end subroutine parallel_sum_reals

   !> x of the root on every rank (in pieces of at most CHUNK values).
   subroutine parallel_broadcast_reals(self, x)
      class(parallel_t), intent(in) :: self
      real(dp), intent(inout) :: x(:)
      integer(i8) :: first, last
      integer :: ierr
      if (self%num_ranks == 1) return
      do first = 1, size(x, kind=i8), CHUNK
         last = min(first + CHUNK - 1, size(x, kind=i8))
         call MPI_Bcast(x(first:last), int(last - first + 1), MPI_DOUBLE_PRECISION, 0, &
            self%comm, ierr)
      end do
   end subroutine parallel_broadcast_reals

   !> The largest `value` over the ranks.
   integer function parallel_max_int(self, value) result(largest)
      class(parallel_t), intent(in) :: self
      integer, intent(in) :: value
      integer :: ierr
      largest = value
      if (self%num_ranks == 1) return
      call MPI_Allreduce(value, largest, 1, MPI_INTEGER, MPI_MAX, self%comm, ierr)
   end function parallel_max_int

   !> `value` of every rank, in rank order, on every rank.
   function parallel_gather_real(self, value) result(values)
      class(parallel_t), intent(in) :: self
      real(dp), intent(in) :: value
      real(dp), allocatable :: values(:)
      integer :: ierr
      allocate (values(self%num_ranks))
      values(1) = value
      if (self%num_ranks == 1) return
      call MPI_Allgather(value, 1, MPI_DOUBLE_PRECISION, values, 1, MPI_DOUBLE_PRECISION, &
         self%comm, ierr)
   end function parallel_gather_real

   !> Rows first..last of n that this rank holds in a row-distributed vector (the distributed
   !> Lanczos basis): contiguous blocks in rank order, n * rank / num_ranks + 1 onwards.
   pure subroutine parallel_row_block(self, n, first, last)
      class(parallel_t), intent(in) :: self
      integer, intent(in) :: n
      integer, intent(out) :: first, last
      first = int(int(n, i8) * self%rank / self%num_ranks) + 1
      last = int(int(n, i8) * (self%rank + 1) / self%num_ranks)
   end subroutine parallel_row_block

   !> The whole vector `full` (size n) on every rank from each rank's block `local` of it
   !> (row_block of n).
   subroutine parallel_allgather_rows(self, local, full)
      class(parallel_t), intent(in) :: self
      real(dp), intent(in) :: local(:)
      real(dp), intent(out) :: full(:)
      integer, allocatable :: counts(:), offsets(:)
      integer :: r, ierr
      if (self%num_ranks == 1) then
         full = local
         return
      end if
      allocate (counts(self%num_ranks), offsets(self%num_ranks))
      do r = 0, self%num_ranks - 1
         offsets(r + 1) = int(size(full, kind=i8) * r / self%num_ranks)
         counts(r + 1) = int(size(full, kind=i8) * (r + 1) / self%num_ranks) - offsets(r + 1)
      end do
      call MPI_Allgatherv(local, size(local), MPI_DOUBLE_PRECISION, full, counts, offsets, &
         MPI_DOUBLE_PRECISION, self%comm, ierr)
   end subroutine parallel_allgather_rows

   !> Make every rank leave with the same error: when some rank failed, all get the error of
   !> the lowest failing rank (its code and message, "rank N: " prefixed when N > 0), so every
   !> rank takes the same branch afterwards (no rank waits in a collective call alone).
   subroutine parallel_agree(self, error)
      class(parallel_t), intent(in) :: self
      type(error_t), allocatable, intent(inout) :: error
      integer :: failing, code, length, ierr
      character(len=:), allocatable :: message
      if (self%num_ranks == 1) return
      call wait_for_all(self)
      failing = self%num_ranks
      if (allocated(error)) failing = self%rank
      call MPI_Allreduce(MPI_IN_PLACE, failing, 1, MPI_INTEGER, MPI_MIN, self%comm, ierr)
      if (failing == self%num_ranks) return
      code = 0
      length = 0
      if (self%rank == failing) then
         code = error%code
         length = len(error%message)
      end if
      call MPI_Bcast(code, 1, MPI_INTEGER, failing, self%comm, ierr)
      call MPI_Bcast(length, 1, MPI_INTEGER, failing, self%comm, ierr)
      allocate (character(len=length) :: message)
      if (self%rank == failing) message = error%message
      call MPI_Bcast(message, length, MPI_CHARACTER, failing, self%comm, ierr)
      if (failing > 0) message = 'rank ' // to_str(failing) // ': ' // message
      if (allocated(error)) deallocate (error)
      call fatal_error(error, code, message)
   end subroutine parallel_agree

   !> A barrier that sleeps while it waits (MPI_Ibarrier tested every WAIT_POLL_US): a rank
   !> waiting for rank 0's METIS ordering or its output gives its core away instead of spinning
   !> in the MPI library (which slows rank 0 down on a busy machine).
   subroutine wait_for_all(self)
      type(parallel_t), intent(in) :: self
      integer :: request, ierr
      logical :: done
      call MPI_Ibarrier(self%comm, request, ierr)
      do
         call MPI_Test(request, done, MPI_STATUS_IGNORE, ierr)
         if (done .or. ierr /= MPI_SUCCESS) exit
         ierr = int(usleep(WAIT_POLL_US))
      end do
   end subroutine wait_for_all

end module ffrf_core_parallel
