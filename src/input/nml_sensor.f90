!> Namelist group &sensor of a mechanism run (repeatable): a named measurement written every
!> recorded step under /sensors/<name> of the results file (docs/sensors.md).
!>   &sensor  name, type, body, marker, joint, node, spring                   (repeatable)
!>   type: position [m], velocity [m/s], acceleration [m/s^2], orientation [1, the marker frame's
!>         axes], angular_velocity [rad/s] (body and marker: a &marker point of a rigid body or
!>         the ground, or an &interface of a flexible body, its virtual node with its elastic
!>         motion); joint_coordinate [rad for a revolute, m for a prismatic], reaction [N, N m]
!>         (joint); energy [J, kinetic and strain] (body); node_displacement [m, elastic, body
!>         frame], node_position [m, global] (body with a mesh, node: a Gmsh node tag of its mesh,
!>         integer >= 1, checked against the mesh when the run builds the body); spring [m, m/s,
!>         N: length, rate, tension] (spring: a &spring name); torsion_spring [rad, rad/s, N m:
!>         angle, rate, torque] (spring: a &torsion_spring name)
!>   name: unique among the sensors, at most 64 characters (default: the type).
!> The body, marker, joint and spring names are checked against the case by ffrf_input_case.
module ffrf_input_nml_sensor
   use ffrf_core_kinds, only: i8
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_lower
   use ffrf_input_nml_common, only: read_status
   use ffrf_input_nml_source, only: key_spec_t, string_key, choice_key, integer_key, &
      nml_source_t
   use ffrf_input_mechanism, only: sensor_input_t
   use ffrf_core_choices, only: choice_words
   use ffrf_mbs_sensors, only: sensor_kind_of, sensor_choices, sensor_needs, NEEDS_MARKER, &
      NEEDS_JOINT, NEEDS_BODY, NEEDS_NODE, NEEDS_SPRING
   implicit none
   private
   public :: read_sensor_groups, sensor_keys

contains

   !> Keys of &sensor (module header).
   function sensor_keys() result(keys)
      type(key_spec_t), allocatable :: keys(:)
      keys = [string_key('name', 64), choice_key('type', 20, choice_words(sensor_choices)), &
         string_key('body', 64), string_key('marker', 64), string_key('joint', 64), &
         integer_key('node', 1_i8, int(huge(1), i8)), string_key('spring', 64)]
   end function sensor_keys

   !> Every &sensor group, in input order; the keys a type needs must be given.
   subroutine read_sensor_groups(unit, src, sensors, error)
      integer, intent(in) :: unit
      !> The checked case text (FILE:LINE of the keys)
      type(nml_source_t), intent(in) :: src
      type(sensor_input_t), allocatable, intent(out) :: sensors(:)
      type(error_t), allocatable, intent(out) :: error
      integer :: stat, k, kind
      character(len=512) :: msg
      character(len=:), allocatable :: where
      allocate (sensors(src%count('sensor')))
      rewind (unit)
      do k = 1, size(sensors)
         associate (s => sensors(k))
            call read_sensor(s%name, s%type, s%body, s%marker, s%joint, s%node, s%spring)
            call read_status(src, 'sensor', k, stat, msg, error)
            if (allocated(error)) return
            s%type = to_lower(s%type)
            if (len_trim(s%name) == 0) s%name = s%type
            where = src%where('sensor', k, '') // ' "' // trim(s%name) // '"'
            kind = sensor_kind_of(s%type)
            if (kind == 0) then
               ! a word given was checked by the key spec (sensor_keys); here only its absence
               call fatal_error(error, FFRF_INPUT_ERROR, src%where('sensor', k, '') // &
                  ': type is missing; give one of ' // choice_words(sensor_choices))
            else if (any(sensors(:k - 1)%name == s%name)) then
               call fatal_error(error, FFRF_INPUT_ERROR, src%where('sensor', k, 'name') // &
                  ': sensor "' // trim(s%name) // '" is given twice; sensor names must be ' // &
                  'unique')
            else if (scan(trim(s%name), '/.') > 0) then
               call fatal_error(error, FFRF_INPUT_ERROR, src%where('sensor', k, 'name') // &
                  ': name = ''' // trim(s%name) // ''' holds a "/" or "."; a sensor name is ' // &
                  'one word of the results file (/sensors/<name>)')
            else if (sensor_needs(kind, NEEDS_MARKER) .and. (len_trim(s%body) == 0 .or. &
               len_trim(s%marker) == 0)) then
               call fatal_error(error, FFRF_INPUT_ERROR, where // ': type ''' // &
                  trim(s%type) // ''' needs body and marker (a &marker point, or an ' // &
                  '&interface of a flexible body)')
            else if (sensor_needs(kind, NEEDS_JOINT) .and. len_trim(s%joint) == 0) then
               call fatal_error(error, FFRF_INPUT_ERROR, where // ': type ''' // &
                  trim(s%type) // ''' needs joint = ''<a &joint name>''')
            else if (sensor_needs(kind, NEEDS_BODY) .and. len_trim(s%body) == 0) then
               call fatal_error(error, FFRF_INPUT_ERROR, where // ': type ''' // &
                  trim(s%type) // ''' needs body = ''<a &body name>''')
            else if (sensor_needs(kind, NEEDS_SPRING) .and. len_trim(s%spring) == 0) then
               call fatal_error(error, FFRF_INPUT_ERROR, where // ': type ''' // &
                  trim(s%type) // ''' needs spring = ''<a &' // trim(s%type) // ' name>''')
            else if (sensor_needs(kind, NEEDS_NODE) .and. s%node < 1) then
               call fatal_error(error, FFRF_INPUT_ERROR, where // ': type ''' // &
                  trim(s%type) // ''' needs node = <a node tag of the body''s mesh>')
            end if
         end associate
         if (allocated(error)) return
      end do
   contains
      !> The namelist read of &sensor k into its fields (absent keys keep their defaults).
      subroutine read_sensor(name, type, body, marker, joint, node, spring)
         character(len=*), intent(inout) :: name, type, body, marker, joint, spring
         integer, intent(inout) :: node
         namelist /sensor/ name, type, body, marker, joint, node, spring
         read (unit, nml=sensor, iostat=stat, iomsg=msg)
      end subroutine read_sensor
   end subroutine read_sensor_groups

end module ffrf_input_nml_sensor
