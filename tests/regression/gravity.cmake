# Gravity on flexible bodies through the driver (issue 24, docs/theory.md 3.6): a double
# pendulum of two flexible steel links (beam_lc6, 6 modes each) released from the horizontal
# pose; --check passes, the run completes, and check_gravity_pendulum.py compares its angles with
# the rigid double pendulum (Lagrange's equations, scipy DOP853) and its /energy gravity work with
# -(V - V_0). About 2 s of CPU.
add_test(NAME regression_gravity_pendulum_check
  COMMAND $<TARGET_FILE:ffrf> ${CMAKE_CURRENT_SOURCE_DIR}/regression/gravity_double_pendulum.nml
    --mesh-dir ${PROJECT_BINARY_DIR}/meshes --output-dir ${_out} --check)
set_tests_properties(regression_gravity_pendulum_check PROPERTIES LABELS "regression;mbs"
  FIXTURES_REQUIRED beam_lc6_mesh)
add_test(NAME regression_gravity_pendulum
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 $<TARGET_FILE:ffrf>
    ${CMAKE_CURRENT_SOURCE_DIR}/regression/gravity_double_pendulum.nml
    --mesh-dir ${PROJECT_BINARY_DIR}/meshes --output-dir ${_out})
set_tests_properties(regression_gravity_pendulum PROPERTIES LABELS "regression;mbs"
  FIXTURES_REQUIRED beam_lc6_mesh FIXTURES_SETUP gravity_pendulum_results)
add_test(NAME regression_gravity_pendulum_values
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_gravity_pendulum.py
    ${_out}/gravity_double_pendulum.h5)
set_tests_properties(regression_gravity_pendulum_values PROPERTIES LABELS "regression;mbs"
  FIXTURES_REQUIRED gravity_pendulum_results)
# --check refuses what the run refuses only after the modes: rho_inf = 1 (generalized-alpha
# refuses it with the constraints every mechanism has), with the run's exit code 2
add_test(NAME error_check_rho_inf_one
  COMMAND ${CMAKE_COMMAND}
    "-DCOMMAND=$<TARGET_FILE:ffrf>;${CMAKE_CURRENT_SOURCE_DIR}/regression/gravity_double_pendulum.nml;--mesh-dir;${PROJECT_BINARY_DIR}/meshes;--output-dir;${_out};--check;--set;integrator.rho_inf=1"
    -DEXIT_CODE=2 "-DMESSAGE=&integrator rho_inf = 1: generalized-alpha without numerical damping is unstable"
    -P ${CMAKE_CURRENT_SOURCE_DIR}/regression/expect_error.cmake)
set_tests_properties(error_check_rho_inf_one PROPERTIES LABELS "regression;errors"
  FIXTURES_REQUIRED beam_lc6_mesh)
# ... and accepts it with the stabilized index-2 constraints (docs/theory.md 4.6): exit 0
add_test(NAME regression_check_rho_inf_one_index2
  COMMAND $<TARGET_FILE:ffrf> ${CMAKE_CURRENT_SOURCE_DIR}/regression/gravity_double_pendulum.nml
    --mesh-dir ${PROJECT_BINARY_DIR}/meshes --output-dir ${_out} --check
    --set integrator.rho_inf=1 --set integrator.constraints=index2)
set_tests_properties(regression_check_rho_inf_one_index2 PROPERTIES LABELS "regression;mbs"
  FIXTURES_REQUIRED beam_lc6_mesh)
