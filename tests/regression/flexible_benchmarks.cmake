# Flexible benchmarks (issue 24 item 4; docs/validation.md "Flexible benchmarks"): scenes of
# input/ that a user copies, each checked against an independent reference.
#
# Static sag of a cantilever under its own weight (input/cantilever_sag.nml, mesh cantilever):
# the scene run to rest with 2, 4, 8 and its own 12 modes; check_cantilever_sag.py compares the
# sag with Timoshenko beam theory and, where CalculiX is installed, with the full static FE
# solution K u = f of the same mesh (the modal truncation error must fall as modes are added).
# About 4 x 0.5 s of CPU, and 0.4 s for CalculiX.
find_program(CCX_EXECUTABLE ccx)
set(_flex "${PROJECT_BINARY_DIR}/tests/flexible_benchmarks")
# flex_run(NAME CASE DIR FIXTURE MESH [ARGS...]): the driver on CASE into ${_flex}/DIR, one thread
function(flex_run name case dir fixture mesh)
  file(MAKE_DIRECTORY "${_flex}/${dir}")
  add_test(NAME ${name}
    COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 $<TARGET_FILE:ffrf> ${case}
      --mesh-dir ${PROJECT_BINARY_DIR}/meshes --output-dir ${_flex}/${dir} --quiet ${ARGN})
  set_tests_properties(${name} PROPERTIES LABELS "regression;mbs"
    FIXTURES_REQUIRED ${mesh}_mesh FIXTURES_SETUP ${fixture})
endfunction()
set(_sag "${PROJECT_SOURCE_DIR}/input/cantilever_sag.nml")
flex_run(regression_cantilever_sag ${_sag} sag cantilever_sag_results cantilever)
set(_sag_runs "")
foreach(_modes 2 4 8)
  flex_run(regression_cantilever_sag_modes${_modes} ${_sag} sag_modes${_modes}
    cantilever_sag_results cantilever --set "body[bar].num_modes=${_modes}")
  list(APPEND _sag_runs ${_flex}/sag_modes${_modes}/cantilever_sag.h5)
endforeach()
set(_ccx_args "")
if(CCX_EXECUTABLE)
  set(_ccx_args --ccx ${CCX_EXECUTABLE} --mesh ${PROJECT_BINARY_DIR}/meshes/cantilever.msh
    --work ${_flex}/sag_ccx)
endif()
add_test(NAME regression_cantilever_sag_values
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_cantilever_sag.py
    ${_ccx_args} ${_sag_runs} ${_flex}/sag/cantilever_sag.h5)
set_tests_properties(regression_cantilever_sag_values PROPERTIES
  LABELS "regression;mbs" FIXTURES_REQUIRED "cantilever_sag_results;cantilever_mesh")

# Spatial double pendulum of flexible links, perpendicular joint axes (input/spatial_pendulum.nml,
# mesh link): runs at h and h/2 (energy T + U - W and its order 2 in h), with the links stiffened
# to 1e13 Pa, and the same scene of rigid bodies (spatial_pendulum_rigid.nml);
# check_spatial_pendulum.py. About 0.5 + 1 + 0.5 + 0.2 s of CPU.
set(_spatial "${PROJECT_SOURCE_DIR}/input/spatial_pendulum.nml")
flex_run(regression_spatial_pendulum ${_spatial} spatial spatial_pendulum_results link)
flex_run(regression_spatial_pendulum_half ${_spatial} spatial_half spatial_pendulum_results link
  --set integrator.h=2.5e-4)
flex_run(regression_spatial_pendulum_stiff ${_spatial} spatial_stiff spatial_pendulum_results link
  --set "body[link1].young=1e13" --set "body[link2].young=1e13")
flex_run(regression_spatial_pendulum_rigid
  ${CMAKE_CURRENT_SOURCE_DIR}/regression/spatial_pendulum_rigid.nml spatial_rigid
  spatial_pendulum_results link)
add_test(NAME regression_spatial_pendulum_values
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_spatial_pendulum.py
    ${_flex}/spatial/spatial_pendulum.h5 --half ${_flex}/spatial_half/spatial_pendulum.h5
    --stiff ${_flex}/spatial_stiff/spatial_pendulum.h5
    --rigid ${_flex}/spatial_rigid/spatial_pendulum_rigid.h5)
set_tests_properties(regression_spatial_pendulum_values PROPERTIES
  LABELS "regression;mbs" FIXTURES_REQUIRED spatial_pendulum_results)

# Flexible slider-crank (input/flexible_slider_crank.nml, mesh slider_rod): a rigid crank driven
# to 150 rad/s, a flexible steel rod (6 simply supported modes), a slider; 0.1 s at h = 2e-5 s.
# check_flexible_slider_crank.py runs the case and a modal run of the rod that exports it to
# Exudyn, then Exudyn's ObjectFFRFreducedOrder of the same rod, crank law and slider: the
# mid-span deflection within 1e-8 of its peak (measured 8.4e-11), the slider's travel within
# 1e-10 m; and a pinned-pinned Euler-Bernoulli beam moved by the rigid mechanism: peak within
# 1 %, history within 4 % of the peak. Skipped (77) without the Exudyn environment. About 7 s
# of CPU (ffrf 1.5 s, Exudyn 4 s).
add_test(NAME regression_flexible_slider_crank
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_flexible_slider_crank.py
    $<TARGET_FILE:ffrf> ${PROJECT_BINARY_DIR}/meshes
    ${PROJECT_SOURCE_DIR}/input/flexible_slider_crank.nml ${_flex}/slider_crank
    --python ${PROJECT_BINARY_DIR}/exudyn_venv/bin/python
    --csv ${_flex}/slider_crank/flexible_slider_crank.csv)
set_tests_properties(regression_flexible_slider_crank PROPERTIES LABELS "regression;mbs;peer"
  ENVIRONMENT OPENBLAS_NUM_THREADS=1 SKIP_RETURN_CODE 77 FIXTURES_REQUIRED "exudyn_venv;slider_rod_mesh")

# Markers at mesh points of a flexible body (&marker node, group; docs/mechanisms.md "Markers at
# mesh points"), on the clamped cantilever (mesh cantilever): a static tip load at the tip face's
# RBE3 marker with 4, 8 and 16 modes against CalculiX's K u = G^T f of the same mesh (where ccx is
# installed), the node marker's position and frame against the node_position sensor and the body
# frame, mode reuse, and the energy balance of a load over time at the node marker, alone and
# with a spring and a bushing at the markers; check_mesh_markers.py writes and runs the cases.
# About 10 s of wall time (8 short runs and CalculiX).
set(_markers_args "")
if(CCX_EXECUTABLE)
  set(_markers_args --ccx ${CCX_EXECUTABLE})
endif()
add_test(NAME regression_mesh_markers
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_mesh_markers.py
    $<TARGET_FILE:ffrf> ${PROJECT_BINARY_DIR}/meshes ${_flex}/mesh_markers ${_markers_args})
set_tests_properties(regression_mesh_markers PROPERTIES LABELS "regression;mbs"
  FIXTURES_REQUIRED cantilever_mesh)
# Markers at the centre of a physical curve and a physical point (the same cantilever meshed with
# its tip corner and tip edge as groups, mesh cantilever_groups): a static load at the curve's
# marker against Timoshenko's tip sag, the curve's marker against the mean of its node markers,
# the point group's marker against the node marker (bitwise, also as the loaded marker), an
# unknown group refused by --check; check_group_markers.py writes and runs the cases (3 short
# runs, about 10 s).
add_test(NAME regression_group_markers
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_group_markers.py
    $<TARGET_FILE:ffrf> ${PROJECT_BINARY_DIR}/meshes ${_flex}/group_markers)
set_tests_properties(regression_group_markers PROPERTIES LABELS "regression;mbs"
  FIXTURES_REQUIRED cantilever_groups_mesh)
# The [mechanism] log line counts interface markers apart from mesh-point markers (issue 24):
# input/cantilever_tip_load.nml has one interface (root) and one group marker (tip_face), run
# for one step. Under a second.
file(MAKE_DIRECTORY "${_flex}/marker_log")
add_test(NAME regression_mesh_marker_log
  COMMAND ${CMAKE_COMMAND}
    "-DCOMMAND=$<TARGET_FILE:ffrf>;${PROJECT_SOURCE_DIR}/input/cantilever_tip_load.nml;--mesh-dir;${PROJECT_BINARY_DIR}/meshes;--output-dir;${_flex}/marker_log;--set;integrator.t_end=1e-3"
    -DWORKING_DIRECTORY=${_flex}/marker_log
    "-DREGEX=bar: flexible \\(FFRF\\), [0-9]+ modes, mass [0-9.]+ kg, 1 interface marker\\(s\\), 1 at mesh points"
    -P ${CMAKE_CURRENT_SOURCE_DIR}/regression/expect_output.cmake)
set_tests_properties(regression_mesh_marker_log PROPERTIES LABELS "regression;mbs"
  FIXTURES_REQUIRED cantilever_mesh)
