# Rigid reference engine (scene.md): observed order of convergence in time of the crank angle and
# of the pin reactions, and the regime speed against the closed-form energy balance. ~4 s Release.
ffrf_add_unit_suite(test_mbs_engine_convergence LABELS mbs)
# The rigid reference engine as a fixture module, shared with test_stability_constraints.
target_sources(ffrf_testing PRIVATE unit/rigid_engine_fixture.f90)
target_sources(ffrf_testing_checked PRIVATE unit/rigid_engine_fixture.f90)
