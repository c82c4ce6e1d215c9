# Memory caps and out-of-core factors (issue 12, item 2) on the small crank
# (lc = 8 mm, RC set 2): check_memory.py compares the out-of-core run with the in-core
# one; a tiny memory limit is refused after the analysis with the figure and the
# remedies (exit 4, numerical/resource failure); bad key values are input errors (exit 2).
if(NOT Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
  set(Python3_EXECUTABLE /usr/bin/python3)
endif()
set(_memory "${PROJECT_BINARY_DIR}/tests/memory")
file(MAKE_DIRECTORY "${_memory}")
set(_memory_case "${CMAKE_CURRENT_SOURCE_DIR}/regression/crank_lc8_rc2.nml")
add_test(NAME memory_out_of_core
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_memory.py
    $<TARGET_FILE:ffrf> ${_memory_case} ${PROJECT_BINARY_DIR}/meshes ${_memory}/runs)
set_tests_properties(memory_out_of_core PROPERTIES LABELS "regression;memory"
  FIXTURES_REQUIRED crank_lc8_mesh TIMEOUT 120 ENVIRONMENT OPENBLAS_NUM_THREADS=1)

set(_memory_expect "${CMAKE_CURRENT_SOURCE_DIR}/regression/expect_input.cmake")
# ffrf_memory_error(<name> <exit code> <message regex> <--set values...>)
function(ffrf_memory_error name code regex)
  set(sets "")
  foreach(value IN LISTS ARGN)
    list(APPEND sets "--set" "${value}")
  endforeach()
  list(JOIN sets ";" sets)
  add_test(NAME memory_error_${name}
    COMMAND ${CMAKE_COMMAND}
      "-DCOMMAND=$<TARGET_FILE:ffrf>;${_memory_case};--mesh-dir;${PROJECT_BINARY_DIR}/meshes;--output-dir;${_memory};--output;${name}.h5;${sets}"
      -DEXIT_CODE=${code} "-DMESSAGE=${regex}" -P ${_memory_expect})
  set_tests_properties(memory_error_${name} PROPERTIES LABELS "regression;errors;memory"
    FIXTURES_REQUIRED crank_lc8_mesh TIMEOUT 30 ENVIRONMENT OPENBLAS_NUM_THREADS=1)
endfunction()

# 1 MB: refused before the factorisation, with the predicted figure, the limit and the remedies
ffrf_memory_error(tiny_limit 4
  "MUMPS factorisation \\(n = [0-9]+\\) would not fit: predicted [0-9]+ MB \\(MUMPS analysis: [1-9][0-9]* MB for the in-core full-rank factorisation, [0-9.]+ M factor entries; \\+ [0-9]+ MB resident \\+ [1-9][0-9]* MB of eigensolver vectors\\) exceeds the memory limit 1 MB \\(&modes memory_limit_mb\\); remedies: more ranks \\(the MPI build: mpirun -np N\\), out-of-core factors \\(&modes out_of_core = \\.true\\.\\), or a coarser mesh"
  modes.memory_limit_mb=1)
# out-of-core on: the remedy text leaves it out, the figure is the out-of-core estimate
ffrf_memory_error(tiny_limit_ooc 4
  "predicted [0-9]+ MB \\(MUMPS analysis: [1-9][0-9]* MB for the out-of-core full-rank factorisation.*remedies: more ranks \\(the MPI build: mpirun -np N\\), or a coarser mesh"
  modes.memory_limit_mb=1 modes.out_of_core=.true.)
ffrf_memory_error(negative_limit 2 "memory_limit_mb = -5" modes.memory_limit_mb=-5)
ffrf_memory_error(compression_one 2 "compression_tolerance = 1" modes.compression_tolerance=1)
# block low-rank factors are refused on this toolchain (SCOTCH crashes, little compression)
ffrf_memory_error(compression_refused 2
  "compression_tolerance = [^:]+: block low-rank factors are not offered: .*SIGSEGV.*use out_of_core"
  modes.compression_tolerance=1e-8)
ffrf_memory_error(compression_negative 2 "compression_tolerance = -1e-8: out of range"
  modes.compression_tolerance=-1e-8)

# Block shift-invert Lanczos (&modes eigensolver = 'block') against ARPACK on the same case,
# in core and out of core (check_block_lanczos.py: frequencies 1e-9, shapes 1e-6).
add_test(NAME modes_block_vs_arpack
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_block_lanczos.py
    $<TARGET_FILE:ffrf> ${_memory_case} ${PROJECT_BINARY_DIR}/meshes ${_memory}/block)
set_tests_properties(modes_block_vs_arpack PROPERTIES LABELS "regression;memory;modes"
  FIXTURES_REQUIRED crank_lc8_mesh TIMEOUT 120 ENVIRONMENT OPENBLAS_NUM_THREADS=1)
ffrf_memory_error(eigensolver_unknown 2 "eigensolver.*auto.*arpack.*block"
  "modes.eigensolver=lobpcg")
