# The energy watch of mechanism runs (issue 30, part 3; src/mbs/energy_watch.f90), read back and
# recomputed independently by check_energy_watch.py (the strain energies from the recorded modal
# coordinates and frequencies, the energy criterion from /energy):
#  - energy_watch_growth: the undamped engine (modal damping set to 0) with the crank of RC set 2
#    and 30 modes per body
#    (lc 8 mm meshes, h = 2.5e-5 s, 2 s), whose crank strain energy grows from about 0.25 J at
#    1 s to 4.4 J at 2 s at a steady crank speed (issue 30, part 2; docs/theory.md 4.5): the run
#    completes with one warning, 'strain energy of body "crank" grows without work to pay for
#    it', at the window close the recomputation finds (measured 1.8 s). About 35 s.
#  - energy_watch_stop: the all-rigid engine of engine.cmake (its case file) with --set
#    energy_watch = 'stop' and energy_watch_tolerance = 1e-9, below the round-off of D_s there
#    (-D_s up to 7e-9 of the energy scale just after the first window, 4.9e-7 at the first
#    combustion): exit 4 naming the energy watch, status 'error: ...', the file holding every step
#    up to the recomputed time of the criterion (measured 0.1254 s). A few seconds.
#  - the regression engines of engine.cmake (all rigid, RC set 1) under the default watch: no
#    warning, and the recomputation finds none.
set(_watch "${PROJECT_BINARY_DIR}/tests/energy_watch")
file(MAKE_DIRECTORY "${_watch}")

# ffrf_undamped_engine(<name> <input case>): the engine case on the lc 8 mm meshes, undamped (the
# engine inputs carry 2 % modal damping), 30 modes per body, h = 2.5e-5 s, 2 s, run as
# regression_<name> (fixture <name>_results)
function(ffrf_undamped_engine name source)
  ffrf_engine_case(${name} ${source} 2.0)
  ffrf_replace(_text "h = 1.0e-4," "h = 2.5e-5,")
  ffrf_replace(_text "num_modes = 10," "num_modes = 30,")
  foreach(mesh crank_lc10 conrod_lc8)
    ffrf_replace(_text "modal_damping = 0.02, num_modes = 30,\n      coarse_meshes = '${mesh}.msh'"
      "modal_damping = 0.0, num_modes = 30,\n      coarse_meshes = '${mesh}.msh'")
  endforeach()
  file(WRITE "${_watch}/${name}.nml" "${_text}")
  add_test(NAME regression_${name}
    COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 $<TARGET_FILE:ffrf>
      ${_watch}/${name}.nml --mesh-dir ${PROJECT_BINARY_DIR}/meshes --output-dir ${_watch} --quiet)
  set_tests_properties(regression_${name} PROPERTIES LABELS "regression;engine"
    FIXTURES_REQUIRED "crank_lc8_mesh;conrod_lc8_mesh" FIXTURES_SETUP ${name}_results)
endfunction()

ffrf_undamped_engine(energy_watch_growth engine_rc2)
add_test(NAME regression_energy_watch_growth_check
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_energy_watch.py
    ${_watch}/energy_watch_growth.h5 --expect growth)
set_tests_properties(regression_energy_watch_growth_check PROPERTIES
  LABELS "regression;engine;postprocess" FIXTURES_REQUIRED energy_watch_growth_results)

# The issue's case, RC set 1: the same undamped engine with the crank of RC set 1 (lc 8 mm, 30
# modes per body, h = 2.5e-5 s, 2 s) runs stably: no warning, none recomputed, and its energy
# series close (check_engine.py: W = dT + dU + D_p + D to 1e-9 of the work, D_s >= 0). About 35 s.
ffrf_undamped_engine(energy_watch_rc1_undamped engine_rc1)
add_test(NAME regression_energy_watch_rc1_undamped_check
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_energy_watch.py
    ${_watch}/energy_watch_rc1_undamped.h5 --expect none)
add_test(NAME regression_energy_watch_rc1_undamped_balance
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_engine.py
    ${_watch}/energy_watch_rc1_undamped.h5)
set_tests_properties(regression_energy_watch_rc1_undamped_check
  regression_energy_watch_rc1_undamped_balance PROPERTIES
  LABELS "regression;engine;postprocess" FIXTURES_REQUIRED energy_watch_rc1_undamped_results)

add_test(NAME regression_energy_watch_stop
  COMMAND ${CMAKE_COMMAND}
    "-DCOMMAND=$<TARGET_FILE:ffrf>;${PROJECT_BINARY_DIR}/tests/engine/engine_lc8_all_rigid.nml;--mesh-dir;${PROJECT_BINARY_DIR}/meshes;--output-dir;${_watch};--output;energy_watch_stop.h5;--set;integrator.energy_watch=stop;--set;integrator.energy_watch_tolerance=1e-9"
    -DEXIT_CODE=4 "-DMESSAGE=energy watch .energy_watch = 'stop'.: t = "
    -P ${CMAKE_CURRENT_SOURCE_DIR}/regression/expect_error.cmake)
set_tests_properties(regression_energy_watch_stop PROPERTIES LABELS "regression;engine;errors"
  FIXTURES_REQUIRED "crank_lc8_mesh;conrod_lc8_mesh" FIXTURES_SETUP energy_watch_stop_results)
add_test(NAME regression_energy_watch_stop_check
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_energy_watch.py
    ${_watch}/energy_watch_stop.h5 --expect created --tolerance 1e-9 --stopped)
set_tests_properties(regression_energy_watch_stop_check PROPERTIES
  LABELS "regression;engine;postprocess" FIXTURES_REQUIRED energy_watch_stop_results)

foreach(case engine_lc8_all_rigid engine_lc8_rc1)
  add_test(NAME regression_energy_watch_none_${case}
    COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_energy_watch.py
      ${PROJECT_BINARY_DIR}/tests/engine/${case}.h5 --expect none)
  set_tests_properties(regression_energy_watch_none_${case} PROPERTIES
    LABELS "regression;engine;postprocess" FIXTURES_REQUIRED ${case}_results)
endforeach()
