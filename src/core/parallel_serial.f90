!> Ranks of a run, sequential build (the default; src/core/parallel_mpi.f90 is the MPI build's
!> module of the same name): always one process, every collective operation the identity.
!> MUMPS is Debian's sequential one (libseq stub): its communicator is the stub's MPI_COMM_WORLD
!> value 9, which the stub ignores. A communicator given to the library is refused with the
!> remedy (rebuild with -DFFRF_MPI=ON).
module ffrf_core_parallel
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   implicit none
   private
   public :: parallel_t, parallel_of_communicator, solver_communicator, check_solver_ready
   public :: FFRF_MPI_BUILD, NO_COMMUNICATOR, use_ranks, current_ranks

   !> .false.: the sequential build
   logical, parameter :: FFRF_MPI_BUILD = .false.
   !> A parallel_t without communicator: one process
   integer, parameter :: NO_COMMUNICATOR = -987654
   !> MPI_COMM_WORLD of the libseq stub mpif.h (/usr/include/mumps_seq); the stub ignores it
   integer, parameter :: SEQUENTIAL_COMM = 9

   !> One process (the interface of the MPI build's parallel_t).
   type :: parallel_t
      integer :: comm = NO_COMMUNICATOR
      integer :: rank = 0
      integer :: num_ranks = 1
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

contains

   !> Nothing to remember: always one process (no state, so runs may go in threads).
   subroutine use_ranks(parallel)
      type(parallel_t), intent(in) :: parallel
      if (parallel%num_ranks < 0) return   ! (never: keeps the argument used)
   end subroutine use_ranks

   !> One process.
   function current_ranks() result(parallel)
      type(parallel_t) :: parallel
      parallel = parallel_t()
   end function current_ranks

   !> Refused: the sequential build has no MPI.
   subroutine parallel_of_communicator(comm, parallel, error)
      integer, intent(in) :: comm
      type(parallel_t), intent(out) :: parallel
      type(error_t), allocatable, intent(out) :: error
      character(len=12) :: text
      write (text, '(i0)') comm
      call fatal_error(error, FFRF_INPUT_ERROR, 'communicator ' // trim(text) // ' given to ' &
         // 'the sequential build of ffrf (MUMPS libseq, no MPI); an MPI host code needs the ' &
         // 'MPI build: configure with -DFFRF_MPI=ON (cmake --preset mpi)')
      parallel = parallel_t()
   end subroutine parallel_of_communicator

   pure integer function solver_communicator(parallel) result(comm)
      type(parallel_t), intent(in) :: parallel
      comm = SEQUENTIAL_COMM
      if (parallel%num_ranks < 0) comm = parallel%comm   ! (never: keeps the argument used)
   end function solver_communicator

   subroutine check_solver_ready(error)
      type(error_t), allocatable, intent(out) :: error
   end subroutine check_solver_ready

   pure logical function parallel_is_root(self)
      class(parallel_t), intent(in) :: self
      parallel_is_root = self%rank == 0
   end function parallel_is_root

   subroutine parallel_sum_reals(self, x)
      class(parallel_t), intent(in) :: self
      real(dp), intent(inout) :: x(:)
   end subroutine parallel_sum_reals

   subroutine parallel_broadcast_reals(self, x)
      class(parallel_t), intent(in) :: self
      real(dp), intent(inout) :: x(:)
   end subroutine parallel_broadcast_reals

   integer function parallel_max_int(self, value) result(largest)
      class(parallel_t), intent(in) :: self
      integer, intent(in) :: value
      largest = value
   end function parallel_max_int

   function parallel_gather_real(self, value) result(values)
      class(parallel_t), intent(in) :: self
      real(dp), intent(in) :: value
      real(dp), allocatable :: values(:)
      values = [value]
   end function parallel_gather_real

   !> All n rows: one process holds the whole vector.
   pure subroutine parallel_row_block(self, n, first, last)
      class(parallel_t), intent(in) :: self
      integer, intent(in) :: n
      integer, intent(out) :: first, last
      first = 1
      last = n
   end subroutine parallel_row_block

   subroutine parallel_allgather_rows(self, local, full)
      class(parallel_t), intent(in) :: self
      real(dp), intent(in) :: local(:)
      real(dp), intent(out) :: full(:)
      full = local
   end subroutine parallel_allgather_rows

   subroutine parallel_agree(self, error)
      class(parallel_t), intent(in) :: self
      type(error_t), allocatable, intent(inout) :: error
   end subroutine parallel_agree

end module ffrf_core_parallel
