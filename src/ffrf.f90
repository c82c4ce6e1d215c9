!> `use ffrf` gives the public API of the library: kinds, errors, logging, the modal pipeline,
!> mechanism runs (bodies, joints, loads, generalized-alpha), the signal handling a batch
!> program installs so that SIGTERM & co. end a run cleanly.
module ffrf
   use ffrf_core_kinds, only: dp, ip, i8
   use ffrf_core_error, only: error_t, fatal_error, add_context, FFRF_INPUT_ERROR, &
      FFRF_IO_ERROR, FFRF_NUMERIC_ERROR, FFRF_INTERRUPTED
   use ffrf_core_posix, only: install_signal_handlers, signals_restart_calls, &
      ignore_file_size_signal, pending_signal, signal_name
   use ffrf_core_log, only: logger_t, stage_times_t, LOG_QUIET, LOG_INFO, LOG_DEBUG
   use ffrf_mesh_mesh, only: mesh_t, extract_body
   use ffrf_mesh_gmsh, only: read_gmsh
   use ffrf_mpc_interface, only: interface_spec_t, interface_t, build_interface
   use ffrf_modes_input, only: body_input_t, modes_spec_t
   use ffrf_input_interface, only: interface_input_t
   use ffrf_input_modes, only: modes_input_t
   use ffrf_model_specs, only: interface_spec_of, modes_spec_of, body_interface_specs, &
      body_modes_spec
   use ffrf_model_model, only: model_t, model_body_t, build_model
   use ffrf_modes_modal_analysis, only: body_modes_t, compute_body_modes
   use ffrf_app_run_options, only: run_options_t
   use ffrf_app_body_modes, only: read_body_mesh, compute_body_modes_from_file, &
      compute_input_body_modes
   use ffrf_app_modal_run, only: run_modal_case, run_modal
   use ffrf_input_case, only: case_input_t, read_case
   use ffrf_mbs_mechanism, only: mechanism_t
   use ffrf_mbs_generalized_alpha, only: galpha_settings_t, galpha_integrator_t
   use ffrf_app_mechanism_run, only: run_mechanism_case, run_mechanism
   use ffrf_app_check_case, only: check_case
   implicit none
   public
end module ffrf
