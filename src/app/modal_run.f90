!> A modal case from its namelist file to its results: read and echo the input, compute the
!> constrained normal modes of every body, write the HDF5 results and a Gmsh file of the modes.
!> The batch driver calls `run_modal_case` (a host program may too); nothing here stops or prints
!> errors. Each body: its Gmsh file read (ffrf_app_body_modes), then compute_body_modes on the
!> mesh with the body resolved by the model (ffrf_model_model: interfaces, modes, rigid flag).
module ffrf_app_modal_run
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, add_context, fatal_error, FFRF_INTERRUPTED, &
      FFRF_INPUT_ERROR
   use ffrf_core_posix, only: pending_signal, signal_name
   use ffrf_core_strings, only: to_str
   use ffrf_core_paths, only: folder_of, join_path, insert_suffix
   use ffrf_core_log, only: logger_t, stage_timer_t, stage_times_t, peak_memory_mib
   use ffrf_app_run_options, only: run_options_t, set_log_level
   use ffrf_app_output_paths, only: check_output_paths
   use ffrf_core_parallel, only: parallel_t, use_ranks
   use ffrf_input_nml_run, only: log_level_code
   use ffrf_input_case, only: case_input_t, read_case, case_echo
   use ffrf_io_hdf5, only: h5_file_t
   use ffrf_io_results, only: results_create, results_write_body, results_finish, &
      output_lock_t, partial_name, commit_file, abandon_file, check_no_overwrite
   use ffrf_io_gmsh_writer, only: write_mode_shapes_msh
   use ffrf_modes_modal_analysis, only: body_modes_t
   use ffrf_modes_input, only: modes_spec_t
   use ffrf_app_body_modes, only: compute_body_modes_from_file
   use ffrf_app_body_export, only: export_body, exports_matrices
   use ffrf_la_sparse, only: csr_t
   use ffrf_model_model, only: model_t, build_model
   implicit none
   private
   !> run_options_t and set_log_level (ffrf_app_run_options) are public here too
   public :: run_options_t, run_modal_case, run_modal, set_log_level

contains

   !> Run the modal case `case_file` ('-': standard input): read_case, then run_modal.
   subroutine run_modal_case(case_file, options, log, error)
      !> Namelist case file
      character(len=*), intent(in) :: case_file
      !> Folders and log level
      type(run_options_t), intent(in) :: options
      !> Logger (its level is set from the case unless the options fix it)
      type(logger_t), intent(inout) :: log
      type(error_t), allocatable, intent(out) :: error
      type(case_input_t) :: case
      call read_case(case_file, case, error)
      if (.not. allocated(error)) call run_modal(case, options, log, error)
   end subroutine run_modal_case

   !> Run a modal case read by read_case; progress goes to `log`'s unit.
   subroutine run_modal(case, options, log, error, modes)
      !> The case, read and checked
      type(case_input_t), intent(in) :: case
      !> Folders and log level
      type(run_options_t), intent(in) :: options
      !> Logger (its level is set from the case unless the options fix it)
      type(logger_t), intent(inout) :: log
      type(error_t), allocatable, intent(out) :: error
      !> The modes of every body (case order; rigid bodies: none), as far as computed (C API)
      type(body_modes_t), allocatable, intent(out), optional :: modes(:)
      type(error_t), allocatable :: close_error
      character(len=:), allocatable :: case_file
      type(h5_file_t) :: h5
      type(stage_times_t) :: times
      type(stage_timer_t) :: total, output_timer
      type(body_modes_t), allocatable :: bodies(:)
      character(len=:), allocatable :: mesh_dir, results_file, msh_file, echo
      type(output_lock_t) :: lock
      integer :: k
      real(dp), allocatable :: rank_peak_mib(:)
      type(parallel_t) :: ranks

      call total%begin()
      ranks = options%parallel
      ! MPI build: every rank computes the modes, rank 0 alone writes (docs/mpi.md "MPI build and
      ! runs")
      call use_ranks(options%parallel)
      case_file = case%file_name
      call set_log_level(log, options, log_level_code(case%run%log_level))
      mesh_dir = options%mesh_dir
      if (len(mesh_dir) == 0) mesh_dir = folder_of(case_file)
      echo = case_echo(case)
      call log%info('input', case_file // ': ' // trim(case%run%title))
      call log%info('input', 'resolved input:' // new_line('a') // echo(:len(echo) - 1))

      results_file = join_path(options%output_dir, trim(case%run%output))
      ! no output on an input or on another output (exit 2), before anything is written
      call check_output_paths(case, options, error)
      if (.not. allocated(error) .and. ranks%is_root()) call lock%acquire(results_file, error)
      call ranks%agree(error)
      if (allocated(error)) return
      call compute_and_write(error)
      if (ranks%is_root()) call lock%release()
      if (present(modes) .and. allocated(bodies)) call move_alloc(bodies, modes)

   contains

      !> The run proper, under the output lock: results written under a temporary name,
      !> renamed over results_file at the end (ffrf_io_results).
      subroutine compute_and_write(error)
         type(error_t), allocatable, intent(out) :: error
         character(len=:), allocatable :: temp_file, stopped_at
         integer :: signal
         logical :: closed
         type(model_t) :: model
         type(csr_t) :: mass_matrix, stiffness_matrix

         if (allocated(options%restart_file)) then
            if (len(options%restart_file) > 0) then
               call fatal_error(error, FFRF_INPUT_ERROR, case_file // ': --restart ' // &
                  options%restart_file // ': a modal case has nothing to continue; ' // &
                  '--restart applies to mechanism cases (with &joint groups)')
               return
            end if
         end if
         if (.not. options%overwrite .and. ranks%is_root()) &
            call check_no_overwrite(results_file, error)
         call ranks%agree(error)
         if (allocated(error)) return
         ! The case resolved once: every body's rigid flag, interfaces and modes to compute
         call build_model(case, model, error)
         if (allocated(error)) then
            call add_context(error, case_file)
            return
         end if
         temp_file = partial_name(results_file)
         if (ranks%is_root()) call results_create(temp_file, case%name, &
            trim(case%run%title), echo, h5, error)
         call ranks%agree(error)
         if (allocated(error) .and. .not. ranks%is_root()) return
         if (allocated(error)) then
            call h5%close(close_error)
            call abandon_file(temp_file)
            call add_context(error, 'results file "' // results_file // '"')
            return
         end if
         call log%info('output', 'results (written when complete): ' // results_file)

         signal = 0
         allocate (bodies(size(case%bodies)))
         do k = 1, size(case%bodies)
            if (model%bodies(k)%rigid) then
               call log%note('input', trim(case%bodies(k)%name) // ' is rigid: no modes')
               cycle
            end if
            associate (body => model%bodies(k))
               if (exports_matrices(case%run%export)) then
                  ! an export wants the FE matrices the modes come from (&run export)
                  call compute_body_modes_from_file(body%body, body%interfaces, &
                     modes_of_run(body%modes, folder_of(results_file)), mesh_dir, log, times, &
                     bodies(k), error, mass_matrix, stiffness_matrix)
               else
                  call compute_body_modes_from_file(body%body, body%interfaces, &
                     modes_of_run(body%modes, folder_of(results_file)), mesh_dir, log, times, &
                     bodies(k), error)
               end if
            end associate
            if (allocated(error)) then
               if (error%code == FFRF_INTERRUPTED) then
                  ! stopped inside the body's eigen solve (every rank at the same check)
                  signal = ranks%max_int(pending_signal())
                  stopped_at = error%message
                  call fatal_error(error, FFRF_INTERRUPTED, case_file // ': ' // stopped_at // &
                     '; body "' // trim(case%bodies(k)%name) // '" is left out, results ' // &
                     'file "' // results_file // '" holds the bodies done, status ' // &
                     '"interrupted: ' // signal_name(signal) // '"')
               end if
            end if
            call output_timer%begin()
            if (.not. allocated(error) .and. ranks%is_root()) then
               call results_write_body(h5, bodies(k), trim(case%modes%rc_label), error)
               if (allocated(error)) call add_context(error, 'results file "' // &
                  results_file // '"')
            end if
            if (.not. allocated(error) .and. len_trim(case%run%mode_shapes_msh) > 0 .and. &
               ranks%is_root()) then
               msh_file = join_path(options%output_dir, trim(case%run%mode_shapes_msh))
               if (size(case%bodies) > 1) msh_file = insert_suffix(msh_file, '_' // &
                  bodies(k)%name)
               call write_mode_shapes_msh(msh_file, bodies(k)%mesh%xyz, bodies(k)%mesh%tets, &
                  bodies(k)%shape, bodies(k)%frequency_hz, error)
               if (.not. allocated(error)) call log%info('output', 'mode shapes for gmsh ' // &
                  'written: ' // msh_file)
            end if
            if (.not. allocated(error) .and. len_trim(case%run%export) > 0 .and. &
               ranks%is_root()) call export_body(trim(case%run%export), results_file, &
               bodies(k), mass_matrix, stiffness_matrix, log, error)
            call ranks%agree(error)
            if (allocated(error)) exit
            call times%add(bodies(k)%name // ': output', output_timer%seconds())
            call log_frequency_table(log, bodies(k), trim(case%modes%rc_label))
            ! A signal (SIGTERM, ...) ends the run between bodies (or inside the eigen solve of
            ! the next, above), with what is done
            signal = ranks%max_int(pending_signal())
            if (signal /= 0 .and. k < size(case%bodies)) then
               call fatal_error(error, FFRF_INTERRUPTED, case_file // ': interrupted by ' // &
                  signal_name(signal) // ' after body "' // bodies(k)%name // '"; results ' // &
                  'file "' // results_file // '" holds the bodies done, status "interrupted: ' &
                  // signal_name(signal) // '"')
               exit
            end if
         end do
         call times%add('total', total%seconds())
         if (ranks%num_ranks > 1) then
            ! every rank's peak memory, in the results (/timings/peak_memory_mib_per_rank)
            rank_peak_mib = ranks%gather_real(peak_memory_mib())
            times%rank_peak_mib = rank_peak_mib
         end if
         if (.not. ranks%is_root()) return

         if (allocated(error)) then
            if (error%code /= FFRF_INTERRUPTED) call add_context(error, case_file)
            if (error%code == FFRF_INTERRUPTED) then
               call results_finish(h5, times, 'interrupted: ' // signal_name(signal), &
                  close_error, closed)
            else
               call results_finish(h5, times, 'error: ' // error%message, close_error, closed)
            end if
            if (closed) then
               call commit_file(temp_file, results_file, close_error)
            else
               call abandon_file(temp_file)
            end if
            return
         end if
         call results_finish(h5, times, 'complete', error, closed)
         if (.not. allocated(error)) call commit_file(temp_file, results_file, error)
         if (allocated(error)) then
            call abandon_file(temp_file)
            call add_context(error, 'results file "' // results_file // '"')
            return
         end if
         call log%info('output', 'results written: ' // results_file)
         if (ranks%num_ranks > 1) then
            call log%info('done', case%name // ': ' // to_str(total%seconds(), 3) // ' s on ' &
               // to_str(ranks%num_ranks) // ' MPI ranks, peak memory per rank max ' // &
               to_str(maxval(rank_peak_mib), 4) // ' MiB (rank 0 ' // &
               to_str(rank_peak_mib(1), 4) // ' MiB)')
         else
            call log%info('done', case%name // ': ' // to_str(total%seconds(), 3) // &
               ' s, peak memory ' // to_str(peak_memory_mib(), 4) // ' MiB')
         end if
      end subroutine compute_and_write

   end subroutine run_modal

   subroutine log_frequency_table(log, body, rc_label)
      type(logger_t), intent(in) :: log
      type(body_modes_t), intent(in) :: body
      character(len=*), intent(in) :: rc_label
      integer :: i
      character(len=64) :: line
      if (len_trim(rc_label) > 0) then
         call log%info('modes', body%name // ', ' // rc_label // ': mode, frequency (Hz), residual')
      else
         call log%info('modes', body%name // ': mode, frequency (Hz), residual')
      end if
      do i = 1, size(body%frequency_hz)
         write (line, '(i6, f16.4, es12.2)') i, body%frequency_hz(i), body%residual(i)
         call log%info('modes', trim(line))
      end do
   end subroutine log_frequency_table

   !> The modes specification as a modal run uses it: the out-of-core folder decided (as given,
   !> else TMPDIR when set, else the folder of the results file), and the eigen solve stopped
   !> at its next solve by a signal (nothing of a body is kept before its modes are complete).
   function modes_of_run(modes, output_folder) result(resolved)
      type(modes_spec_t), intent(in) :: modes
      character(len=*), intent(in) :: output_folder
      type(modes_spec_t) :: resolved
      integer :: length, stat
      resolved = modes
      resolved%stop_on_signal = .true.
      if (len_trim(resolved%ooc_directory) > 0) return
      call get_environment_variable('TMPDIR', length=length, status=stat)
      if (stat == 0 .and. length > 0) return
      resolved%ooc_directory = output_folder
      if (len_trim(output_folder) == 0) resolved%ooc_directory = '.'
   end function modes_of_run

end module ffrf_app_modal_run
