!> Checkpoints and --restart of a mechanism run (a submodule of ffrf_app_mechanism_output;
!> docs/restart.md): the restart state written, the checkpoint file, an earlier run read,
!> its model compared, its state and history applied.
submodule (ffrf_app_mechanism_output) ffrf_app_mechanism_output_restart
   use ffrf_core_error, only: add_context, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_posix, only: copy_file, rename_file, remove_file, check_input_file
   use ffrf_core_strings, only: to_str
   use ffrf_io_hdf5, only: H5_READ_ONLY
   use ffrf_io_results, only: partial_name
   use ffrf_modes_fingerprint, only: modes_fingerprint_t
   use ffrf_mesh_mesh, only: mesh_t
   use ffrf_app_restart_fingerprint, only: model_entries, first_difference, entries_hash
   implicit none

contains

   module procedure checkpoint_name
      name = results_file // '.checkpoint'
   end procedure checkpoint_name

   module procedure remove_checkpoint
      type(error_t), allocatable :: ignored
      call remove_file(checkpoint_name(results_file), ignored)
   end procedure remove_checkpoint

   module procedure write_restart_state
      real(dp), allocatable :: reals(:)
      integer(i8), allocatable :: ints(:)
      character(len=64), allocatable :: names(:)
      integer :: k
      call results%flush(error)
      if (allocated(error)) return
      call integrator%export_state(reals, ints)
      allocate (names(size(bodies)))
      do k = 1, size(bodies)
         names(k) = mech%bodies(bodies(k)%index)%name
      end do
      call results%write_real('/checkpoint/integrator_reals', reals, '1', error)
      if (.not. allocated(error)) call results%write_long('/checkpoint/integrator_ints', ints, &
         error)
      if (.not. allocated(error)) call results%write_real('/checkpoint/energy_balance', &
         balance%export_state(), '1', error)
      ! the crank angle's unwrapping reference: an engine (a mechanism with a crank) only
      if (.not. allocated(error) .and. mech%rotor > 0) call results%write_real( &
         '/checkpoint/crank_reference', [crank_reference], 'rad', error)
      ! the torsion springs' unwrapping references (their whole turns): a case with some only
      if (.not. allocated(error) .and. size(torsion_reference) > 0) call results%write_real( &
         '/checkpoint/torsion_reference', torsion_reference, 'rad', error)
      ! the output interval being recorded (decimated output with peaks, &output)
      if (.not. allocated(error) .and. present(interval)) then
         if (size(interval) > 0) call results%write_real('/checkpoint/output_interval', &
            interval, '1', error)
      end if
      if (.not. allocated(error)) call results%write_long('/checkpoint/num_steps', &
         [int(num_steps, i8)], error)
      if (.not. allocated(error)) call results%write_long('/checkpoint/num_coordinates', &
         [int(mech%num_coordinates(), i8)], error)
      if (.not. allocated(error)) call results%write_strings('/checkpoint/bodies', names, error)
      if (.not. allocated(error)) call results%write_long('/checkpoint/body_modes', &
         int(bodies%num_modes, i8), error)
      if (.not. allocated(error)) call results%write_strings('/checkpoint/fingerprint_input', &
         fingerprint_input, error)
      if (.not. allocated(error)) call results%write_strings('/checkpoint/fingerprint_model', &
         fingerprint_model, error)
      if (.not. allocated(error)) call results%flush(error)
   end procedure write_restart_state

   module procedure write_checkpoint_file
      type(error_t), allocatable :: ignored
      character(len=:), allocatable :: checkpoint
      checkpoint = checkpoint_name(results_file)
      call copy_file(partial_name(results_file), partial_name(checkpoint), error)
      if (.not. allocated(error)) call rename_file(partial_name(checkpoint), checkpoint, error)
      if (allocated(error)) then
         call remove_file(partial_name(checkpoint), ignored)
         call add_context(error, 'checkpoint "' // checkpoint // '"')
      end if
   end procedure write_checkpoint_file

   module procedure read_restart
      integer(i8), allocatable :: counts(:)
      ! a regular file: HDF5 would block on a FIFO (exit 3 naming the option otherwise)
      call check_input_file(file_name, '--restart file', huge(1_i8), error)
      if (allocated(error)) return
      call source%open(file_name, H5_READ_ONLY, error)
      if (allocated(error)) then
         call add_context(error, '--restart')
         return
      end if
      if (.not. source%exists('/checkpoint/integrator_ints')) then
         call fatal_error(error, FFRF_INPUT_ERROR, '--restart "' // file_name // '": no ' // &
            'restart state (/checkpoint) in it; give the results file (.h5) or the ' // &
            '.checkpoint file of an earlier run of this mechanism case')
         return
      end if
      call source%read_real('/checkpoint/integrator_reals', restart%reals, error)
      if (.not. allocated(error)) call source%read_int('/checkpoint/integrator_ints', &
         restart%ints, error)
      if (.not. allocated(error)) call source%read_real('/checkpoint/energy_balance', &
         restart%balance, error)
      if (.not. allocated(error)) then
         if (source%exists('/checkpoint/crank_reference')) then
            call source%read_real('/checkpoint/crank_reference', restart%crank_reference, error)
         else
            ! a run without a crank writes none: the unwrapping reference stays 0
            restart%crank_reference = [0.0_dp]
         end if
      end if
      ! written since issue 24; apply_restart refuses a case with torsion springs without it
      restart%has_torsion_reference = source%exists('/checkpoint/torsion_reference')
      if (.not. allocated(error) .and. restart%has_torsion_reference) call source%read_real( &
         '/checkpoint/torsion_reference', restart%torsion_reference, error)
      allocate (restart%interval(0))
      if (.not. allocated(error) .and. source%exists('/checkpoint/output_interval')) &
         call source%read_real('/checkpoint/output_interval', restart%interval, error)
      if (.not. allocated(error)) call source%read_int('/checkpoint/num_steps', counts, error)
      if (.not. allocated(error)) restart%num_steps = int(counts(1))
      if (.not. allocated(error)) call source%read_int('/checkpoint/num_coordinates', counts, &
         error)
      if (.not. allocated(error)) restart%num_coordinates = int(counts(1))
      if (.not. allocated(error)) call source%read_string_list('/checkpoint/bodies', &
         restart%bodies, error)
      if (.not. allocated(error)) call source%read_int('/checkpoint/body_modes', &
         restart%body_modes, error)
      if (allocated(error)) then
         error%code = FFRF_INPUT_ERROR
         call add_context(error, '--restart "' // file_name // '": unreadable restart state')
         return
      end if
      if (.not. source%exists('/checkpoint/fingerprint_model')) then
         call fatal_error(error, FFRF_INPUT_ERROR, '--restart "' // file_name // '": its ' // &
            'restart state has no restart fingerprint (/checkpoint/fingerprint_input, ' // &
            '/checkpoint/fingerprint_model: written by ffrf since issue 23), so ffrf cannot ' // &
            'check that it is a run of this model; run the case from t = 0')
         return
      end if
      call source%read_string_list('/checkpoint/fingerprint_input', restart%fingerprint_input, &
         error)
      if (.not. allocated(error)) call source%read_string_list('/checkpoint/fingerprint_model', &
         restart%fingerprint_model, error)
      if (allocated(error)) then
         error%code = FFRF_INPUT_ERROR
         call add_context(error, '--restart "' // file_name // '": unreadable restart state')
      end if
   end procedure read_restart

   module procedure model_fingerprint
      character(len=64), allocatable :: names(:)
      type(modes_fingerprint_t), allocatable :: fingerprints(:)
      type(mesh_t), allocatable :: meshes(:)
      integer :: k
      allocate (names(size(bodies)), fingerprints(size(bodies)), meshes(size(bodies)))
      do k = 1, size(bodies)
         names(k) = mech%bodies(bodies(k)%index)%name
         if (.not. bodies(k)%meshed) cycle
         fingerprints(k) = bodies(k)%modes%fingerprint
         meshes(k) = bodies(k)%modes%mesh
      end do
      entries = model_entries(names, fingerprints, bodies%meshed, meshes, integrator%settings%h, &
         integrator%settings%rho_inf)
   end procedure model_fingerprint

   module procedure check_same_model
      character(len=:), allocatable :: difference
      difference = first_difference(here, there)
      if (len(difference) == 0) return
      call fatal_error(error, FFRF_INPUT_ERROR, '--restart "' // file_name // '": not a run ' // &
         'of this model: ' // difference // '; continue only a run of the same model (what ' // &
         'may change, e.g. t_end and the outputs: docs/restart.md)')
   end procedure check_same_model

   module procedure write_restart_origin
      character(len=:), allocatable :: files(:), hashes(:)
      real(dp), allocatable :: times(:)
      character(len=max(len(file_name), 16)), allocatable :: all_files(:)
      character(len=16), allocatable :: all_hashes(:)
      allocate (all_files(0), all_hashes(0), times(0))
      if (source%exists('/restart_origin/file')) then
         call source%read_string_list('/restart_origin/file', files, error)
         if (.not. allocated(error)) call source%read_string_list('/restart_origin/fingerprint', &
            hashes, error)
         if (.not. allocated(error)) call source%read_real('/restart_origin/time', times, error)
         if (allocated(error)) return
         all_files = [character(len=len(all_files)) :: files]
         all_hashes = [character(len=16) :: hashes]
      end if
      all_files = [character(len=len(all_files)) :: all_files, file_name]
      all_hashes = [character(len=16) :: all_hashes, entries_hash(fingerprint)]
      times = [times, t]
      call results%write_strings('/restart_origin/file', all_files, error)
      if (.not. allocated(error)) call results%write_strings('/restart_origin/fingerprint', &
         all_hashes, error)
      if (.not. allocated(error)) call results%write_real('/restart_origin/time', times, 's', &
         error)
   end procedure write_restart_origin

   module procedure apply_restart
      character(len=:), allocatable :: here, there
      logical :: ok
      integer :: k
      here = ''
      do k = 1, size(bodies)
         here = here // ' ' // mech%bodies(bodies(k)%index)%name // '(' // &
            to_str(bodies(k)%num_modes) // ' modes)'
      end do
      there = ''
      do k = 1, size(restart%bodies)
         there = there // ' ' // trim(restart%bodies(k))
         if (k <= size(restart%body_modes)) there = there // '(' // &
            to_str(int(restart%body_modes(k))) // ' modes)'
      end do
      if (restart%num_coordinates /= mech%num_coordinates() .or. here /= there) then
         call fatal_error(error, FFRF_INPUT_ERROR, '--restart "' // file_name // '": its ' // &
            'run had ' // to_str(restart%num_coordinates) // ' coordinates and bodies' // &
            there // '; this case has ' // to_str(mech%num_coordinates()) // &
            ' coordinates and bodies' // here // '; restart only from a run of the same ' // &
            'case (t_end may differ)')
         return
      end if
      call integrator%import_state(restart%reals, restart%ints, error)
      if (allocated(error)) then
         call add_context(error, '--restart "' // file_name // '"')
         return
      end if
      call balance%import_state(restart%balance, ok)
      if (.not. ok .or. size(restart%crank_reference) /= 1) then
         call fatal_error(error, FFRF_INPUT_ERROR, '--restart "' // file_name // &
            '": its energy balance or crank reference state has the wrong size')
         return
      end if
      mech%rotor_reference = restart%crank_reference(1)
      call restore_torsion_references(file_name, restart, mech, error)
   end procedure apply_restart

   !> The torsion springs' unwrapping references of the restart state into the mechanism; a
   !> case with torsion springs and a restart state without them (written before issue 24) is
   !> refused: its springs would continue from the starting pose's reference and lose every
   !> whole turn wound at the restart state (docs/restart.md "Unwrapped angles").
   subroutine restore_torsion_references(file_name, restart, mech, error)
      character(len=*), intent(in) :: file_name
      type(restart_state_t), intent(in) :: restart
      type(mechanism_t), intent(inout) :: mech
      type(error_t), allocatable, intent(out) :: error
      integer :: count
      count = size(mech%torsion_references())
      if (.not. restart%has_torsion_reference) then
         if (count == 0) return
         call fatal_error(error, FFRF_INPUT_ERROR, '--restart "' // file_name // '": its ' // &
            'restart state has no torsion-spring unwrapping references (/checkpoint/' // &
            'torsion_reference: written by ffrf since issue 24) and this case has ' // &
            to_str(count) // ' torsion spring(s), whose whole turns it would lose; run the ' // &
            'case from t = 0')
         return
      end if
      call mech%set_torsion_references(restart%torsion_reference, error)
      if (allocated(error)) call add_context(error, '--restart "' // file_name // '"')
   end subroutine restore_torsion_references

   module procedure history_from
      real(dp), allocatable :: t(:), angle(:), zeta(:, :)
      integer :: k, first, capacity
      capacity = max(1024, 2 * num_steps)
      allocate (history%t(capacity), history%angle(capacity), &
         history%zeta(sum(bodies%num_modes), capacity))
      call source%read_real('/time/t', t, error)
      if (allocated(error)) return
      if (mech%rotor > 0) then
         call source%read_real('/time/crank_angle', angle, error)
         if (allocated(error)) return
      else
         ! a run without a crank records no angle (write_animations then spreads over time)
         allocate (angle(size(t)), source=0.0_dp)
      end if
      history%t(:num_steps) = t(:num_steps)
      history%angle(:num_steps) = angle(:num_steps)
      first = 0
      do k = 1, size(bodies)
         if (bodies(k)%num_modes == 0) cycle
         associate (path => '/bodies/' // mech%bodies(bodies(k)%index)%name // &
               '/modal_coordinates')
            ! a body whose histories were not written (&output histories): no deformation shown
            if (source%exists(path)) then
               call source%read_real(path, zeta, error)
               if (allocated(error)) return
               history%zeta(first + 1:first + bodies(k)%num_modes, :num_steps) = &
                  zeta(:, :num_steps)
            else
               history%zeta(first + 1:first + bodies(k)%num_modes, :num_steps) = 0.0_dp
            end if
         end associate
         first = first + bodies(k)%num_modes
      end do
      history%num_steps = num_steps
   end procedure history_from

end submodule ffrf_app_mechanism_output_restart
