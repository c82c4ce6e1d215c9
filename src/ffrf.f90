!> `use ffrf`: the public Fortran API of the library (docs/api.md).
!>
!> The case object `ffrf_case_t` is the Fortran face of the C API (include/ffrf.h), with the
!> same entry points as type-bound procedures, 1-based indices and an error object:
!>
!>     type(ffrf_case_t) :: engine
!>     type(error_t), allocatable :: error
!>     call engine%open('engine.nml', error, mesh_dir='meshes')       ! nothing written
!>     call engine%advance(1.0e-3_dp, error)                          ! prepares, then steps
!>     call engine%crank_state(angle, speed, error)
!>     call engine%set_marker_load(1, 3, [0, 0, 0]*1.0_dp, [0.0_dp, 0.0_dp, torque], error)
!>
!> error%code is FFRF_BAD_CALL (1: call out of order, bad index), FFRF_INPUT_ERROR (2),
!> FFRF_IO_ERROR (3), FFRF_NUMERIC_ERROR (4) or FFRF_INTERRUPTED (5), the statuses of the C API.
!> Below it, for programs that drive the stages themselves (the batch driver among them):
!> kinds, errors, logging, the case reader, the modal pipeline, mechanism runs, and the signal
!> handling a batch program may install so that SIGTERM & co. end a run cleanly (the library
!> never installs it on its own).
module ffrf
   use ffrf_core_kinds, only: dp, ip, i8
   use ffrf_core_error, only: error_t, fatal_error, add_context, FFRF_INPUT_ERROR, &
      FFRF_IO_ERROR, FFRF_NUMERIC_ERROR, FFRF_INTERRUPTED
   use ffrf_core_posix, only: install_signal_handlers, signals_restart_calls, &
      ignore_file_size_signal, pending_signal, signal_name, exit_guard
   use ffrf_core_log, only: logger_t, stage_times_t, LOG_QUIET, LOG_INFO, LOG_DEBUG
   use ffrf_mesh_mesh, only: mesh_t, extract_body
   use ffrf_mesh_gmsh, only: read_gmsh
   use ffrf_mpc_interface, only: interface_spec_t, interface_t, build_interface
   use ffrf_modes_input, only: body_spec_t, modes_spec_t
   use ffrf_input_body, only: body_input_t
   use ffrf_input_interface, only: interface_input_t
   use ffrf_input_modes, only: modes_input_t
   use ffrf_model_specs, only: interface_spec_of, modes_spec_of, body_interface_specs, &
      body_modes_spec
   use ffrf_model_model, only: model_t, model_body_t, build_model, body_spec_of
   use ffrf_modes_modal_analysis, only: body_modes_t, compute_body_modes
   use ffrf_app_run_options, only: run_options_t
   use ffrf_app_body_modes, only: read_body_mesh, compute_body_modes_from_file, &
      compute_input_body_modes
   use ffrf_app_modal_run, only: run_modal_case, run_modal
   use ffrf_input_case, only: case_input_t, read_case, read_case_with_overrides, case_echo, &
      case_name_of
   use ffrf_input_overrides, only: override_t, parse_override
   use ffrf_input_sweep, only: batch_overrides, NO_TASK
   use ffrf_la_blas_threads, only: set_blas_threads, blas_threads, reserve_blas_buffers, &
      fit_blas_address_limit
   use ffrf_mbs_mechanism, only: mechanism_t
   use ffrf_mbs_generalized_alpha, only: galpha_settings_t, galpha_integrator_t
   use ffrf_app_mechanism_run, only: run_mechanism_case, run_mechanism
   use ffrf_app_check_case, only: check_case
   use ffrf_app_mechanism_session, only: mechanism_session_t
   use ffrf_capi_case, only: ffrf_case_t, FFRF_BAD_CALL, FFRF_RBE2, FFRF_RBE3, &
      FFRF_RBE3_AREA, FFRF_RBE3_AREA_CONSISTENT
   use ffrf_core_parallel, only: parallel_t, parallel_of_communicator, FFRF_MPI_BUILD
   use ffrf_core_build_info, only: FFRF_VERSION, FFRF_VERSION_MAJOR, FFRF_VERSION_MINOR, &
      FFRF_VERSION_PATCH, build_versions
   implicit none
   public
end module ffrf
