# Mode reuse (&body modes_file, issue 12 part 4), by mode_reuse.py on the lc 8 mm engine of
# engine.cmake (tests/engine of the build), 20 ms: the engine with both bodies' modes read back
# from a computed run's results file (and the crank's from a modal run) equals the computed run
# bit for bit; the bad uses (missing file, not HDF5, truncated, no modes of the body, another mesh,
# material, interface RC or number of modes, a rigid body, a modal run) stop with exit 3 or 2 and
# one line matching a regex; `ffrf --check` on the same cases: 0 on matching files, the run's exit
# code and message on each refusal.
foreach(test bitwise errors check fields)
  add_test(NAME regression_mode_reuse_${test}
    COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/mode_reuse.py ${test}
      $<TARGET_FILE:ffrf> ${PROJECT_BINARY_DIR}/meshes ${PROJECT_BINARY_DIR}/tests/engine
      ${PROJECT_BINARY_DIR}/tests/mode_reuse/${test})
  set_tests_properties(regression_mode_reuse_${test} PROPERTIES
    LABELS "regression;engine" TIMEOUT 600
    FIXTURES_REQUIRED "crank_lc8_mesh;crank_lc10_mesh;conrod_lc8_mesh")
endforeach()
