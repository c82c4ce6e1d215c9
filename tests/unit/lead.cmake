# Suites of the MPC/RC/modal pipeline.
ffrf_add_unit_suite(test_mpc_rbe CHECKED LABELS mpc)
ffrf_add_unit_suite(test_modes_crank LABELS modes FIXTURES crank_lc8_mesh)
ffrf_add_unit_suite(test_modes_beam LABELS modes FIXTURES "beam_lc6_mesh;beam_lc4_mesh;beam_lc3_mesh;beam_tet4_mesh")
