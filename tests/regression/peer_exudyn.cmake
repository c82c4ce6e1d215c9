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

# The Exudyn export (issue 26; docs/results.md "Exudyn export"; tests/regression/exudyn_export.py)
# checked by Exudyn itself: each body (lc 8 mm meshes) exported by a modal run loads with
# FEMinterface.LoadFromFile; scipy's eigen-solution of the loaded M and K gives ffrf's free-free
# frequencies (1e-8; measured 2.5e-10 crank, 1.0e-9 conrod), the mass, the Tet10 (C3D10) and
# Trigs6 node orders, the outward surface, the node sets and the RC normal and Craig-Bampton
# bases (Psi^T M Psi = I, Psi^T K Psi = diag(eigenValues), 1e-9; measured 2e-14) are checked;
# and the conrod exported, hinged to the ground in Exudyn and driven by a torque, follows ffrf's
# run of the same scene (angle 1e-10 rad, measured 4.9e-13). About 15 + 10 + 10 s of CPU.
foreach(_body crank conrod)
  add_test(NAME peer_exudyn_export_${_body}
    COMMAND ${Python3_EXECUTABLE} ${PROJECT_SOURCE_DIR}/tests/regression/exudyn_export.py load
      $<TARGET_FILE:ffrf> ${PROJECT_BINARY_DIR}/meshes ${PROJECT_SOURCE_DIR}/input
      ${_peer}/export_${_body} --python ${PROJECT_BINARY_DIR}/exudyn_venv/bin/python
      --body ${_body})
  set_tests_properties(peer_exudyn_export_${_body} PROPERTIES LABELS "regression;peer"
    SKIP_RETURN_CODE 77 FIXTURES_REQUIRED "exudyn_venv;crank_lc8_mesh;conrod_lc8_mesh")
endforeach()
add_test(NAME peer_exudyn_export_hinge
  COMMAND ${Python3_EXECUTABLE} ${PROJECT_SOURCE_DIR}/tests/regression/exudyn_export.py hinge
    $<TARGET_FILE:ffrf> ${PROJECT_BINARY_DIR}/meshes ${PROJECT_SOURCE_DIR}/input
    ${_peer}/export_hinge --python ${PROJECT_BINARY_DIR}/exudyn_venv/bin/python)
set_tests_properties(peer_exudyn_export_hinge PROPERTIES LABELS "regression;peer"
  SKIP_RETURN_CODE 77 FIXTURES_REQUIRED "exudyn_venv;conrod_lc8_mesh")

# The Exudyn export of a mechanism run (issue 26; tests/regression/exudyn_export.py mechanism and
# hinge_mechanism): the engine (lc 8 mm, crank RC set 1 and conrod, 10 modes each) run 5 ms with
# --set run.export=exudyn writes each flexible body's file as a modal run does: it loads; scipy's
# eigen-solution of its M and K gives the free-free frequencies of ffrf's modal run of the body
# (1e-8; measured 2.5e-10 crank, 1.0e-9 conrod); its basis is the mechanism's modes with
# Psi^T M Psi = I, Psi^T K Psi = diag(omega^2) (1e-9; measured 2e-14). The hinge scene with the
# file its own run wrote reproduces ffrf's angles (1e-10 rad; measured 4.9e-13). About 15 + 3 s
# of CPU.
add_test(NAME peer_exudyn_export_mechanism
  COMMAND ${Python3_EXECUTABLE} ${PROJECT_SOURCE_DIR}/tests/regression/exudyn_export.py mechanism
    $<TARGET_FILE:ffrf> ${PROJECT_BINARY_DIR}/meshes ${PROJECT_SOURCE_DIR}/input
    ${_peer}/export_mechanism --python ${PROJECT_BINARY_DIR}/exudyn_venv/bin/python
    --case ${PROJECT_BINARY_DIR}/tests/engine/engine_lc8_rc1.nml)
set_tests_properties(peer_exudyn_export_mechanism PROPERTIES LABELS "regression;engine;peer"
  SKIP_RETURN_CODE 77 FIXTURES_REQUIRED "exudyn_venv;crank_lc8_mesh;conrod_lc8_mesh")
add_test(NAME peer_exudyn_export_hinge_mechanism
  COMMAND ${Python3_EXECUTABLE} ${PROJECT_SOURCE_DIR}/tests/regression/exudyn_export.py
    hinge_mechanism $<TARGET_FILE:ffrf> ${PROJECT_BINARY_DIR}/meshes ${PROJECT_SOURCE_DIR}/input
    ${_peer}/export_hinge_mechanism --python ${PROJECT_BINARY_DIR}/exudyn_venv/bin/python)
set_tests_properties(peer_exudyn_export_hinge_mechanism PROPERTIES LABELS "regression;peer"
  SKIP_RETURN_CODE 77 FIXTURES_REQUIRED "exudyn_venv;conrod_lc8_mesh")
