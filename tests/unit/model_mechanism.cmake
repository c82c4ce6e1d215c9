# The mechanism part of the model (src/model/mechanism.f90): joint and load kinds, selection,
# bodies as indices and markers as handles; on a case built in memory, no mesh. Instant.
ffrf_add_unit_suite(test_model_mechanism CHECKED LABELS model)
