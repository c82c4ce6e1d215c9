# The model layer (src/model/): strings of &interface and &modes to enumerations, num_modes
# decided once, interfaces as marker handles; on a case built in memory, no mesh. Instant.
ffrf_add_unit_suite(test_model_specs CHECKED LABELS model)
