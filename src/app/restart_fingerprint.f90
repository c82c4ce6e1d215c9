!> The restart fingerprint of a mechanism run (docs/restart.md): what the continuation of a run
!> depends on, stored with every restart state (/checkpoint/fingerprint_input and
!> /checkpoint/fingerprint_model) and compared by `--restart`, so that a run continues only the
!> run of the same model. Entries are `label=value` texts:
!>
!> - input entries, one per key of the resolved input echo (ffrf_input_case's case_echo), labelled
!>   like the `--set` overrides (`body[piston].mass`, `integrator.rho_inf`), except the keys of
!>   MAY_CHANGE; every key a group gains is in the fingerprint unless listed there. They are
!>   compared before anything is computed.
!> - model entries, once the model is built: each meshed body's modes fingerprint
!>   (ffrf_modes_fingerprint: the mesh as cut from its file, bitwise, the material and interfaces
!>   in exact decimals, the modes kept), and the integrator's step and rho_inf in exact decimals
!>   (the automatic model chooses the step).
module ffrf_app_restart_fingerprint
   use ffrf_core_kinds, only: dp
   use ffrf_core_hash, only: hash_t
   use ffrf_core_strings, only: to_str
   use ffrf_mesh_mesh, only: mesh_t
   use ffrf_modes_fingerprint, only: modes_fingerprint_t, COMPONENT_NAMES, NUM_COMPONENTS, &
      exact_text, label_of, value_of
   implicit none
   private
   public :: RESTART_ENTRY_LENGTH, MAY_CHANGE, input_entries, model_entries, first_difference, &
      entries_hash

   !> Length of one `label=value` entry
   integer, parameter :: RESTART_ENTRY_LENGTH = 512
   !> The keys that may differ between a run and its continuation (GROUP.KEY): what and where
   !> to write, how much to log, when to stop, the energy watch (it watches, it does not change
   !> the motion), the memory of the modal solver, and the mesh file names (the meshes
   !> themselves are compared by their modes fingerprints).
   character(len=*), parameter :: MAY_CHANGE(*) = [character(len=40) :: &
      'run.title', 'run.output', 'run.mode_shapes_msh', 'run.log_level', 'run.export', &
      'body.mesh_file', 'body.coarse_meshes', 'body.modes_file', &
      'modes.out_of_core', 'modes.ooc_tmpdir', 'modes.memory_limit_mb', &
      'mechanism.label', 'mechanism.progress_interval', 'mechanism.animation_frames', &
      'integrator.t_end', 'integrator.max_steps', 'integrator.checkpoint_steps', &
      'integrator.checkpoint_seconds', 'integrator.energy_watch', &
      'integrator.energy_watch_tolerance', 'integrator.energy_watch_window', &
      'output.compression', 'output.ignore_free_space']

contains

   !> The input entries of a resolved input echo (namelist text, one group per line; comment
   !> lines `!` are skipped).
   function input_entries(echo) result(entries)
      character(len=*), intent(in) :: echo
      character(len=RESTART_ENTRY_LENGTH), allocatable :: entries(:)
      character(len=:), allocatable :: line, group, instance
      character(len=:), allocatable :: keys(:), values(:)
      character(len=64), allocatable :: seen(:)
      integer :: first, last, k, copies
      allocate (entries(0), seen(0))
      first = 1
      do while (first <= len(echo))
         last = index(echo(first:), new_line('a'))
         if (last == 0) then
            last = len(echo)
         else
            last = first + last - 2
         end if
         line = trim(adjustl(echo(first:last)))
         first = last + 2
         if (len(line) < 2) cycle
         if (line(1:1) /= '&') cycle
         call split_group(line, group, keys, values)
         instance = ''
         do k = 1, size(keys)
            if (keys(k) == 'name') instance = unquoted(trim(values(k)))
         end do
         if (len(instance) > 0) then
            ! the same name twice in one group (e.g. markers of two bodies): number the copies
            copies = count(seen == group // '[' // instance // ']')
            seen = [character(len=64) :: seen, group // '[' // instance // ']']
            if (copies > 0) instance = instance // '#' // to_str(copies + 1)
            instance = '[' // instance // ']'
         end if
         do k = 1, size(keys)
            if (any(MAY_CHANGE == group // '.' // trim(keys(k)))) cycle
            if (keys(k) == 'name' .and. len(instance) > 0) cycle   ! in the label
            entries = [character(len=RESTART_ENTRY_LENGTH) :: entries, group // instance // &
               '.' // trim(keys(k)) // '=' // trim(values(k))]
         end do
      end do
   end function input_entries

   !> The model entries: per body (`names`, `fingerprints`, `meshes` in the same order) its
   !> modes fingerprint when set, else, for a rigid body with the inertia of its mesh
   !> (`meshed`), the hashes of the mesh as cut from its file; and the integrator's step `h`
   !> and `rho_inf`.
   function model_entries(names, fingerprints, meshed, meshes, h, rho_inf) result(entries)
      character(len=*), intent(in) :: names(:)
      type(modes_fingerprint_t), intent(in) :: fingerprints(:)
      logical, intent(in) :: meshed(:)
      type(mesh_t), intent(in) :: meshes(:)
      real(dp), intent(in) :: h, rho_inf
      character(len=RESTART_ENTRY_LENGTH), allocatable :: entries(:)
      type(hash_t) :: coordinates, connectivity
      integer :: b, c, k
      allocate (entries(0))
      do b = 1, size(names)
         if (.not. fingerprints(b)%is_set()) then
            if (.not. meshed(b)) cycle
            coordinates = hash_t()
            call coordinates%add_reals_2d(meshes(b)%xyz)
            connectivity = hash_t()
            call connectivity%add_ints_2d(meshes(b)%tets)
            entries = [character(len=RESTART_ENTRY_LENGTH) :: entries, 'body[' // &
               trim(names(b)) // '].mesh: node coordinates=hash ' // coordinates%hex(), &
               'body[' // trim(names(b)) // '].mesh: connectivity=hash ' // connectivity%hex()]
            cycle
         end if
         do c = 1, NUM_COMPONENTS
            associate (list => fingerprints(b)%components(c)%entries)
               do k = 1, size(list)
                  entries = [character(len=RESTART_ENTRY_LENGTH) :: entries, 'body[' // &
                     trim(names(b)) // '].modes ' // trim(COMPONENT_NAMES(c)) // ': ' // &
                     trim(list(k))]
               end do
            end associate
         end do
      end do
      entries = [character(len=RESTART_ENTRY_LENGTH) :: entries, &
         'integrator.h (step used)=' // exact_text(h), 'integrator.rho_inf (used)=' // &
         exact_text(rho_inf)]
   end function model_entries

   !> The first difference between this run's entries (`here`) and those of the restart file
   !> (`there`), '' when they agree: "body[piston].mass = 0.5 here, 0.45 in the restart
   !> file", "integrator.h ... only in the restart file".
   function first_difference(here, there) result(text)
      character(len=*), intent(in) :: here(:), there(:)
      character(len=:), allocatable :: text
      integer :: k, j
      text = ''
      do k = 1, size(here)
         j = find_label(there, label_of(here(k)))
         if (j == 0) then
            text = label_of(here(k)) // ' = ' // value_of(here(k)) // &
               ' here, not set in the restart file''s run'
            return
         end if
         if (here(k) /= there(j)) then
            text = label_of(here(k)) // ' = ' // value_of(here(k)) // ' here, ' // &
               value_of(there(j)) // ' in the restart file'
            return
         end if
      end do
      do j = 1, size(there)
         if (find_label(here, label_of(there(j))) == 0) then
            text = label_of(there(j)) // ' = ' // value_of(there(j)) // &
               ' in the restart file, not set here'
            return
         end if
      end do
   end function first_difference

   !> Hash (16 hex digits) of a list of entries, as the continued file records its origin.
   function entries_hash(entries) result(hex)
      character(len=*), intent(in) :: entries(:)
      character(len=:), allocatable :: hex
      type(hash_t) :: h
      integer :: k
      h = hash_t()
      do k = 1, size(entries)
         call h%add_text(trim(entries(k)))
      end do
      hex = h%hex()
   end function entries_hash

   ! ------------------------------------------------------------------ private

   !> `&group key = value, key = value, ... /` into the group name, keys and values (values as
   !> echoed; commas inside quotes or between the items of a list stay in the value).
   subroutine split_group(line, group, keys, values)
      character(len=*), intent(in) :: line
      character(len=:), allocatable, intent(out) :: group
      character(len=:), allocatable, intent(out) :: keys(:), values(:)
      character(len=:), allocatable :: body, item, key
      character(len=RESTART_ENTRY_LENGTH), allocatable :: key_list(:), value_list(:)
      integer :: blank, start, k, equals
      logical :: quoted
      blank = index(line, ' ')
      if (blank == 0) blank = len(line) + 1
      group = line(2:blank - 1)
      body = trim(adjustl(line(blank:)))
      if (len(body) > 0) then
         if (body(len(body):len(body)) == '/') body = trim(body(:len(body) - 1))
      end if
      allocate (key_list(0), value_list(0))
      quoted = .false.
      start = 1
      do k = 1, len(body) + 1
         if (k <= len(body)) then
            if (body(k:k) == '''') quoted = .not. quoted
            if (quoted .or. body(k:k) /= ',') cycle
         end if
         item = trim(adjustl(body(start:k - 1)))
         start = k + 1
         equals = index(item, '=')
         key = ''
         if (equals > 1) key = trim(item(:equals - 1))
         if (len(key) > 0 .and. verify(key, 'abcdefghijklmnopqrstuvwxyz0123456789_') == 0) then
            key_list = [character(len=RESTART_ENTRY_LENGTH) :: key_list, key]
            value_list = [character(len=RESTART_ENTRY_LENGTH) :: value_list, &
               trim(adjustl(item(equals + 1:)))]
         else if (size(value_list) > 0) then
            ! the next item of a list value (position = 0, 0, 0)
            value_list(size(value_list)) = trim(value_list(size(value_list))) // ', ' // item
         end if
      end do
      keys = key_list
      values = value_list
   end subroutine split_group

   pure function unquoted(text) result(inner)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: inner
      inner = text
      if (len(text) >= 2) then
         if (text(1:1) == '''' .and. text(len(text):len(text)) == '''') &
            inner = text(2:len(text) - 1)
      end if
   end function unquoted

   pure integer function find_label(entries, label) result(found)
      character(len=*), intent(in) :: entries(:), label
      integer :: k
      found = 0
      do k = 1, size(entries)
         if (label_of(entries(k)) == label) then
            found = k
            return
         end if
      end do
   end function find_label

end module ffrf_app_restart_fingerprint
