!> The mechanism of an ffrf_case_t (a submodule of ffrf_capi_case): advance, time and crank,
!> body and marker state, joints and their reactions, sensors, the host's marker loads, the
!> starting pose of a body.
submodule (ffrf_capi_case) ffrf_capi_case_mechanism
   use ffrf_core_error, only: fatal_error, add_context, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: stage_times_t
   use ffrf_core_parallel, only: use_ranks
   use ffrf_app_mechanism_session, only: move_modes
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_input_case, only: case_input_t, read_case_with_overrides
   use ffrf_input_overrides, only: override_t
   implicit none

contains

   !> FFRF_BAD_CALL unless the case is a mechanism case with a prepared session.
   subroutine check_session(self, what, error)
      class(ffrf_case_t), intent(in) :: self
      character(len=*), intent(in) :: what
      type(error_t), allocatable, intent(out) :: error
      call check_mechanism(self, what, error)
      if (allocated(error)) return
      if (.not. self%session%prepared) then
         if (self%have_final) then
            call bad_call(error, what // ': not available after ffrf_case_run with an ' // &
               'output folder (the run is over); open the case without one to query the state')
         else
            call bad_call(error, what // ': the mechanism is not prepared yet; call ' // &
               'ffrf_mechanism_advance first (advance to t_start only prepares)')
         end if
      end if
   end subroutine check_session

   !> FFRF_BAD_CALL unless the case is open and a mechanism case.
   subroutine check_mechanism(self, what, error)
      class(ffrf_case_t), intent(in) :: self
      character(len=*), intent(in) :: what
      type(error_t), allocatable, intent(out) :: error
      call check_open(self, what, error)
      if (.not. allocated(error) .and. .not. self%case%is_mechanism) call bad_call(error, &
         what // ': "' // self%case%file_name // '" is a modal case (no &joint groups); ' // &
         'only a mechanism case moves')
   end subroutine check_mechanism

   module procedure case_advance
      type(stage_times_t) :: times
      integer :: k
      call check_mechanism(self, 'mechanism_advance', error)
      if (allocated(error)) return
      if (self%have_final) then
         call bad_call(error, 'mechanism_advance: the case has run to t_end with an output ' &
            // 'folder; open it again to advance it')
         return
      end if
      if (.not. self%session%prepared) then
         ! a time beyond t_end is refused before the modes are computed (session_advance
         ! checks it again with the h of the automatic model)
         associate (settings => self%case%mechanism%integrator)
            if (.not. (t <= settings%t_end + 1.0e-6_dp * settings%h)) then
               call fatal_error(error, FFRF_INPUT_ERROR, self%case%file_name // &
                  ': mechanism: advance to t = ' // to_str(t, 12) // ' s, beyond the ' // &
                  'case''s t_end = ' // to_str(settings%t_end, 12) // ' s; raise ' // &
                  '&integrator t_end')
               return
            end if
         end associate
         call use_ranks(self%options%parallel)
         if (self%write_output .and. self%options%parallel%is_root()) then
            ! recorded as the driver's run (ffrf_app_mechanism_session); the session keeps its
            ! modes for the results file and the animations (MPI: rank 0 records)
            call self%session%prepare(self%case, mesh_folder(self), self%log, times, error, &
               options=self%options)
         else
            call self%session%prepare(self%case, mesh_folder(self), self%log, times, error)
         end if
         if (allocated(error)) return
         allocate (self%modes(size(self%session%bodies)))
         do k = 1, size(self%session%bodies)
            if (self%write_output) then
               self%modes(k) = self%session%bodies(k)%modes
            else
               call move_modes(self%session%bodies(k)%modes, self%modes(k))
            end if
         end do
         self%have_modes = .true.
      end if
      call self%session%advance(t, error)
      if (allocated(error)) then
         ! (a recorded run's error names the case already)
         if (index(error%message, self%case%file_name // ':') /= 1) call add_context(error, &
            self%case%file_name)
      end if
   end procedure case_advance

   module procedure case_crank_state
      angle = 0.0_dp
      speed = 0.0_dp
      if (self%have_final) then
         angle = self%final_state(2)
         speed = self%final_state(3)
         return
      end if
      call check_session(self, 'crank_state', error)
      if (allocated(error)) return
      angle = self%session%crank_angle()
      speed = self%session%crank_speed()
   end procedure case_crank_state

   module procedure case_time
      t = 0.0_dp
      t_end = 0.0_dp
      if (self%have_final) then
         t = self%final_state(1)
         t_end = session_end_time(self)
         return
      end if
      call check_session(self, 'mechanism_time', error)
      if (allocated(error)) return
      t = self%session%time()
      t_end = self%session%end_time()
   end procedure case_time

   module procedure case_body_state
      allocate (q(0), v(0))
      call check_session(self, 'body_state', error)
      if (.not. allocated(error)) call check_body(self, 'body_state', body, error)
      if (.not. allocated(error)) call self%session%body_state(body, q, v, error)
   end procedure case_body_state

   module procedure case_marker_count
      n = 0
      call check_session(self, 'marker_count', error)
      if (.not. allocated(error)) call check_body(self, 'marker_count', body, error)
      if (.not. allocated(error)) n = self%session%num_markers(body)
   end procedure case_marker_count

   !> FFRF_BAD_CALL unless the marker exists on the body.
   subroutine check_marker(self, what, body, marker, error)
      class(ffrf_case_t), intent(in) :: self
      character(len=*), intent(in) :: what
      integer, intent(in) :: body, marker
      type(error_t), allocatable, intent(out) :: error
      integer :: n
      call check_session(self, what, error)
      if (.not. allocated(error)) call check_body(self, what, body, error)
      if (allocated(error)) return
      n = self%session%num_markers(body)
      if (marker < 1 .or. marker > n) call bad_call(error, what // ': marker ' // &
         to_str(marker - 1) // ' does not exist; body "' // trim(self%case%bodies(body)%name) &
         // '" has ' // to_str(n) // ' markers, 0..' // to_str(n - 1))
   end subroutine check_marker

   module procedure case_marker_state
      position = 0.0_dp
      velocity = 0.0_dp
      angular_velocity = 0.0_dp
      call check_marker(self, 'marker_state', body, marker, error)
      if (.not. allocated(error)) call self%session%marker_motion(body, marker, position, &
         velocity, angular_velocity, error)
   end procedure case_marker_state

   module procedure case_joint_count
      n = 0
      call check_session(self, 'joint_count', error)
      if (.not. allocated(error)) n = self%session%num_joints()
   end procedure case_joint_count

   module procedure case_joint_name
      name = ''
      call check_item(self, 'joint_name', 'joint', joint, error)
      if (.not. allocated(error)) name = self%session%mech%joints(joint)%name
   end procedure case_joint_name

   module procedure case_joint_reaction
      force = 0.0_dp
      moment = 0.0_dp
      call check_item(self, 'joint_reaction', 'joint', joint, error)
      if (.not. allocated(error)) call self%session%joint_reaction(joint, force, moment, error)
   end procedure case_joint_reaction

   module procedure case_driver_state
      integer :: d
      values = 0.0_dp
      call check_item(self, 'driver_state', 'joint', joint, error)
      if (allocated(error)) return
      d = 0
      associate (s => self%session)
         if (allocated(s%mech%drivers)) d = findloc(s%mech%drivers%joint, joint, dim=1)
         if (d == 0) then
            call bad_call(error, 'driver_state: joint ' // to_str(joint - 1) // ' ("' // &
               s%mech%joints(joint)%name // '") has no driver; add &driver joint = ''' // &
               s%mech%joints(joint)%name // ''' to the case')
            return
         end if
         values = s%mech%driver_state(d, s%integrator%q, s%integrator%v, s%integrator%lambda)
      end associate
   end procedure case_driver_state

   module procedure case_sensor_count
      n = 0
      call check_session(self, 'sensor_count', error)
      if (.not. allocated(error)) n = self%session%num_sensors()
   end procedure case_sensor_count

   !> FFRF_BAD_CALL unless the session runs and its `word` (joint or sensor) `index` exists.
   subroutine check_item(self, what, word, index, error)
      class(ffrf_case_t), intent(in) :: self
      character(len=*), intent(in) :: what, word
      integer, intent(in) :: index
      type(error_t), allocatable, intent(out) :: error
      call check_session(self, what, error)
      if (allocated(error)) return
      if (word == 'joint') then
         call check_index(what, word, index, self%session%num_joints(), error)
      else
         call check_index(what, word, index, self%session%num_sensors(), error)
      end if
   end subroutine check_item

   !> FFRF_BAD_CALL unless 1 <= index <= count: "<what>: <word> <index - 1> does not exist; the
   !> case has <count> <word>s" (0-based, as the C API counts).
   subroutine check_index(what, word, index, count, error)
      character(len=*), intent(in) :: what, word
      integer, intent(in) :: index, count
      type(error_t), allocatable, intent(out) :: error
      if (index < 1 .or. index > count) call bad_call(error, what // ': ' // word // ' ' // &
         to_str(index - 1) // ' does not exist; the case has ' // to_str(count) // ' ' // &
         word // 's')
   end subroutine check_index

   module procedure case_sensor_name
      name = ''
      call check_item(self, 'sensor_name', 'sensor', sensor, error)
      if (.not. allocated(error)) call self%session%sensor_name(sensor, name, error)
   end procedure case_sensor_name

   module procedure case_sensor_values
      allocate (values(0))
      call check_item(self, 'sensor_values', 'sensor', sensor, error)
      if (.not. allocated(error)) call self%session%sensor_values(sensor, values, error)
   end procedure case_sensor_values

   module procedure case_set_marker_load
      call check_marker(self, 'marker_set_load', body, marker, error)
      if (.not. allocated(error)) call self%session%set_marker_load(body, marker, force, &
         moment, error)
   end procedure case_set_marker_load

   module procedure case_set_pose
      type(override_t), allocatable :: overrides(:)
      type(case_input_t) :: case
      character(len=:), allocatable :: name
      integer :: n, m
      call check_mechanism(self, 'body_set_pose', error)
      if (allocated(error)) return
      if (self%session%prepared .or. self%ran .or. self%have_final) then
         call bad_call(error, 'body_set_pose: the motion has started (the pose is the ' // &
            'starting pose); set it before the first ffrf_mechanism_advance or ffrf_case_run')
         return
      end if
      call check_body(self, 'body_set_pose', body, error)
      if (allocated(error)) return
      name = trim(self%case%bodies(body)%name)
      if (.not. allocated(self%pose_overrides)) allocate (self%pose_overrides(0))
      ! grown by hand (gfortran 12 leaks array constructors of types with allocatable parts)
      n = size(self%pose_overrides)
      allocate (overrides(n + 5))
      overrides(:n) = self%pose_overrides
      if (present(position)) call add('position', position)
      if (present(orientation)) call add('orientation', reshape(transpose(orientation), [9]))
      if (present(velocity)) call add('velocity', velocity)
      if (present(angular_velocity)) call add('angular_velocity', angular_velocity)
      if (allocated(error)) return
      ! the exports set (set_export) are read again with the poses
      m = n
      if (allocated(self%export_override)) then
         m = n + 1
         overrides(m) = self%export_override
      end if
      call read_case_with_overrides(self%case%file_name, overrides(:m), case, error)
      if (allocated(error)) return
      self%case = case
      self%pose_overrides = overrides(:n)
   contains
      !> Override n + 1: body[name].key = values (17 significant digits: read back exactly);
      !> FFRF_INPUT_ERROR for a value that is not finite.
      subroutine add(key, values)
         character(len=*), intent(in) :: key
         real(dp), intent(in) :: values(:)
         character(len=32) :: word
         integer :: i
         if (allocated(error)) return
         do i = 1, size(values)
            if (.not. ieee_is_finite(values(i))) then
               call fatal_error(error, FFRF_INPUT_ERROR, 'body_set_pose: body ' // &
                  to_str(body - 1) // ' "' // name // '": ' // key // ' value ' // to_str(i) // &
                  ' is not finite (NaN or Inf); give finite values')
               return
            end if
         end do
         n = n + 1
         overrides(n)%group = 'body'
         overrides(n)%name = name
         overrides(n)%key = key
         overrides(n)%origin = 'body_set_pose body[' // name // '].' // key
         overrides(n)%value = ''
         do i = 1, size(values)
            write (word, '(es25.17e3)') values(i)
            overrides(n)%value = overrides(n)%value // trim(adjustl(word))
            if (i < size(values)) overrides(n)%value = overrides(n)%value // ', '
         end do
      end subroutine add
   end procedure case_set_pose

   module procedure case_set_export
      type(override_t), allocatable :: overrides(:)
      type(case_input_t) :: case
      integer :: n
      call check_open(self, 'case_set_export', error)
      if (allocated(error)) return
      if (self%from_arrays) then
         call bad_call(error, 'case_set_export: a case built from arrays writes no files; ' // &
            'export the results of a case file opened with an output folder')
         return
      end if
      if (self%session%prepared .or. self%ran .or. self%have_final) then
         call bad_call(error, 'case_set_export: the case has run or started its motion; set ' // &
            'the exports before ffrf_case_run or the first ffrf_mechanism_advance')
         return
      end if
      if (index(formats, '''') > 0 .or. index(formats, '"') > 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'case_set_export: formats "' // formats // &
            '" holds a quote; give the words alone, e.g. "xdmf"')
         return
      end if
      n = 0
      if (allocated(self%pose_overrides)) n = size(self%pose_overrides)
      ! grown by hand (gfortran 12 leaks array constructors of types with allocatable parts)
      allocate (overrides(n + 1))
      if (n > 0) overrides(:n) = self%pose_overrides
      overrides(n + 1)%group = 'run'
      overrides(n + 1)%name = ''
      overrides(n + 1)%key = 'export'
      overrides(n + 1)%value = '''' // formats // ''''
      overrides(n + 1)%origin = 'case_set_export run.export'
      call read_case_with_overrides(self%case%file_name, overrides, case, error)
      if (allocated(error)) return
      self%case = case
      self%export_override = overrides(n + 1)
   end procedure case_set_export

end submodule ffrf_capi_case_mechanism
