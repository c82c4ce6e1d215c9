!> The driver's start and end of its ranks, sequential build: one process, nothing to do
!> (driver/ranks_mpi.f90 is the MPI build's module of the same name).
module ffrf_driver_ranks
   use ffrf, only: error_t, parallel_t
   implicit none
   private
   public :: start_ranks, end_ranks

contains

   !> One process.
   subroutine start_ranks(parallel, error)
      type(parallel_t), intent(out) :: parallel
      type(error_t), allocatable, intent(out) :: error
      parallel = parallel_t()
   end subroutine start_ranks

   !> Nothing to end.
   subroutine end_ranks()
   end subroutine end_ranks

end module ffrf_driver_ranks
