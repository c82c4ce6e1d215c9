!> One table per choice: the words a user may write for a word-valued key and the kind constants
!> they stand for, kept beside the kind constants (joint_choices of ffrf_mbs_joints, ...). The
!> readers' key specs take their accepted words from the table (choice_words), the model maps a
!> word to its kind (choice_position), and messages and results name a kind by its word
!> (choice_name): each word is written once (docs/developer.md "One table per choice").
module ffrf_core_choices
   use ffrf_core_strings, only: to_lower, join_words
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   implicit none
   private
   public :: choice_t, choice_words, choice_position, choice_name, choice_kind, choice_kind_of
   public :: MPC_RBE2, MPC_RBE3, mpc_choices
   public :: FORMULATION_NONE, FORMULATION_MULTIPLIERS, FORMULATION_NULL_SPACE, formulation_choices
   public :: BASIS_NONE, BASIS_RC_NORMAL, BASIS_CRAIG_BAMPTON, basis_choices
   public :: choice_kinds
   public :: EXPORT_XDMF, EXPORT_EXUDYN, export_choices
   public :: SENSOR_POSITION, SENSOR_VELOCITY, SENSOR_ACCELERATION, SENSOR_ORIENTATION, &
      SENSOR_ANGULAR_VELOCITY, SENSOR_JOINT_COORDINATE, SENSOR_REACTION, SENSOR_ENERGY, &
      SENSOR_NODE_DISPLACEMENT, SENSOR_NODE_POSITION, SENSOR_SPRING, SENSOR_DRIVER, &
      SENSOR_TORSION_SPRING, SENSOR_BUSHING, SENSOR_ROTOR_ANGLE, SENSOR_ROTOR_SPEED, &
      sensor_choices, rotor_sensor_choices
   public :: WEIGHTING_UNIFORM, WEIGHTING_AREA, WEIGHTING_AREA_CONSISTENT, WEIGHTING_GIVEN, &
      weighting_choices, weighting_names
   public :: TIME_CONSTANT, TIME_CONSTANT_SPEED, TIME_RAMP, TIME_SMOOTH_STEP, TIME_TABLE, &
      time_law_choices
   public :: INTERPOLATION_LINEAR, INTERPOLATION_CUBIC, interpolation_choices
   public :: BEYOND_HOLD, BEYOND_PERIODIC, beyond_choices

   !> One row of a choice table: the word (any case in the input) and its kind constant
   type :: choice_t
      character(len=20) :: word = ''
      integer :: kind = 0
   end type choice_t

   ! The tables whose kinds the numerics below the input use in more than one layer (mpc, modes,
   ! io): kept here, the lowest layer, so that the readers' key specs, the model's word map and
   ! the names in logs, fingerprints and results all come from one list. The numerics modules
   ! re-export the kinds (ffrf_mpc_interface, ffrf_mpc_reduction, ffrf_modes_input).

   !> MPC kinds (&interface mpc): rigid spider q_B = F q_V; interpolation element q_V = G q_B
   integer, parameter :: MPC_RBE2 = 1, MPC_RBE3 = 2
   type(choice_t), parameter :: mpc_choices(*) = [choice_t('RBE2', MPC_RBE2), &
      choice_t('RBE3', MPC_RBE3)]

   !> Formulations of the reference conditions (&modes formulation): none (no RC rows); RBE2
   !> eliminated, RBE3 reference conditions as constraint rows (Lagrange multipliers); explicit
   !> null spaces B2 = null(D) or null(D G) (LAPACK SVD). FORMULATION_NONE has no word.
   integer, parameter :: FORMULATION_NONE = 0, FORMULATION_MULTIPLIERS = 1, &
      FORMULATION_NULL_SPACE = 2
   type(choice_t), parameter :: formulation_choices(*) = [ &
      choice_t('multipliers', FORMULATION_MULTIPLIERS), &
      choice_t('null_space', FORMULATION_NULL_SPACE)]

   !> Mode bases (&modes basis): none (no modes asked, no word), the constrained normal modes of
   !> the RC set, or Craig-Bampton (src/modes/craig_bampton.f90)
   integer, parameter :: BASIS_NONE = 0, BASIS_RC_NORMAL = 1, BASIS_CRAIG_BAMPTON = 2
   type(choice_t), parameter :: basis_choices(*) = [choice_t('rc_normal', BASIS_RC_NORMAL), &
      choice_t('craig_bampton', BASIS_CRAIG_BAMPTON)]

   !> Exports beside the results file (&run export, a list of words, each one dispatched by the
   !> applications): XDMF 3 for ParaView (src/io/xdmf.f90); each flexible body of a modal run as a
   !> file Exudyn's FEMinterface.LoadFromFile loads (src/io/exudyn_body.f90; docs/results.md
   !> "Exudyn export")
   integer, parameter :: EXPORT_XDMF = 1, EXPORT_EXUDYN = 2
   type(choice_t), parameter :: export_choices(*) = [ &
      choice_t('xdmf', EXPORT_XDMF), choice_t('exudyn', EXPORT_EXUDYN)]

   !> RBE3 node weightings (&interface weighting, &marker weighting): every node weight 1
   !> (Nastran's default), tributary areas, consistent areas int N_i dA (Tri6 corners ~0); given
   !> (a node-set interface's own weights: no word, named in the mode fingerprint). The kinds
   !> are re-exported by ffrf_mpc_interface, weighting_choices by ffrf_input_interface
   integer, parameter :: WEIGHTING_UNIFORM = 1, WEIGHTING_AREA = 2, &
      WEIGHTING_AREA_CONSISTENT = 3, WEIGHTING_GIVEN = 4
   type(choice_t), parameter :: weighting_names(*) = [choice_t('uniform', WEIGHTING_UNIFORM), &
      choice_t('area', WEIGHTING_AREA), choice_t('area_consistent', WEIGHTING_AREA_CONSISTENT), &
      choice_t('given', WEIGHTING_GIVEN)]
   !> The words a user may write: all but given
   type(choice_t), parameter :: weighting_choices(*) = weighting_names(1:3)

   !> Sensor kinds (&sensor type; src/mbs/sensors.f90 has their values and units). The rotor
   !> kinds have no &sensor word: the engine adds them (rotor_sensor_choices names them).
   integer, parameter :: SENSOR_POSITION = 1, SENSOR_VELOCITY = 2, SENSOR_ACCELERATION = 3, &
      SENSOR_ORIENTATION = 4, SENSOR_ANGULAR_VELOCITY = 5, SENSOR_JOINT_COORDINATE = 6, &
      SENSOR_REACTION = 7, SENSOR_ENERGY = 8, SENSOR_NODE_DISPLACEMENT = 9, &
      SENSOR_NODE_POSITION = 10, SENSOR_SPRING = 11, SENSOR_DRIVER = 12, &
      SENSOR_TORSION_SPRING = 13, SENSOR_BUSHING = 14, SENSOR_ROTOR_ANGLE = 15, &
      SENSOR_ROTOR_SPEED = 16
   type(choice_t), parameter :: sensor_choices(*) = [choice_t('position', SENSOR_POSITION), &
      choice_t('velocity', SENSOR_VELOCITY), choice_t('acceleration', SENSOR_ACCELERATION), &
      choice_t('orientation', SENSOR_ORIENTATION), &
      choice_t('angular_velocity', SENSOR_ANGULAR_VELOCITY), &
      choice_t('joint_coordinate', SENSOR_JOINT_COORDINATE), &
      choice_t('reaction', SENSOR_REACTION), choice_t('energy', SENSOR_ENERGY), &
      choice_t('node_displacement', SENSOR_NODE_DISPLACEMENT), &
      choice_t('node_position', SENSOR_NODE_POSITION), choice_t('spring', SENSOR_SPRING), &
      choice_t('driver', SENSOR_DRIVER), choice_t('torsion_spring', SENSOR_TORSION_SPRING), &
      choice_t('bushing', SENSOR_BUSHING)]
   type(choice_t), parameter :: rotor_sensor_choices(*) = [ &
      choice_t('rotor_angle', SENSOR_ROTOR_ANGLE), choice_t('rotor_speed', SENSOR_ROTOR_SPEED)]

   !> Time laws g(t) (&driver law, &load law; src/mbs/time_function.f90 evaluates them)
   integer, parameter :: TIME_CONSTANT = 1, TIME_CONSTANT_SPEED = 2, TIME_RAMP = 3, &
      TIME_SMOOTH_STEP = 4, TIME_TABLE = 5
   type(choice_t), parameter :: time_law_choices(*) = [choice_t('constant', TIME_CONSTANT), &
      choice_t('constant_speed', TIME_CONSTANT_SPEED), choice_t('ramp', TIME_RAMP), &
      choice_t('smooth_step', TIME_SMOOTH_STEP), choice_t('table', TIME_TABLE)]

   !> Between the points of a table law (&driver, &load interpolation): straight lines or a
   !> cubic spline (src/mbs/time_function.f90)
   integer, parameter :: INTERPOLATION_LINEAR = 1, INTERPOLATION_CUBIC = 2
   type(choice_t), parameter :: interpolation_choices(*) = [ &
      choice_t('linear', INTERPOLATION_LINEAR), choice_t('cubic', INTERPOLATION_CUBIC)]

   !> Outside the times of a table law (&driver, &load beyond): the end values held, or the
   !> table repeated with its period (src/mbs/time_function.f90)
   integer, parameter :: BEYOND_HOLD = 1, BEYOND_PERIODIC = 2
   type(choice_t), parameter :: beyond_choices(*) = [choice_t('hold', BEYOND_HOLD), &
      choice_t('periodic', BEYOND_PERIODIC)]

contains

   !> The words of a table, in table order, as a ', '-separated list (key specs, messages).
   pure function choice_words(table) result(list)
      type(choice_t), intent(in) :: table(:)
      character(len=:), allocatable :: list
      list = join_words(table%word, ', ')
   end function choice_words

   !> The row of `word` (any case, blanks around it ignored) in the table; 0 when it holds none.
   pure integer function choice_position(table, word) result(position)
      type(choice_t), intent(in) :: table(:)
      character(len=*), intent(in) :: word
      integer :: k
      position = 0
      do k = 1, size(table)
         if (to_lower(trim(table(k)%word)) == to_lower(trim(adjustl(word)))) then
            position = k
            return
         end if
      end do
   end function choice_position

   !> The kind of `word` (any case, blanks around it ignored) in the table; 0 when it holds none.
   pure integer function choice_kind_of(table, word) result(kind)
      type(choice_t), intent(in) :: table(:)
      character(len=*), intent(in) :: word
      associate (position => choice_position(table, word))
         kind = 0
         if (position > 0) kind = table(position)%kind
      end associate
   end function choice_kind_of

   !> The word of kind `kind` (`missing`, default 'unknown', for a value no row holds).
   pure function choice_name(table, kind, missing) result(name)
      type(choice_t), intent(in) :: table(:)
      integer, intent(in) :: kind
      character(len=*), intent(in), optional :: missing
      character(len=:), allocatable :: name
      integer :: k
      do k = 1, size(table)
         if (table(k)%kind == kind) then
            name = trim(table(k)%word)
            return
         end if
      end do
      name = 'unknown'
      if (present(missing)) name = missing
   end function choice_name

   !> The kind of `word` in `table`. An unknown word (a case built in memory: the readers' key
   !> specs refuse one in a file) is an FFRF_INPUT_ERROR naming the key and the table's words:
   !> `key = "word" is not <what>; use one of a, b, c`.
   subroutine choice_kind(table, key, what, word, kind, error)
      type(choice_t), intent(in) :: table(:)
      !> The key (with its group or owner) and what a word of the table is, for the message
      character(len=*), intent(in) :: key, what
      character(len=*), intent(in) :: word
      integer, intent(out) :: kind
      type(error_t), allocatable, intent(out) :: error
      integer :: position
      kind = 0
      position = choice_position(table, word)
      if (position == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, key // ' = "' // trim(word) // &
            '" is not ' // what // '; use one of ' // choice_words(table))
         return
      end if
      kind = table(position)%kind
   end subroutine choice_kind

   !> The kinds of a list of words of `table` (separated by blanks or commas, any case), in the
   !> order given, a repeated word kept once; an unknown word is choice_kind's error.
   subroutine choice_kinds(table, key, what, words, kinds, error)
      type(choice_t), intent(in) :: table(:)
      !> The key (with its group or owner) and what a word of the table is, for the message
      character(len=*), intent(in) :: key, what
      !> The list, e.g. 'xdmf'
      character(len=*), intent(in) :: words
      integer, allocatable, intent(out) :: kinds(:)
      type(error_t), allocatable, intent(out) :: error
      character(len=len(words)) :: text
      integer :: first, last, kind, n
      integer, allocatable :: grown(:)
      text = words
      do first = 1, len(text)
         if (text(first:first) == ',') text(first:first) = ' '
      end do
      allocate (kinds(0))
      last = 0
      do
         first = verify(text(last + 1:), ' ')
         if (first == 0) exit
         first = first + last
         last = index(text(first:), ' ') + first - 2
         if (last < first) last = len(text)
         call choice_kind(table, key, what, text(first:last), kind, error)
         if (allocated(error)) return
         if (any(kinds == kind)) cycle
         n = size(kinds)
         allocate (grown(n + 1))
         grown(:n) = kinds
         grown(n + 1) = kind
         call move_alloc(grown, kinds)
      end do
   end subroutine choice_kinds

end module ffrf_core_choices
