!> Shared helpers of the namelist readers: the error text of a failed namelist read (a fallback:
!> ffrf_input_nml_source checks groups, keys and types before any namelist read), the keys of a
!> group as its key spec lists them, and the rule every named repeatable group shares.
module ffrf_input_nml_common
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str, join_words
   use ffrf_input_nml_source, only: nml_source_t
   implicit none
   private
   public :: namelist_read_error, group_keys, check_unique_name, read_status

contains

   !> "&interface #2: Cannot match namelist object name rcc (keys: body, name, ...)".
   subroutine namelist_read_error(error, group, occurrence, message, keys)
      type(error_t), allocatable, intent(out) :: error
      !> Group name without '&'
      character(len=*), intent(in) :: group
      !> Which occurrence of a repeated group (0 for a single group)
      integer, intent(in) :: occurrence
      !> The iomsg of the read
      character(len=*), intent(in) :: message
      !> The valid keys of the group, for the hint
      character(len=*), intent(in) :: keys
      character(len=:), allocatable :: where
      where = '&' // group
      if (occurrence > 0) where = where // ' #' // to_str(occurrence)
      call fatal_error(error, FFRF_INPUT_ERROR, where // ': ' // trim(message) // &
         ' (valid keys: ' // keys // ')')
   end subroutine namelist_read_error

   !> "a, b, c": the keys of group `group` (without '&') in the key specs `src` was checked
   !> against, in their order (the hint of namelist_read_error); '' for a group it does not know.
   function group_keys(src, group) result(keys)
      type(nml_source_t), intent(in) :: src
      character(len=*), intent(in) :: group
      character(len=:), allocatable :: keys
      integer :: g
      g = findloc(src%groups%name, group, dim=1)
      if (g == 0) then
         keys = ''
      else
         keys = join_words(pack(src%groups(g)%keys%name, src%groups(g)%keys%in_namelist), ', ')
      end if
   end function group_keys

   !> After the namelist read of occurrence `occurrence` of `group` (0: a single group):
   !> namelist_read_error when its status `stat` (iomsg `message`) is not 0, with the group's
   !> keys from the key specs as the hint.
   subroutine read_status(src, group, occurrence, stat, message, error)
      type(nml_source_t), intent(in) :: src
      character(len=*), intent(in) :: group, message
      integer, intent(in) :: occurrence, stat
      type(error_t), allocatable, intent(out) :: error
      if (stat /= 0) call namelist_read_error(error, group, occurrence, message, &
         group_keys(src, group))
   end subroutine read_status

   !> The rule of every named repeatable group (occurrence k of `group`, `names` those of the
   !> occurrences before it): a name, and one no other occurrence has.
   subroutine check_unique_name(src, group, k, name, names, error)
      type(nml_source_t), intent(in) :: src
      character(len=*), intent(in) :: group, name
      integer, intent(in) :: k
      character(len=*), intent(in) :: names(:)
      type(error_t), allocatable, intent(out) :: error
      if (len_trim(name) == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, src%where(group, k, '') // &
            ': name is missing')
      else if (any(names == name)) then
         call fatal_error(error, FFRF_INPUT_ERROR, src%where(group, k, 'name') // &
            ': the name is used twice; ' // group // ' names must be unique')
      end if
   end subroutine check_unique_name

end module ffrf_input_nml_common
