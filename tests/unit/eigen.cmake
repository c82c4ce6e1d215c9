# Sparse direct solver (MUMPS + METIS) and shift-invert Lanczos eigen solver suites (owner: eigen).
# Both run in well under a second; CHECKED also runs them against the -fcheck=all library.
ffrf_add_unit_suite(test_la_mumps CHECKED LABELS la)
# spring-chain fixture (module ffrf_test_spring_chain), shared with test_stability_modes
target_sources(ffrf_testing PRIVATE unit/spring_chain_fixture.f90)
target_sources(ffrf_testing_checked PRIVATE unit/spring_chain_fixture.f90)
ffrf_add_unit_suite(test_modes_shift_invert CHECKED LABELS modes)
# Spectra you can trust (issue 22): exact multiplicities, deflated null vectors, Sturm check and
# recovery, shift windows, on grids with closed-form spectra. ~3 s, checked ~8 s.
ffrf_add_unit_suite(test_modes_spectrum CHECKED LABELS modes)
# The same through the modal pipeline on finite-element bodies: the free-free crank with 1..3
# modes (each eigensolver), a free cube with exact multiplets built in the test, hinged cubes,
# max_frequency_hz on crank RC set 1. One ctest entry per test (they run in parallel); ~35 s.
ffrf_add_unit_suite(test_modes_free_spectra LABELS modes FIXTURES crank_mesh
  ARGS symmetric_cube)
foreach(_test free_crank_few_modes free_crank_few_modes_block symmetric_cube_rbe2_face hinged_cubes
    crank_max_frequency)
  add_test(NAME test_modes_free_spectra_${_test} COMMAND test_modes_free_spectra ${_test}
    WORKING_DIRECTORY ${PROJECT_BINARY_DIR})
  set_tests_properties(test_modes_free_spectra_${_test} PROPERTIES LABELS "unit;modes"
    ENVIRONMENT "${FFRF_TEST_ENVIRONMENT}" FIXTURES_REQUIRED crank_mesh)
endforeach()
