# The automatic engine model's error estimates (ffrf_app_engine_model_selection) against closed
# forms: generalized-alpha as the trapezoidal rule, forced responses, jointed masses, harmonics, the
# mean torque by a second route, the greedy mode and step choices. Under a second.
ffrf_add_unit_suite(test_sim_model_selection CHECKED LABELS mbs)
