!> The readers of the mechanism's loads, drivers and force elements (ffrf_input_nml_mechanism):
!> &load and &driver with their laws over time, &spring, &torsion_spring and &bushing.
submodule (ffrf_input_nml_mechanism) ffrf_input_nml_mechanism_forces
   implicit none

contains

   module procedure read_load_groups
      type(load_input_t) :: defaults
      character(len=64) :: name, body, marker
      character(len=16) :: type
      real(dp) :: direction(3), value, stall_torque, free_speed, switch_off, coefficient
      integer :: stat, k
      character(len=512) :: msg
      character(len=:), allocatable :: where
      type(time_law_input_t) :: given_law
      type(time_function_t) :: fun
      character(len=16) :: law
      real(dp) :: initial, final, speed, t_start, duration
      real(dp) :: table_time(max_table_points), table_value(max_table_points)
      character(len=8) :: interpolation, beyond
      namelist /load/ name, type, body, marker, direction, value, stall_torque, free_speed, &
         switch_off, coefficient, law, initial, final, speed, t_start, duration, table_time, &
         table_value, interpolation, beyond
      allocate (loads(0))
      rewind (unit)
      do
         call reset_law_keys(law, initial, final, speed, t_start, duration, table_time, &
            table_value, interpolation, beyond)
         name = defaults%name
         type = defaults%type
         body = defaults%body
         marker = defaults%marker
         direction = defaults%direction
         ! unset: 1 with a law (the law gives the magnitude), else the default
         value = huge(1.0_dp)
         stall_torque = defaults%stall_torque
         free_speed = defaults%free_speed
         switch_off = defaults%switch_off
         coefficient = defaults%coefficient
         read (unit, nml=load, iostat=stat, iomsg=msg)
         if (is_iostat_end(stat)) exit
         k = size(loads) + 1
         if (stat /= 0) then
            call namelist_read_error(error, 'load', k, msg, 'name, type, body, marker, ' // &
               'direction, value, stall_torque, free_speed, switch_off, coefficient, ' // &
               law_key_names)
            return
         end if
         given_law = law_as_given(law, initial, final, speed, t_start, duration, &
            table_time, table_value, interpolation, beyond)
         if (value == huge(1.0_dp)) value = merge(1.0_dp, defaults%value, len_trim(law) > 0)
         type = to_lower(type)
         if (len_trim(name) == 0) name = type
         where = src%where('load', k, '') // ' "' // trim(name) // '"'
         if (len_trim(type) == 0) then
            ! a word given was checked by the key spec (load_keys); here only its absence
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': type is missing; give one of ' &
               // choice_words(load_choices))
         else if (len_trim(body) == 0 .or. len_trim(marker) == 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': body and marker are required')
         else if (.not. (norm2(direction) > 0.0_dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('load', k, 'direction') // &
               ': the direction is zero; give a direction')
         else if (type == 'starter' .and. .not. (free_speed > 0.0_dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': free_speed = ' // &
               to_str(free_speed) // ' rad/s, must be > 0')
         else if (type == 'drag' .and. .not. (coefficient >= 0.0_dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': coefficient = ' // &
               to_str(coefficient) // ' N m s^2, must be >= 0')
         else if (len_trim(law) > 0 .and. type /= 'force' .and. type /= 'torque') then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('load', k, 'law') // ': ' // &
               '&load "' // trim(name) // '" of type ' // trim(type) // ' takes no law; a ' // &
               'law scales a force or torque load')
         else if (len_trim(law) > 0) then
            call law_function(given_law, src%where('load', k, 'law') // ': &load "' // &
               trim(name) // '"', fun, error)
         end if
         if (allocated(error)) return
         ! grown by hand: gfortran 12 leaks the allocatable components of a structure
         ! constructor inside an array constructor (the law's table; seen by ctest
         ! capi_bad_calls_asan)
         block
            type(load_input_t), allocatable :: grown(:)
            allocate (grown(size(loads) + 1))
            grown(:size(loads)) = loads
            grown(size(grown)) = load_input_t(name, type, body, marker, &
               direction / norm2(direction), value, stall_torque, free_speed, switch_off, &
               coefficient, given_law)
            call move_alloc(grown, loads)
         end block
      end do
   end procedure read_load_groups

   module procedure read_driver_groups
      type(driver_input_t) :: defaults
      character(len=64) :: name, joint
      character(len=16) :: quantity
      real(dp) :: offset
      integer :: stat, k
      character(len=512) :: msg
      type(time_law_input_t) :: given_law
      type(time_function_t) :: fun
      character(len=16) :: law
      real(dp) :: initial, final, speed, t_start, duration
      real(dp) :: table_time(max_table_points), table_value(max_table_points)
      character(len=8) :: interpolation, beyond
      namelist /driver/ name, joint, quantity, offset, law, initial, final, speed, t_start, &
         duration, table_time, table_value, interpolation, beyond
      allocate (drivers(0))
      rewind (unit)
      do
         name = defaults%name
         joint = defaults%joint
         quantity = defaults%quantity
         offset = defaults%offset
         call reset_law_keys(law, initial, final, speed, t_start, duration, table_time, &
            table_value, interpolation, beyond)
         law = 'constant_speed'
         read (unit, nml=driver, iostat=stat, iomsg=msg)
         if (is_iostat_end(stat)) exit
         k = size(drivers) + 1
         if (stat /= 0) then
            call namelist_read_error(error, 'driver', k, msg, 'name, joint, quantity, ' // &
               'offset, ' // law_key_names)
            return
         end if
         given_law = law_as_given(law, initial, final, speed, t_start, duration, &
            table_time, table_value, interpolation, beyond)
         quantity = to_lower(quantity)
         if (len_trim(name) == 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('driver', k, '') // &
               ': name is missing')
         else if (any(drivers%name == name)) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('driver', k, 'name') // &
               ': the name is used twice; driver names must be unique')
         else if (len_trim(joint) == 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('driver', k, '') // &
               ': &driver "' // trim(name) // '": joint is required (a revolute or ' // &
               'prismatic &joint)')
         else
            call law_function(given_law, src%where('driver', k, 'law') // ': &driver "' // &
               trim(name) // '"', fun, error)
         end if
         if (allocated(error)) return
         block   ! grown by hand, as the loads (read_load_groups)
            type(driver_input_t), allocatable :: grown(:)
            allocate (grown(size(drivers) + 1))
            grown(:size(drivers)) = drivers
            grown(size(grown)) = driver_input_t(name, joint, quantity, offset, given_law)
            call move_alloc(grown, drivers)
         end block
      end do
   end procedure read_driver_groups

   !> The law keys' defaults before a read (time_law_input_t; table entries unset: huge).
   pure subroutine reset_law_keys(law, initial, final, speed, t_start, duration, table_time, &
         table_value, interpolation, beyond)
      character(len=*), intent(out) :: law, interpolation, beyond
      real(dp), intent(out) :: initial, final, speed, t_start, duration
      real(dp), intent(out) :: table_time(:), table_value(:)
      type(time_law_input_t) :: defaults
      law = defaults%law
      initial = defaults%initial
      final = defaults%final
      speed = defaults%speed
      t_start = defaults%t_start
      duration = defaults%duration
      table_time = huge(1.0_dp)
      table_value = huge(1.0_dp)
      interpolation = defaults%interpolation
      beyond = defaults%beyond
   end subroutine reset_law_keys

   !> The law keys as read (the table entries given: those before the first unset one).
   pure function law_as_given(law, initial, final, speed, t_start, duration, table_time, &
         table_value, interpolation, beyond) result(given)
      character(len=*), intent(in) :: law, interpolation, beyond
      real(dp), intent(in) :: initial, final, speed, t_start, duration
      real(dp), intent(in) :: table_time(:), table_value(:)
      type(time_law_input_t) :: given
      given%law = to_lower(law)
      given%initial = initial
      given%final = final
      given%speed = speed
      given%t_start = t_start
      given%duration = duration
      given%table_time = table_time(:count_set(table_time))
      given%table_value = table_value(:count_set(table_value))
      given%interpolation = to_lower(interpolation)
      given%beyond = to_lower(beyond)
   end function law_as_given

   !> Number of leading entries not unset (huge).
   pure integer function count_set(values) result(n)
      real(dp), intent(in) :: values(:)
      do n = 0, size(values) - 1
         if (values(n + 1) == huge(1.0_dp)) return
      end do
      n = size(values)
   end function count_set

   module procedure read_spring_groups
      type(spring_input_t) :: defaults
      character(len=64) :: name, body1, marker1, body2, marker2
      real(dp) :: stiffness, damping, free_length
      integer :: stat, k
      character(len=512) :: msg
      namelist /spring/ name, body1, marker1, body2, marker2, stiffness, damping, free_length
      allocate (springs(0))
      rewind (unit)
      do
         name = defaults%name
         body1 = defaults%body1
         marker1 = defaults%marker1
         body2 = defaults%body2
         marker2 = defaults%marker2
         stiffness = defaults%stiffness
         damping = defaults%damping
         free_length = defaults%free_length
         read (unit, nml=spring, iostat=stat, iomsg=msg)
         if (is_iostat_end(stat)) exit
         k = size(springs) + 1
         if (stat /= 0) then
            call namelist_read_error(error, 'spring', k, msg, 'name, body1, marker1, body2, ' &
               // 'marker2, stiffness, damping, free_length')
            return
         end if
         call check_marker_pair_group(src, 'spring', k, name, springs%name, body1, marker1, &
            body2, marker2, error)
         if (allocated(error)) return
         springs = [springs, spring_input_t(name, body1, marker1, body2, marker2, stiffness, &
            damping, free_length)]
      end do
   end procedure read_spring_groups

   module procedure read_torsion_spring_groups
      type(torsion_spring_input_t) :: defaults
      character(len=64) :: name, joint
      real(dp) :: stiffness, damping, free_angle
      real(dp), parameter :: unset = huge(1.0_dp)
      integer :: stat, k
      character(len=512) :: msg
      namelist /torsion_spring/ name, joint, stiffness, damping, free_angle
      allocate (springs(0))
      rewind (unit)
      do
         name = defaults%name
         joint = defaults%joint
         stiffness = defaults%stiffness
         damping = defaults%damping
         free_angle = unset
         read (unit, nml=torsion_spring, iostat=stat, iomsg=msg)
         if (is_iostat_end(stat)) exit
         k = size(springs) + 1
         if (stat /= 0) then
            call namelist_read_error(error, 'torsion_spring', k, msg, 'name, joint, ' // &
               'stiffness, damping, free_angle')
            return
         end if
         if (len_trim(name) == 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('torsion_spring', k, '') // &
               ': name is missing')
         else if (any(springs%name == name)) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('torsion_spring', k, 'name') &
               // ': the name is used twice; torsion spring names must be unique')
         else if (len_trim(joint) == 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, src%where('torsion_spring', k, '') // &
               ' "' // trim(name) // '": joint is required (a revolute or cylindrical &joint)')
         end if
         if (allocated(error)) return
         springs = [springs, torsion_spring_input_t(name, joint, stiffness, damping, &
            merge(0.0_dp, free_angle, free_angle == unset), free_angle /= unset)]
      end do
   end procedure read_torsion_spring_groups

   !> The rules a group between two markers of two bodies shares (&spring, &bushing; group k,
   !> `names` those of the groups before it): a unique name, all four ends, two bodies.
   subroutine check_marker_pair_group(src, group, k, name, names, body1, marker1, body2, &
      marker2, error)
      type(nml_source_t), intent(in) :: src
      character(len=*), intent(in) :: group, name, body1, marker1, body2, marker2
      integer, intent(in) :: k
      character(len=*), intent(in) :: names(:)
      type(error_t), allocatable, intent(out) :: error
      if (len_trim(name) == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, src%where(group, k, '') // &
            ': name is missing')
      else if (any(names == name)) then
         call fatal_error(error, FFRF_INPUT_ERROR, src%where(group, k, 'name') // &
            ': the name is used twice; ' // group // ' names must be unique')
      else if (len_trim(body1) == 0 .or. len_trim(marker1) == 0 .or. &
         len_trim(body2) == 0 .or. len_trim(marker2) == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, src%where(group, k, '') // ' "' // &
            trim(name) // '": body1, marker1, body2 and marker2 are required')
      else if (body1 == body2) then
         call fatal_error(error, FFRF_INPUT_ERROR, src%where(group, k, 'body2') // ': &' // &
            group // ' "' // trim(name) // '": body1 and body2 are both "' // trim(body1) // &
            '"; a ' // group // ' connects two different bodies')
      end if
   end subroutine check_marker_pair_group

   module procedure read_bushing_groups
      type(bushing_input_t) :: defaults
      character(len=64) :: name, body1, marker1, body2, marker2
      real(dp) :: stiffness(6), damping(6)
      integer :: stat, k
      character(len=512) :: msg
      namelist /bushing/ name, body1, marker1, body2, marker2, stiffness, damping
      allocate (bushings(0))
      rewind (unit)
      do
         name = defaults%name
         body1 = defaults%body1
         marker1 = defaults%marker1
         body2 = defaults%body2
         marker2 = defaults%marker2
         stiffness = defaults%stiffness
         damping = defaults%damping
         read (unit, nml=bushing, iostat=stat, iomsg=msg)
         if (is_iostat_end(stat)) exit
         k = size(bushings) + 1
         if (stat /= 0) then
            call namelist_read_error(error, 'bushing', k, msg, 'name, body1, marker1, body2, ' &
               // 'marker2, stiffness, damping')
            return
         end if
         call check_marker_pair_group(src, 'bushing', k, name, bushings%name, body1, marker1, &
            body2, marker2, error)
         if (allocated(error)) return
         bushings = [bushings, bushing_input_t(name, body1, marker1, body2, marker2, &
            stiffness, damping)]
      end do
   end procedure read_bushing_groups

end submodule ffrf_input_nml_mechanism_forces
