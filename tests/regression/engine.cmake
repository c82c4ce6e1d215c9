# Engine runs of the ffrf driver on the lc = 8 mm meshes, made from the real input files
# (input/engine_*.nml) with the mesh names, end time and animation changed, read back by
# check_engine.py:
#  - engine_lc8_all_rigid (0.3 s, three engine cycles for the charts): every body rigid (crank
#    and conrod with their meshes' inertia). The
#    redundant equations must be exactly those of the Gruebler-Kutzbach count: 4 moving bodies
#    (24 dofs) - 31 joint equations (5 revolute x 3 + 6 fixed + 5 prismatic) = -7 dofs for a
#    mechanism that has 1, so 8 equations are redundant; the run must complete.
#  - engine_lc8_rc1: flexible crank (RC set 1) and conrod, 10 modes each: the run completes,
#    the redundant equations are found and flagged, and the energy balance closes.
# These runs fix the model by hand (&model selection = 'manual', 10 modes, h = 1e-4 s); the
# automatic model is tested by regression_engine_auto below.
set(_out "${PROJECT_BINARY_DIR}/tests/engine")
file(MAKE_DIRECTORY "${_out}")

# ffrf_engine_case(<name> <input case> <t_end>): write ${_out}/<name>.nml
function(ffrf_engine_case name source t_end)
  file(READ "${PROJECT_SOURCE_DIR}/input/${source}.nml" text)
  ffrf_replace(text "'crank.msh'" "'crank_lc8.msh'")
  ffrf_replace(text "'conrod.msh'" "'conrod_lc8.msh'")
  ffrf_replace(text "t_end = 2.0" "t_end = ${t_end}")
  ffrf_replace(text "label = '" "animation_frames = 4, label = '")
  # the hand-set model of these tests: 10 modes per flexible body, h = 1e-4 s
  ffrf_replace(text "selection = 'auto'" "selection = 'manual'")
  ffrf_replace(text "&integrator t_end" "&integrator h = 1.0e-4, t_end")
  ffrf_replace(text "type = 'flexible', modal_damping = 0.02,\n"
    "type = 'flexible', modal_damping = 0.02, num_modes = 10,\n")
  set(_text "${text}" PARENT_SCOPE)
endfunction()

ffrf_engine_case(engine_lc8_rc1 engine_rc1 0.1)
file(WRITE "${_out}/engine_lc8_rc1.nml" "${_text}")

ffrf_engine_case(engine_lc8_all_rigid engine_rigid 0.3)
# The conrod rigid too: its interfaces become markers at the bore centres
ffrf_replace(_text "type = 'flexible', modal_damping = 0.02, num_modes = 10,\n      coarse_meshes = 'conrod_lc8.msh', position = 0.0, 0.045, 0.0 /"
  "type = 'rigid', position = 0.0, 0.045, 0.0 /\n&marker body = 'conrod', name = 'big_end', position = 0.0, 0.0, 0.0 /\n&marker body = 'conrod', name = 'small_end', position = 0.0, 0.150, 0.0 /")
string(REGEX MATCHALL "&interface body = 'conrod'[^/]*/\n" _conrod_interfaces "${_text}")
list(LENGTH _conrod_interfaces _count)
if(NOT _count EQUAL 2)
  message(FATAL_ERROR "engine.cmake: ${_count} &interface groups of the conrod in "
    "input/engine_rigid.nml, expected 2: the input file changed; update the edit")
endif()
string(REGEX REPLACE "&interface body = 'conrod'[^/]*/\n" "" _text "${_text}")
file(WRITE "${_out}/engine_lc8_all_rigid.nml" "${_text}")

# Started at a crank speed (check_start_speed.py): the all-rigid engine and the flexible crank of
# RC set 2 (whose flywheel interface turns in the modes), 1 ms each, the same kinetic energy at
# t = 0
string(REPLACE "crank_speed = 0.0" "crank_speed = 424.0" _spin "${_text}")
ffrf_replace(_spin "t_end = 0.3" "t_end = 0.001")
file(WRITE "${_out}/engine_lc8_spin_rigid.nml" "${_spin}")
ffrf_engine_case(engine_lc8_spin_rc2 engine_rc2 0.001)
ffrf_replace(_text "crank_speed = 0.0" "crank_speed = 424.0")
file(WRITE "${_out}/engine_lc8_spin_rc2.nml" "${_text}")
foreach(case engine_lc8_spin_rigid engine_lc8_spin_rc2)
  add_test(NAME regression_${case}
    COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 $<TARGET_FILE:ffrf> ${_out}/${case}.nml
      --mesh-dir ${PROJECT_BINARY_DIR}/meshes --output-dir ${_out} --quiet)
  set_tests_properties(regression_${case} PROPERTIES LABELS "regression;engine"
    FIXTURES_REQUIRED "crank_lc8_mesh;conrod_lc8_mesh" FIXTURES_SETUP ${case}_results)
endforeach()
add_test(NAME regression_engine_start_speed_check
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_start_speed.py
    ${_out}/engine_lc8_spin_rc2.h5 ${_out}/engine_lc8_spin_rigid.h5 --speed 424)
set_tests_properties(regression_engine_start_speed_check PROPERTIES
  LABELS "regression;engine;postprocess"
  FIXTURES_REQUIRED "engine_lc8_spin_rigid_results;engine_lc8_spin_rc2_results")


foreach(case engine_lc8_all_rigid engine_lc8_rc1)
  add_test(NAME regression_${case}
    COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 $<TARGET_FILE:ffrf> ${_out}/${case}.nml
      --mesh-dir ${PROJECT_BINARY_DIR}/meshes --output-dir ${_out})
  set_tests_properties(regression_${case} PROPERTIES LABELS "regression;engine"
    FIXTURES_REQUIRED "crank_lc8_mesh;conrod_lc8_mesh" FIXTURES_SETUP ${case}_results)
endforeach()
add_test(NAME regression_engine_lc8_all_rigid_check
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_engine.py
    ${_out}/engine_lc8_all_rigid.h5 --redundant 8)
set_tests_properties(regression_engine_lc8_all_rigid_check PROPERTIES
  LABELS "regression;engine;postprocess" FIXTURES_REQUIRED engine_lc8_all_rigid_results)
add_test(NAME regression_engine_lc8_rc1_check
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_engine.py
    ${_out}/engine_lc8_rc1.h5 --animation ${_out}/engine_lc8_rc1_crank_animation.msh
    # 10x its measured D = 6.05e-6 W, D_s = 4.0e-6 W, |D - D_s| <= 2.15e-6 W (0.1 s)
    --dissipation-max 6e-5 --scheme-max 4e-5 --residual-max 2.2e-5)
set_tests_properties(regression_engine_lc8_rc1_check PROPERTIES
  LABELS "regression;engine;postprocess" FIXTURES_REQUIRED engine_lc8_rc1_results)
add_test(NAME regression_engine_charts
  COMMAND ${CMAKE_COMMAND} -E chdir ${_out} ${Python3_EXECUTABLE}
    ${PROJECT_SOURCE_DIR}/postprocess/plot_engine.py engine_lc8_all_rigid.h5 engine_lc8_rc1.h5
    -o engine_lc8_speed.png --pressure engine_lc8_pressure.png)
set_tests_properties(regression_engine_charts PROPERTIES LABELS "regression;engine;postprocess"
  FIXTURES_REQUIRED "engine_lc8_all_rigid_results;engine_lc8_rc1_results"
  FIXTURES_SETUP engine_lc8_charts)
# the charts read back: PNG files of a real size, not blank
add_test(NAME regression_engine_charts_content
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_outputs.py png
    ${_out}/engine_lc8_speed.png ${_out}/engine_lc8_pressure.png)
set_tests_properties(regression_engine_charts_content PROPERTIES
  LABELS "regression;engine;postprocess" FIXTURES_REQUIRED engine_lc8_charts)

# A failing integration (Newton allowed 2 iterations, no step cut allowed): exit 4, one-line
# message naming the time, and the results file closed with status 'error: ...', every recorded
# step and the last converged state.
ffrf_engine_case(engine_lc8_fail engine_rigid 0.1)
ffrf_replace(_text "rho_inf = 0.8 /" "rho_inf = 0.8, max_iterations = 2, min_step = 1.0e-4 /")
file(WRITE "${_out}/engine_lc8_fail.nml" "${_text}")
add_test(NAME regression_engine_lc8_fail
  COMMAND ${CMAKE_COMMAND}
    "-DCOMMAND=$<TARGET_FILE:ffrf>;${_out}/engine_lc8_fail.nml;--mesh-dir;${PROJECT_BINARY_DIR}/meshes;--output-dir;${_out}"
    -DEXIT_CODE=4 "-DMESSAGE=generalized-alpha: no convergence at t = "
    -P ${CMAKE_CURRENT_SOURCE_DIR}/regression/expect_error.cmake)
set_tests_properties(regression_engine_lc8_fail PROPERTIES LABELS "regression;engine;errors"
  FIXTURES_REQUIRED "crank_lc8_mesh;conrod_lc8_mesh" FIXTURES_SETUP engine_lc8_fail_results)
add_test(NAME regression_engine_lc8_fail_check
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_engine.py
    ${_out}/engine_lc8_fail.h5 --failed)
set_tests_properties(regression_engine_lc8_fail_check PROPERTIES
  LABELS "regression;engine;postprocess" FIXTURES_REQUIRED engine_lc8_fail_results)

# The real gmsh reads the crank's animation as one view with one time step per frame (4).
file(WRITE "${_out}/count_views.geo"
  "Merge \"engine_lc8_rc1_crank_animation.msh\";\nPrintf(\"views %g steps %g\", PostProcessing.NbViews, View[0].NbTimeStep);\n")
add_test(NAME regression_engine_animation_gmsh
  COMMAND ${CMAKE_COMMAND} "-DCOMMAND=${GMSH_EXECUTABLE};count_views.geo;-0;-o;count_views.geo_unrolled"
    -DWORKING_DIRECTORY=${_out} "-DREGEX=views 1 steps 4"
    -P ${CMAKE_CURRENT_SOURCE_DIR}/regression/expect_output.cmake)
set_tests_properties(regression_engine_animation_gmsh PROPERTIES LABELS "regression;engine"
  FIXTURES_REQUIRED engine_lc8_rc1_results)

# The automatic model (issue 4, part 3): the real input/engine_rc1.nml (2 s, candidate meshes
# crank lc 10/8/6 mm, conrod 8/5 mm) against its hand-set model input/engine_rc1_manual.nml
# (10 modes per body, lc 6/5 mm, h = 1e-4 s): check_auto_model.py. About 6 + 7 s.
set(_auto "${PROJECT_BINARY_DIR}/tests/engine_auto")
file(MAKE_DIRECTORY "${_auto}")
foreach(case engine_rc1 engine_rc1_manual)
  add_test(NAME regression_auto_${case}
    COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 $<TARGET_FILE:ffrf>
      ${PROJECT_SOURCE_DIR}/input/${case}.nml --mesh-dir ${PROJECT_BINARY_DIR}/meshes
      --output-dir ${_auto} --quiet)
  set_tests_properties(regression_auto_${case} PROPERTIES LABELS "regression;engine"
    FIXTURES_REQUIRED "crank_mesh;crank_lc8_mesh;crank_lc10_mesh;conrod_mesh;conrod_lc8_mesh"
    FIXTURES_SETUP auto_${case}_results)
endforeach()
# The converged reference of the same engine (issue 30; postprocess/benchmark_auto_model.py, run
# 'converged'): the finest meshes, every mode the joints leave free among 30 candidates that
# moves a joint force by more than 1e-5, h = 2.5e-5 s. About 30 s.
add_test(NAME regression_auto_engine_rc1_converged
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 $<TARGET_FILE:ffrf>
    ${PROJECT_SOURCE_DIR}/input/engine_rc1.nml --mesh-dir ${PROJECT_BINARY_DIR}/meshes
    --output-dir ${_auto} --output engine_rc1_converged.h5 --quiet
    --set model.speed_tolerance=1e-6 --set model.force_tolerance=1e-5
    --set model.candidate_modes=30 --set integrator.h=2.5e-5
    --set "body[crank].coarse_meshes=''" --set "body[conrod].coarse_meshes=''")
set_tests_properties(regression_auto_engine_rc1_converged PROPERTIES LABELS "regression;engine"
  FIXTURES_REQUIRED "crank_mesh;conrod_mesh" FIXTURES_SETUP auto_engine_rc1_converged_results)
add_test(NAME regression_auto_model_check
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_auto_model.py
    ${_auto}/engine_rc1.h5 ${_auto}/engine_rc1_manual.h5
    --converged ${_auto}/engine_rc1_converged.h5)
set_tests_properties(regression_auto_model_check PROPERTIES
  LABELS "regression;engine;postprocess"
  FIXTURES_REQUIRED
    "auto_engine_rc1_results;auto_engine_rc1_manual_results;auto_engine_rc1_converged_results")

# Reactions of near-redundant joints (issue 30, part 4): the first engine variant of the issue
# (piston 0.9 kg, compression ratio 12) on a hand-set model that keeps what the automatic model
# kept before its joint-free candidates (issue 30, part 1): the crank on lc 10 mm with 4 modes,
# the conrod on lc 8 mm with 2, both of which are in-plane, so that the out-of-plane loop (main
# bearings, crank pin, piston pin, cylinder) closes through modes that barely move along it
# (participation down to 1e-6). Its pin-axis reactions reach 2.5e8 N in 0.3 s (main bearings
# 4e8 N) without the minimum-norm rule of ffrf_mbs_reaction_split. 0.3 s, against the same
# variant with every body rigid (engine_lc8_all_rigid.nml, same h = 1e-4 s): check_reactions.py.
# Tolerances (tests/TOLERANCES.md): pin-axis force <= 0.1 x the peak conrod force (measured
# 0.033; 9.4e3 without the rule), in-plane pin forces within 1e-3 of the rigid engine's peak
# (measured <= 6.1e-5). About 2 + 1 s.
set(_variant --set "body[piston].mass=0.9" --set "pressure.compression_ratio=12"
  --set "integrator.t_end=0.3")
add_test(NAME regression_reactions_variant_flexible
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 $<TARGET_FILE:ffrf>
    ${PROJECT_SOURCE_DIR}/input/engine_rc1_manual.nml --mesh-dir ${PROJECT_BINARY_DIR}/meshes
    --output-dir ${_auto} --output reactions_variant.h5 --quiet ${_variant}
    --set "body[crank].mesh_file=crank_lc10.msh" --set "body[crank].num_modes=4"
    --set "body[conrod].mesh_file=conrod_lc8.msh" --set "body[conrod].num_modes=2")
set_tests_properties(regression_reactions_variant_flexible PROPERTIES LABELS "regression;engine"
  FIXTURES_REQUIRED "crank_lc10_mesh;conrod_lc8_mesh" FIXTURES_SETUP reactions_variant_flexible)
add_test(NAME regression_reactions_variant_rigid
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 $<TARGET_FILE:ffrf>
    ${_out}/engine_lc8_all_rigid.nml --mesh-dir ${PROJECT_BINARY_DIR}/meshes
    --output-dir ${_auto} --output reactions_variant_rigid.h5 --quiet ${_variant})
set_tests_properties(regression_reactions_variant_rigid PROPERTIES LABELS "regression;engine"
  FIXTURES_REQUIRED "crank_lc8_mesh;conrod_lc8_mesh" FIXTURES_SETUP reactions_variant_rigid)
add_test(NAME regression_reactions_variant_check
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_reactions.py
    ${_auto}/reactions_variant.h5 ${_auto}/reactions_variant_rigid.h5
    --out-of-plane-max 0.1 --in-plane-rtol 1e-3)
set_tests_properties(regression_reactions_variant_check PROPERTIES
  LABELS "regression;engine;postprocess"
  FIXTURES_REQUIRED "reactions_variant_flexible;reactions_variant_rigid")

# The restart fingerprint (issue 23 item 3, issue 28 item 2; docs/restart.md), by
# restart_fingerprint.py on the finished lc 8 mm engine run above: every entry of the file's own
# /checkpoint/fingerprint_input changed alone through --set is refused by --restart (exit 2, one
# line naming the entry and both values, before any modes are computed); a mesh node moved by
# 1e-9 m and Young's modulus changed in its 14th digit (equal in the echo) are refused by the
# model entries; what may change (t_end, outputs, energy watch, progress, checkpoints) is
# accepted and the continued file records /restart_origin.
add_test(NAME regression_restart_fingerprint
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/restart_fingerprint.py
    $<TARGET_FILE:ffrf> ${PROJECT_BINARY_DIR}/meshes ${_out}/engine_lc8_rc1.nml
    ${_out}/engine_lc8_rc1.h5 ${PROJECT_BINARY_DIR}/tests/restart_fingerprint)
set_tests_properties(regression_restart_fingerprint PROPERTIES LABELS "regression;engine"
  TIMEOUT 300 FIXTURES_REQUIRED "engine_lc8_rc1_results;crank_lc8_mesh;conrod_lc8_mesh")
