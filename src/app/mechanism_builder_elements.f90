!> The joints, loads, drivers and force elements of a mechanism being built
!> (ffrf_app_mechanism_builder), and the engine's pressure model.
submodule (ffrf_app_mechanism_builder) ffrf_app_mechanism_builder_elements
   implicit none

contains

   module procedure add_joints
      integer :: j
      associate (joints => resolved%mechanism%joints)
         do j = 1, size(joints)
            call mech%add_joint(joints(j)%kind, trim(joints(j)%name), &
               mechanism_index(bodies, ground_index, joints(j)%body(1)), ends(1, j), &
               mechanism_index(bodies, ground_index, joints(j)%body(2)), ends(2, j), error)
            call group_context(error, 'joint', joints(j)%name)
            if (allocated(error)) return
         end do
      end associate
   end procedure add_joints

   module procedure group_context
      if (allocated(error)) call add_context(error, '&' // group // ' "' // trim(name) // '"')
   end procedure group_context

   module procedure mechanism_index
      mechanism_index = ground_index
      if (k > 0) mechanism_index = bodies(k)%index
   end procedure mechanism_index

   module procedure add_drivers
      type(joint_driver_t) :: driver
      integer :: d
      do d = 1, size(resolved%mechanism%drivers)
         associate (given => resolved%mechanism%drivers(d))
            driver%name = given%name
            driver%joint = given%joint
            driver%rate = given%rate
            driver%offset = given%offset
            driver%law = given%law
            call mech%add_driver(driver, error)
            call group_context(error, 'driver', given%name)
            if (allocated(error)) return
         end associate
      end do
   end procedure add_drivers

   module procedure add_force_elements
      type(spring_damper_t) :: spring
      type(bushing_t) :: bushing
      integer :: s
      associate (springs => resolved%mechanism%springs)
         do s = 1, size(springs)
            spring%name = springs(s)%name
            spring%body_a = mechanism_index(bodies, ground_index, springs(s)%body(1))
            spring%marker_a = spring_ends(1, s)
            spring%body_b = mechanism_index(bodies, ground_index, springs(s)%body(2))
            spring%marker_b = spring_ends(2, s)
            spring%stiffness = springs(s)%stiffness
            spring%damping = springs(s)%damping
            spring%free_length = springs(s)%free_length
            call mech%add_spring(spring, error)
            call group_context(error, 'spring', springs(s)%name)
            if (allocated(error)) return
         end do
      end associate
      do s = 1, size(resolved%mechanism%bushings)
         bushing = resolved%mechanism%bushings(s)
         bushing%body_a = mechanism_index(bodies, ground_index, bushing%body_a)
         bushing%body_b = mechanism_index(bodies, ground_index, bushing%body_b)
         bushing%marker_a = bushing_ends(1, s)
         bushing%marker_b = bushing_ends(2, s)
         call mech%add_bushing(bushing, error)
         call group_context(error, 'bushing', bushing%name)
         if (allocated(error)) return
      end do
      do s = 1, size(resolved%mechanism%torsion_springs)
         call mech%add_torsion_spring(resolved%mechanism%torsion_springs(s), error)
         call group_context(error, 'torsion_spring', resolved%mechanism%torsion_springs(s)%name)
         if (allocated(error)) return
      end do
   end procedure add_force_elements

   module procedure add_loads
      type(pressure_force_t) :: gas
      type(starter_torque_t) :: starter
      type(drag_torque_t) :: drag
      type(constant_load_t) :: constant
      type(timed_load_t) :: timed
      integer :: l
      do l = 1, size(resolved%mechanism%loads)
         associate (input => resolved%mechanism%loads(l))
            select case (input%kind)
            case (LOAD_PRESSURE)
               gas%model = pressure
               call fill(gas, input, LOAD_FORCE, ends(3, l))
               call mech%add_load(gas, error)
            case (LOAD_STARTER)
               starter%stall_torque = input%stall_torque
               starter%free_speed = input%free_speed
               starter%switch_off = input%switch_off
               call fill(starter, input, LOAD_TORQUE, ends(3, l))
               call mech%add_load(starter, error)
            case (LOAD_DRAG)
               drag%coefficient = input%coefficient
               call fill(drag, input, LOAD_TORQUE, ends(3, l))
               call mech%add_load(drag, error)
            case (LOAD_CONSTANT_FORCE, LOAD_CONSTANT_TORQUE)
               if (input%timed) then
                  timed%value = input%value
                  timed%law = input%law
                  call fill(timed, input, merge(LOAD_FORCE, LOAD_TORQUE, &
                     input%kind == LOAD_CONSTANT_FORCE), ends(3, l))
                  call mech%add_load(timed, error)
               else
                  constant%value = input%value
                  call fill(constant, input, merge(LOAD_FORCE, LOAD_TORQUE, &
                     input%kind == LOAD_CONSTANT_FORCE), ends(3, l))
                  call mech%add_load(constant, error)
               end if
            end select
            call group_context(error, 'load', input%name)
            if (allocated(error)) return
         end associate
      end do

   contains

      !> The load_t part of a load from its resolved &load group.
      subroutine fill(load, input, kind, marker)
         class(load_t), intent(inout) :: load
         type(model_load_t), intent(in) :: input
         integer, intent(in) :: kind, marker
         load%kind = kind
         load%body = bodies(input%body)%index
         load%marker = marker
         load%direction = input%direction
         load%name = input%name(:len(load%name))
      end subroutine fill

   end procedure add_loads

   module procedure make_pressure_model
      !> Largest pressure table read (bytes): 16 MiB, ~500 000 rows (0.1 deg needs 7200)
      integer(i8), parameter :: MAX_TABLE_BYTES = 16_i8 * 1024_i8**2
      real(dp), allocatable :: angles(:), values(:)
      real(dp) :: pair(2)
      character(len=512) :: line, msg
      character(len=:), allocatable :: file_name, where
      integer :: unit, stat, line_number, rows, pass, n
      if (len_trim(case%mechanism%pressure_table) == 0) then
         call pressure%init(case%mechanism%pressure, error)
         if (allocated(error)) call add_context(error, '&pressure')
         return
      end if
      file_name = trim(case%mechanism%pressure_table)
      where = '&pressure table_file "' // file_name // '"'
      call check_input_file(file_name, '&pressure table_file', MAX_TABLE_BYTES, error)
      if (allocated(error)) return
      ! one unit per file in the process (Fortran 2008, 9.5.4): threads reading it take turns
      call enter_serial_section(SECTION_FILES)
      open (newunit=unit, file=file_name, status='old', action='read', iostat=stat, iomsg=msg)
      if (stat /= 0) then
         call leave_serial_section(SECTION_FILES)
         call fatal_error(error, FFRF_IO_ERROR, where // ': ' // trim(msg))
         return
      end if
      ! pass 1 counts the rows and checks them, pass 2 stores them
      rows = 0
      do pass = 1, 2
         if (pass == 2) allocate (angles(rows), values(rows))
         rewind (unit)
         line_number = 0
         rows = 0
         do
            read (unit, '(a)', advance='no', iostat=stat, size=n) line
            if (is_iostat_end(stat)) exit
            line_number = line_number + 1
            if (stat == 0) then
               call fatal_error(error, FFRF_INPUT_ERROR, where // ', line ' // &
                  to_str(line_number) // ': longer than ' // to_str(len(line)) // &
                  ' characters; one angle and one pressure per line')
               exit
            else if (.not. is_iostat_eor(stat)) then
               call fatal_error(error, FFRF_IO_ERROR, where // ', line ' // &
                  to_str(line_number) // ': cannot read it')
               exit
            end if
            line = adjustl(line(:n))
            if (len_trim(line) == 0 .or. line(1:1) == '#') cycle
            read (line, *, iostat=stat) pair
            if (stat /= 0 .or. .not. all(abs(pair) <= huge(1.0_dp))) then
               call fatal_error(error, FFRF_INPUT_ERROR, where // ', line ' // &
                  to_str(line_number) // ': expected two numbers, angle (deg) ' // &
                  'and absolute pressure (Pa), both finite')
               exit
            end if
            rows = rows + 1
            if (pass == 2) then
               angles(rows) = pair(1)
               values(rows) = pair(2)
            end if
         end do
         if (allocated(error)) exit
      end do
      close (unit)
      call leave_serial_section(SECTION_FILES)
      if (allocated(error)) return
      call pressure%init_from_table(case%mechanism%pressure, angles, values, error)
      if (allocated(error)) call add_context(error, where)
   end procedure make_pressure_model

end submodule ffrf_app_mechanism_builder_elements
