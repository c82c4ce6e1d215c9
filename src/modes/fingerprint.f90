!> The fingerprint of a body's modes: what they depend on, so that modes stored in a results file
!> can be reused by a later run only when they are the modes that run would compute
!> (&body modes_file, docs/mode_reuse.md). Four components, each a list of `label=value`
!> entries and a hash of them (ffrf_core_hash):
!>
!> - mesh: node and element counts and the hashes of the body's node coordinates (bitwise) and
!>   connectivity, after the body is cut from its mesh file (so the volumes count, the file's
!>   formatting and other bodies in it do not);
!> - material: Young's modulus, Poisson's ratio, density (exact decimal forms);
!> - interfaces: their order, and per interface its MPC, RBE3 weighting, reference conditions,
!>   virtual-node position (exact), node count and the hashes of its nodes and weights;
!> - modes: number of modes, basis, formulation, shift, ARPACK tolerance and Lanczos basis size,
!>   the upper bound max_frequency_hz when set
!>   (each changes the stored vectors at least in their last bits), and the candidates kept
!>   when the automatic model kept a subset.
!>
!> The total hash combines the four. Comparing two fingerprints names the first component that
!> differs and its first differing entry, e.g. `the interfaces differ (B2: rc 'Tx Ty Tz' here,
!> 'Tx Ty' in the file)`.
module ffrf_modes_fingerprint
   use ffrf_core_kinds, only: dp, ip
   use ffrf_core_hash, only: hash_t
   use ffrf_core_strings, only: to_str
   use ffrf_mesh_mesh, only: mesh_t
   use ffrf_core_choices, only: choice_name, weighting_names
   use ffrf_mpc_interface, only: interface_t, mpc_name, dofs_text
   use ffrf_mpc_reduction, only: formulation_name
   use ffrf_modes_input, only: body_spec_t, modes_spec_t, basis_name
   implicit none
   private
   public :: modes_fingerprint_t, make_fingerprint, set_kept_modes, set_joint_projection, &
      compare_fingerprints, &
      COMPONENT_NAMES, NUM_COMPONENTS, ENTRY_LENGTH, exact_text, label_of, value_of

   integer, parameter :: NUM_COMPONENTS = 4
   !> Length of one `label=value` entry
   integer, parameter :: ENTRY_LENGTH = 160
   !> Component names, in the order of modes_fingerprint_t%entries
   character(len=10), parameter :: COMPONENT_NAMES(NUM_COMPONENTS) = [character(len=10) :: &
      'mesh', 'material', 'interfaces', 'modes']
   !> Labels of the modes entries that a reuse without num_modes takes from the file (the
   !> automatic model's count, selection and joint projection)
   character(len=*), parameter :: COUNT_LABELS(3) = [character(len=9) :: 'num_modes', 'kept', &
      'joints']

   !> One list of entries.
   type :: entry_list_t
      character(len=ENTRY_LENGTH), allocatable :: entries(:)
   end type entry_list_t

   !> The fingerprint of a body's modes (module header); empty (not set) when no entries.
   type :: modes_fingerprint_t
      !> Entries of mesh, material, interfaces, modes (COMPONENT_NAMES)
      type(entry_list_t) :: components(NUM_COMPONENTS)
   contains
      !> .true. once made (or read)
      procedure :: is_set => fingerprint_is_set
      !> Hash of component k (16 hex digits)
      procedure :: component_hash => fingerprint_component_hash
      !> Hash of the four component hashes
      procedure :: total_hash => fingerprint_total_hash
   end type modes_fingerprint_t

contains

   !> The fingerprint of modes computed on `mesh` (the body as cut from its mesh file) with
   !> `interfaces`, material `body` and `modes` (num_modes: the number of modes asked, the
   !> flexible modes of rc_normal, the fixed-interface modes of craig_bampton).
   subroutine make_fingerprint(mesh, interfaces, body, modes, num_modes, fingerprint)
      type(mesh_t), intent(in) :: mesh
      type(interface_t), intent(in) :: interfaces(:)
      type(body_spec_t), intent(in) :: body
      type(modes_spec_t), intent(in) :: modes
      integer, intent(in) :: num_modes
      type(modes_fingerprint_t), intent(out) :: fingerprint
      type(hash_t) :: h
      character(len=:), allocatable :: order, prefix
      integer :: k

      associate (c => fingerprint%components(1))
         allocate (c%entries(0))
         call add(c, 'nodes', to_str(mesh%num_nodes))
         call add(c, 'elements', to_str(mesh%num_tets()) // ' Tet' // to_str(mesh%nodes_per_tet))
         h = hash_t()
         call h%add_reals_2d(mesh%xyz)
         call add(c, 'node coordinates', 'hash ' // h%hex())
         h = hash_t()
         call h%add_ints_2d(mesh%tets)
         call add(c, 'connectivity', 'hash ' // h%hex())
      end associate
      associate (c => fingerprint%components(2))
         allocate (c%entries(0))
         call add(c, 'young', exact_text(body%young) // ' Pa')
         call add(c, 'poisson', exact_text(body%poisson))
         call add(c, 'density', exact_text(body%density) // ' kg/m^3')
      end associate
      associate (c => fingerprint%components(3))
         allocate (c%entries(0))
         order = ''
         do k = 1, size(interfaces)
            order = order // ' ' // interfaces(k)%name
         end do
         call add(c, 'order', trim(adjustl(order)))
         do k = 1, size(interfaces)
            associate (f => interfaces(k))
               prefix = f%name // ': '
               call add(c, prefix // 'mpc', trim(mpc_name(f%mpc)))
               call add(c, prefix // 'weighting', choice_name(weighting_names, f%weighting, &
                  to_str(f%weighting)))
               call add(c, prefix // 'rc', dofs_text(f%rc, none='none'))
               call add(c, prefix // 'virtual node', '(' // exact_text(f%virtual_xyz(1)) // &
                  ', ' // exact_text(f%virtual_xyz(2)) // ', ' // &
                  exact_text(f%virtual_xyz(3)) // ') m')
               call add(c, prefix // 'nodes', to_str(size(f%nodes)))
               h = hash_t()
               call h%add_ints(f%nodes)
               call add(c, prefix // 'node set', 'hash ' // h%hex())
               h = hash_t()
               call h%add_reals(f%weights)
               call add(c, prefix // 'weights', 'hash ' // h%hex())
            end associate
         end do
      end associate
      associate (c => fingerprint%components(4))
         allocate (c%entries(0))
         call add(c, 'num_modes', to_str(num_modes))
         call add(c, 'basis', basis_name(modes%basis))
         call add(c, 'formulation', formulation_name(modes%formulation))
         if (modes%shift_hz == 0.0_dp) then
            call add(c, 'shift_hz', '0 (automatic)')
         else
            call add(c, 'shift_hz', exact_text(modes%shift_hz))
         end if
         call add(c, 'tolerance', exact_text(modes%tolerance))
         call add(c, 'lanczos_vectors', to_str(modes%lanczos_vectors))
         ! only when set: the fingerprints of modes computed without it stay as they were
         if (modes%max_frequency_hz > 0.0_dp) call add(c, 'max_frequency_hz', &
            exact_text(modes%max_frequency_hz))
      end associate
   end subroutine make_fingerprint

   !> Record that only the modes `kept` of `num_candidates` computed ones are stored (the
   !> automatic model's selection): num_modes becomes size(kept) and an entry `kept` lists them.
   subroutine set_kept_modes(fingerprint, kept, num_candidates)
      type(modes_fingerprint_t), intent(inout) :: fingerprint
      integer, intent(in) :: kept(:), num_candidates
      character(len=:), allocatable :: list
      integer :: k
      if (.not. fingerprint%is_set()) return
      associate (c => fingerprint%components(4))
         k = entry_index(c, 'num_modes')
         if (k > 0) c%entries(k) = 'num_modes=' // to_str(size(kept))
         list = ''
         do k = 1, size(kept)
            list = list // ' ' // to_str(kept(k))
         end do
         call add(c, 'kept', trim(adjustl(list)) // ' of ' // to_str(num_candidates) // &
            ' candidates')
      end associate
   end subroutine set_kept_modes

   !> Record that the stored modes are combinations of the computed ones (the automatic model's
   !> modes free of the joint locks, ffrf_app_joint_free_modes): an entry `joints` says how.
   subroutine set_joint_projection(fingerprint, text)
      type(modes_fingerprint_t), intent(inout) :: fingerprint
      character(len=*), intent(in) :: text
      if (.not. fingerprint%is_set()) return
      call add(fingerprint%components(4), 'joints', text)
   end subroutine set_joint_projection

   !> Compare the fingerprint of this run (`here`) with a stored one (`there`). `same` when
   !> every component agrees; otherwise `difference` says what differs, e.g. "the interfaces
   !> differ (B2: rc 'Tx Ty Tz' here, 'Tx Ty' in the file)". With take_count, the number of
   !> modes (and the automatic model's selection) is taken from `there` and not compared.
   subroutine compare_fingerprints(here, there, take_count, same, difference)
      type(modes_fingerprint_t), intent(in) :: here, there
      logical, intent(in) :: take_count
      logical, intent(out) :: same
      character(len=:), allocatable, intent(out) :: difference
      type(entry_list_t) :: a, b
      character(len=:), allocatable :: label
      integer :: c, k, j
      same = .true.
      difference = ''
      do c = 1, NUM_COMPONENTS
         a = here%components(c)
         b = there%components(c)
         if (c == 4 .and. take_count) then
            a = without(a, COUNT_LABELS)
            b = without(b, COUNT_LABELS)
         end if
         if (size(a%entries) == size(b%entries)) then
            if (all(a%entries == b%entries)) cycle
         end if
         same = .false.
         select case (c)
         case (1)
            difference = 'the mesh differs'
         case (2)
            difference = 'the material differs'
         case (3)
            difference = 'the interfaces differ'
         case default
            difference = 'the modes specification differs'
         end select
         ! the first entry of `here` that `there` has otherwise (or not at all)
         do k = 1, size(a%entries)
            label = label_of(a%entries(k))
            j = entry_index(b, label)
            if (j == 0) then
               difference = difference // ' (' // label // ' ''' // value_of(a%entries(k)) // &
                  ''' here, none in the file)'
               return
            end if
            if (a%entries(k) /= b%entries(j)) then
               difference = difference // ' (' // label // ' ''' // value_of(a%entries(k)) // &
                  ''' here, ''' // value_of(b%entries(j)) // ''' in the file)'
               return
            end if
         end do
         do k = 1, size(b%entries)
            label = label_of(b%entries(k))
            if (entry_index(a, label) == 0) then
               difference = difference // ' (' // label // ': none here, ''' // &
                  value_of(b%entries(k)) // ''' in the file)'
               return
            end if
         end do
         return
      end do
   end subroutine compare_fingerprints

   pure logical function fingerprint_is_set(self)
      class(modes_fingerprint_t), intent(in) :: self
      fingerprint_is_set = allocated(self%components(NUM_COMPONENTS)%entries)
   end function fingerprint_is_set

   !> Hash of the entries of component k.
   function fingerprint_component_hash(self, k) result(hex)
      class(modes_fingerprint_t), intent(in) :: self
      integer, intent(in) :: k
      character(len=16) :: hex
      type(hash_t) :: h
      integer :: i
      h = hash_t()
      call h%add_text(trim(COMPONENT_NAMES(k)))
      if (allocated(self%components(k)%entries)) then
         do i = 1, size(self%components(k)%entries)
            call h%add_text(trim(self%components(k)%entries(i)))
         end do
      end if
      hex = h%hex()
   end function fingerprint_component_hash

   !> Hash of the component hashes.
   function fingerprint_total_hash(self) result(hex)
      class(modes_fingerprint_t), intent(in) :: self
      character(len=16) :: hex
      type(hash_t) :: h
      integer :: k
      h = hash_t()
      do k = 1, NUM_COMPONENTS
         call h%add_text(self%component_hash(k))
      end do
      hex = h%hex()
   end function fingerprint_total_hash

   !> The shortest decimal form of x that reads back as x (up to 17 significant digits).
   function exact_text(x) result(text)
      real(dp), intent(in) :: x
      character(len=:), allocatable :: text
      real(dp) :: back
      integer :: digits, stat
      do digits = 1, 17
         text = to_str(x, digits)
         read (text, *, iostat=stat) back
         if (stat == 0 .and. back == x) return
      end do
   end function exact_text

   subroutine add(list, label, value)
      type(entry_list_t), intent(inout) :: list
      character(len=*), intent(in) :: label, value
      list%entries = [character(len=ENTRY_LENGTH) :: list%entries, label // '=' // value]
   end subroutine add

   !> The label of a `label=value` entry.
   pure function label_of(entry) result(label)
      character(len=*), intent(in) :: entry
      character(len=:), allocatable :: label
      integer :: k
      k = index(entry, '=')
      label = entry(:max(k - 1, 0))
   end function label_of

   !> The value of a `label=value` entry.
   pure function value_of(entry) result(value)
      character(len=*), intent(in) :: entry
      character(len=:), allocatable :: value
      value = trim(entry(index(entry, '=') + 1:))
   end function value_of

   !> Index of the entry with `label` (0: none).
   pure integer function entry_index(list, label)
      type(entry_list_t), intent(in) :: list
      character(len=*), intent(in) :: label
      integer :: k
      entry_index = 0
      do k = 1, size(list%entries)
         if (label_of(list%entries(k)) == label) then
            entry_index = k
            return
         end if
      end do
   end function entry_index

   !> The list without the entries of the given labels.
   pure function without(list, labels) result(kept)
      type(entry_list_t), intent(in) :: list
      character(len=*), intent(in) :: labels(:)
      type(entry_list_t) :: kept
      integer :: k
      allocate (kept%entries(0))
      do k = 1, size(list%entries)
         if (any(label_of(list%entries(k)) == labels)) cycle
         kept%entries = [character(len=ENTRY_LENGTH) :: kept%entries, list%entries(k)]
      end do
   end function without

end module ffrf_modes_fingerprint
