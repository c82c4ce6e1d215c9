!> Plain input types of a mechanism run, with their defaults (namelist groups &body's motion
!> keys, &marker, &joint, &load, &spring, &driver, &pressure, &integrator, &mechanism; readers in
!> src/input/nml_mechanism.f90 and src/input/nml_body.f90). SI units; angles in degrees where named
!> so.
module ffrf_input_mechanism
   use ffrf_core_kinds, only: dp, i8
   use ffrf_core_choices, only: choice_t
   use ffrf_input_pressure, only: pressure_input_t
   use ffrf_mbs_generalized_alpha, only: galpha_settings_t
   use ffrf_mbs_energy_watch, only: energy_watch_settings_t
   use ffrf_mbs_time_function, only: time_function_t, new_time_function
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_lower
   implicit none
   private
   public :: body_motion_input_t, marker_input_t, joint_input_t, load_input_t, sensor_input_t
   public :: spring_input_t, torsion_spring_input_t, bushing_input_t, time_law_input_t, driver_input_t, law_function
   public :: mechanism_input_t, mechanism_case_input_t, model_input_t, GROUND_NAME
   public :: load_choices, selection_choices, body_type_choices, quantity_choices
   public :: BODY_FLEXIBLE, BODY_RIGID, DRIVER_COORDINATE, DRIVER_RATE
   public :: LOAD_PRESSURE, LOAD_STARTER, LOAD_DRAG, LOAD_CONSTANT_FORCE, LOAD_CONSTANT_TORQUE
   public :: SELECTION_MANUAL, SELECTION_AUTO, parse_targets

   !> Name of the ground body in &marker and &joint (it needs no &body group)
   character(len=*), parameter :: GROUND_NAME = 'ground'

   !> Load kinds (&load type): the cylinder gas force (&pressure), the starter torque, the drag
   !> torque T = -c omega |omega|, a constant force, a constant torque (the model resolves the
   !> word, ffrf_model_mechanism; the builder makes the load)
   integer, parameter :: LOAD_PRESSURE = 1, LOAD_STARTER = 2, LOAD_DRAG = 3, &
      LOAD_CONSTANT_FORCE = 4, LOAD_CONSTANT_TORQUE = 5
   !> The load kinds' table: &load type words, kinds, names in messages (docs/developer.md
   !> "One table per choice")
   type(choice_t), parameter :: load_choices(*) = [choice_t('pressure', LOAD_PRESSURE), &
      choice_t('starter', LOAD_STARTER), choice_t('drag', LOAD_DRAG), &
      choice_t('force', LOAD_CONSTANT_FORCE), choice_t('torque', LOAD_CONSTANT_TORQUE)]
   !> &model selection: none (manual defaults) or the automatic model of an engine run
   integer, parameter :: SELECTION_MANUAL = 0, SELECTION_AUTO = 1
   !> The &model selection table
   type(choice_t), parameter :: selection_choices(*) = [choice_t('auto', SELECTION_AUTO), &
      choice_t('manual', SELECTION_MANUAL)]

   !> Body types (&body type): a reduced FFRF body from its mesh, or a rigid body. The word
   !> travels on as text (body_motion_input_t%type); the model decides the rigid flag once
   integer, parameter :: BODY_FLEXIBLE = 1, BODY_RIGID = 2
   !> The &body type table
   type(choice_t), parameter :: body_type_choices(*) = [choice_t('flexible', BODY_FLEXIBLE), &
      choice_t('rigid', BODY_RIGID)]

   !> Driver quantities (&driver quantity): the law gives the joint coordinate, or its rate
   integer, parameter :: DRIVER_COORDINATE = 1, DRIVER_RATE = 2
   !> The &driver quantity table
   type(choice_t), parameter :: quantity_choices(*) = [ &
      choice_t('coordinate', DRIVER_COORDINATE), choice_t('rate', DRIVER_RATE)]

   !> How a &body moves in a mechanism run.
   type :: body_motion_input_t
      !> 'flexible' (reduced FFRF body from its mesh) or 'rigid'
      character(len=16) :: type = 'flexible'
      !> Flexible bodies: modes kept (-1: &modes num_modes). 0 keeps none: the body moves rigidly
      !> with the mesh's exact mass properties and its interfaces' virtual nodes as markers.
      integer :: num_modes = -1
      !> Flexible bodies: modal damping ratio of every mode (0: none)
      real(dp) :: modal_damping = 0.0_dp
      !> Rigid bodies without a mesh: mass (kg), centre of mass (m, body frame) and inertia about
      !> the centre of mass, body axes: Jxx Jyy Jzz Jxy Jyz Jxz (kg m^2). A rigid body with a
      !> mesh takes the mesh's exact mass properties; its markers are &marker groups either way.
      real(dp) :: mass = 0.0_dp
      real(dp) :: center_of_mass(3) = 0.0_dp
      real(dp) :: inertia(6) = 0.0_dp
      !> Global position of the body-frame origin at the start (m)
      real(dp) :: position(3) = 0.0_dp
      !> Flexible bodies under &model selection = 'auto': coarser meshes of the same geometry,
      !> coarse to fine (mesh_file is the finest); the selection takes the coarsest one whose
      !> estimated error meets the targets (ffrf_app_engine_model_selection)
      character(len=256) :: coarse_meshes(4) = ''
      !> Starting orientation A (body -> global, r = R + A x_bar): its columns are the body axes
      !> in global coordinates; &body orientation gives its rows (A11 A12 A13 A21 ... A33).
      !> Default: the identity (body axes parallel to the global axes)
      real(dp) :: orientation(3, 3) = reshape([1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, &
         0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp], [3, 3])
      !> Starting velocity of the body-frame origin (m/s) and angular velocity (rad/s), global;
      !> the assembly projects them onto the joints' velocity constraints
      real(dp) :: velocity(3) = 0.0_dp
      real(dp) :: angular_velocity(3) = 0.0_dp
   end type body_motion_input_t

   !> A named point of a body without a mesh, or of the ground (&marker).
   type :: marker_input_t
      !> Body name ('ground' for the ground)
      character(len=64) :: body = ''
      !> Marker name, unique on its body
      character(len=64) :: name = ''
      !> Position in the body frame (m); for the ground, global
      real(dp) :: position(3) = 0.0_dp
      !> Orientation of the marker frame (its columns the marker axes in the body frame; for
      !> the ground, global), given by rows as &marker orientation; the identity when not given
      real(dp) :: orientation(3, 3) = reshape([1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, &
         0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp], [3, 3])
      !> orientation was given: the joints at this marker act between this frame and the
      !> other end's (ffrf_app_mechanism_builder)
      logical :: oriented = .false.
      !> Flexible body only: a Gmsh node tag of its mesh (the marker moves with the node), 0: none
      integer :: node = 0
      !> Flexible body only: a physical surface of its mesh (curves and points are not read),
      !> the marker at its RBE3 reference point (docs/mechanisms.md "Markers at mesh points");
      !> '': none
      character(len=64) :: group = ''
      !> A group marker's RBE3 node weights: a word of weighting_choices (as &interface)
      character(len=16) :: weighting = 'uniform'
   end type marker_input_t

   !> A joint between a marker of body1 and a marker of body2 (&joint).
   type :: joint_input_t
      character(len=64) :: name = ''
      !> A word of joint_choices (ffrf_mbs_joints): 'revolute', ...
      character(len=16) :: type = ''
      !> Bodies and markers; a flexible body's markers are its interfaces (virtual nodes)
      character(len=64) :: body1 = '', marker1 = '', body2 = '', marker2 = ''
      !> Joint axis, global, in the starting pose: rotation axis of a revolute, sliding direction
      !> of a prismatic, shaft of body 1 of a universal (ignored by spherical and fixed)
      real(dp) :: axis(3) = [0.0_dp, 0.0_dp, 1.0_dp]
   end type joint_input_t

   !> A law over time g(t) as given (&driver, &load; ffrf_mbs_time_function, docs/mechanisms.md
   !> "Laws over time").
   type :: time_law_input_t
      !> constant, constant_speed, ramp, smooth_step or table; '' for none (a &load's constant
      !> value)
      character(len=16) :: law = ''
      !> g(0) or g before t_start; g after t_start + duration; dg/dt of constant_speed
      real(dp) :: initial = 0.0_dp, final = 0.0_dp, speed = 0.0_dp
      !> Start (s) and duration (s) of a ramp or smooth step
      real(dp) :: t_start = 0.0_dp, duration = 1.0_dp
      !> Table points: times (s, strictly increasing) and values
      real(dp), allocatable :: table_time(:), table_value(:)
      !> Table: 'linear' or 'cubic'; 'hold' or 'periodic' beyond the points
      character(len=8) :: interpolation = 'linear', beyond = 'hold'
   end type time_law_input_t

   !> A driver of a revolute or prismatic joint (&driver; ffrf_mbs_joint_driver).
   type :: driver_input_t
      character(len=64) :: name = ''
      !> The &joint it drives
      character(len=64) :: joint = ''
      !> 'coordinate' (the law gives the angle or travel) or 'rate' (the law gives its rate)
      character(len=16) :: quantity = 'coordinate'
      !> Added to the law or its integral (rad or m)
      real(dp) :: offset = 0.0_dp
      !> The law
      type(time_law_input_t) :: law
   end type driver_input_t

   !> An applied load on a body at one of its markers (&load).
   type :: load_input_t
      character(len=64) :: name = ''
      !> A word of load_choices: pressure (in-cylinder gas force, &pressure), starter, drag
      !> (T = -c omega |omega|), force or torque (constant value)
      character(len=16) :: type = ''
      character(len=64) :: body = '', marker = ''
      !> Global direction of the force or axis of the moment
      real(dp) :: direction(3) = [0.0_dp, 0.0_dp, 1.0_dp]
      !> force / torque: magnitude (N, N m)
      real(dp) :: value = 0.0_dp
      !> starter: stall torque (N m), no-load speed (rad/s), switch-off time (s)
      real(dp) :: stall_torque = 40.0_dp, free_speed = 157.0_dp, switch_off = 0.5_dp
      !> drag: coefficient c (N m s^2)
      real(dp) :: coefficient = 3.6e-4_dp
      !> force / torque over time: magnitude value * g(t) (law '' : constant value)
      type(time_law_input_t) :: law
   end type load_input_t

   !> A linear spring-damper between marker1 of body1 and marker2 of body2 (&spring;
   !> ffrf_mbs_spring_damper): tension k (l - L0) + c l' along the line between the markers.
   type :: spring_input_t
      character(len=64) :: name = ''
      !> Bodies ('ground' for the ground) and markers: &marker points or a flexible body's
      !> &interface (its virtual node); two different bodies
      character(len=64) :: body1 = '', marker1 = '', body2 = '', marker2 = ''
      !> Stiffness k (N/m) and damping c (N s/m), >= 0
      real(dp) :: stiffness = 0.0_dp, damping = 0.0_dp
      !> Free length L0 (m); negative (the default): the distance of the markers at the start
      real(dp) :: free_length = -1.0_dp
   end type spring_input_t

   !> A rotational spring-damper about a revolute or cylindrical joint (&torsion_spring;
   !> ffrf_mbs_torsion_spring): torque -k (phi - phi0) - c phi' about the joint axis.
   type :: torsion_spring_input_t
      character(len=64) :: name = ''
      !> The &joint it acts about (revolute or cylindrical)
      character(len=64) :: joint = ''
      !> Stiffness k (N m/rad) and damping c (N m s/rad), >= 0
      real(dp) :: stiffness = 0.0_dp, damping = 0.0_dp
      !> Free angle phi0 (rad); not given (free_angle_given = .false.): the joint angle at the
      !> start
      real(dp) :: free_angle = 0.0_dp
      logical :: free_angle_given = .false.
   end type torsion_spring_input_t

   !> A 6-dof linear bushing between marker1 of body1 and marker2 of body2 (&bushing;
   !> ffrf_mbs_bushing): F = -K d - C d', M = -K_r phi - C_r phi' in marker1's frame.
   type :: bushing_input_t
      character(len=64) :: name = ''
      !> Bodies ('ground' for the ground) and markers, as &spring; two different bodies
      character(len=64) :: body1 = '', marker1 = '', body2 = '', marker2 = ''
      !> Stiffness kx, ky, kz (N/m), krx, kry, krz (N m/rad) and damping (N s/m, N m s/rad)
      real(dp) :: stiffness(6) = 0.0_dp, damping(6) = 0.0_dp
   end type bushing_input_t

   !> A sensor: a named measurement written every recorded step under /sensors/<name> (&sensor;
   !> ffrf_mbs_sensors lists the types, docs/sensors.md the results).
   type :: sensor_input_t
      !> Name, unique among the sensors
      character(len=64) :: name = ''
      !> position, velocity, acceleration, orientation, angular_velocity (body, marker);
      !> joint_coordinate, reaction (joint); energy (body); node_displacement, node_position
      !> (body with a mesh, node); spring (spring)
      character(len=20) :: type = ''
      !> Body ('ground' for the ground) and marker: a &marker point or a flexible body's
      !> &interface (its virtual node)
      character(len=64) :: body = '', marker = ''
      !> Joint name (joint types)
      character(len=64) :: joint = ''
      !> Mesh node of the body (node types: its Gmsh node tag; 0: none)
      integer :: node = 0
      !> Spring name (type spring: length, rate, tension of a &spring; type torsion_spring:
      !> angle, rate, torque of a &torsion_spring; type bushing: a &bushing)
      character(len=64) :: spring = ''
   end type sensor_input_t

   !> Mechanism-wide settings (&mechanism).
   type :: mechanism_input_t
      !> Body whose rotation about z is the crank angle (pressure, starter, drag, output)
      character(len=64) :: crank = ''
      !> Crank angle (deg) and speed (rad/s) at the start
      real(dp) :: crank_angle_deg = 0.0_dp, crank_speed = 0.0_dp
      !> Gravity (m/s^2), global; off by default
      real(dp) :: gravity(3) = 0.0_dp
      !> Label of the run in charts and tables, e.g. 'RC set 1' or 'rigid crank'
      character(len=64) :: label = ''
      !> Progress line every this many simulated seconds
      real(dp) :: progress_interval = 0.1_dp
      !> Frames of the deformed-shape animation over the last 720 deg cycle (0: none)
      integer :: animation_frames = 24
   end type mechanism_input_t

   !> Automatic model selection (&model; ffrf_app_engine_model_selection).
   type :: model_input_t
      !> 'auto': an engine run (a crank, a pressure and a drag load) gets the smallest model whose
      !> predicted error meets the tolerances for every choice the input leaves open (a flexible
      !> body's num_modes and mesh among its coarse_meshes, &integrator h); 'manual': no
      !> selection (open choices take &modes num_modes and h = 1e-3 s)
      character(len=16) :: selection = 'auto'
      !> Relative error targets of the regime (mean) crank speed and of the joint forces
      real(dp) :: speed_tolerance = 1.0e-3_dp, force_tolerance = 1.0e-2_dp
      !> Modes computed per body to choose from
      integer :: candidate_modes = 20
      !> Floor of |1 - r^2| in a mode's forced response (ffrf_app_engine_model_selection, 2)
      real(dp) :: resonance_floor = 0.1_dp
      !> Targets of a scene without a crank: pairs "<&sensor name> <relative tolerance of its
      !> peak>" separated by blanks (ffrf_app_scene_model; '': none)
      character(len=512) :: targets = ''
      !> .true. when &integrator gives h (set by the reader, not a namelist key)
      logical :: h_given = .false.
   end type model_input_t

   !> Everything of a mechanism run besides the modal input of the flexible bodies.
   type :: mechanism_case_input_t
      type(mechanism_input_t) :: mechanism
      type(marker_input_t), allocatable :: markers(:)
      type(joint_input_t), allocatable :: joints(:)
      type(load_input_t), allocatable :: loads(:)
      !> Spring-dampers (&spring), in input order
      type(spring_input_t), allocatable :: springs(:)
      !> Torsion spring-dampers (&torsion_spring), in input order
      type(torsion_spring_input_t), allocatable :: torsion_springs(:)
      !> Bushings (&bushing), in input order
      type(bushing_input_t), allocatable :: bushings(:)
      !> Drivers of joints (&driver), in input order
      type(driver_input_t), allocatable :: drivers(:)
      !> Sensors (&sensor), in input order
      type(sensor_input_t), allocatable :: sensors(:)
      !> Pressure model data (&pressure); table_file: angle (deg) and absolute pressure (Pa) per
      !> line instead of the single-zone model
      type(pressure_input_t) :: pressure
      character(len=256) :: pressure_table = ''
      type(galpha_settings_t) :: integrator
      !> Largest number of integration steps (t_end - t_start)/h a run may take (&integrator
      !> max_steps): a guard against a slip such as t_end = 1e5; raise it on purpose
      integer(i8) :: max_steps = 10000000_i8
      !> Energy watch (&integrator energy_watch, energy_watch_tolerance, energy_watch_window;
      !> ffrf_mbs_energy_watch)
      type(energy_watch_settings_t) :: energy_watch
      type(model_input_t) :: model
   end type mechanism_case_input_t

contains

   !> The time function of a law as given (checked by new_time_function; `where` names the
   !> place in its messages).
   subroutine law_function(given, where, fun, error)
      type(time_law_input_t), intent(in) :: given
      character(len=*), intent(in) :: where
      type(time_function_t), intent(out) :: fun
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: times(:), values(:)
      times = [real(dp) ::]
      values = [real(dp) ::]
      if (allocated(given%table_time)) times = given%table_time
      if (allocated(given%table_value)) values = given%table_value
      call new_time_function(given%law, where, fun, error, initial=given%initial, &
         final=given%final, speed=given%speed, t_start=given%t_start, duration=given%duration, &
         times=times, values=values, interpolation=given%interpolation, beyond=given%beyond)
   end subroutine law_function

   !> The &model targets (docs/mechanisms.md "Targets on sensors"): each a &sensor name, an
   !> optional statistic (`peak`, the default, or `mean`: the sensor's mean over the run) and
   !> the relative tolerance, in (0, 1), separated by blanks ('': none).
   subroutine parse_targets(text, names, tolerances, error, means)
      character(len=*), intent(in) :: text
      character(len=64), allocatable, intent(out) :: names(:)
      real(dp), allocatable, intent(out) :: tolerances(:)
      type(error_t), allocatable, intent(out) :: error
      !> .true. for a target on the sensor's mean
      logical, allocatable, intent(out), optional :: means(:)
      character(len=64), allocatable :: words(:)
      character(len=64) :: word
      logical, allocatable :: mean(:)
      real(dp) :: value
      integer :: first, last, stat, k
      allocate (words(0), names(0), tolerances(0), mean(0))
      last = 0
      do
         first = verify(text(last + 1:), ' ') + last
         if (first == last) exit
         last = scan(text(first:), ' ') + first - 2
         if (last < first) last = len_trim(text)
         word = text(first:last)
         words = [words, word]
      end do
      k = 1
      do while (k <= size(words))
         names = [names, words(k)]
         mean = [mean, to_lower(words(min(k + 1, size(words)))) == 'mean']
         if (k < size(words)) then
            if (any(to_lower(words(k + 1)) == ['peak', 'mean'])) k = k + 1
         end if
         if (k == size(words)) then
            call fatal_error(error, FFRF_INPUT_ERROR, '&model targets = ''' // trim(text) // &
               ''': "' // trim(names(size(names))) // '" has no tolerance; give a &sensor ' // &
               'name, optionally peak or mean, and a relative tolerance, e.g. ''tip 1e-2 ' // &
               'speed mean 1e-3''')
            return
         end if
         read (words(k + 1), *, iostat=stat) value
         if (stat /= 0 .or. .not. (value > 0.0_dp .and. value < 1.0_dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, '&model targets: the tolerance of "' // &
               trim(names(size(names))) // '" is "' // trim(words(k + 1)) // '", must be a ' // &
               'number in (0, 1) (a relative error of the sensor''s peak or mean)')
            return
         end if
         tolerances = [tolerances, value]
         k = k + 2
      end do
      if (present(means)) means = mean
   end subroutine parse_targets

end module ffrf_input_mechanism
