!> Prints the readers' key specs, one key a line: `group key choice words...` (the words of a
!> choice key, from its table; nothing more for other keys). check_key_tables.py compares
!> them with the docs' `&group key` tables (docs/developer.md "One table per choice").
program list_keys
   use ffrf_input_nml_source, only: group_spec_t
   use ffrf_input_case, only: case_groups
   implicit none
   type(group_spec_t), allocatable :: groups(:)
   integer :: g, k
   groups = case_groups()
   do g = 1, size(groups)
      do k = 1, size(groups(g)%keys)
         write (*, '(a)') trim(groups(g)%name) // ' ' // trim(groups(g)%keys(k)%name) // ' ' // &
            trim(groups(g)%keys(k)%choices)
      end do
   end do
end program list_keys
