# Peer code (issue 30, part 2; docs/theory.md 4.5): the engine in Exudyn on ffrf's bodies and modes
# (postprocess/peer_exudyn_engine.py; M and K assembled in numpy, Exudyn's FFRF reduced-order
# bodies, generalized-alpha with the case's rho_inf). The fixture makes a virtual environment with
# Exudyn from PyPI (postprocess/exudyn_venv.py); without it (no python3-venv, no network) both
# tests are skipped (exit 77). The check: crank RC set 2, 2 % modal damping, 10 RC modes per body,
# lc 8 mm meshes, h = 1e-4 s, 0.2 s: Exudyn's crank speed against ffrf's at every step, and the
# Rayleigh quotients of ffrf's modes with the numpy M and K (1e-7).
set(_peer "${PROJECT_BINARY_DIR}/tests/peer_exudyn")
add_test(NAME peer_exudyn_venv
  COMMAND ${Python3_EXECUTABLE} ${PROJECT_SOURCE_DIR}/postprocess/exudyn_venv.py
    ${PROJECT_BINARY_DIR}/exudyn_venv)
set_tests_properties(peer_exudyn_venv PROPERTIES LABELS "regression;peer" SKIP_RETURN_CODE 77
  FIXTURES_SETUP exudyn_venv)
add_test(NAME peer_exudyn_engine_rc2
  COMMAND ${Python3_EXECUTABLE} ${PROJECT_SOURCE_DIR}/postprocess/study_exudyn_engine.py
    --ffrf $<TARGET_FILE:ffrf> --mesh-dir ${PROJECT_BINARY_DIR}/meshes
    --input-dir ${PROJECT_SOURCE_DIR}/input --work ${_peer}
    --python ${PROJECT_BINARY_DIR}/exudyn_venv/bin/python --skip-code 77
    --cases rc2_damped --t-end 0.2 --num-modes 10 --h 1e-4 --csv ${_peer}/peer_exudyn_engine_rc2.csv
    # measured: max 1.07e-4 rad/s (at 227 rad/s), mean 5.0e-6 rad/s; strain energies 2.4e-6 of
    # their maxima (crank and conrod); bounds 10x those
    -- --speed-tol 1e-3 --mean-speed-tol 5e-5 --strain-tol 2.5e-5)
set_tests_properties(peer_exudyn_engine_rc2 PROPERTIES LABELS "regression;engine;peer"
  SKIP_RETURN_CODE 77 FIXTURES_REQUIRED "exudyn_venv;crank_lc8_mesh;conrod_lc8_mesh")
