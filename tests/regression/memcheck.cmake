# Memcheck (valgrind) of a small flexible mechanism, label memcheck: the flexible double
# pendulum of tests/regression/gravity_double_pendulum.nml on the coarse beam mesh beam_lc40,
# 4 steps: modes (MUMPS, ARPACK), the starting pose assembled, generalized-alpha steps, the
# results file and its restart state written. Fails on any memcheck error that
# tests/memcheck.supp does not suppress (library internals only, each entry with its reason) and
# when the run fails; skipped (exit 77) when valgrind is not installed. About 10 s of CPU.
set(_memcheck "${PROJECT_BINARY_DIR}/tests/memcheck")
file(MAKE_DIRECTORY "${_memcheck}")
add_test(NAME memcheck_flexible_pendulum
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/memcheck_run.py
    $<TARGET_FILE:ffrf> ${CMAKE_CURRENT_SOURCE_DIR}/regression/gravity_double_pendulum.nml
    ${PROJECT_BINARY_DIR}/meshes ${_memcheck}/flexible_pendulum
    ${CMAKE_CURRENT_SOURCE_DIR}/memcheck.supp
    --set "body[link1].mesh_file=beam_lc40.msh" --set "body[link2].mesh_file=beam_lc40.msh"
    --set "integrator.t_end=0.001")
set_tests_properties(memcheck_flexible_pendulum PROPERTIES LABELS "memcheck" SKIP_RETURN_CODE 77
  FIXTURES_REQUIRED beam_lc40_mesh TIMEOUT 600)
