!> The mechanism part of a case's model (ffrf_model_model builds it): the &joint, &load,
!> &marker, &mechanism, &integrator and &model groups with every choice made once. A joint's
!> type word becomes its kind (JOINT_* of ffrf_mbs_joints), a load's its kind (LOAD_*), the
!> &model selection word SELECTION_*; body names become model body indices (0: the ground) and
!> marker names marker handles: a flexible body's interface index (model_body_t%interfaces), or
!> for a rigid body and the ground the index of its &marker group (mechanism_model_t%markers).
!> A flexible body's node or group marker (&marker node, group) has the handle n_I + k, n_I
!> the body's number of interfaces and k its &marker index (no joint takes it).
!> The words were checked by the readers (src/input/, with FILE:LINE); an unknown one here comes
!> from a case built in memory and is an input error listing the valid words.
module ffrf_model_mechanism
   use ffrf_core_kinds, only: dp, i8
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_choices, only: choice_kind, choice_name
   use ffrf_mbs_joints, only: joint_choices
   use ffrf_input_mechanism, only: load_choices, selection_choices, LOAD_PRESSURE, &
      LOAD_STARTER, LOAD_DRAG, LOAD_CONSTANT_FORCE, LOAD_CONSTANT_TORQUE, SELECTION_MANUAL, &
      SELECTION_AUTO
   use ffrf_mbs_generalized_alpha, only: galpha_settings_t
   use ffrf_mbs_energy_watch, only: energy_watch_settings_t
   use ffrf_mbs_time_function, only: time_function_t
   use ffrf_mbs_torsion_spring, only: torsion_spring_t
   use ffrf_mbs_bushing, only: bushing_t
   use ffrf_mpc_interface, only: WEIGHTING_UNIFORM
   implicit none
   private
   public :: model_joint_t, model_load_t, model_marker_t, model_sensor_t, mechanism_model_t
   public :: model_spring_t, model_driver_t
   public :: joint_kind_of, selection_of, load_kind_name
   public :: LOAD_PRESSURE, LOAD_STARTER, LOAD_DRAG, LOAD_CONSTANT_FORCE, LOAD_CONSTANT_TORQUE
   public :: SELECTION_MANUAL, SELECTION_AUTO

   ! LOAD_* and SELECTION_* come with their tables from ffrf_input_mechanism (load_choices,
   ! selection_choices), the joint kinds with joint_choices from ffrf_mbs_joints

   !> A point of a rigid body without interfaces or of the ground (&marker).
   type :: model_marker_t
      !> Model body index (0: the ground)
      integer :: body = 0
      character(len=64) :: name = ''
      !> Position in the body frame (m); for the ground, global
      real(dp) :: position(3) = 0.0_dp
      !> &marker orientation (marker axes in the body frame; ground: global), when oriented
      real(dp) :: orientation(3, 3) = 0.0_dp
      logical :: oriented = .false.
      !> Flexible body: the mesh node (Gmsh tag; 0: none) or physical group ('': none) that
      !> places the marker (docs/mechanisms.md "Markers at mesh points")
      integer :: node = 0
      character(len=64) :: group = ''
      !> A group marker's RBE3 node weights (WEIGHTING_* of ffrf_mpc_interface)
      integer :: weighting = WEIGHTING_UNIFORM
   end type model_marker_t

   !> A joint (&joint), resolved.
   type :: model_joint_t
      character(len=64) :: name = ''
      !> JOINT_* of ffrf_mbs_joints
      integer :: kind = 0
      !> Model body indices of its two ends (0: the ground)
      integer :: body(2) = 0
      !> Marker handles of its two ends (module header)
      integer :: marker(2) = 0
      !> Joint axis, global, in the starting pose
      real(dp) :: axis(3) = [0.0_dp, 0.0_dp, 1.0_dp]
   end type model_joint_t

   !> An applied load (&load), resolved.
   type :: model_load_t
      character(len=64) :: name = ''
      !> LOAD_*
      integer :: kind = 0
      !> Model body index (a moving body, > 0) and marker handle (module header)
      integer :: body = 0, marker = 0
      !> Global direction of the force or axis of the moment
      real(dp) :: direction(3) = [0.0_dp, 0.0_dp, 1.0_dp]
      !> Constant force / torque: magnitude (N, N m)
      real(dp) :: value = 0.0_dp
      !> Starter: stall torque (N m), no-load speed (rad/s), switch-off time (s)
      real(dp) :: stall_torque = 0.0_dp, free_speed = 0.0_dp, switch_off = 0.0_dp
      !> Drag: coefficient c (N m s^2)
      real(dp) :: coefficient = 0.0_dp
      !> Force / torque over time: magnitude value * law(t) (ffrf_mbs_time_function)
      logical :: timed = .false.
      type(time_function_t) :: law
   end type model_load_t

   !> A driver of a joint (&driver), resolved (ffrf_mbs_joint_driver).
   type :: model_driver_t
      character(len=64) :: name = ''
      !> Joint number (&joint order)
      integer :: joint = 0
      !> .true.: the law gives the rate (quantity = 'rate')
      logical :: rate = .false.
      !> Added to the law or its integral (rad or m)
      real(dp) :: offset = 0.0_dp
      type(time_function_t) :: law
   end type model_driver_t

   !> A spring-damper (&spring), resolved (ffrf_mbs_spring_damper).
   type :: model_spring_t
      character(len=64) :: name = ''
      !> Model body indices of its two ends (0: the ground) and their marker handles
      integer :: body(2) = 0, marker(2) = 0
      !> Stiffness (N/m), damping (N s/m), free length (m; negative: the starting distance)
      real(dp) :: stiffness = 0.0_dp, damping = 0.0_dp, free_length = -1.0_dp
   end type model_spring_t

   !> A sensor (&sensor), resolved: its kind (SENSOR_* of ffrf_mbs_sensors) and what it measures.
   type :: model_sensor_t
      character(len=64) :: name = ''
      !> SENSOR_*
      integer :: kind = 0
      !> Model body index (0: the ground) and marker handle (module header; 0: none)
      integer :: body = 0, marker = 0
      !> Joint number (&joint order; 0: none)
      integer :: joint = 0
      !> Mesh node (Gmsh node tag; 0: none)
      integer :: node = 0
      !> Spring number (&spring order, or the &torsion_spring or &bushing order for a
      !> torsion_spring or bushing sensor; 0: none)
      integer :: spring = 0
   end type model_sensor_t

   !> The mechanism of a case, resolved (empty arrays for a modal case).
   type :: mechanism_model_t
      type(model_marker_t), allocatable :: markers(:)
      type(model_joint_t), allocatable :: joints(:)
      type(model_load_t), allocatable :: loads(:)
      !> Spring-dampers (&spring), input order
      type(model_spring_t), allocatable :: springs(:)
      !> Torsion spring-dampers (&torsion_spring), input order, as the mechanism takes them
      !> (joint: the &joint number)
      type(torsion_spring_t), allocatable :: torsion_springs(:)
      !> Bushings (&bushing), input order: body_a, body_b model body indices (0: the ground),
      !> marker_a, marker_b marker handles (module header); the builder maps both
      type(bushing_t), allocatable :: bushings(:)
      !> Drivers of joints (&driver), input order
      type(model_driver_t), allocatable :: drivers(:)
      !> Sensors (&sensor), input order
      type(model_sensor_t), allocatable :: sensors(:)
      !> Model body index of the crank (0: none)
      integer :: crank = 0
      !> .true. when a load of kind LOAD_PRESSURE exists (the cylinder pressure model is made)
      logical :: has_pressure = .false.
      !> SELECTION_AUTO or SELECTION_MANUAL (&model selection)
      integer :: selection = SELECTION_MANUAL
      !> .true. when &integrator gives h (else the automatic model or the default chooses it)
      logical :: h_given = .false.
      !> Integrator settings (&integrator) and the largest number of steps a run may take
      type(galpha_settings_t) :: integrator
      integer(i8) :: max_steps = 0_i8
      !> Energy watch of the run (&integrator energy_watch ...; ffrf_mbs_energy_watch)
      type(energy_watch_settings_t) :: energy_watch
   end type mechanism_model_t

contains

   !> The joint kind (JOINT_* of ffrf_mbs_joints) of a &joint type word (any case).
   subroutine joint_kind_of(word, kind, error)
      character(len=*), intent(in) :: word
      !> JOINT_*
      integer, intent(out) :: kind
      type(error_t), allocatable, intent(out) :: error
      call choice_kind(joint_choices, 'type', 'a joint kind', word, kind, error)
   end subroutine joint_kind_of

   !> The name of a load kind (the &load type word), for messages.
   pure function load_kind_name(kind) result(name)
      integer, intent(in) :: kind
      character(len=:), allocatable :: name
      name = choice_name(load_choices, kind)
   end function load_kind_name

   !> SELECTION_AUTO or SELECTION_MANUAL of the &model selection word (any case).
   subroutine selection_of(word, selection, error)
      character(len=*), intent(in) :: word
      integer, intent(out) :: selection
      type(error_t), allocatable, intent(out) :: error
      call choice_kind(selection_choices, '&model: selection', 'known', word, selection, error)
      if (allocated(error)) selection = SELECTION_MANUAL
   end subroutine selection_of

end module ffrf_model_mechanism
