!> The model layer (src/model/) on a case built in memory: the strings of &interface and &modes
!> become the numerics' enumerations and flags (each word against the constant it names), rc is
!> taken as the reader parsed it, a body's num_modes is decided once (rigid 0, else &body
!> num_modes, else &modes num_modes), and interfaces become marker handles: a body's k-th
!> &interface group in input order is its marker k, whatever other bodies' groups lie between.
!> Unknown words give an input error naming the word. Exact comparisons: no arithmetic involved.
module test_model_specs
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, FFRF_INPUT_ERROR
   use ffrf_mpc_interface, only: interface_spec_t, MPC_RBE2, MPC_RBE3, WEIGHTING_AREA, &
      WEIGHTING_UNIFORM, VIRTUAL_NODE_POSITION, VIRTUAL_NODE_CENTROID
   use ffrf_mpc_reduction, only: FORMULATION_NULL_SPACE, FORMULATION_MULTIPLIERS
   use ffrf_modes_input, only: modes_spec_t, BASIS_CRAIG_BAMPTON, BASIS_RC_NORMAL
   use ffrf_input_body, only: body_input_t
   use ffrf_input_interface, only: interface_input_t
   use ffrf_input_modes, only: modes_input_t
   use ffrf_input_mechanism, only: body_motion_input_t
   use ffrf_input_case, only: case_input_t
   use ffrf_model_specs, only: interface_spec_of, modes_spec_of, body_modes_spec
   use ffrf_model_model, only: model_t, build_model
   use ffrf_testing, only: unittest_t, new_unittest, check
   implicit none
   private
   public :: collect_model_specs

contains

   subroutine collect_model_specs(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [ &
         new_unittest('interface_words_to_enumerations', test_interface_words), &
         new_unittest('interface_rc_parsed_once', test_interface_rc), &
         new_unittest('interface_unknown_mpc_refused', test_interface_unknown), &
         new_unittest('modes_words_to_enumerations', test_modes_words), &
         new_unittest('modes_unknown_basis_refused', test_modes_unknown), &
         new_unittest('num_modes_decided_once', test_num_modes), &
         new_unittest('interfaces_are_marker_handles', test_marker_handles)]
   end subroutine collect_model_specs

   !> Two bodies, crank (flexible, no num_modes) and conrod (flexible, num_modes 5), a rigid
   !> piston; the crank's interfaces interleaved with the conrod's in the input.
   function three_body_case() result(case)
      type(case_input_t) :: case
      case%bodies = [body_input_t(name='crank'), body_input_t(name='conrod'), &
         body_input_t(name='piston')]
      case%motions = [body_motion_input_t(), body_motion_input_t(num_modes=5), &
         body_motion_input_t(type='rigid', mass=1.0_dp)]
      case%interfaces = [interface_input_t(body='crank', name='main', rc='Tx Ty Tz', &
         rc_dofs=[.true., .true., .true., .false., .false., .false.]), &
         interface_input_t(body='conrod', name='big_end'), &
         interface_input_t(body='crank', name='pin', mpc='RBE2'), &
         interface_input_t(body='conrod', name='small_end')]
      case%modes = modes_input_t(num_modes=12)
   end function three_body_case

   subroutine test_interface_words(error)
      type(error_t), allocatable, intent(out) :: error
      type(interface_spec_t) :: spec
      call interface_spec_of(interface_input_t(body='b', name='face', mpc='rbe2', &
         weighting='Area', virtual_node='position', position=[1.0_dp, 2.0_dp, 3.0_dp]), spec, error)
      if (allocated(error)) return
      call check(error, 'mpc rbe2 -> MPC_RBE2, weighting Area -> WEIGHTING_AREA, virtual_node ' &
         // 'position -> VIRTUAL_NODE_POSITION, position and name copied', &
         spec%mpc == MPC_RBE2 .and. spec%weighting == WEIGHTING_AREA .and. &
         spec%virtual_node == VIRTUAL_NODE_POSITION .and. &
         all(spec%position == [1.0_dp, 2.0_dp, 3.0_dp]) .and. spec%name == 'face')
      if (allocated(error)) return
      call interface_spec_of(interface_input_t(body='b', name='face'), spec, error)
      if (allocated(error)) return
      call check(error, 'defaults: RBE3, uniform, centroid, no rc', spec%mpc == MPC_RBE3 .and. &
         spec%weighting == WEIGHTING_UNIFORM .and. spec%virtual_node == VIRTUAL_NODE_CENTROID &
         .and. .not. any(spec%rc))
   end subroutine test_interface_words

   !> The reader's flags are taken as they are (the rc text is not parsed again); a case built
   !> in memory with rc text only gets it parsed here.
   subroutine test_interface_rc(error)
      type(error_t), allocatable, intent(out) :: error
      type(interface_spec_t) :: spec
      call interface_spec_of(interface_input_t(body='b', name='f', rc='Rz', &
         rc_dofs=[.false., .false., .false., .false., .false., .true.]), spec, error)
      if (allocated(error)) return
      call check(error, 'rc_dofs of the reader taken', &
         all(spec%rc .eqv. [.false., .false., .false., .false., .false., .true.]))
      if (allocated(error)) return
      call interface_spec_of(interface_input_t(body='b', name='f', rc='Tx 5'), spec, error)
      if (allocated(error)) return
      call check(error, 'rc text only: parsed (Tx and Nastran 5 = Ry)', &
         all(spec%rc .eqv. [.true., .false., .false., .false., .true., .false.]))
   end subroutine test_interface_rc

   subroutine test_interface_unknown(error)
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: expected
      type(interface_spec_t) :: spec
      call interface_spec_of(interface_input_t(body='b', name='face', mpc='RBE4'), spec, &
         expected)
      call check(error, 'mpc = RBE4 refused', allocated(expected))
      if (allocated(error)) return
      call check(error, 'input error naming the word and the interface: ' // expected%message, &
         expected%code == FFRF_INPUT_ERROR .and. index(expected%message, '"RBE4"') > 0 .and. &
         index(expected%message, 'interface "face"') > 0)
   end subroutine test_interface_unknown

   subroutine test_modes_words(error)
      type(error_t), allocatable, intent(out) :: error
      type(modes_spec_t) :: spec
      call modes_spec_of(modes_input_t(num_modes=7, shift_hz=-3.0_dp, formulation='null_space', &
         rc_label='RC set 1', tolerance=0.0_dp, lanczos_vectors=40, basis='craig_bampton'), spec, &
         error)
      if (allocated(error)) return
      call check(error, 'null_space, craig_bampton and the numbers copied', &
         spec%formulation == FORMULATION_NULL_SPACE .and. spec%basis == BASIS_CRAIG_BAMPTON &
         .and. spec%num_modes == 7 .and. spec%shift_hz == -3.0_dp .and. spec%tolerance == 0.0_dp &
         .and. spec%lanczos_vectors == 40 .and. spec%rc_label == 'RC set 1')
      if (allocated(error)) return
      call modes_spec_of(modes_input_t(), spec, error)
      if (allocated(error)) return
      call check(error, 'defaults: multipliers, rc_normal', &
         spec%formulation == FORMULATION_MULTIPLIERS .and. spec%basis == BASIS_RC_NORMAL)
   end subroutine test_modes_words

   subroutine test_modes_unknown(error)
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: expected
      type(modes_spec_t) :: spec
      call modes_spec_of(modes_input_t(basis='ritz'), spec, expected)
      call check(error, 'basis = ritz refused', allocated(expected))
      if (allocated(error)) return
      call check(error, 'input error naming the word: ' // expected%message, &
         expected%code == FFRF_INPUT_ERROR .and. index(expected%message, '"ritz"') > 0)
   end subroutine test_modes_unknown

   subroutine test_num_modes(error)
      type(error_t), allocatable, intent(out) :: error
      type(case_input_t) :: case
      type(modes_spec_t) :: crank, conrod, piston
      case = three_body_case()
      call body_modes_spec(case, 1, crank, error)
      if (.not. allocated(error)) call body_modes_spec(case, 2, conrod, error)
      if (.not. allocated(error)) call body_modes_spec(case, 3, piston, error)
      if (allocated(error)) return
      call check(error, 'crank: &modes 12; conrod: its own 5; rigid piston: 0', &
         crank%num_modes == 12 .and. conrod%num_modes == 5 .and. piston%num_modes == 0)
   end subroutine test_num_modes

   subroutine test_marker_handles(error)
      type(error_t), allocatable, intent(out) :: error
      type(model_t) :: model
      call build_model(three_body_case(), model, error)
      if (allocated(error)) return
      call check(error, 'body indices by name; the ground is none', &
         model%body_index('crank') == 1 .and. model%body_index('conrod') == 2 .and. &
         model%body_index('piston') == 3 .and. model%body_index('ground') == 0)
      if (allocated(error)) return
      associate (crank => model%bodies(1), conrod => model%bodies(2))
         call check(error, 'crank: main is marker 1, pin marker 2 (groups 1 and 3), pin RBE2', &
            crank%marker_index('main') == 1 .and. crank%marker_index('pin') == 2 .and. &
            all(crank%interface_groups == [1, 3]) .and. crank%interfaces(2)%mpc == MPC_RBE2 &
            .and. all(crank%interfaces(1)%rc(1:3)) .and. crank%marker_index('big_end') == 0)
         if (allocated(error)) return
         call check(error, 'conrod: big_end marker 1, small_end marker 2 (groups 2 and 4)', &
            conrod%marker_index('big_end') == 1 .and. conrod%marker_index('small_end') == 2 &
            .and. all(conrod%interface_groups == [2, 4]))
         if (allocated(error)) return
      end associate
      call check(error, 'rigid flags and one record per body', .not. model%bodies(1)%rigid &
         .and. .not. model%bodies(2)%rigid .and. model%bodies(3)%rigid .and. &
         model%bodies(3)%motion%mass == 1.0_dp .and. size(model%bodies(3)%interfaces) == 0)
   end subroutine test_marker_handles

end module test_model_specs

program main_model_specs
   use ffrf_testing, only: unittest_t, run_suite
   use test_model_specs, only: collect_model_specs
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_model_specs(tests)
   call run_suite('model_specs', tests)
end program main_model_specs
