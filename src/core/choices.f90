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
   public :: choice_t, choice_words, choice_position, choice_name, choice_kind

   !> One row of a choice table: the word (any case in the input) and its kind constant
   type :: choice_t
      character(len=16) :: word = ''
      integer :: kind = 0
   end type choice_t

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

end module ffrf_core_choices
