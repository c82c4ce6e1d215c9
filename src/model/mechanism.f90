!> The mechanism part of a case's model (ffrf_model_model builds it): the &joint, &load,
!> &marker, &mechanism, &integrator and &model groups with every choice made once. A joint's
!> type word becomes its kind (JOINT_* of ffrf_mbs_joints), a load's its kind (LOAD_*), the
!> &model selection word SELECTION_*; body names become model body indices (0: the ground) and
!> marker names marker handles: a flexible body's interface index (model_body_t%interfaces), or
!> for a rigid body and the ground the index of its &marker group (mechanism_model_t%markers).
!> The words were checked by the readers (src/input/, with FILE:LINE); an unknown one here comes
!> from a case built in memory and is an input error listing the valid words.
module ffrf_model_mechanism
   use ffrf_core_kinds, only: dp, i8
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_lower
   use ffrf_mbs_joints, only: JOINT_SPHERICAL, JOINT_REVOLUTE, JOINT_UNIVERSAL, &
      JOINT_PRISMATIC, JOINT_FIXED, joint_kinds
   use ffrf_mbs_generalized_alpha, only: galpha_settings_t
   use ffrf_mbs_energy_watch, only: energy_watch_settings_t
   implicit none
   private
   public :: model_joint_t, model_load_t, model_marker_t, model_sensor_t, mechanism_model_t
   public :: model_spring_t
   public :: joint_kind_of, load_kind_of, selection_of, load_kind_name
   public :: LOAD_PRESSURE, LOAD_STARTER, LOAD_DRAG, LOAD_CONSTANT_FORCE, LOAD_CONSTANT_TORQUE
   public :: SELECTION_MANUAL, SELECTION_AUTO

   !> Load kinds (&load type): the cylinder gas force (&pressure), the starter torque, the drag
   !> torque T = -c omega |omega|, a constant force, a constant torque
   integer, parameter :: LOAD_PRESSURE = 1, LOAD_STARTER = 2, LOAD_DRAG = 3, &
      LOAD_CONSTANT_FORCE = 4, LOAD_CONSTANT_TORQUE = 5
   !> &model selection: none (manual defaults) or the automatic model of an engine run
   integer, parameter :: SELECTION_MANUAL = 0, SELECTION_AUTO = 1

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
   end type model_load_t

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
      !> Spring number (&spring order; 0: none)
      integer :: spring = 0
   end type model_sensor_t

   !> The mechanism of a case, resolved (empty arrays for a modal case).
   type :: mechanism_model_t
      type(model_marker_t), allocatable :: markers(:)
      type(model_joint_t), allocatable :: joints(:)
      type(model_load_t), allocatable :: loads(:)
      !> Spring-dampers (&spring), input order
      type(model_spring_t), allocatable :: springs(:)
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

   !> The joint kind of a &joint type word (any case).
   subroutine joint_kind_of(word, kind, error)
      character(len=*), intent(in) :: word
      !> JOINT_* of ffrf_mbs_joints
      integer, intent(out) :: kind
      type(error_t), allocatable, intent(out) :: error
      kind = 0
      select case (to_lower(trim(adjustl(word))))
      case ('spherical')
         kind = JOINT_SPHERICAL
      case ('revolute')
         kind = JOINT_REVOLUTE
      case ('universal')
         kind = JOINT_UNIVERSAL
      case ('prismatic')
         kind = JOINT_PRISMATIC
      case ('fixed')
         kind = JOINT_FIXED
      case default
         call fatal_error(error, FFRF_INPUT_ERROR, 'type = "' // trim(word) // &
            '" is not a joint kind; use one of ' // joint_kinds)
      end select
   end subroutine joint_kind_of

   !> The load kind of a &load type word (any case).
   subroutine load_kind_of(word, kind, error)
      character(len=*), intent(in) :: word
      !> LOAD_*
      integer, intent(out) :: kind
      type(error_t), allocatable, intent(out) :: error
      kind = 0
      select case (to_lower(trim(adjustl(word))))
      case ('pressure')
         kind = LOAD_PRESSURE
      case ('starter')
         kind = LOAD_STARTER
      case ('drag')
         kind = LOAD_DRAG
      case ('force')
         kind = LOAD_CONSTANT_FORCE
      case ('torque')
         kind = LOAD_CONSTANT_TORQUE
      case default
         call fatal_error(error, FFRF_INPUT_ERROR, 'type = "' // trim(word) // &
            '" is not a load kind; use one of pressure, starter, drag, force, torque')
      end select
   end subroutine load_kind_of

   !> The name of a load kind (the &load type word), for messages.
   pure function load_kind_name(kind) result(name)
      integer, intent(in) :: kind
      character(len=:), allocatable :: name
      select case (kind)
      case (LOAD_PRESSURE)
         name = 'pressure'
      case (LOAD_STARTER)
         name = 'starter'
      case (LOAD_DRAG)
         name = 'drag'
      case (LOAD_CONSTANT_FORCE)
         name = 'force'
      case (LOAD_CONSTANT_TORQUE)
         name = 'torque'
      case default
         name = 'unknown'
      end select
   end function load_kind_name

   !> SELECTION_AUTO or SELECTION_MANUAL of the &model selection word (any case).
   subroutine selection_of(word, selection, error)
      character(len=*), intent(in) :: word
      integer, intent(out) :: selection
      type(error_t), allocatable, intent(out) :: error
      selection = SELECTION_MANUAL
      select case (to_lower(trim(adjustl(word))))
      case ('auto')
         selection = SELECTION_AUTO
      case ('manual')
         selection = SELECTION_MANUAL
      case default
         call fatal_error(error, FFRF_INPUT_ERROR, '&model: selection = "' // trim(word) // &
            '" is not known; use "auto" or "manual"')
      end select
   end subroutine selection_of

end module ffrf_model_mechanism
