!> A load whose force or moment a host program sets between intervals of the integration
!> (co-simulation through the C or Fortran API, ffrf_app_mechanism_session).
!>
!> The host gives a global vector F (N) or M (N m) that stays constant over the next interval:
!> it is stored as its length `value` along the unit `direction` (load_t's form), so the
!> mechanism applies value * direction at the marker like any other load (theory.md 3.5). Its
!> magnitude does not depend on t, the rotor angle or the rotor speed, so the Newton tangent
!> sees the marker-force term only (mechanism header).
module ffrf_mbs_host_load
   use ffrf_core_kinds, only: dp
   use ffrf_mbs_mechanism_loads, only: constant_load_t
   implicit none
   private
   public :: host_load_t

   !> A force or moment set by the host: a constant load (value * direction) whose vector the
   !> host replaces between intervals.
   type, extends(constant_load_t) :: host_load_t
   contains
      !> Set the global vector (a zero vector keeps the direction with value 0)
      procedure :: set_vector => host_set_vector
   end type host_load_t

contains

   !> value = |vector|, direction = vector / |vector| (unchanged for a zero vector).
   pure subroutine host_set_vector(self, vector)
      class(host_load_t), intent(inout) :: self
      !> Global force (N) or moment (N m)
      real(dp), intent(in) :: vector(3)
      self%value = norm2(vector)
      if (self%value > 0.0_dp) self%direction = vector / self%value
   end subroutine host_set_vector

end module ffrf_mbs_host_load
