!> The &interface group as read (strings, as the user wrote them) and the parser of its rc key.
!> The model (ffrf_model_specs) turns it into an interface_spec_t of ffrf_mpc_interface.
module ffrf_input_interface
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_lower
   use ffrf_core_choices, only: choice_t, mpc_choices, weighting_choices
   use ffrf_mpc_interface, only: DOF_NAMES, WEIGHTING_UNIFORM, VIRTUAL_NODE_CENTROID, &
      VIRTUAL_NODE_POSITION
   implicit none
   private
   public :: interface_input_t, parse_dofs
   public :: mpc_choices, weighting_choices, virtual_node_choices

   !> The &interface choice tables: words (any case), kinds of ffrf_mpc_interface, names in
   !> messages (docs/developer.md "One table per choice"); the key specs (interface_keys) take
   !> their words from here, the model (ffrf_model_specs) their kinds; mpc_choices and
   !> weighting_choices are those of ffrf_core_choices (the numerics name their kinds with them)
   type(choice_t), parameter :: virtual_node_choices(*) = [ &
      choice_t('centroid', VIRTUAL_NODE_CENTROID), choice_t('position', VIRTUAL_NODE_POSITION)]

   !> One interface as the user describes it (namelist group &interface).
   type :: interface_input_t
      !> Body the interface belongs to
      character(len=64) :: body = ''
      !> Physical surface name in the body's mesh
      character(len=64) :: name = ''
      !> 'RBE2' or 'RBE3'
      character(len=8) :: mpc = 'RBE3'
      !> RBE3 weights: 'uniform' (Nastran's default, every node weight 1), 'area', 'area_consistent'
      character(len=16) :: weighting = 'uniform'
      !> Virtual node: 'centroid' (area centroid of the face) or 'position'
      character(len=16) :: virtual_node = 'centroid'
      !> Virtual node position when virtual_node = 'position' (m, body mesh frame)
      real(dp) :: position(3) = 0.0_dp
      !> Reference conditions: forbidden virtual-node dofs ('Tx Ty Tz Rz', or Nastran '1234')
      character(len=64) :: rc = ''
      !> rc parsed by the reader (parse_dofs), Tx..Rz; not a namelist key. rc is parsed there
      !> once, where its errors can name FILE:LINE; the model takes these flags.
      logical :: rc_dofs(6) = .false.
   end type interface_input_t

contains

   !> Parse forbidden dofs: names Tx Ty Tz Rx Ry Rz (any case, separated by blanks or commas) or
   !> Nastran component digits ('123456'); '', 'none' or '-' mean no reference condition. A dof
   !> named twice ('Tx Tx', '113') is an error: it is a slip, not a stronger condition.
   subroutine parse_dofs(text, dofs, error)
      !> Text to parse
      character(len=*), intent(in) :: text
      !> Selected dofs, Tx..Rz
      logical, intent(out) :: dofs(6)
      type(error_t), allocatable, intent(out) :: error
      character(len=len(text)) :: words
      integer :: i, start, finish, d
      character(len=:), allocatable :: token
      dofs = .false.
      words = to_lower(text)
      do i = 1, len(words)
         if (words(i:i) == ',' .or. words(i:i) == ';') words(i:i) = ' '
      end do
      start = 1
      do
         do while (start <= len(words))
            if (words(start:start) /= ' ') exit
            start = start + 1
         end do
         if (start > len(words)) exit
         finish = index(words(start:), ' ') + start - 2
         if (finish < start) finish = len(words)
         token = words(start:finish)
         start = finish + 1
         if (token == 'none' .or. token == '-') cycle
         d = 0
         do i = 1, 6
            if (token == to_lower(DOF_NAMES(i))) d = i
         end do
         if (d > 0) then
            if (dofs(d)) then
               call fatal_error(error, FFRF_INPUT_ERROR, 'dof ' // DOF_NAMES(d) // &
                  ' is given twice; name each dof once (Tx Ty Tz Rx Ry Rz or digits 1-6)')
               return
            end if
            dofs(d) = .true.
         else if (verify(token, '123456') == 0) then
            do i = 1, len(token)
               d = iachar(token(i:i)) - iachar('0')
               if (dofs(d)) then
                  call fatal_error(error, FFRF_INPUT_ERROR, 'dof ' // DOF_NAMES(d) // ' (' // &
                     token(i:i) // ') is given twice; name each dof once (Tx Ty Tz Rx Ry Rz ' // &
                     'or digits 1-6)')
                  return
               end if
               dofs(d) = .true.
            end do
         else
            call fatal_error(error, FFRF_INPUT_ERROR, 'unknown dof "' // token // &
               '"; use Tx Ty Tz Rx Ry Rz or Nastran digits 1-6')
            return
         end if
      end do
   end subroutine parse_dofs

end module ffrf_input_interface
