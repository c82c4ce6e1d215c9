!> The driver's MPI start and end (MPI build; driver/ranks_serial.f90 is the sequential one):
!> MPI_Init_thread and MPI_COMM_WORLD as the run's ranks, the exit code agreed by every rank,
!> MPI_Finalize. The library itself never initialises or finalises MPI.
module ffrf_driver_ranks
   use mpi
   use ffrf, only: error_t, parallel_t, parallel_of_communicator
   implicit none
   private
   public :: start_ranks, end_ranks

contains

   !> MPI_Init_thread (funneled: only the main thread calls MPI) and the ranks of MPI_COMM_WORLD.
   subroutine start_ranks(parallel, error)
      type(parallel_t), intent(out) :: parallel
      type(error_t), allocatable, intent(out) :: error
      integer :: provided, ierr
      call MPI_Init_thread(MPI_THREAD_FUNNELED, provided, ierr)
      call parallel_of_communicator(MPI_COMM_WORLD, parallel, error)
   end subroutine start_ranks

   !> MPI_Finalize (before the process ends with its exit code).
   subroutine end_ranks()
      integer :: ierr
      logical :: done
      call MPI_Finalized(done, ierr)
      if (.not. done) call MPI_Finalize(ierr)
   end subroutine end_ranks

end module ffrf_driver_ranks
