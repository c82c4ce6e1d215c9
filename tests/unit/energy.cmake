# Energy balance (numerical and modal-damping dissipation) and momentum conservation of free rigid
# and flexible bodies under generalized-alpha (src/mbs/energy_balance.f90). ~2 s, checked ~6 s.
ffrf_add_unit_suite(test_mbs_energy CHECKED LABELS mbs)

# The balance's terms on two scenes of a meshed flexible beam (spin_beam_lc20): clamped free
# vibration against closed forms and the scheme's identity, and a driven, damped spin-up
# (conservation and the two quadratures); every term seen on a second scene (issue 28, item 5).
ffrf_add_unit_suite(test_mbs_energy_scenes LABELS mbs FIXTURES spin_beam_lc20_mesh)
