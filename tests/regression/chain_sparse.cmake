# Sparse against dense LU of the iteration matrix (issue 24), by check_chain_sparse.py: a chain
# of 4 flexible links (input/link.geo, 6 + 8 modes each), 200 steps, run with &integrator
# sparse_threshold = 1 (MUMPS) and 10**9 (LAPACK): the same trajectory (positions, Euler
# parameters, modal coordinates, joint reactions) within the Newton tolerance; then chains of 8 and
# 16 links (50 steps), the block-sparse path against the dense one: final link angles to 1e-10
# relative. About 10 s of CPU (60 s wall on a loaded machine).
add_test(NAME regression_chain_sparse_dense
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_chain_sparse.py
    $<TARGET_FILE:ffrf> ${PROJECT_BINARY_DIR}/meshes ${PROJECT_BINARY_DIR}/tests/chain_sparse
    --postprocess ${PROJECT_SOURCE_DIR}/postprocess)
set_tests_properties(regression_chain_sparse_dense PROPERTIES
  LABELS "regression;results" TIMEOUT 300 FIXTURES_REQUIRED link_mesh
  ENVIRONMENT "${FFRF_TEST_ENVIRONMENT}")
