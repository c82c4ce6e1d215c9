!> The results file of a modal run (HDF5; schema in docs/results.md "Results file (HDF5)"). It is
!> created first with status 'running' and the input echo, filled body by body, and closed with
!> status 'complete' or the error message, so a failed run keeps what it computed.
!>
!> Results files are never damaged (issue 10, part 1; docs/faults.md "Faults"):
!> - One run per output: `output_lock_t` holds `<results file>.lock` (flock, released by the
!>   kernel when the run ends, even by kill -9); a second run on the same output stops at once
!>   (FFRF_IO_ERROR) and touches nothing of the first.
!> - Every results file is written under `partial_name(file)` = `<file>.part` in the same folder,
!>   closed, forced to the device and renamed over its final name by `commit_file`: an existing
!>   file is replaced only once the new one is completely written. A run that fails after its
!>   file was created commits it with status `error: ...` when the file could still be closed
!>   cleanly; otherwise it removes its `.part` file and the previous file stays as it was.
module ffrf_io_results
   use ffrf_core_kinds, only: dp, ip, i8
   use ffrf_core_error, only: error_t, add_context, fatal_error, FFRF_IO_ERROR
   use ffrf_core_posix, only: lock_output, unlock_file, ERRNO_WOULD_BLOCK, errno_text, &
      remove_file, commit_durably, file_kind, FILE_MISSING
   use ffrf_core_log, only: stage_times_t
   use ffrf_core_build_info, only: FFRF_VERSION, build_versions
   use ffrf_io_hdf5, only: h5_file_t
   use ffrf_mpc_interface, only: mpc_name, dofs_text
   use ffrf_mpc_reduction, only: formulation_name
   use ffrf_modes_input, only: basis_name, BASIS_CRAIG_BAMPTON
   use ffrf_modes_modal_analysis, only: body_modes_t
   use ffrf_io_modes_file, only: write_fingerprint
   use ffrf_io_schema, only: RESULTS_SCHEMA_VERSION
   use ffrf_modes_shift_invert, only: eigen_result_t
   implicit none
   private
   public :: results_create, results_write_body, results_finish
   public :: output_lock_t, partial_name, commit_file, abandon_file, check_no_overwrite
   public :: RESULTS_SCHEMA_VERSION

   !> The lock that keeps two runs off one output (module notes).
   type :: output_lock_t
      !> Lock file, `<results file>.lock`
      character(len=:), allocatable :: path
      !> Descriptor that holds the lock (-1: none)
      integer :: fd = -1
   contains
      procedure :: acquire => output_lock_acquire
      procedure :: release => output_lock_release
   end type output_lock_t

contains

   !> Take the lock of `results_file` (its `.lock` file); FFRF_IO_ERROR naming the file when
   !> another run holds it or the lock file cannot be made.
   subroutine output_lock_acquire(self, results_file, error)
      class(output_lock_t), intent(inout) :: self
      !> Final name of the results file
      character(len=*), intent(in) :: results_file
      type(error_t), allocatable, intent(out) :: error
      integer :: status
      self%path = results_file // '.lock'
      call lock_output(self%path, self%fd, status)
      if (status == ERRNO_WOULD_BLOCK) then
         call fatal_error(error, FFRF_IO_ERROR, 'results file "' // results_file // '" is ' // &
            'being written by another ffrf run (it holds the lock "' // self%path // '"); ' // &
            'wait until that run ends or give this one another output')
      else if (status /= 0) then
         call fatal_error(error, FFRF_IO_ERROR, 'results file "' // results_file // &
            '": cannot create its lock file "' // self%path // '": ' // errno_text(status) // &
            '; check that the output folder exists and is writable')
      end if
   end subroutine output_lock_acquire

   !> Release the lock and remove the lock file (nothing when not held).
   subroutine output_lock_release(self)
      class(output_lock_t), intent(inout) :: self
      if (self%fd < 0) return
      call unlock_file(self%path, self%fd)
   end subroutine output_lock_release

   !> The temporary name a results file is written under: `<file>.part`, same folder.
   pure function partial_name(file_name) result(name)
      character(len=*), intent(in) :: file_name
      character(len=:), allocatable :: name
      name = file_name // '.part'
   end function partial_name

   !> FFRF_IO_ERROR when `file_name` exists and must not be overwritten (--no-overwrite).
   subroutine check_no_overwrite(file_name, error)
      character(len=*), intent(in) :: file_name
      type(error_t), allocatable, intent(out) :: error
      integer :: kind
      integer(i8) :: size_bytes
      call file_kind(file_name, kind, size_bytes, error)
      if (allocated(error)) return
      if (kind /= FILE_MISSING) call fatal_error(error, FFRF_IO_ERROR, 'results file "' // &
         file_name // '" exists and --no-overwrite was given; remove or rename it, or run ' // &
         'without --no-overwrite to replace it when this run has finished')
   end subroutine check_no_overwrite

   !> Force the closed file `temp` to the device and rename it over `final` (module notes;
   !> ffrf_core_posix's commit_durably). On failure `temp` is removed and `final` is left as it was.
   subroutine commit_file(temp, final, error)
      character(len=*), intent(in) :: temp, final
      type(error_t), allocatable, intent(out) :: error
      call commit_durably(temp, final, 'results file', error)
   end subroutine commit_file

   !> Remove the temporary file of a run that could not finish it (errors ignored).
   subroutine abandon_file(temp)
      character(len=*), intent(in) :: temp
      type(error_t), allocatable :: ignored
      call remove_file(temp, ignored)
   end subroutine abandon_file

   !> Create the results file: status 'running', schema version, case name, input echo, build
   !> versions.
   subroutine results_create(file_name, case_name, title, echo, h5, error)
      !> Results file (truncated if it exists)
      character(len=*), intent(in) :: file_name
      !> Case name and title
      character(len=*), intent(in) :: case_name, title
      !> Resolved input as namelist text
      character(len=*), intent(in) :: echo
      !> The open file
      type(h5_file_t), intent(inout) :: h5
      type(error_t), allocatable, intent(out) :: error
      call h5%create(file_name, error)
      if (allocated(error)) return
      call h5%set_status('running', error)
      if (.not. allocated(error)) call h5%set_attribute('/', 'schema_version', &
         RESULTS_SCHEMA_VERSION, error)
      if (.not. allocated(error)) call h5%set_attribute('/', 'ffrf_version', FFRF_VERSION, error)
      if (.not. allocated(error)) call h5%set_attribute('/', 'case_name', case_name, error)
      if (.not. allocated(error)) call h5%set_attribute('/', 'title', title, error)
      if (.not. allocated(error)) call h5%write_string('/input/namelist', echo, error)
      if (.not. allocated(error)) call h5%write_string_list('/build/versions', build_versions(), &
         error)
      if (.not. allocated(error)) call h5%flush(error)
   end subroutine results_create

   !> Write one body: mesh, mass properties, interfaces, modes.
   subroutine results_write_body(h5, body, rc_label, error)
      type(h5_file_t), intent(inout) :: h5
      !> Body with its modes
      type(body_modes_t), intent(in) :: body
      !> Label of the RC set ('RC set 1')
      character(len=*), intent(in) :: rc_label
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: root, path
      character(len=64), allocatable :: order(:)
      integer :: k

      root = '/bodies/' // body%name
      call h5%write_real(root // '/mesh/coordinates', body%mesh%xyz, 'm', error)
      if (.not. allocated(error)) call h5%write_int(root // '/mesh/tets', body%mesh%tets, error)
      if (.not. allocated(error)) call h5%write_int(root // '/mesh/node_tags', &
         body%mesh%node_tags, error)
      if (.not. allocated(error)) call h5%write_real(root // '/mass/mass', body%mass, 'kg', error)
      if (.not. allocated(error)) call h5%write_real(root // '/mass/center_of_mass', &
         body%center_of_mass, 'm', error)
      if (.not. allocated(error)) call h5%write_real(root // '/mass/inertia', body%inertia, &
         'kg m^2', error)
      if (allocated(error)) return

      allocate (order(size(body%interfaces)))
      do k = 1, size(body%interfaces)
         associate (f => body%interfaces(k))
            order(k) = f%name
            path = root // '/interfaces/' // f%name
            call h5%write_int(path // '/nodes', f%nodes, error)
            if (.not. allocated(error)) call h5%write_real(path // '/weights', f%weights, '1', &
               error)
            if (.not. allocated(error)) call h5%write_real(path // '/virtual_node', &
               f%virtual_xyz, 'm', error)
            if (.not. allocated(error)) call h5%write_real(path // '/area', f%area, 'm^2', error)
            if (.not. allocated(error)) call h5%write_string(path // '/mpc', &
               trim(mpc_name(f%mpc)), error)
            if (.not. allocated(error)) call h5%write_string(path // '/rc_dofs', &
               dofs_text(f%rc), error)
            if (allocated(error)) return
         end associate
      end do
      if (size(order) > 0) call h5%write_string_list(root // '/interfaces/order', order, error)
      if (allocated(error)) return

      path = root // '/modes'
      call h5%write_real(path // '/frequency', body%frequency_hz, 'Hz', error)
      if (.not. allocated(error)) call h5%write_real(path // '/shape', body%shape, &
         'm kg^-1/2', error)
      if (.not. allocated(error)) call h5%write_real(path // '/virtual_node_shape', &
         body%virtual_node_shape, 'm kg^-1/2 (u), rad kg^-1/2 (theta)', error)
      if (.not. allocated(error)) call h5%write_real(path // '/residual', body%residual, '1', &
         error)
      if (.not. allocated(error)) call h5%write_real(path // '/orthonormality_error', &
         body%orthonormality_error, '1', error)
      if (.not. allocated(error) .and. allocated(body%rigid_frequency_hz)) call h5%write_real( &
         path // '/rigid_frequency', body%rigid_frequency_hz, 'Hz', error)
      if (.not. allocated(error)) call h5%set_attribute(path, 'rc_set', rc_label, error)
      if (.not. allocated(error)) call h5%set_attribute(path, 'mpc', mpc_summary(body), error)
      if (.not. allocated(error)) call h5%set_attribute(path, 'formulation', &
         formulation_name(body%formulation), error)
      if (.not. allocated(error)) call h5%set_attribute(path, 'basis', basis_name(body%basis), &
         error)
      if (.not. allocated(error) .and. body%basis == BASIS_CRAIG_BAMPTON) call h5%write_int( &
         path // '/num_static_modes', body%num_static, error)
      if (.not. allocated(error) .and. body%basis == BASIS_CRAIG_BAMPTON) call h5%write_real( &
         path // '/fixed_interface_frequency', body%fixed_interface_hz, 'Hz', error)
      if (.not. allocated(error)) call h5%set_attribute(path, 'num_rc', body%rc%num_rc, error)
      if (.not. allocated(error)) call h5%set_attribute(path, 'rc_redundancy', &
         body%rc%redundancy, error)
      if (.not. allocated(error)) call write_sizes(h5, root // '/sizes', body, error)
      if (.not. allocated(error)) call write_solver(h5, path // '/solver', body, error)
      if (.not. allocated(error) .and. body%eigen%n > 0) call write_sturm_check(h5, &
         path // '/sturm_check', body%eigen, error)
      if (.not. allocated(error)) call write_fingerprint(h5, body%name, body%fingerprint, error)
      if (.not. allocated(error)) call h5%flush(error)
      if (allocated(error)) call add_context(error, 'body "' // body%name // '"')
   end subroutine results_write_body

   subroutine write_sizes(h5, path, body, error)
      type(h5_file_t), intent(inout) :: h5
      character(len=*), intent(in) :: path
      type(body_modes_t), intent(in) :: body
      type(error_t), allocatable, intent(out) :: error
      call h5%write_int(path // '/num_dofs', body%num_dofs, error)
      if (.not. allocated(error)) call h5%write_int(path // '/num_reduced', body%num_reduced, &
         error)
      if (.not. allocated(error)) call h5%write_int(path // '/num_constraints', &
         body%num_constraints, error)
      if (.not. allocated(error)) call h5%write_int(path // '/stiffness_nnz', &
         body%stiffness_nnz, error)
   end subroutine write_sizes

   !> Shift-invert Lanczos statistics: shift, Sturm count, factor size, solves, restarts.
   subroutine write_solver(h5, path, body, error)
      type(h5_file_t), intent(inout) :: h5
      character(len=*), intent(in) :: path
      type(body_modes_t), intent(in) :: body
      type(error_t), allocatable, intent(out) :: error
      associate (e => body%eigen)
         call h5%write_real(path // '/shift', e%shift, 's^-2', error)
         if (.not. allocated(error)) call h5%write_int(path // '/num_below_shift', &
            e%num_below_shift, error)
         if (.not. allocated(error)) call h5%write_int(path // '/factor_entries', &
            e%factor_entries, error)
         if (.not. allocated(error)) call h5%write_int(path // '/factor_memory_mb', &
            e%factor_memory_mb, error)
         if (.not. allocated(error)) call h5%write_int(path // '/num_solves', e%num_solves, error)
         if (.not. allocated(error)) call h5%write_int(path // '/num_restarts', &
            e%num_iterations, error)
         if (.not. allocated(error)) call h5%write_int(path // '/lanczos_vectors', e%ncv, error)
         ! the block method's own figures (ARPACK runs keep the datasets they had)
         if (e%eigensolver == 'block') then
            if (.not. allocated(error)) call h5%write_string(path // '/eigensolver', &
               trim(e%eigensolver), error)
            if (.not. allocated(error)) call h5%write_int(path // '/block_size', e%block_size, &
               error)
            if (.not. allocated(error)) call h5%write_int(path // '/num_block_solves', &
               e%num_block_solves, error)
         end if
      end associate
      if (.not. allocated(error)) call write_memory_estimates(h5, path, body%eigen, error)
   end subroutine write_solver

   !> The completeness proof of the modes (theory.md 5.7): the inertia of K - s M at `shift`
   !> counts `count` eigenvalues below it (the deflated rigid-body modes included) and
   !> `count_low` below `shift_low` (sigma, or a shift below the lowest mode when some lie below
   !> sigma); every eigenvalue in [shift_low, shift) is among the returned modes (Craig-Bampton:
   !> of the fixed-interface modes). rigid_modes deflated, windows, recoveries, the
   !> factorisations made for counts (and window shifts; their wall time is the stage
   !> "<body>: Sturm check" of /timings, so that these datasets depend on the input only).
   !> Attribute `status`: 'proven', or 'off' (sturm_check = .false.: shift and count are then
   !> those of the eigen shift).
   subroutine write_sturm_check(h5, path, e, error)
      type(h5_file_t), intent(inout) :: h5
      character(len=*), intent(in) :: path
      type(eigen_result_t), intent(in) :: e
      type(error_t), allocatable, intent(out) :: error
      call h5%write_real(path // '/shift', e%sturm_shift, 's^-2', error)
      if (.not. allocated(error)) call h5%write_real(path // '/shift_hz', hz(e%sturm_shift), &
         'Hz', error)
      if (.not. allocated(error)) call h5%write_int(path // '/count', e%sturm_count, error)
      if (.not. allocated(error)) call h5%set_attribute(path // '/count', 'units', '1', error)
      if (.not. allocated(error)) call h5%write_real(path // '/shift_low', e%sturm_shift_low, &
         's^-2', error)
      if (.not. allocated(error)) call h5%write_int(path // '/count_low', e%sturm_count_low, &
         error)
      if (.not. allocated(error)) call h5%set_attribute(path // '/count_low', 'units', '1', &
         error)
      if (.not. allocated(error)) call h5%write_int(path // '/rigid_modes', e%num_rigid, error)
      if (.not. allocated(error)) call h5%set_attribute(path // '/rigid_modes', 'units', '1', &
         error)
      if (.not. allocated(error)) call h5%write_int(path // '/windows', e%num_windows, error)
      if (.not. allocated(error)) call h5%set_attribute(path // '/windows', 'units', '1', error)
      if (.not. allocated(error)) call h5%write_int(path // '/recoveries', e%num_recoveries, &
         error)
      if (.not. allocated(error)) call h5%set_attribute(path // '/recoveries', 'units', '1', &
         error)
      if (.not. allocated(error)) call h5%write_int(path // '/count_factorisations', &
         e%num_count_factorisations, error)
      if (.not. allocated(error)) call h5%set_attribute(path // '/count_factorisations', &
         'units', '1', error)
      if (.not. allocated(error)) call h5%set_attribute(path, 'status', &
         trim(merge('proven', 'off   ', e%sturm_checked)), error)
   contains
      pure real(dp) function hz(lambda)
         real(dp), intent(in) :: lambda
         hz = sign(sqrt(abs(lambda)), lambda) / (2.0_dp * acos(-1.0_dp))
      end function hz
   end subroutine write_sturm_check

   !> MUMPS analysis estimates and memory options next to the factor statistics (issue 12):
   !> estimated factor entries INFOG(20), flops RINFOG(1), MB in-core INFOG(16)/(17) and
   !> out-of-core INFOG(26)/(27) (max over processes / sum), low-rank INFOG(36) or (38), the MB
   !> predicted for the options used, stored factor entries. All are determined by the matrix and
   !> the options (the bitwise digests hold them); the limit checked, which depends on the
   !> machine's free memory at the time, goes to the log only.
   subroutine write_memory_estimates(h5, path, e, error)
      type(h5_file_t), intent(inout) :: h5
      character(len=*), intent(in) :: path
      type(eigen_result_t), intent(in) :: e
      type(error_t), allocatable, intent(out) :: error
      call h5%write_int(path // '/estimated_factor_entries', e%estimated_factor_entries, error)
      if (.not. allocated(error)) call h5%write_real(path // '/estimated_flops', &
         e%estimated_flops, '', error)
      if (.not. allocated(error)) call h5%write_int(path // '/estimated_memory_incore_mb', &
         e%estimated_memory_incore_mb, error)
      if (.not. allocated(error)) call h5%write_int(path // &
         '/estimated_memory_incore_total_mb', e%estimated_memory_incore_total_mb, error)
      if (.not. allocated(error)) call h5%write_int(path // '/estimated_memory_ooc_mb', &
         e%estimated_memory_ooc_mb, error)
      if (.not. allocated(error)) call h5%write_int(path // '/estimated_memory_ooc_total_mb', &
         e%estimated_memory_ooc_total_mb, error)
      if (.not. allocated(error)) call h5%write_int(path // '/estimated_memory_blr_mb', &
         e%estimated_memory_blr_mb, error)
      if (.not. allocated(error)) call h5%write_int(path // '/predicted_memory_mb', &
         e%predicted_memory_mb, error)
      if (.not. allocated(error)) call h5%write_int(path // '/compressed_factor_entries', &
         e%compressed_factor_entries, error)
      if (.not. allocated(error)) call h5%write_int(path // '/out_of_core', &
         merge(1, 0, e%out_of_core), error)
      if (.not. allocated(error)) call h5%write_real(path // '/compression_tolerance', &
         e%compression_tolerance, '', error)
   end subroutine write_memory_estimates

   !> 'RBE3', 'RBE2' or 'mixed'.
   function mpc_summary(body) result(text)
      type(body_modes_t), intent(in) :: body
      character(len=:), allocatable :: text
      integer :: k
      text = 'none'
      if (size(body%interfaces) == 0) return
      text = trim(mpc_name(body%interfaces(1)%mpc))
      do k = 2, size(body%interfaces)
         if (body%interfaces(k)%mpc /= body%interfaces(1)%mpc) text = 'mixed'
      end do
   end function mpc_summary

   !> Stage timings, then the final status ('complete' or the error message); closes the file
   !> whatever happens. When a write fails the status becomes `error: <that failure>`;
   !> `closed` tells whether the file was closed cleanly (then it is readable).
   subroutine results_finish(h5, times, status, error, closed)
      type(h5_file_t), intent(inout) :: h5
      !> Stage wall times and peak memory
      type(stage_times_t), intent(in) :: times
      !> 'complete' or the error message
      character(len=*), intent(in) :: status
      type(error_t), allocatable, intent(out) :: error
      !> True when the file was closed without error
      logical, intent(out), optional :: closed
      type(error_t), allocatable :: close_error, ignored
      if (allocated(times%names)) then
         if (size(times%names) > 0) then
            call h5%write_string_list('/timings/stage', times%names, error)
            if (.not. allocated(error)) call h5%write_real('/timings/seconds', times%seconds, &
               's', error)
            if (.not. allocated(error)) call h5%write_real('/timings/peak_memory_mib', &
               times%peak_mib, 'MiB', error)
         end if
      end if
      if (allocated(times%rank_peak_mib) .and. .not. allocated(error)) call h5%write_real( &
         '/timings/peak_memory_mib_per_rank', times%rank_peak_mib, 'MiB', error)
      if (.not. allocated(error)) call h5%set_status(status, error)
      if (allocated(error)) call h5%set_status('error: ' // error%message, ignored)
      call h5%close(close_error)
      if (present(closed)) closed = .not. allocated(close_error)
      if (.not. allocated(error) .and. allocated(close_error)) call move_alloc(close_error, error)
   end subroutine results_finish

end module ffrf_io_results
