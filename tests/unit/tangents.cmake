# Analytic Newton tangents of the mechanism (stiffness, damping, constraint and mass stiffness)
# against central differences: rigid engine with gravity and drive, engine with a synthetic
# flexible crank, universal and spherical joints. Under a second, checked a few seconds.
ffrf_add_unit_suite(test_mbs_tangents CHECKED LABELS mbs)
