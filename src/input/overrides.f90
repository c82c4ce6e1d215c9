!> Command-line overrides of a case's keys: `GROUP.KEY=VALUE` for a single group (&run, &modes,
!> &mechanism, ...) and `GROUP[NAME].KEY=VALUE` for a repeatable group chosen by its name key
!> (`interface[B2].rc=Tx`, `body[crank].mesh_file=crank_lc4.msh`). They are parsed here and
!> injected into the checked case text (ffrf_input_nml_source set) before the groups are read,
!> so that a value goes through the checks of the namelist and a bad one gets its message, with
!> the override's origin (`--set interface[B2].rc`, `table.csv:3 modes.num_modes`) in place of
!> FILE:LINE. VALUE is written as in the namelist (`4`, `1, 0, 0`, `.true.`, `'Tx Ty'`); a
!> string may also be given without quotes (`rc=Tx Ty`: the whole VALUE is the string).
module ffrf_input_overrides
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_lower
   use ffrf_input_nml_source, only: nml_source_t
   implicit none
   private
   public :: override_t, parse_override, parse_override_key, apply_overrides, overrides_echo
   public :: overrides_set

   !> One `key = value` set from outside the case file.
   type :: override_t
      !> Group (as written, e.g. 'interface'), name of the chosen occurrence ('' for a single
      !> group), key
      character(len=:), allocatable :: group, name, key
      !> Value text (namelist syntax, or a bare string)
      character(len=:), allocatable :: value
      !> Where it came from, for messages and the echo: "--set interface[B2].rc"
      character(len=:), allocatable :: origin
   end type override_t

   character(len=*), parameter :: LETTERS = 'abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ'
   character(len=*), parameter :: NAME_CHARS = LETTERS // '0123456789_'

contains

   !> `GROUP.KEY` or `GROUP[NAME].KEY` into ov's group, name and key; problem /= '' when the text
   !> has another form.
   subroutine parse_override_key(text, ov, problem)
      character(len=*), intent(in) :: text
      type(override_t), intent(inout) :: ov
      character(len=:), allocatable, intent(out) :: problem
      integer :: open_bracket, close_bracket, dot
      problem = 'not GROUP.KEY or GROUP[NAME].KEY (e.g. modes.num_modes, interface[B2].rc)'
      open_bracket = index(text, '[')
      if (open_bracket > 0) then
         close_bracket = index(text, ']', back=.true.)
         if (close_bracket < open_bracket + 2) return
         ov%group = text(:open_bracket - 1)
         ov%name = text(open_bracket + 1:close_bracket - 1)
         if (close_bracket == len(text)) return
         if (text(close_bracket + 1:close_bracket + 1) /= '.') return
         ov%key = text(close_bracket + 2:)
      else
         dot = index(text, '.')
         if (dot == 0) return
         ov%group = text(:dot - 1)
         ov%name = ''
         ov%key = text(dot + 1:)
      end if
      if (.not. is_identifier(ov%group) .or. .not. is_identifier(ov%key)) return
      problem = ''
   end subroutine parse_override_key

   !> `GROUP[NAME].KEY=VALUE` (text of a --set); origin "--set GROUP[NAME].KEY".
   subroutine parse_override(text, ov, error)
      character(len=*), intent(in) :: text
      type(override_t), intent(out) :: ov
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: problem
      integer :: equals
      equals = index(text, '=')
      if (equals == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, '--set ' // text // ': no "="; write ' // &
            'GROUP.KEY=VALUE or GROUP[NAME].KEY=VALUE (e.g. modes.num_modes=12, ' // &
            'interface[B2].rc=Tx)')
         return
      end if
      call parse_override_key(trim(adjustl(text(:equals - 1))), ov, problem)
      if (len(problem) > 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, '--set ' // text // ': ' // problem // &
            ' before the "="')
         return
      end if
      ov%value = trim(adjustl(text(equals + 1:)))
      ov%origin = '--set ' // trim(adjustl(text(:equals - 1)))
   end subroutine parse_override

   !> Set each override into the checked case text, in order (a later one wins).
   subroutine apply_overrides(src, overrides, error)
      type(nml_source_t), intent(inout) :: src
      type(override_t), intent(in) :: overrides(:)
      type(error_t), allocatable, intent(out) :: error
      integer :: k
      do k = 1, size(overrides)
         associate (ov => overrides(k))
            call src%set(ov%group, ov%name, ov%key, ov%value, ov%origin, error)
         end associate
         if (allocated(error)) return
      end do
   end subroutine apply_overrides

   !> The overrides as namelist comment lines ("! --set modes.num_modes = 12"), '' for none:
   !> appended to the echo of the input, so that a results file says what produced it.
   function overrides_echo(overrides) result(text)
      type(override_t), intent(in) :: overrides(:)
      character(len=:), allocatable :: text
      integer :: k, n, pos
      ! sized first, then filled: linear in the number of overrides (not text = text // ...)
      n = 0
      do k = 1, size(overrides)
         n = n + len(line_of(overrides(k)))
      end do
      allocate (character(len=n) :: text)
      pos = 0
      do k = 1, size(overrides)
         n = len(line_of(overrides(k)))
         text(pos + 1:pos + n) = line_of(overrides(k))
         pos = pos + n
      end do
   contains
      pure function line_of(ov) result(line)
         type(override_t), intent(in) :: ov
         character(len=:), allocatable :: line
         line = '! ' // ov%origin // ' = ' // ov%value // new_line('a')
      end function line_of
   end function overrides_echo

   !> .true. when an override sets `key` of the single group `group`.
   pure logical function overrides_set(overrides, group, key) result(found)
      type(override_t), intent(in) :: overrides(:)
      character(len=*), intent(in) :: group, key
      integer :: k
      found = .false.
      do k = 1, size(overrides)
         if (to_lower(overrides(k)%group) == group .and. to_lower(overrides(k)%key) == key) &
            found = .true.
      end do
   end function overrides_set

   pure logical function is_identifier(text) result(ok)
      character(len=*), intent(in) :: text
      ok = len(text) > 0
      if (ok) ok = verify(text(1:1), LETTERS) == 0 .and. verify(text, NAME_CHARS) == 0
   end function is_identifier

end module ffrf_input_overrides
