!> The rigid pre-run of the automatic model for a scene without a crank (ffrf_app_scene_model,
!> 1): the same mechanism with every flexible body the selection chooses moved rigidly
!> (num_modes = 0: its mesh's exact inertia), the same loads, drivers and springs, over the
!> case's t_end in SCENE_SAMPLES steps, recording per such body the joint forces and moments at
!> its interfaces and its rigid motion (body axes), and the pre-run value of each reaction
!> target. Nothing is written and nothing is logged but one summary line.
module ffrf_app_scene_prerun
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, add_context, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: logger_t, stage_times_t, stage_timer_t, LOG_QUIET
   use ffrf_input_case, only: case_input_t
   use ffrf_input_mechanism, only: parse_targets
   use ffrf_model_model, only: model_t, build_model
   use ffrf_model_mechanism, only: SELECTION_AUTO
   use ffrf_mbs_sensors, only: sensor_t, sensor_word, SENSOR_REACTION, &
      SENSOR_NODE_DISPLACEMENT, SENSOR_POSITION, SENSOR_VELOCITY, SENSOR_ANGULAR_VELOCITY, &
      SENSOR_JOINT_COORDINATE
   use ffrf_mbs_joints, only: JOINT_REVOLUTE
   use ffrf_mbs_mechanism, only: mechanism_t
   use ffrf_mbs_rotation, only: euler_rotation, euler_g_bar
   use ffrf_mbs_generalized_alpha, only: galpha_integrator_t, galpha_settings_t
   use ffrf_app_mechanism_builder, only: built_body_t, build_mechanism
   use ffrf_app_engine_pressure, only: pressure_model_t
   use ffrf_app_scene_model, only: scene_record_t, TARGET_REACTION, TARGET_NODE, &
      TARGET_INTERFACE
   implicit none
   private
   public :: needs_scene_prerun, scene_prerun, check_scene_targets, SCENE_SAMPLES

   !> Steps of the pre-run over t_end - t_start
   integer, parameter :: SCENE_SAMPLES = 2000

contains

   !> .true. when the case is a scene without a crank whose automatic model has targets and a
   !> body to choose for (flexible, meshed, no num_modes, no modes_file).
   pure logical function needs_scene_prerun(case, resolved)
      type(case_input_t), intent(in) :: case
      type(model_t), intent(in) :: resolved
      needs_scene_prerun = resolved%mechanism%selection == SELECTION_AUTO .and. &
         resolved%mechanism%crank == 0 .and. len_trim(case%mechanism%model%targets) > 0 .and. &
         any(chosen(resolved))
   end function needs_scene_prerun

   pure function chosen(resolved) result(selects)
      type(model_t), intent(in) :: resolved
      logical :: selects(size(resolved%bodies))
      integer :: k
      do k = 1, size(selects)
         selects(k) = .not. resolved%bodies(k)%rigid .and. .not. &
            resolved%bodies(k)%num_modes_given .and. resolved%bodies(k)%meshed .and. &
            len_trim(resolved%bodies(k)%body%modes_file) == 0
      end do
   end function chosen

   !> What `ffrf --check` checks of the targets of a scene whose automatic model runs: the
   !> sensors named and the estimate's reach (resolve_targets); the pre-run is not run.
   subroutine check_scene_targets(case, resolved, error)
      type(case_input_t), intent(in) :: case
      type(model_t), intent(in) :: resolved
      type(error_t), allocatable, intent(out) :: error
      type(scene_record_t) :: record
      if (needs_scene_prerun(case, resolved)) call resolve_targets(case, resolved, record, error)
   end subroutine check_scene_targets

   !> The targets resolved, the rigid pre-run, its record (module header).
   subroutine scene_prerun(case, resolved, mesh_dir, log, times, record, error)
      type(case_input_t), intent(in) :: case
      type(model_t), intent(in) :: resolved
      character(len=*), intent(in) :: mesh_dir
      type(logger_t), intent(in) :: log
      type(stage_times_t), intent(inout) :: times
      type(scene_record_t), intent(out) :: record
      type(error_t), allocatable, intent(out) :: error
      type(case_input_t) :: rigid_case
      type(model_t) :: rigid_model
      type(mechanism_t) :: mech
      type(built_body_t), allocatable :: bodies(:)
      type(pressure_model_t) :: pressure
      type(galpha_integrator_t) :: integrator
      type(galpha_settings_t) :: settings
      type(sensor_t), allocatable :: sensors(:)
      type(logger_t) :: quiet
      type(stage_timer_t) :: timer
      real(dp), allocatable :: q(:), v(:)
      logical, allocatable :: selects(:)
      logical :: has_pressure
      integer :: k, n

      call resolve_targets(case, resolved, record, error)
      if (allocated(error)) return
      call timer%begin()
      selects = chosen(resolved)
      rigid_case = case
      rigid_case%mechanism%model%selection = 'manual'
      do k = 1, size(selects)
         if (selects(k)) rigid_case%motions(k)%num_modes = 0
      end do
      settings = case%mechanism%integrator
      record%h = (settings%t_end - settings%t_start) / real(SCENE_SAMPLES, dp)
      rigid_case%mechanism%integrator%h = record%h
      rigid_case%mechanism%model%h_given = .true.
      quiet = log
      quiet%level = LOG_QUIET
      call build_model(rigid_case, rigid_model, error)
      if (.not. allocated(error)) call build_mechanism(rigid_case, rigid_model, mesh_dir, quiet, &
         times, mech, bodies, q, v, pressure, has_pressure, error, sensors=sensors)
      if (.not. allocated(error)) call integrator%init(mech, rigid_case%mechanism%integrator, &
         q, v, error)
      if (allocated(error)) then
         call add_context(error, 'automatic model, rigid pre-run')
         return
      end if
      allocate (record%time(SCENE_SAMPLES + 1), record%bodies(size(selects)))
      allocate (record%series(SCENE_SAMPLES + 1, size(record%names)), source=0.0_dp)
      do k = 1, size(selects)
         record%bodies(k)%selected = selects(k)
         if (.not. selects(k)) cycle
         allocate (record%bodies(k)%load(6 * size(resolved%bodies(k)%interfaces), &
            SCENE_SAMPLES + 1), source=0.0_dp)
         allocate (record%bodies(k)%acceleration(3, SCENE_SAMPLES + 1), &
            record%bodies(k)%omega(3, SCENE_SAMPLES + 1), &
            record%bodies(k)%alpha(3, SCENE_SAMPLES + 1), &
            record%bodies(k)%gravity(3, SCENE_SAMPLES + 1), source=0.0_dp)
      end do
      do n = 1, SCENE_SAMPLES + 1
         if (n > 1) call integrator%step(mech, error)
         if (allocated(error)) then
            call add_context(error, 'automatic model, rigid pre-run at t = ' // &
               to_str(integrator%t, 6) // ' s')
            return
         end if
         record%time(n) = integrator%t - settings%t_start
         call record_state(n)
         if (allocated(error)) then
            call add_context(error, 'automatic model, rigid pre-run')
            return
         end if
      end do
      record%peak = [(maxval(record%series(:, k)), k=1, size(record%names))]
      record%curvature = [(curvature(record%series(:, k), record%h), k=1, size(record%names))]
      ! a mean target: its mean over the run, read without the peak's sampling error
      where (record%mean)
         record%peak = sum(record%series, dim=1) / real(SCENE_SAMPLES + 1, dp)
         record%curvature = 0.0_dp
      end where
      call times%add('automatic model: rigid pre-run', timer%seconds())
      call log%info('model', 'loads: rigid pre-run of the mechanism (the chosen bodies rigid) ' &
         // 'over ' // to_str(settings%t_end - settings%t_start, 4) // ' s in ' // &
         to_str(SCENE_SAMPLES) // ' steps, ' // to_str(timer%seconds(), 3) // ' s')

   contains

      !> The record of step n: joint loads and motion of each chosen body, reaction targets.
      subroutine record_state(n)
         integer, intent(in) :: n
         real(dp) :: force(3, 2), moment(3, 2), rotation(3, 3), g_bar(3, 4)
         real(dp), allocatable :: values(:)
         integer :: j, e, b, offset, p, s
         do p = 1, size(record%names)
            if (record%kinds(p) /= TARGET_INTERFACE) cycle
            s = findloc([(sensors(s)%name == record%names(p), s=1, size(sensors))], .true., &
               dim=1)
            call sensors(s)%evaluate(mech, integrator%q, integrator%v, integrator%qdd, &
               integrator%lambda, values, error)
            if (allocated(error)) return
            record%series(n, p) = norm2(values(1:min(3, size(values))))
         end do
         do j = 1, size(resolved%mechanism%joints)
            call mech%reaction(j, integrator%q, integrator%lambda, force, moment)
            do p = 1, size(record%names)
               if (record%kinds(p) == TARGET_REACTION .and. record%joint(p) == j) &
                  record%series(n, p) = norm2(force(:, 1))
            end do
            do e = 1, 2
               k = resolved%mechanism%joints(j)%body(e)
               if (k <= 0) cycle
               if (.not. selects(k)) cycle
               b = bodies(k)%index
               offset = mech%bodies(b)%offset
               rotation = euler_rotation(integrator%q(offset + 4:offset + 7))
               associate (i => resolved%mechanism%joints(j)%marker(e), &
                     load => record%bodies(k)%load)
                  load(6 * i - 5:6 * i - 3, n) = load(6 * i - 5:6 * i - 3, n) + &
                     matmul(transpose(rotation), force(:, e))
                  load(6 * i - 2:6 * i, n) = load(6 * i - 2:6 * i, n) + &
                     matmul(transpose(rotation), moment(:, e))
               end associate
            end do
         end do
         do k = 1, size(selects)
            if (.not. selects(k)) cycle
            b = bodies(k)%index
            offset = mech%bodies(b)%offset
            rotation = euler_rotation(integrator%q(offset + 4:offset + 7))
            g_bar = euler_g_bar(integrator%q(offset + 4:offset + 7))
            associate (rec => record%bodies(k))
               rec%acceleration(:, n) = matmul(transpose(rotation), &
                  integrator%qdd(offset + 1:offset + 3))
               rec%omega(:, n) = matmul(g_bar, integrator%v(offset + 4:offset + 7))
               rec%alpha(:, n) = matmul(g_bar, integrator%qdd(offset + 4:offset + 7))
               rec%gravity(:, n) = matmul(transpose(rotation), case%mechanism%mechanism%gravity)
            end associate
         end do
      end subroutine record_state

   end subroutine scene_prerun

   !> |r''| / max r at the largest sample (central second difference, one-sided at the ends).
   pure real(dp) function curvature(r, h)
      real(dp), intent(in) :: r(:), h
      integer :: i
      curvature = 0.0_dp
      if (size(r) < 3) return
      i = min(max(maxloc(r, dim=1), 2), size(r) - 1)
      curvature = abs(r(i + 1) - 2.0_dp * r(i) + r(i - 1)) / h**2 / max(maxval(r), tiny(1.0_dp))
   end function curvature

   !> The &model targets: each a &sensor the estimate serves (docs/mechanisms.md "Targets on
   !> sensors"): a reaction; a node_displacement of a body the selection chooses; a position,
   !> velocity or angular_velocity of a marker at an interface of such a body; a
   !> joint_coordinate of a joint with an end at such an interface. Anything else is refused
   !> here, before any modes or pre-run (`ffrf --check` calls it too).
   subroutine resolve_targets(case, resolved, record, error)
      type(case_input_t), intent(in) :: case
      type(model_t), intent(in) :: resolved
      type(scene_record_t), intent(inout) :: record
      type(error_t), allocatable, intent(out) :: error
      character(len=*), parameter :: served = 'reaction, node_displacement, ' // &
         'joint_coordinate, position, velocity, angular_velocity'
      logical, allocatable :: selects(:)
      integer :: p, s, n, e
      call parse_targets(case%mechanism%model%targets, record%names, record%tolerances, error, &
         record%mean)
      if (allocated(error)) return
      n = size(record%names)
      allocate (record%kinds(n), record%body(n), record%node(n), record%joint(n), &
         record%rows(n), record%order(n), record%side_body(2, n), record%side_interface(2, n), &
         source=0)
      allocate (record%peak(n), record%curvature(n), source=0.0_dp)
      selects = chosen(resolved)
      do p = 1, n
         s = findloc([(resolved%mechanism%sensors(s)%name == record%names(p), &
            s=1, size(resolved%mechanism%sensors))], .true., dim=1)
         if (s == 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, '&model targets: no &sensor "' // &
               trim(record%names(p)) // '"; name a &sensor of type ' // served)
            return
         end if
         associate (sensor => resolved%mechanism%sensors(s))
            select case (sensor%kind)
            case (SENSOR_REACTION)
               record%kinds(p) = TARGET_REACTION
               record%joint(p) = sensor%joint
               cycle
            case (SENSOR_NODE_DISPLACEMENT)
               record%kinds(p) = TARGET_NODE
               record%body(p) = sensor%body
               record%node(p) = sensor%node
               if (sensor%body > 0) then
                  if (selects(sensor%body)) cycle
               end if
               call fatal_error(error, FFRF_INPUT_ERROR, '&model targets: &sensor "' // &
                  trim(record%names(p)) // '" measures a body whose modes the automatic ' // &
                  'model does not choose; target a flexible body without num_modes')
               return
            case (SENSOR_POSITION, SENSOR_VELOCITY, SENSOR_ANGULAR_VELOCITY)
               record%kinds(p) = TARGET_INTERFACE
               record%rows(p) = merge(2, 1, sensor%kind == SENSOR_ANGULAR_VELOCITY)
               record%order(p) = merge(0, 1, sensor%kind == SENSOR_POSITION)
               call add_side(p, 1, sensor%body, sensor%marker)
            case (SENSOR_JOINT_COORDINATE)
               record%kinds(p) = TARGET_INTERFACE
               record%joint(p) = sensor%joint
               associate (joint => resolved%mechanism%joints(sensor%joint))
                  record%rows(p) = merge(2, 1, joint%kind == JOINT_REVOLUTE)
                  do e = 1, 2
                     call add_side(p, e, joint%body(e), joint%marker(e))
                  end do
               end associate
            case default
               call fatal_error(error, FFRF_INPUT_ERROR, '&model targets: &sensor "' // &
                  trim(record%names(p)) // '" is of type ' // sensor_word(sensor%kind) // &
                  '; the automatic model estimates targets on ' // served)
               return
            end select
            if (all(record%side_body(:, p) == 0)) then
               call fatal_error(error, FFRF_INPUT_ERROR, '&model targets: &sensor "' // &
                  trim(record%names(p)) // '" (' // sensor_word(sensor%kind) // ') measures ' &
                  // 'no interface of a body whose modes the automatic model chooses; put ' // &
                  'its marker (joint) at an interface of a flexible body without num_modes')
               return
            end if
         end associate
      end do
   contains
      !> End e of target p: body k's marker handle, if it is an interface of a chosen body.
      subroutine add_side(p, e, k, handle)
         integer, intent(in) :: p, e, k, handle
         if (k <= 0) return
         if (.not. selects(k) .or. handle < 1 .or. handle > &
            size(resolved%bodies(k)%interfaces)) return
         record%side_body(e, p) = k
         record%side_interface(e, p) = handle
      end subroutine add_side
   end subroutine resolve_targets

end module ffrf_app_scene_prerun
