# IFToMM / MBS benchmark problems with published definitions (issue 24, item 4), each against an
# exact solution, a published reference, an independent second method or a conservation law
# (docs/validation.md "Multibody benchmark problems").

# One IFToMM check: NAME runs tests/regression/SCRIPT on input/CASE with the driver, the mesh
# folder and the work folder tests/NAME, then any further arguments; labels regression, iftomm.
function(add_iftomm_test name script case)
  add_test(NAME ${name}
    COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 ${Python3_EXECUTABLE}
      ${CMAKE_CURRENT_SOURCE_DIR}/regression/${script} $<TARGET_FILE:ffrf>
      ${PROJECT_SOURCE_DIR}/input/${case} ${PROJECT_BINARY_DIR}/meshes
      ${PROJECT_BINARY_DIR}/tests/${name} ${ARGN})
  set_tests_properties(${name} PROPERTIES LABELS "regression;iftomm")
endfunction()

# The checks:
#  - regression_iftomm_a01: the simple pendulum (input/iftomm_a01_pendulum.nml, 10 s of the
#    benchmark's 2000 s) against the exact elliptic-function solution, at the benchmark's
#    high-precision tolerance 1e-3 m, with order 2 between h and h/2 and the energy kept
#    (tests/regression/check_iftomm_pendulum.py). About 2 s.
add_iftomm_test(regression_iftomm_a01 check_iftomm_pendulum.py iftomm_a01_pendulum.nml)
#  - regression_iftomm_a01_index2: the same with the stabilized index-2 constraints and no
#    numerical damping (constraints = 'index2', rho_inf = 1; docs/theory.md 4.6), under the same
#    tolerances: 1e-3 m, order 2 +- 0.2, energy 1e-4 m g L. About 2 s.
add_iftomm_test(regression_iftomm_a01_index2 check_iftomm_pendulum.py iftomm_a01_pendulum.nml
  integrator.constraints=index2 integrator.rho_inf=1)

#  - regression_iftomm_a03: Andrews' squeezing mechanism (input/iftomm_a03_andrews.nml, 7 rigid
#    bodies, 10 revolute joints of which 9 equations are redundant in 3D, a spring, a constant
#    torque) against the IVP test set's reference solution at t = 0.03 s (Mazzia & Magherini,
#    Bari; Hairer & Wanner II sec. VII.7): angles to 5e-4 rad, rates to 1e-2, order 2 between
#    h = 2e-5 and 1e-5 s (tests/regression/check_iftomm_andrews.py). About 8 s.
add_iftomm_test(regression_iftomm_a03 check_iftomm_andrews.py iftomm_a03_andrews.nml)

#  - regression_iftomm_a02: the N-four-bar, N = 1 (input/iftomm_a02_fourbar.nml), 10 s through
#    ten singular configurations, against the exact solution of the parallelogram (a rotating
#    pendulum, Jacobi elliptic functions): the benchmark's high precision 1e-3 on B0's position
#    and velocity at h = 5e-4 s, order 2 between h = 1e-3 and 5e-4 s. About 5 s.
#  - regression_iftomm_a02_n40: the benchmark's N = 40 (input/iftomm_a02_fourbar_n40.nml, 81
#    bodies, 120 redundant equations dropped), its first 1.3 s (both singular configurations,
#    theta = 0 and -pi) at h = 2e-3 s, same reference and precision. About 10 s.
#  (tests/regression/check_iftomm_fourbar.py; the full 20 s of N = 40 is the target
#  benchmark_iftomm_a02 in postprocess/CMakeLists.txt.)
add_iftomm_test(regression_iftomm_a02 check_iftomm_fourbar.py iftomm_a02_fourbar.nml
  --steps 1e-3,5e-4)
add_iftomm_test(regression_iftomm_a02_n40 check_iftomm_fourbar.py iftomm_a02_fourbar_n40.nml
  --t-end 1.3 --steps 2e-3)

#  - regression_iftomm_a05: the stiff flyball governor (input/iftomm_a05_flyball.nml, revolute,
#    prismatic and two stiff spring-dampers, 10 s) against the laws it must keep: angular momentum
#    about the shaft to 1e-5, energy balance with the dampers' dissipation to 1e-5, order >= 1.8
#    of the momentum drift between h = 1e-3 and 5e-4 s (tests/regression/check_iftomm_flyball.py; the
#    benchmark's s history is a data file not available here). About 10 s.
add_iftomm_test(regression_iftomm_a05 check_iftomm_flyball.py iftomm_a05_flyball.nml)

#  - regression_iftomm_a04: Bricard's mechanism (input/iftomm_a04_bricard.nml, five rods and six
#    hinges in one loop, over-constrained: one equation redundant at every pose), 10 s, against
#    P3 from an independent joint-coordinate solution (tests/regression/iftomm_bricard_reference.py,
#    its table in the check): 1e-4 m at h = 1e-3 s, order 2 between 2e-3 and 1e-3 s, energy to
#    1e-5 (tests/regression/check_iftomm_bricard.py). It fails without issue 24's fix of
#    find_redundant_rows (a body's Euler-parameter normalisation was dropped; the run stopped at
#    t = 2.495 s). About 5 s.
add_iftomm_test(regression_iftomm_a04 check_iftomm_bricard.py iftomm_a04_bricard.nml)
