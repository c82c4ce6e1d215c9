# The automatic engine model's error estimates (ffrf_app_engine_model_selection) against closed
# forms: generalized-alpha as the trapezoidal rule, forced responses, jointed masses, harmonics, the
# mean torque by a second route, the greedy mode and step choices. Under a second.
ffrf_add_unit_suite(test_sim_model_selection CHECKED LABELS mbs)
# The modes the joints leave free (ffrf_app_joint_free_modes) on manufactured bodies whose free
# modes, free shares and combinations are written out by hand. Well under a second.
ffrf_add_unit_suite(test_app_joint_free_modes CHECKED LABELS model)
