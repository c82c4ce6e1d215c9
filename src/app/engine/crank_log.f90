!> The engine's words in the progress log of a mechanism run: the hook the mechanism output
!> calls for its progress line and its final summary. An engine (a mechanism whose rotor is its
!> crank, &mechanism crank) reports its crank speed, and its final crank angle and speed; any
!> other mechanism adds nothing.
module ffrf_app_engine_crank_log
   use ffrf_core_kinds, only: dp, pi
   use ffrf_core_strings, only: to_str
   use ffrf_mbs_mechanism, only: mechanism_t
   implicit none
   private
   public :: crank_progress, crank_summary

contains

   !> The progress line's engine part, ', crank <speed> rad/s'; '' without a crank.
   function crank_progress(mech, q, v) result(text)
      type(mechanism_t), intent(in) :: mech
      !> Coordinates and velocities of the state
      real(dp), intent(in) :: q(:), v(:)
      character(len=:), allocatable :: text
      text = ''
      if (mech%rotor > 0) text = ', crank ' // to_str(mech%rotor_speed(q, v), 6) // ' rad/s'
   end function crank_progress

   !> The final log line of an engine, 'final crank angle <deg> deg, speed <rad/s> rad/s'; ''
   !> without a crank.
   function crank_summary(mech, q, v) result(text)
      type(mechanism_t), intent(in) :: mech
      !> Coordinates and velocities of the last state
      real(dp), intent(in) :: q(:), v(:)
      character(len=:), allocatable :: text
      text = ''
      if (mech%rotor > 0) text = 'final crank angle ' // &
         to_str(mech%rotor_angle(q) * 180.0_dp / pi, 8) // ' deg, speed ' // &
         to_str(mech%rotor_speed(q, v), 8) // ' rad/s'
   end function crank_summary

end module ffrf_app_engine_crank_log
