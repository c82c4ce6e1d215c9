# geometry: the independent beam reference (Timoshenko, torsion) used by the accuracy test on
# input/beam.geo, and its checks. The meshes themselves are ctest fixtures in input/CMakeLists.txt.
target_sources(ffrf_testing PRIVATE unit/beam_reference.f90)
target_sources(ffrf_testing_checked PRIVATE unit/beam_reference.f90)
ffrf_add_unit_suite(test_reference_beam)
