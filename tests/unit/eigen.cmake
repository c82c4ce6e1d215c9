# Sparse direct solver (MUMPS + METIS) and shift-invert Lanczos eigen solver suites (owner: eigen).
# Both run in well under a second; CHECKED also runs them against the -fcheck=all library.
ffrf_add_unit_suite(test_la_mumps CHECKED LABELS la)
ffrf_add_unit_suite(test_modes_shift_invert CHECKED LABELS modes)
