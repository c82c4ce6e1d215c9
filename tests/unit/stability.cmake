# Stability where methods fail (issue 4, part 2; docs/validation.md "Stability where methods fail").
# generalized-alpha's amplification against its closed-form characteristic cubic and steps far
# beyond the highest mode (vs central differences and the trapezoidal rule); well under a second.
# Generalized-alpha written out for the tests (module ffrf_test_galpha_reference), shared with
# test_sim_model_selection.
target_sources(ffrf_testing PRIVATE unit/galpha_reference.f90)
target_sources(ffrf_testing_checked PRIVATE unit/galpha_reference.f90)
ffrf_add_unit_suite(test_stability_integrator CHECKED LABELS mbs)
# rho_inf = 1 refused with constraints; multipliers as rho_inf -> 1 on the pendulum and the rigid
# engine. ~0.4 s, checked ~1.2 s.
ffrf_add_unit_suite(test_stability_constraints CHECKED LABELS mbs)
# RBE3 on nearly collinear nodes and collinear interfaces in an RC set (a Tet4 box built in code).
ffrf_add_unit_suite(test_stability_mpc CHECKED LABELS mpc)
# Shift-invert with the shift next to an eigenvalue or to zero (spring chains). ~0.5 s each.
ffrf_add_unit_suite(test_stability_modes CHECKED LABELS modes)
# Free-free Tet10 beam (beam_lc6) with shifts next to zero through the modal pipeline. ~6 s.
ffrf_add_unit_suite(test_stability_free_body LABELS modes FIXTURES beam_lc6_mesh)
# The energy watch of mechanism runs (issue 30, part 3) on energy histories with closed-form
# warning times: energy created, strain energy growing unpaid, paid growth, round-off. < 1 s.
ffrf_add_unit_suite(test_stability_energy_watch CHECKED LABELS mbs)
