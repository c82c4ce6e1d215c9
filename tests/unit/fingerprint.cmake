# The fingerprint of stored modes (&body modes_file): FNV-1a against its published vectors and
# an independent Python implementation, each kind of difference named. Instant, no mesh.
ffrf_add_unit_suite(test_modes_fingerprint CHECKED LABELS model)
