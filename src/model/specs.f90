!> The model layer's one place where the strings of the input become the enumerations and flags
!> of the numerics: &interface -> interface_spec_t (ffrf_mpc_interface), &modes ->
!> modes_spec_t (ffrf_modes_input), and the interfaces of one body in the order that makes an
!> interface's marker handle its index in the body (body_modes_t%interfaces(k),
!> virtual_node_shape rows 6k-5..6k). The choices were checked by the readers (src/input/, with
!> FILE:LINE); an unknown word here comes from a case built in memory and is an input error.
module ffrf_model_specs
   use ffrf_core_error, only: error_t
   use ffrf_core_choices, only: choice_kind
   use ffrf_mpc_interface, only: interface_spec_t
   use ffrf_modes_input, only: modes_spec_t
   use ffrf_input_interface, only: interface_input_t, parse_dofs, mpc_choices, &
      weighting_choices, virtual_node_choices
   use ffrf_input_modes, only: modes_input_t, formulation_choices, basis_choices
   use ffrf_input_case, only: case_input_t
   implicit none
   private
   public :: interface_spec_of, modes_spec_of, body_interface_specs, body_interface_indices
   public :: body_modes_spec

contains

   !> The resolved interface of an &interface group; rc comes parsed by the reader (rc_dofs).
   subroutine interface_spec_of(input, spec, error)
      !> The group as read
      type(interface_input_t), intent(in) :: input
      !> The interface for build_interface
      type(interface_spec_t), intent(out) :: spec
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: where
      spec%name = input%name
      spec%position = input%position
      ! rc was parsed once by the reader (rc_dofs); a case built in memory may give rc only
      spec%rc = input%rc_dofs
      if (.not. any(spec%rc) .and. len_trim(input%rc) > 0) then
         call parse_dofs(input%rc, spec%rc, error)
         if (allocated(error)) return
      end if
      where = 'interface "' // trim(input%name) // '": '
      call choice_kind(mpc_choices, where // 'mpc', 'known', input%mpc, spec%mpc, error)
      if (.not. allocated(error)) call choice_kind(weighting_choices, where // 'weighting', &
         'known', input%weighting, spec%weighting, error)
      if (.not. allocated(error)) call choice_kind(virtual_node_choices, &
         where // 'virtual_node', 'known', input%virtual_node, spec%virtual_node, error)
   end subroutine interface_spec_of

   !> The resolved modes specification of &modes (num_modes as given there; a body's own
   !> choice is made by the caller, see ffrf_model_case).
   subroutine modes_spec_of(input, spec, error)
      !> The group as read
      type(modes_input_t), intent(in) :: input
      !> The specification for compute_body_modes
      type(modes_spec_t), intent(out) :: spec
      type(error_t), allocatable, intent(out) :: error
      spec = modes_spec_t(num_modes=input%num_modes, shift_hz=input%shift_hz, &
         rc_label=input%rc_label, tolerance=input%tolerance, &
         lanczos_vectors=input%lanczos_vectors, out_of_core=input%out_of_core, &
         ooc_directory=input%ooc_tmpdir, memory_limit_mb=input%memory_limit_mb, &
         compression_tolerance=input%compression_tolerance, eigensolver=input%eigensolver, &
         max_frequency_hz=input%max_frequency_hz, sturm_check=input%sturm_check)
      call choice_kind(formulation_choices, '&modes: formulation', 'known', input%formulation, &
         spec%formulation, error)
      if (.not. allocated(error)) call choice_kind(basis_choices, '&modes: basis', 'known', &
         input%basis, spec%basis, error)
   end subroutine modes_spec_of

   !> The modes of body k, num_modes decided here once for every run: 0 for a rigid body (its
   !> mesh, if any, gives only mass properties and virtual nodes), else the body's own &body
   !> num_modes when given (>= 0), else &modes num_modes. (Before, modal runs ignored &body
   !> num_modes; no modal case of input/ gives it, so no result changes.) A flexible body left
   !> open may still be chosen by the automatic model (ffrf_app_engine_auto_model), which then
   !> replaces num_modes with its own candidate count.
   subroutine body_modes_spec(case, k, spec, error)
      !> The case as read
      type(case_input_t), intent(in) :: case
      !> Body index into case%bodies
      integer, intent(in) :: k
      !> The modes to compute for body k
      type(modes_spec_t), intent(out) :: spec
      type(error_t), allocatable, intent(out) :: error
      call modes_spec_of(case%modes, spec, error)
      if (allocated(error)) return
      if (case%motions(k)%type == 'rigid') then
         spec%num_modes = 0
      else if (case%motions(k)%num_modes >= 0) then
         spec%num_modes = case%motions(k)%num_modes
      end if
   end subroutine body_modes_spec

   !> Indices into `interfaces` of the groups of body `body_name`, in input order: the k-th is
   !> the body's interface (and marker) k.
   pure function body_interface_indices(interfaces, body_name) result(indices)
      type(interface_input_t), intent(in) :: interfaces(:)
      character(len=*), intent(in) :: body_name
      integer, allocatable :: indices(:)
      integer :: k
      indices = pack([(k, k = 1, size(interfaces))], interfaces%body == body_name)
   end function body_interface_indices

   !> The resolved interfaces of body `body_name` (body_interface_indices order).
   subroutine body_interface_specs(interfaces, body_name, specs, error)
      !> All &interface groups of the case
      type(interface_input_t), intent(in) :: interfaces(:)
      !> The body
      character(len=*), intent(in) :: body_name
      !> Its interfaces, resolved
      type(interface_spec_t), allocatable, intent(out) :: specs(:)
      type(error_t), allocatable, intent(out) :: error
      integer, allocatable :: indices(:)
      integer :: k
      indices = body_interface_indices(interfaces, body_name)
      allocate (specs(size(indices)))
      do k = 1, size(indices)
         call interface_spec_of(interfaces(indices(k)), specs(k), error)
         if (allocated(error)) return
      end do
   end subroutine body_interface_specs

end module ffrf_model_specs
