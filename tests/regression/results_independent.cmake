# Results by value (issue 28 item 3): check_results_independent.py reads a results file and checks
# every dataset against a computation independent of ffrf's Fortran (K and M assembled in numpy by
# postprocess/peer_tet10.py, the 14-point mass rule, the rigid fits, the FFRF kinematics of
# docs/theory.md 3), one test per kind of run, each on a run the suite already makes (fixtures):
#  - modal, rc_normal basis: regression_crank_lc8_rc2 (crank lc 8 mm, RC set 2, RBE3);
#  - modal, Craig-Bampton: the same case with --set modes.basis=craig_bampton (the one run added
#    here, about 3 s);
#  - mechanism: engine_lc8_rc1 (flexible crank and conrod, 10 modes each, 0.1 s);
#  - restarted: the run of regression_output_safety_restart continued with --restart to 0.2 s;
#  - reused modes: regression_mode_reuse_bitwise's engine with both bodies' modes from a file;
#  - MPI: results_independent_mpi_crank_rc2_rbe2 checks the MPI run of mpi_modes_crank_rc2_rbe2
#    (label mpi; skipped with the MPI tests when the MPI build is not there).
# About 8-15 s each (the numpy assembly of the lc 8 mm crank takes 3-10 s).
set(_ri_checker ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_results_independent.py)
set(_ri_env ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1)
set(_ri_out "${PROJECT_BINARY_DIR}/tests/regression")
set(_ri_cb "${PROJECT_BINARY_DIR}/tests/results_independent")
file(MAKE_DIRECTORY "${_ri_cb}")

add_test(NAME results_independent_modal
  COMMAND ${_ri_env} ${_ri_checker} ${_ri_out}/crank_lc8_rc2.h5 --kind modal
    --mesh-dir ${PROJECT_BINARY_DIR}/meshes)
set_tests_properties(results_independent_modal PROPERTIES LABELS "regression;postprocess"
  FIXTURES_REQUIRED "crank_lc8_results;crank_lc8_mesh")

add_test(NAME results_independent_craig_bampton_run
  COMMAND ${_ri_env} $<TARGET_FILE:ffrf> ${CMAKE_CURRENT_SOURCE_DIR}/regression/crank_lc8_rc2.nml
    --mesh-dir ${PROJECT_BINARY_DIR}/meshes --output-dir ${_ri_cb} --output crank_lc8_rc2_cb.h5
    --set modes.basis=craig_bampton --quiet)
set_tests_properties(results_independent_craig_bampton_run PROPERTIES LABELS regression
  FIXTURES_REQUIRED crank_lc8_mesh FIXTURES_SETUP crank_lc8_cb_results)
add_test(NAME results_independent_craig_bampton
  COMMAND ${_ri_env} ${_ri_checker} ${_ri_cb}/crank_lc8_rc2_cb.h5 --kind craig_bampton
    --mesh-dir ${PROJECT_BINARY_DIR}/meshes)
set_tests_properties(results_independent_craig_bampton PROPERTIES LABELS "regression;postprocess"
  FIXTURES_REQUIRED "crank_lc8_cb_results;crank_lc8_mesh")

add_test(NAME results_independent_mechanism
  COMMAND ${_ri_env} ${_ri_checker} ${PROJECT_BINARY_DIR}/tests/engine/engine_lc8_rc1.h5
    --kind mechanism --mesh-dir ${PROJECT_BINARY_DIR}/meshes)
set_tests_properties(results_independent_mechanism PROPERTIES
  LABELS "regression;engine;postprocess"
  FIXTURES_REQUIRED "engine_lc8_rc1_results;crank_lc8_mesh;conrod_lc8_mesh")

# the runs of two existing tests, kept in their work folders, become fixtures here
set_property(TEST regression_output_safety_restart APPEND PROPERTY FIXTURES_SETUP
  output_safety_restart_results)
add_test(NAME results_independent_restarted
  COMMAND ${_ri_env} ${_ri_checker}
    ${PROJECT_BINARY_DIR}/tests/output_safety/restart/split/engine.h5 --kind mechanism
    --restarted --mesh-dir ${PROJECT_BINARY_DIR}/meshes)
set_tests_properties(results_independent_restarted PROPERTIES
  LABELS "regression;engine;postprocess"
  FIXTURES_REQUIRED "output_safety_restart_results;crank_lc8_mesh;conrod_lc8_mesh")

set_property(TEST regression_mode_reuse_bitwise APPEND PROPERTY FIXTURES_SETUP
  mode_reuse_bitwise_results)
add_test(NAME results_independent_reused
  COMMAND ${_ri_env} ${_ri_checker} ${PROJECT_BINARY_DIR}/tests/mode_reuse/bitwise/reused.h5
    --kind mechanism --reused --mesh-dir ${PROJECT_BINARY_DIR}/meshes)
set_tests_properties(results_independent_reused PROPERTIES
  LABELS "regression;engine;postprocess"
  FIXTURES_REQUIRED "mode_reuse_bitwise_results;crank_lc8_mesh;conrod_lc8_mesh")

# MPI: the results file of the MPI run of mpi_modes_crank_rc2_rbe2 (mpirun -np 2, crank lc 8 mm,
# RC set 2, RBE2 faces). That test and the MPI build are skipped (exit 77) when MPI or the MPI
# MUMPS is missing; this one then finds no file and is skipped too.
set_property(TEST mpi_modes_crank_rc2_rbe2 APPEND PROPERTY FIXTURES_SETUP
  mpi_crank_rc2_rbe2_results)
add_test(NAME results_independent_mpi_crank_rc2_rbe2
  COMMAND ${_ri_env} ${_ri_checker}
    ${PROJECT_BINARY_DIR}/tests/mpi/crank_rc2_rbe2/mpi/result.h5 --kind modal --skip-missing
    --mesh-dir ${PROJECT_BINARY_DIR}/meshes)
set_tests_properties(results_independent_mpi_crank_rc2_rbe2 PROPERTIES LABELS "mpi;postprocess"
  SKIP_RETURN_CODE 77 FIXTURES_REQUIRED "mpi_crank_rc2_rbe2_results;crank_lc8_mesh")

# The checks can fail: 11 faults planted in copies of the modal, Craig-Bampton and engine files
# (a virtual-node block x 1.0001, a frequency x (1 + 1e-9), a shape entry, Jxx, an area, a
# fixed-interface frequency, a step's strain energy, the final kinetic energy x (1 + 1e-12), a
# damping dissipation, a joint force, a crank angle) each reported by the check meant for it,
# the unchanged files passing (one process, each mesh assembled once; about 15 s).
add_test(NAME results_independent_faults
  COMMAND ${_ri_env} ${Python3_EXECUTABLE}
    ${CMAKE_CURRENT_SOURCE_DIR}/regression/results_independent_faults.py
    ${_ri_out}/crank_lc8_rc2.h5 ${_ri_cb}/crank_lc8_rc2_cb.h5
    ${PROJECT_BINARY_DIR}/tests/engine/engine_lc8_rc1.h5 ${PROJECT_BINARY_DIR}/meshes
    ${_ri_cb}/faults)
set_tests_properties(results_independent_faults PROPERTIES LABELS "regression;postprocess"
  FIXTURES_REQUIRED
    "crank_lc8_results;crank_lc8_cb_results;engine_lc8_rc1_results;crank_lc8_mesh;conrod_lc8_mesh")
