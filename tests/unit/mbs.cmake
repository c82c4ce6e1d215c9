# Reduced flexible body (FFRF): Euler parameters, invariants, mass matrix, quadratic velocity
# vector, markers; on the crank_lc8 (RC set 3) and beam_lc6 (free-free) meshes. ~3 s, checked ~7 s.
ffrf_add_unit_suite(test_mbs_flexible_body CHECKED LABELS mbs FIXTURES "crank_lc8_mesh;beam_lc6_mesh")
# Generalized-alpha integrator; about a second.
ffrf_add_unit_suite(test_mbs_generalized_alpha CHECKED LABELS mbs)
# In-cylinder pressure model and slider-crank kinematics.
ffrf_add_unit_suite(test_mbs_pressure CHECKED LABELS mbs)
# Rigid bodies, ground, flexible bodies and joints between markers; rigid-flexible pairs on
# the crank_lc8 mesh (RC set 3). ~3 s, checked a few seconds more.
ffrf_add_unit_suite(test_mbs_joints CHECKED LABELS mbs FIXTURES crank_lc8_mesh)
# Mechanism with generalized-alpha: driven slider-crank, free body, engine start. ~4 s, checked ~10
# s.
ffrf_add_unit_suite(test_mbs_mechanism CHECKED LABELS mbs)
# Engine with a flexible crank (stiffened modes) against the rigid-crank engine. ~7 s.
ffrf_add_unit_suite(test_mbs_flexible_engine LABELS mbs FIXTURES crank_lc8_mesh)
# The abstract body and its extensions (ground, rigid, flexible) through class(body_t): energies
# of the energy balance, a flexible body added to a mechanism directly. Well under a second.
ffrf_add_unit_suite(test_mbs_body CHECKED LABELS mbs)
# Reported multipliers of near-redundant constraint rows (issue 30): minimum norm on a
# self-stress the modes resolve poorly, closed form. Well under a second.
ffrf_add_unit_suite(test_mbs_reaction_split CHECKED LABELS mbs)
# Uniform gravity on flexible bodies (issue 24, docs/theory.md 3.6): the generalized force
# against the potential and point masses, its tangent, a cantilever's static sag against beam
# theory (beam_lc6, beam_lc4 for the mesh part), a damped run to rest, a flexible double
# pendulum's energy (beam_lc40), and the same with rho_inf = 1 and the stabilized index-2
# constraints over 2 s (theory.md 4.6; 0.8 s CPU, checked 2.5 s). ~10 s (beam_lc4's modes: 6 s),
# checked ~25 s.
ffrf_add_unit_suite(test_mbs_gravity CHECKED LABELS mbs FIXTURES "beam_lc6_mesh;beam_lc4_mesh;beam_lc40_mesh")
# Sparse LU of the iteration matrix (MUMPS) against the dense LU on a chain's saddle-point
# matrix, pattern growth, singular matrix; the integrator on a chain of point masses with both;
# its steps on one BLAS thread (issue 24). About a second.
ffrf_add_unit_suite(test_mbs_sparse_iteration CHECKED LABELS mbs)
# Laws over time, drivers of joints and loads over time (issue 24): time functions against
# closed forms, a driven pendulum's torque and a driven slider's force against closed forms,
# energy balance, a table force on a free mass. A few seconds.
ffrf_add_unit_suite(test_mbs_drivers CHECKED LABELS mbs)
