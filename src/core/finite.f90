!> NaN/Inf screening of whole arrays by one comparison per element, |x| <= huge (false for NaN and
!> for infinities), which the compiler vectorises: the n x n matrices of every Newton iteration
!> of a mechanism are screened this way.
module ffrf_core_finite
   use ffrf_core_kinds, only: dp
   implicit none
   private
   public :: all_finite

   !> .true. when every element is finite (no NaN, no infinity)
   interface all_finite
      module procedure all_finite_1, all_finite_2
   end interface all_finite

contains

   pure logical function all_finite_1(x)
      !> The array
      real(dp), intent(in) :: x(:)
      all_finite_1 = all(abs(x) <= huge(1.0_dp))
   end function all_finite_1

   pure logical function all_finite_2(x)
      !> The array
      real(dp), intent(in) :: x(:, :)
      integer :: j
      all_finite_2 = .true.
      do j = 1, size(x, 2)
         if (.not. all(abs(x(:, j)) <= huge(1.0_dp))) then
            all_finite_2 = .false.
            return
         end if
      end do
   end function all_finite_2

end module ffrf_core_finite
