# Generalized-alpha on a statically indeterminate reaction through a stiff spring (k = 1e6 ..
# 1e15 N/m): the round-off floor of the Newton increment. Under a second, checked too.
ffrf_add_unit_suite(test_mbs_stiff CHECKED LABELS mbs)
