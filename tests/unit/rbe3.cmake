# RBE3 weights pinned by closed forms (uniform, tributary and consistent area weights on Tri3 and
# Tri6 faces), node-set interfaces with given weights.
ffrf_add_unit_suite(test_rbe3_weights CHECKED LABELS "mpc;rbe3")
