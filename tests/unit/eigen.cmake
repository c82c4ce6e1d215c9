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
