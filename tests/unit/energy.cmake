# Energy balance (numerical and modal-damping dissipation) and momentum conservation of free rigid
# and flexible bodies under generalized-alpha (src/mbs/energy_balance.f90). ~2 s, checked ~6 s.
ffrf_add_unit_suite(test_mbs_energy CHECKED LABELS mbs)
