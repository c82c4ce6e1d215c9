!> The model of a case: the input as read (case_input_t, strings) resolved once for the
!> applications. One record per body (its &body keys, material and motion together, no parallel
!> arrays), with every choice made here: rigid or flexible, whether it has a mesh, the modes to
!> compute (num_modes decided once, ffrf_model_specs body_modes_spec), and its interfaces
!> resolved (interface_spec_t) in the order that makes an interface's marker handle its index:
!> body_modes_t%interfaces(k), the k-th virtual node of the mode shapes and the flexible body's
!> marker k are the body's k-th interface. Names become indices here (body_index, marker_index),
!> so nothing downstream recounts the case's &interface groups.
module ffrf_model_model
   use ffrf_core_error, only: error_t, add_context
   use ffrf_mpc_interface, only: interface_spec_t
   use ffrf_modes_input, only: body_input_t, modes_spec_t
   use ffrf_input_case, only: case_input_t
   use ffrf_input_mechanism, only: body_motion_input_t
   use ffrf_model_specs, only: body_modes_spec, body_interface_specs, body_interface_indices
   implicit none
   private
   public :: model_body_t, model_t, build_model

   !> One body of the case, resolved.
   type :: model_body_t
      !> Body name (&body name)
      character(len=64) :: name = ''
      !> Material, volumes and mesh file (&body)
      type(body_input_t) :: body
      !> Mechanism keys of the &body (mass properties of a rigid body without a mesh, modal
      !> damping, start position, coarse meshes)
      type(body_motion_input_t) :: motion
      !> .true. for a rigid body (&body type = 'rigid'), decided here once
      logical :: rigid = .false.
      !> .true. when the body has a mesh file
      logical :: meshed = .false.
      !> num_modes given on the &body (>= 0); .false.: left open (&modes num_modes, or the
      !> automatic model of an engine run)
      logical :: num_modes_given = .false.
      !> Modes to compute (0 modes for a rigid body)
      type(modes_spec_t) :: modes
      !> The body's interfaces, resolved; interface k is marker handle k
      type(interface_spec_t), allocatable :: interfaces(:)
      !> Index into case%interfaces of interface k
      integer, allocatable :: interface_groups(:)
   contains
      !> Marker handle (interface index) of the interface called name, 0 if none
      procedure :: marker_index => body_marker_index
   end type model_body_t

   !> A case resolved for the applications.
   type :: model_t
      type(model_body_t), allocatable :: bodies(:)
   contains
      !> Index of the body called name, 0 if none (e.g. the ground)
      procedure :: body_index => model_body_index
   end type model_t

contains

   !> Resolve `case` into `model` (names to indices, strings to enumerations, choices made).
   subroutine build_model(case, model, error)
      !> The case as read and checked (read_case)
      type(case_input_t), intent(in) :: case
      type(model_t), intent(out) :: model
      type(error_t), allocatable, intent(out) :: error
      integer :: k
      allocate (model%bodies(size(case%bodies)))
      do k = 1, size(case%bodies)
         associate (b => model%bodies(k))
            b%name = case%bodies(k)%name
            b%body = case%bodies(k)
            b%motion = case%motions(k)
            b%rigid = case%motions(k)%type == 'rigid'
            b%meshed = len_trim(case%bodies(k)%mesh_file) > 0
            b%num_modes_given = case%motions(k)%num_modes >= 0
            call body_modes_spec(case, k, b%modes, error)
            if (.not. allocated(error)) call body_interface_specs(case%interfaces, b%name, &
               b%interfaces, error)
            if (allocated(error)) then
               call add_context(error, '&body "' // trim(b%name) // '"')
               return
            end if
            b%interface_groups = body_interface_indices(case%interfaces, b%name)
         end associate
      end do
   end subroutine build_model

   !> Index of the body called name, 0 if none.
   pure integer function model_body_index(self, name) result(k)
      class(model_t), intent(in) :: self
      !> Body name
      character(len=*), intent(in) :: name
      do k = 1, size(self%bodies)
         if (self%bodies(k)%name == name) return
      end do
      k = 0
   end function model_body_index

   !> Marker handle (index among the body's interfaces) of the interface called name, 0 if none.
   pure integer function body_marker_index(self, name) result(k)
      class(model_body_t), intent(in) :: self
      !> Interface (physical surface) name
      character(len=*), intent(in) :: name
      do k = 1, size(self%interfaces)
         if (self%interfaces(k)%name == name) return
      end do
      k = 0
   end function body_marker_index

end module ffrf_model_model
