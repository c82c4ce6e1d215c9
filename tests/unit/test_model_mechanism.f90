!> The mechanism part of the model (src/model/mechanism.f90, built by build_model) on a case
!> built in memory: the &joint and &load type words become JOINT_* and LOAD_* (each word against
!> the constant it names, any case), &model selection SELECTION_*, body names model body indices
!> (0: the ground) and marker names handles: a flexible body's interface index, a rigid body's
!> or the ground's &marker group index. The crank is an index, the crank's MPC a label from the
!> model. Unknown words, bodies and markers (possible only in a case built in memory: the
!> readers check a case file) are input errors naming what is wrong and what is valid. Exact
!> comparisons: no arithmetic involved.
module test_model_mechanism
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_lower
   use ffrf_mbs_joints, only: JOINT_REVOLUTE, JOINT_PRISMATIC, JOINT_SPHERICAL, &
      JOINT_UNIVERSAL, JOINT_FIXED, JOINT_CYLINDRICAL, joint_kind_name
   use ffrf_input_body, only: body_input_t
   use ffrf_input_interface, only: interface_input_t
   use ffrf_input_mechanism, only: body_motion_input_t, marker_input_t, joint_input_t, &
      load_input_t
   use ffrf_input_case, only: case_input_t
   use ffrf_model_mechanism, only: LOAD_PRESSURE, LOAD_DRAG, LOAD_CONSTANT_TORQUE, &
      SELECTION_AUTO, SELECTION_MANUAL
   use ffrf_model_model, only: model_t, build_model
   use ffrf_model_mechanism, only: joint_kind_of
   use ffrf_testing, only: unittest_t, new_unittest, check, report
   implicit none
   private
   public :: collect_model_mechanism

contains

   subroutine collect_model_mechanism(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [ &
         new_unittest('joints_resolved', test_joints), &
         new_unittest('loads_crank_selection_resolved', test_loads), &
         new_unittest('unknown_words_refused', test_unknown_words), &
         new_unittest('unknown_marker_refused', test_unknown_marker), &
         new_unittest('mesh_point_markers', test_mesh_point_markers), &
         new_unittest('joint_word_map', test_joint_word_map)]
   end subroutine collect_model_mechanism

   !> A slider-crank: flexible crank (interfaces main, pin), rigid piston with &marker points,
   !> ground markers; joints ground-crank (revolute), crank-piston (spherical), ground-piston
   !> (prismatic); loads pressure on the piston, drag and a torque on the crank.
   function slider_crank() result(case)
      type(case_input_t) :: case
      case%bodies = [body_input_t(name='crank', mesh_file='crank.msh'), &
         body_input_t(name='piston')]
      case%motions = [body_motion_input_t(), body_motion_input_t(type='rigid', mass=0.4_dp)]
      case%interfaces = [interface_input_t(body='crank', name='main', mpc='RBE2'), &
         interface_input_t(body='crank', name='pin')]
      case%is_mechanism = .true.
      case%mechanism%markers = [marker_input_t('ground','bearing', [0.0_dp, 0.0_dp, 0.0_dp]), &
         marker_input_t('piston','pin', [0.0_dp, 0.0_dp, 0.0_dp]), &
         marker_input_t('ground','cylinder', [0.0_dp, 0.2_dp, 0.0_dp]), &
         marker_input_t('piston','slider', [0.0_dp, 0.0_dp, 0.0_dp])]
      case%mechanism%joints = [ &
         joint_input_t('B1','Revolute','ground','bearing','crank','main'), &
         joint_input_t('pin','spherical','crank','pin','piston','pin'), &
         joint_input_t('cylinder','prismatic','ground','cylinder','piston','slider', &
         [0.0_dp, 1.0_dp, 0.0_dp])]
      case%mechanism%loads = [load_input_t(name='gas', type='pressure', body='piston', &
         marker='slider'), load_input_t(name='drag', type='DRAG', body='crank', marker='main', &
         coefficient=2.0e-4_dp), load_input_t(name='brake', type='torque', body='crank', &
         marker='main', value=-3.0_dp)]
      case%mechanism%mechanism%crank = 'crank'
      case%mechanism%integrator%h = 2.5e-4_dp
      case%mechanism%max_steps = 77
      case%mechanism%model%selection = 'manual'
      case%mechanism%model%h_given = .true.
   end function slider_crank

   subroutine test_joints(error)
      type(error_t), allocatable, intent(out) :: error
      type(model_t) :: model
      call build_model(slider_crank(), model, error)
      if (allocated(error)) return
      associate (j => model%mechanism%joints)
         call check(error, 'kinds: Revolute -> JOINT_REVOLUTE, spherical, prismatic', &
            size(j) == 3 .and. j(1)%kind == JOINT_REVOLUTE .and. j(2)%kind == JOINT_SPHERICAL &
            .and. j(3)%kind == JOINT_PRISMATIC)
         if (allocated(error)) return
         call check(error, 'bodies: ground 0, crank 1, piston 2', all(j(1)%body == [0, 1]) &
            .and. all(j(2)%body == [1, 2]) .and. all(j(3)%body == [0, 2]))
         if (allocated(error)) return
         ! crank: interface handles (main 1, pin 2); ground and piston: &marker group indices
         call check(error, 'markers: B1 ground bearing (group 1) - crank main (interface 1);' &
            // 'pin crank pin (interface 2) - piston pin (group 2); cylinder groups 3 and 4', &
            all(j(1)%marker == [1, 1]) .and. all(j(2)%marker == [2, 2]) .and. &
            all(j(3)%marker == [3, 4]))
         if (allocated(error)) return
         call check(error, 'names and axis copied', j(3)%name =='cylinder' .and. &
            all(j(3)%axis == [0.0_dp, 1.0_dp, 0.0_dp]))
         if (allocated(error)) return
      end associate
      call check(error, 'markers: bodies as indices', &
         all(model%mechanism%markers%body == [0, 2, 0, 2]))
   end subroutine test_joints

   subroutine test_loads(error)
      type(error_t), allocatable, intent(out) :: error
      type(model_t) :: model
      type(case_input_t) :: case
      case = slider_crank()
      call build_model(case, model, error)
      if (allocated(error)) return
      associate (m => model%mechanism, l => model%mechanism%loads)
         call check(error, 'kinds: pressure, DRAG -> LOAD_DRAG, torque -> LOAD_CONSTANT_TORQUE', &
            l(1)%kind == LOAD_PRESSURE .and. l(2)%kind == LOAD_DRAG .and. &
            l(3)%kind == LOAD_CONSTANT_TORQUE)
         if (allocated(error)) return
         call check(error, 'bodies, markers (piston slider: group 4; crank main: interface 1)' &
            // 'and parameters', all(l%body == [2, 1, 1]) .and. all(l%marker == [4, 1, 1]) &
            .and. l(2)%coefficient == 2.0e-4_dp .and. l(3)%value == -3.0_dp)
         if (allocated(error)) return
         call check(error, 'crank index 1, has_pressure, SELECTION_MANUAL, h given,' // &
            'integrator and max_steps copied', m%crank == 1 .and. m%has_pressure .and. &
            m%selection == SELECTION_MANUAL .and. m%h_given .and. &
            m%integrator%h == 2.5e-4_dp .and. m%max_steps == 77)
         if (allocated(error)) return
      end associate
      call check(error, 'crank MPC label: RBE2 (its first interface)', &
         model%crank_mpc() == 'RBE2')
      if (allocated(error)) return
      ! (a rigid crank would need &marker points for its joints; num_modes = 0 moves it rigidly)
      case%mechanism%model%selection = 'Auto'
      case%motions(1)%num_modes = 0
      call build_model(case, model, error)
      if (allocated(error)) return
      call check(error, 'Auto -> SELECTION_AUTO; a crank without modes is labelled rigid', &
         model%mechanism%selection == SELECTION_AUTO .and. model%crank_mpc() == 'rigid')
   end subroutine test_loads

   !> An unknown joint type, load type or selection word: FFRF_INPUT_ERROR naming the group,
   !> the word and the valid ones.
   subroutine test_unknown_words(error)
      type(error_t), allocatable, intent(out) :: error
      type(case_input_t) :: case
      case = slider_crank()
      case%mechanism%joints(2)%type = 'hinge'
      call expect(case, [character(len=64) :: '&joint "pin"', &
         'type = "hinge" is not a joint kind', &
         'revolute, prismatic, spherical, universal, fixed'], error)
      if (allocated(error)) return
      case = slider_crank()
      case%mechanism%loads(3)%type = 'spring'
      call expect(case, [character(len=64) :: '&load "brake"', &
         'type = "spring" is not a load kind', &
         'pressure, starter, drag, force, torque'], error)
      if (allocated(error)) return
      case = slider_crank()
      case%mechanism%model%selection = 'smart'
      call expect(case, [character(len=64) :: '&model: selection = "smart" is not known', &
         'use one of auto, manual'], error)
   end subroutine test_unknown_words

   !> A joint or load naming a marker or body that does not exist: FFRF_INPUT_ERROR naming it.
   subroutine test_unknown_marker(error)
      type(error_t), allocatable, intent(out) :: error
      type(case_input_t) :: case
      case = slider_crank()
      case%mechanism%joints(1)%marker2 = 'mian'
      call expect(case, [character(len=64) :: '&joint "B1"', &
         'marker "mian" is neither an &interface nor a &marker of the'], error)
      if (allocated(error)) return
      case = slider_crank()
      case%mechanism%joints(2)%marker2 = 'pinn'
      call expect(case, [character(len=64) :: '&joint "pin"', &
         'marker "pinn" of body "piston" is not a &marker'], error)
      if (allocated(error)) return
      case = slider_crank()
      case%mechanism%loads(1)%body = 'pistn'
      call expect(case, [character(len=64) :: '&load "gas"', &
         'body "pistn" is neither a &body nor the ground'], error)
   end subroutine test_unknown_marker

   !> A flexible body's node or group marker (&marker node, group): a load takes it, with the
   !> handle n_I + k (ffrf_model_mechanism: n_I = 2 interfaces of the crank, k its &marker
   !> index 5); a joint there is refused naming the marker and the fix.
   subroutine test_mesh_point_markers(error)
      type(error_t), allocatable, intent(out) :: error
      type(case_input_t) :: case
      type(model_t) :: model
      case = slider_crank()
      case%mechanism%markers = [case%mechanism%markers, marker_input_t('crank', 'web', &
         [0.0_dp, 0.0_dp, 0.0_dp], group='B3')]
      case%mechanism%loads(3)%marker = 'web'
      call build_model(case, model, error)
      if (allocated(error)) return
      call check(error, 'load at the group marker: body 1, handle 2 + 5', &
         model%mechanism%loads(3)%body == 1 .and. model%mechanism%loads(3)%marker == 7)
      if (allocated(error)) return
      case%mechanism%joints(1)%marker2 = 'web'
      call expect(case, [character(len=64) :: '&joint "B1"', &
         'marker "web" of the flexible body "crank" is a node or group', &
         'declare the group as an &interface and join there'], error)
   end subroutine test_mesh_point_markers

   !> The &joint type word map (joint_kind_of) against the JOINT_* constants written out here,
   !> each word in another case, and back through joint_kind_name; a partial word ('cyl', the
   !> substring the readers once let through) is refused.
   subroutine test_joint_word_map(error)
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: failure
      character(len=11), parameter :: words(6) = [character(len=11) :: 'Revolute', 'PRISMATIC', &
         'spherical', 'Universal', 'fixed', 'Cylindrical']
      integer, parameter :: expected(6) = [JOINT_REVOLUTE, JOINT_PRISMATIC, JOINT_SPHERICAL, &
         JOINT_UNIVERSAL, JOINT_FIXED, JOINT_CYLINDRICAL]
      integer :: k, kind
      do k = 1, size(words)
         call joint_kind_of(words(k), kind, error)
         if (allocated(error)) return
         call check(error, trim(words(k)) // ' -> ' // joint_kind_name(kind), &
            kind == expected(k) .and. joint_kind_name(kind) == to_lower(trim(words(k))))
         if (allocated(error)) return
      end do
      call joint_kind_of('cyl', kind, failure)
      call check(error, '"cyl" refused with the list of words', allocated(failure))
      if (allocated(error)) return
      call check(error, failure%message, index(failure%message, 'type = "cyl" is not a joint ' &
         // 'kind; use one of revolute, prismatic, spherical, universal, fixed, cylindrical') > 0)
   end subroutine test_joint_word_map

   !> build_model refuses `case` with FFRF_INPUT_ERROR and a message holding every fragment.
   subroutine expect(case, fragments, error)
      type(case_input_t), intent(in) :: case
      character(len=*), intent(in) :: fragments(:)
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: failure
      type(model_t) :: model
      integer :: k
      call build_model(case, model, failure)
      call check(error, 'refused with an input error', allocated(failure))
      if (allocated(error)) return
      call report(failure%message)
      call check(error, 'FFRF_INPUT_ERROR', failure%code == FFRF_INPUT_ERROR)
      do k = 1, size(fragments)
         if (allocated(error)) return
         call check(error, 'message "' // failure%message //'" says: ' // trim(fragments(k)), &
            index(failure%message, trim(fragments(k))) > 0)
      end do
   end subroutine expect

end module test_model_mechanism

program main_model_mechanism
   use ffrf_testing, only: unittest_t, run_suite
   use test_model_mechanism, only: collect_model_mechanism
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_model_mechanism(tests)
   call run_suite('model_mechanism', tests)
end program main_model_mechanism
