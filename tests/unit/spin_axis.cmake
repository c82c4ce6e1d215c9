# FFRF inertia coupling at mechanism level (issue 13, item 5): the spin-up beam with a cantilever
# RC basis spun about its own axis; the inertial tip motion must not depend on the spin
# (test_mbs_spin_axis.f90). ~2 s.
ffrf_add_unit_suite(test_mbs_spin_axis LABELS mbs FIXTURES spin_shaft_lc10_mesh)
