!> Output paths that never land on an input or on another output (issue 23, item 2; docs/faults.md
!> "Faults"): before a run computes or locks anything, every file it will write (the results file,
!> its `.part`, `.lock` and `.checkpoint`, the Gmsh mode shapes or animations and their `.opt` and
!> `.part` files) is compared with every file it reads (the case, each body's mesh and modes_file,
!> the pressure table, the --sweep table, the --restart file) and with every other output. Same
!> file: the same device and inode when both exist (links followed), else the same resolved path
!> (ffrf_core_posix same_file); a temporary stands for its folder entry (a stale link there is
!> removed, never followed, so where it leads does not matter). A match is FFRF_INPUT_ERROR (exit 2)
!> naming both roles and both paths. The one exception is the documented restart in place:
!> `--restart` may name the run's own results file or its checkpoint.
module ffrf_app_output_paths
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_paths, only: join_path, insert_suffix, folder_of
   use ffrf_core_posix, only: same_file
   use ffrf_core_choices, only: choice_kinds, export_choices, EXPORT_XDMF
   use ffrf_input_case, only: case_input_t
   use ffrf_io_xdmf, only: xdmf_name
   use ffrf_app_run_options, only: run_options_t
   implicit none
   private
   public :: check_output_paths, export_asked

   !> A file of the run and what it is to the run ("the mesh of body ""crank""").
   type :: named_path_t
      character(len=:), allocatable :: role, path
      !> A temporary (`.part`, `.lock`): removed and made anew, never followed; it stands for
      !> its folder entry, not for where a stale link there leads
      logical :: entry = .false.
   end type named_path_t

contains

   !> Whether &run export asks for the export `kind` (EXPORT_* of ffrf_core_choices); the words
   !> were checked when the case was read (a case built in memory has none).
   logical function export_asked(case, kind)
      type(case_input_t), intent(in) :: case
      integer, intent(in) :: kind
      integer, allocatable :: kinds(:)
      type(error_t), allocatable :: error
      call choice_kinds(export_choices, 'export', 'an export format', case%run%export, kinds, &
         error)
      export_asked = .false.
      if (.not. allocated(error)) export_asked = any(kinds == kind)
   end function export_asked

   !> FFRF_INPUT_ERROR when an output of the run is one of its inputs or another of its
   !> outputs (module notes); nothing is created or changed.
   subroutine check_output_paths(case, options, error)
      type(case_input_t), intent(in) :: case
      !> Folders, --restart and --sweep files
      type(run_options_t), intent(in) :: options
      type(error_t), allocatable, intent(out) :: error
      type(named_path_t), allocatable :: inputs(:), outputs(:)
      character(len=:), allocatable :: results, mesh_dir, msh, restart
      integer :: i, j, k

      allocate (inputs(0), outputs(0))
      mesh_dir = ''
      if (allocated(options%mesh_dir)) mesh_dir = options%mesh_dir
      if (len(mesh_dir) == 0) mesh_dir = folder_of(case%file_name)
      if (case%file_name /= '-' .and. case%file_name /= 'stdin') &
         call add(inputs, 'the case file', case%file_name)
      do k = 1, size(case%bodies)
         associate (body => case%bodies(k))
            if (len_trim(body%mesh_file) > 0) call add(inputs, 'the mesh of body "' // &
               trim(body%name) // '"', join_path(mesh_dir, trim(body%mesh_file)))
            if (len_trim(body%modes_file) > 0) call add(inputs, 'the modes_file of body "' &
               // trim(body%name) // '"', trim(body%modes_file))
         end associate
      end do
      if (case%is_mechanism .and. len_trim(case%mechanism%pressure_table) > 0) &
         call add(inputs, 'the pressure table_file', trim(case%mechanism%pressure_table))
      if (allocated(options%sweep_file)) then
         if (len(options%sweep_file) > 0) call add(inputs, 'the --sweep table', &
            options%sweep_file)
      end if
      restart = ''
      if (allocated(options%restart_file)) restart = options%restart_file
      if (len(restart) > 0) call add(inputs, 'the --restart file', restart)

      results = join_path(options%output_dir, trim(case%run%output))
      call add(outputs, 'the results file', results)
      call add(outputs, 'the temporary results file', results // '.part', .true.)
      call add(outputs, 'the lock of the results file', results // '.lock', .true.)
      if (export_asked(case, EXPORT_XDMF)) then
         call add(outputs, 'the XDMF file (&run export)', xdmf_name(results))
         call add(outputs, 'the temporary XDMF file', xdmf_name(results) // '.part', .true.)
      end if
      if (case%is_mechanism) then
         call add(outputs, 'the checkpoint', results // '.checkpoint')
         call add(outputs, 'the temporary checkpoint', results // '.checkpoint.part', .true.)
         if (case%mechanism%mechanism%animation_frames > 0) then
            do k = 1, size(case%bodies)
               if (len_trim(case%bodies(k)%mesh_file) == 0) cycle
               msh = insert_suffix(results, '_' // trim(case%bodies(k)%name) // '_animation')
               msh = msh(:index(msh, '.', back=.true.)) // 'msh'
               call add_gmsh(outputs, 'the animation of body "' // trim(case%bodies(k)%name) &
                  // '"', msh)
            end do
         end if
      else if (len_trim(case%run%mode_shapes_msh) > 0 .and. case%run%mode_shapes_msh /= &
         'none') then
         msh = join_path(options%output_dir, trim(case%run%mode_shapes_msh))
         if (size(case%bodies) == 1) then
            call add_gmsh(outputs, 'the mode shapes file (mode_shapes_msh)', msh)
         else
            do k = 1, size(case%bodies)
               call add_gmsh(outputs, 'the mode shapes file (mode_shapes_msh) of body "' // &
                  trim(case%bodies(k)%name) // '"', insert_suffix(msh, '_' // &
                  trim(case%bodies(k)%name)))
            end do
         end if
      end if

      do i = 1, size(outputs)
         do j = 1, size(inputs)
            ! restart in place: --restart names this run's own results file or checkpoint
            if (inputs(j)%role == 'the --restart file' .and. (outputs(i)%role == &
               'the results file' .or. outputs(i)%role == 'the checkpoint')) cycle
            call check_distinct(case%file_name, outputs(i), inputs(j), 'an input', error)
            if (allocated(error)) return
         end do
         do j = i + 1, size(outputs)
            call check_distinct(case%file_name, outputs(i), outputs(j), 'another output', error, &
               other_entry=outputs(j)%entry)
            if (allocated(error)) return
         end do
      end do
   end subroutine check_output_paths

   !> FFRF_INPUT_ERROR when `output` is the same file as `other` (an input, whose path is
   !> followed, or another output, whose folder entry other_entry compares as for `output`).
   subroutine check_distinct(case_file, output, other, what, error, other_entry)
      !> The case file, named first
      character(len=*), intent(in) :: case_file
      type(named_path_t), intent(in) :: output, other
      !> "an input" or "another output"
      character(len=*), intent(in) :: what
      type(error_t), allocatable, intent(out) :: error
      !> other is a temporary (its entry, as named_path_t%entry)
      logical, intent(in), optional :: other_entry
      logical :: same
      call same_file(output%path, other%path, same, error, a_entry=output%entry, &
         b_entry=other_entry)
      if (allocated(error) .or. .not. same) return
      call fatal_error(error, FFRF_INPUT_ERROR, case_file // ': output path refused: ' // &
         output%role // &
         ' "' // output%path // '" is the same file as ' // other%role // ' "' // other%path // &
         '" (' // what // ' of this run); give the output another name (&run output, ' // &
         'mode_shapes_msh, --output or --output-dir)')
   end subroutine check_distinct

   !> A Gmsh file with its temporary, its option file and the option file's temporary.
   subroutine add_gmsh(list, role, path)
      type(named_path_t), allocatable, intent(inout) :: list(:)
      character(len=*), intent(in) :: role, path
      call add(list, role, path)
      call add(list, 'the temporary of ' // role, path // '.part', .true.)
      call add(list, 'the option file of ' // role, path // '.opt')
      call add(list, 'the temporary option file of ' // role, path // '.opt.part', .true.)
   end subroutine add_gmsh

   subroutine add(list, role, path, entry)
      type(named_path_t), allocatable, intent(inout) :: list(:)
      character(len=*), intent(in) :: role, path
      !> A temporary file (named_path_t entry); default .false.
      logical, intent(in), optional :: entry
      type(named_path_t), allocatable :: longer(:)
      integer :: n
      n = size(list)
      allocate (longer(n + 1))
      longer(:n) = list
      longer(n + 1)%role = role
      longer(n + 1)%path = path
      if (present(entry)) longer(n + 1)%entry = entry
      call move_alloc(longer, list)
   end subroutine add

end module ffrf_app_output_paths
