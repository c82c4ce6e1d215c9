!> Reported multipliers of near-redundant constraint rows (ffrf_mbs_reaction_split, issue 30).
!> Closed form: three coordinates (x, y rigid; zeta modal) and three kept rows
!>     row 1 = [1, 0, 0],   row 2 = [1, 0, eps],   row 3 = [0, 1, 0],
!> plus a fourth row dropped at the start. Rows 1 and 2 are one constraint for the rigid
!> coordinates: the self-stress w = (1, -1, 0)/sqrt(2) loads only zeta, with participation
!> |Jn^T w| = eps/sqrt(2) (the rigid block's largest column norm |R_11| is 1). With
!> lambda = (3 + c, 3 - c, 7) the minimum-norm multipliers on w are (3, 3, 7) whatever c.
!> Asserted: for eps = 1e-3 (participation 7.1e-4 below the threshold 0.1) the reported
!> multipliers are (3, 3, 7) (atol 100 eps |c|, c = 1e6: the round-off of removing c), rows 1
!> and 2 are flagged and row 3 is not, the participation is eps/sqrt(2) (1e-10 relative), and the
!> rigid part of Phi_q^T lambda is unchanged (100 eps |c|: the rule moves only the modal force);
!> for eps = 0.5 (participation 0.35) nothing changes, bit for bit, and nothing is flagged; the
!> dropped row keeps its zero.
module test_mbs_reaction_split
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t
   use ffrf_mbs_reaction_split, only: min_norm_multipliers
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check
   implicit none
   private
   public :: collect_mbs_reaction_split

   !> Self-stress amplitude in the multipliers (N) and the threshold on the participation
   real(dp), parameter :: c = 1.0e6_dp, threshold = 0.1_dp

contains

   subroutine collect_mbs_reaction_split(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [new_unittest('near_redundant_pair_min_norm', test_near_redundant), &
         new_unittest('resolved_pair_unchanged', test_resolved)]
   end subroutine collect_mbs_reaction_split

   !> The three rows and the dropped fourth (nc = 4, n = 3) for a given eps.
   function jacobian(eps) result(Phi_q)
      real(dp), intent(in) :: eps
      real(dp) :: Phi_q(4, 3)
      Phi_q(1, :) = [1.0_dp, 0.0_dp, 0.0_dp]
      Phi_q(2, :) = [1.0_dp, 0.0_dp, eps]
      Phi_q(3, :) = [0.0_dp, 1.0_dp, 0.0_dp]
      Phi_q(4, :) = [0.0_dp, 2.0_dp, 0.0_dp]
   end function jacobian

   subroutine test_near_redundant(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: eps = 1.0e-3_dp
      real(dp), parameter :: expected(4) = [3.0_dp, 3.0_dp, 7.0_dp, 0.0_dp]
      real(dp) :: Phi_q(4, 3), lambda(4), reported(4), ratio, before(3), after(3)
      logical :: min_norm(4)
      integer :: i
      Phi_q = jacobian(eps)
      lambda = [3.0_dp + c, 3.0_dp - c, 7.0_dp, 0.0_dp]
      call min_norm_multipliers(Phi_q, [1, 2, 3], lambda, [.false., .false., .true.], &
         threshold, reported, min_norm, ratio, error)
      if (allocated(error)) return
      do i = 1, 4
         call check_close(error, 'reported multiplier', reported(i), expected(i), &
            atol=100.0_dp * epsilon(1.0_dp) * c)
         if (allocated(error)) return
      end do
      call check(error, 'rows 1 and 2 flagged, 3 and the dropped 4 not', &
         all(min_norm .eqv. [.true., .true., .false., .false.]))
      if (allocated(error)) return
      call check_close(error, 'participation', ratio, eps / sqrt(2.0_dp), rtol=1.0e-10_dp)
      if (allocated(error)) return
      before = matmul(transpose(Phi_q), lambda)
      after = matmul(transpose(Phi_q), reported)
      do i = 1, 2
         call check_close(error, 'rigid generalized force', after(i), before(i), &
            atol=100.0_dp * epsilon(1.0_dp) * c)
         if (allocated(error)) return
      end do
   end subroutine test_near_redundant

   subroutine test_resolved(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: lambda(4), reported(4), ratio
      logical :: min_norm(4)
      lambda = [3.0_dp + c, 3.0_dp - c, 7.0_dp, 0.0_dp]
      call min_norm_multipliers(jacobian(0.5_dp), [1, 2, 3], lambda, [.false., .false., &
         .true.], threshold, reported, min_norm, ratio, error)
      if (allocated(error)) return
      call check(error, 'multipliers unchanged', all(reported == lambda))
      if (.not. allocated(error)) call check(error, 'nothing flagged', .not. any(min_norm))
      if (.not. allocated(error)) call check_close(error, 'participation', ratio, &
         0.5_dp / sqrt(2.0_dp), rtol=1.0e-10_dp)
   end subroutine test_resolved

end module test_mbs_reaction_split

program main_mbs_reaction_split
   use ffrf_testing, only: unittest_t, run_suite
   use test_mbs_reaction_split, only: collect_mbs_reaction_split
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_mbs_reaction_split(tests)
   call run_suite('mbs_reaction_split', tests)
end program main_mbs_reaction_split
