!> Namelist group &interface (repeatable): a physical surface of a body reduced to a virtual node.
!>   body          body name (&body name), required, <= 64 characters
!>   name          physical surface name in the body's mesh, required, <= 64 characters
!>   mpc           'RBE3' (default, interpolation) or 'RBE2' (rigid), any case
!>   weighting     RBE3 node weights: 'uniform' (default, as Nastran), 'area' (tributary areas)
!>                 or 'area_consistent' (int N_i dA; docs/input.md "RBE3 weights")
!>   virtual_node  'centroid' (default: area centroid of the face) or 'position'
!>   position      virtual node position [m] when virtual_node = 'position': 3 finite reals in
!>                 [-1e4, 1e4] m
!>   rc            reference conditions: forbidden virtual-node dofs, 'Tx Ty Tz Rx Ry Rz'
!>                 or Nastran component digits '123456'; each dof at most once
module ffrf_input_nml_interface
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, add_context, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str, to_lower
   use ffrf_core_choices, only: choice_words
   use ffrf_input_interface, only: interface_input_t, parse_dofs, mpc_choices, &
      weighting_choices, virtual_node_choices
   use ffrf_input_nml_common, only: read_status
   use ffrf_input_nml_source, only: key_spec_t, real_key, string_key, choice_key, nml_source_t
   implicit none
   private
   public :: read_interface_groups, interface_keys

contains

   !> Keys of &interface, their types and ranges (module header).
   function interface_keys() result(keys)
      type(key_spec_t), allocatable :: keys(:)
      keys = [string_key('body', 64), string_key('name', 64), &
         choice_key('mpc', 8, choice_words(mpc_choices)), &
         choice_key('weighting', 16, choice_words(weighting_choices)), &
         choice_key('virtual_node', 16, choice_words(virtual_node_choices)), &
         real_key('position', -1.0e4_dp, 1.0e4_dp, 'm', count=3), string_key('rc', 64)]
   end function interface_keys

   !> Read every &interface group and check each choice.
   subroutine read_interface_groups(unit, src, interfaces, error)
      integer, intent(in) :: unit
      !> The checked case text (FILE:LINE of the keys)
      type(nml_source_t), intent(in) :: src
      type(interface_input_t), allocatable, intent(out) :: interfaces(:)
      type(error_t), allocatable, intent(out) :: error
      character(len=512) :: msg
      integer :: stat, k
      allocate (interfaces(src%count('interface')))
      rewind (unit)
      do k = 1, size(interfaces)
         associate (f => interfaces(k))
            call read_interface(f%body, f%name, f%mpc, f%weighting, f%virtual_node, f%position, &
               f%rc)
            call read_status(src, 'interface', k, stat, msg, error)
            if (allocated(error)) return
            if (len_trim(f%body) == 0 .or. len_trim(f%name) == 0) then
               call fatal_error(error, FFRF_INPUT_ERROR, src%where('interface', k, '') // &
                  ': body and name (the physical surface) are required')
               return
            end if
            ! mpc, weighting and virtual_node were checked by the key spec (interface_keys)
            call parse_dofs(f%rc, f%rc_dofs, error)
         end associate
         if (allocated(error)) then
            call add_context(error, src%where('interface', k, 'rc'))
            return
         end if
      end do
   contains
      !> The namelist read of &interface k into its fields (absent keys keep their defaults).
      subroutine read_interface(body, name, mpc, weighting, virtual_node, position, rc)
         character(len=*), intent(inout) :: body, name, mpc, weighting, virtual_node, rc
         real(dp), intent(inout) :: position(3)
         namelist /interface/ body, name, mpc, weighting, virtual_node, position, rc
         read (unit, nml=interface, iostat=stat, iomsg=msg)
      end subroutine read_interface
   end subroutine read_interface_groups

end module ffrf_input_nml_interface
