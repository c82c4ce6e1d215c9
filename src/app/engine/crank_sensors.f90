!> The engine's sensors: an engine case (&mechanism crank = ...) measures its crank angle
!> (unwrapped, rad) and speed (rad/s) as the sensors "crank_angle" and "crank_speed"
!> (/sensors/crank_angle, /sensors/crank_speed; docs/sensors.md), besides its /time/crank_angle
!> and /time/crank_speed. The crank is the mechanism's rotor (ffrf_mbs_mechanism set_rotor), so
!> the sensors are its rotor angle and speed: the same numbers as the /time series.
module ffrf_app_engine_crank_sensors
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_mbs_sensors, only: sensor_t, SENSOR_ROTOR_ANGLE, SENSOR_ROTOR_SPEED
   implicit none
   private
   public :: add_crank_sensors

contains

   !> Append the crank sensors to `sensors` (their names must be free: a &sensor of the case
   !> named crank_angle or crank_speed is an error).
   subroutine add_crank_sensors(sensors, error)
      type(sensor_t), allocatable, intent(inout) :: sensors(:)
      type(error_t), allocatable, intent(out) :: error
      type(sensor_t) :: angle, speed
      angle%name = 'crank_angle'
      angle%kind = SENSOR_ROTOR_ANGLE
      speed%name = 'crank_speed'
      speed%kind = SENSOR_ROTOR_SPEED
      if (any(sensors%name == angle%name .or. sensors%name == speed%name)) then
         call fatal_error(error, FFRF_INPUT_ERROR, '&sensor: the names crank_angle and ' // &
            'crank_speed belong to the engine''s own sensors (a case with &mechanism crank); ' // &
            'name the sensor otherwise')
         return
      end if
      sensors = [sensors, angle, speed]
   end subroutine add_crank_sensors

end module ffrf_app_engine_crank_sensors
