# FFRF limits, rotating-beam spin-up (docs/validation.md "FFRF limits"): element geometric stiffness
# and the centrifugal load cases (0.05 s, checked 0.3 s); the modal geometric stiffness of the
# scaled spin-up beam against the rotating cantilever's closed forms (1.2 s, checked 4 s); the
# spin-up benchmark of Kane et al. against a Hencky bar chain (4 s; Release only: 15 s checked).
# The beam's data and the references are in spin_beam_reference.f90 (module ffrf_test_spin_beam).
target_sources(ffrf_testing PRIVATE unit/spin_beam_reference.f90)
target_sources(ffrf_testing_checked PRIVATE unit/spin_beam_reference.f90)
ffrf_add_unit_suite(test_fe_geometric_stiffness CHECKED LABELS fe)
ffrf_add_unit_suite(test_modes_geometric_stiffness CHECKED LABELS modes
  FIXTURES "spin_beam_lc20_mesh;spin_beam_lc10_mesh")
ffrf_add_unit_suite(test_mbs_spin_up LABELS mbs FIXTURES "spin_beam_lc20_mesh;spin_beam_lc10_mesh")
