!> Spring-mass chains with closed-form spectra as test fixtures (shared by
!> test_modes_shift_invert and test_stability_modes): n masses m on springs k between
!> neighbours and, if fixed, to the walls; and the empty constraint matrix.
module ffrf_test_spring_chain
   use ffrf_core_kinds, only: dp, ip
   use ffrf_core_error, only: error_t
   use ffrf_la_sparse, only: csr_t, csr_from_coo
   implicit none
   private
   public :: chain, no_constraints, spring, mass

   !> Chain spring stiffness k (N/m) and point mass m (kg)
   real(dp), parameter :: spring = 1.7e4_dp, mass = 0.3_dp

contains

   !> Stiffness and mass matrices of the chain of n masses (fixed: springs to both walls too).
   subroutine chain(n, fixed, K, M, error)
      integer(ip), intent(in) :: n
      logical, intent(in) :: fixed
      type(csr_t), intent(out) :: K, M
      type(error_t), allocatable, intent(out) :: error
      integer(ip), allocatable :: rows(:), cols(:)
      real(dp), allocatable :: vals(:)
      integer(ip) :: i
      allocate (rows(0), cols(0), vals(0))
      do i = 1, n
         rows = [rows, i]
         cols = [cols, i]
         if (fixed .or. (i > 1 .and. i < n)) then
            vals = [vals, 2.0_dp * spring]
         else
            vals = [vals, spring]
         end if
         if (i < n) then
            rows = [rows, i, i + 1]
            cols = [cols, i + 1, i]
            vals = [vals, -spring, -spring]
         end if
      end do
      call csr_from_coo(n, n, rows, cols, vals, K, error)
      if (allocated(error)) return
      call csr_from_coo(n, n, [(i, i=1, n)], [(i, i=1, n)], [(mass, i=1, n)], M, error)
   end subroutine chain

   !> A 0 x n constraint matrix.
   subroutine no_constraints(n, C)
      integer(ip), intent(in) :: n
      type(csr_t), intent(out) :: C
      C%num_rows = 0
      C%num_cols = n
      allocate (C%row_ptr(1), C%col(0), C%val(0))
      C%row_ptr(1) = 1
   end subroutine no_constraints

end module ffrf_test_spring_chain
