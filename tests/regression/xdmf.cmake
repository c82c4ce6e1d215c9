# The XDMF export (&run export = 'xdmf'; issue 26, item 1; docs/results.md "XDMF export"), read
# back by meshio and checked against the HDF5 results it points into (check_xdmf.py: mesh,
# every mode and frame bitwise, node order geometrically):
#  - xdmf_crank_rc1: input/crank_rc1.nml on its full mesh (crank.msh, Tet10, 12 modes), the
#    export asked by --set run.export=xdmf;
#  - xdmf_beam_tet4: a clamped Tet4 beam (beam_tet4.msh, 4 modes), the export in the namelist;
#  - xdmf_engine: the lc 8 mm engine of engine.cmake (flexible crank and conrod, 4 animation
#    frames), --set run.export=xdmf; the frames also against the Gmsh animations;
#  - xdmf_export_bogus: --set run.export=bogus: exit 2, one line listing the export words;
#  - capi_export: ffrf_case_set_export (test_capi_export.c), its XDMF read back by
#    capi_export_xdmf; capi_export_fortran: ffrf_case_t%set_export with 'xdmf exudyn'
#    (test_export_fortran.f90), its XDMF read back by capi_export_fortran_xdmf.
# Each run takes seconds (crank ~10 s, engine ~7 s, beam ~2 s on one core).
set(_xdmf_out "${PROJECT_BINARY_DIR}/tests/xdmf")
file(MAKE_DIRECTORY "${_xdmf_out}" "${_xdmf_out}/capi")
set(_xdmf_check ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_xdmf.py)
set(_xdmf_options --mesh-dir ${PROJECT_BINARY_DIR}/meshes --output-dir ${_xdmf_out} --quiet)
set(_xdmf_beam "&body name = 'beam', mesh_file = 'beam_tet4.msh', young = 210.0e9, poisson = 0.3, density = 7850.0 /\n&interface body = 'beam', name = 'end0', mpc = 'RBE2', rc = 'Tx Ty Tz Rx Ry Rz' /\n&modes num_modes = 4 /\n")
file(WRITE "${_xdmf_out}/xdmf_beam_tet4.nml"
  "&run title = 'Tet4 beam, XDMF export', export = 'xdmf' /\n${_xdmf_beam}")
file(WRITE "${_xdmf_out}/xdmf_beam_tet4_plain.nml"
  "&run title = 'Tet4 beam, XDMF export through the C API' /\n${_xdmf_beam}")

add_test(NAME xdmf_crank_rc1_run COMMAND $<TARGET_FILE:ffrf>
  ${PROJECT_SOURCE_DIR}/input/crank_rc1.nml ${_xdmf_options} --set run.export=xdmf)
add_test(NAME xdmf_crank_rc1 COMMAND ${_xdmf_check} ${_xdmf_out}/crank_rc1.xdmf --bodies 1)
add_test(NAME xdmf_beam_tet4_run COMMAND $<TARGET_FILE:ffrf> ${_xdmf_out}/xdmf_beam_tet4.nml
  ${_xdmf_options})
add_test(NAME xdmf_beam_tet4 COMMAND ${_xdmf_check} ${_xdmf_out}/xdmf_beam_tet4.xdmf --bodies 1)
add_test(NAME xdmf_engine_run COMMAND $<TARGET_FILE:ffrf>
  ${PROJECT_BINARY_DIR}/tests/engine/engine_lc8_rc1.nml ${_xdmf_options} --set run.export=xdmf)
add_test(NAME xdmf_engine COMMAND ${_xdmf_check} ${_xdmf_out}/engine_lc8_rc1.xdmf --bodies 2
  --frames 4 --animation crank=${_xdmf_out}/engine_lc8_rc1_crank_animation.msh
  --animation conrod=${_xdmf_out}/engine_lc8_rc1_conrod_animation.msh)
foreach(_case crank_rc1 beam_tet4 engine)
  set_tests_properties(xdmf_${_case}_run PROPERTIES LABELS "regression;xdmf"
    ENVIRONMENT OPENBLAS_NUM_THREADS=1 FIXTURES_SETUP xdmf_${_case})
  set_tests_properties(xdmf_${_case} PROPERTIES LABELS "regression;xdmf;postprocess"
    FIXTURES_REQUIRED xdmf_${_case})
endforeach()
set_tests_properties(xdmf_crank_rc1_run PROPERTIES FIXTURES_REQUIRED crank_mesh)
set_tests_properties(xdmf_beam_tet4_run PROPERTIES FIXTURES_REQUIRED beam_tet4_mesh)
set_tests_properties(xdmf_engine_run PROPERTIES
  FIXTURES_REQUIRED "crank_lc8_mesh;conrod_lc8_mesh")

add_test(NAME xdmf_export_bogus COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:ffrf>;${_xdmf_out}/xdmf_beam_tet4_plain.nml;--mesh-dir;${PROJECT_BINARY_DIR}/meshes;--output-dir;${_xdmf_out};--set;run.export=xdmf bogus"
  -DEXIT_CODE=2
  "-DMESSAGE=--set run.export = xdmf bogus: export = \"bogus\" is not an export format; use one of xdmf"
  -P ${CMAKE_CURRENT_SOURCE_DIR}/regression/expect_error.cmake)
set_tests_properties(xdmf_export_bogus PROPERTIES LABELS "regression;xdmf;errors")

add_executable(test_capi_export capi/test_capi_export.c)
target_link_libraries(test_capi_export PRIVATE ffrf::ffrf m)
target_compile_options(test_capi_export PRIVATE ${_capi_flags})
target_link_options(test_capi_export PRIVATE ${_capi_link})
set_target_properties(test_capi_export PROPERTIES C_STANDARD 99 C_EXTENSIONS OFF)
add_test(NAME capi_export COMMAND test_capi_export ${_xdmf_out}/xdmf_beam_tet4_plain.nml
  ${PROJECT_BINARY_DIR}/meshes ${_xdmf_out}/capi)
set_tests_properties(capi_export PROPERTIES LABELS "capi;xdmf" ENVIRONMENT OPENBLAS_NUM_THREADS=1
  FIXTURES_REQUIRED beam_tet4_mesh FIXTURES_SETUP capi_export)
add_test(NAME capi_export_xdmf COMMAND ${_xdmf_check}
  ${_xdmf_out}/capi/xdmf_beam_tet4_plain.xdmf --bodies 1)
set_tests_properties(capi_export_xdmf PROPERTIES LABELS "capi;xdmf;postprocess"
  FIXTURES_REQUIRED capi_export)

# the same through the Fortran API, both exports (test_export_fortran.f90), its XDMF read back
file(MAKE_DIRECTORY "${_xdmf_out}/fortran")
add_executable(test_export_fortran capi/test_export_fortran.f90)
target_link_libraries(test_export_fortran PRIVATE ffrf_api_checks)
target_link_libraries(test_export_fortran PRIVATE ffrf::ffrf)
target_link_options(test_export_fortran PRIVATE "$<$<Fortran_COMPILER_ID:GNU>:-fno-lto>")
add_test(NAME capi_export_fortran COMMAND test_export_fortran
  ${_xdmf_out}/xdmf_beam_tet4_plain.nml ${PROJECT_BINARY_DIR}/meshes ${_xdmf_out}/fortran)
set_tests_properties(capi_export_fortran PROPERTIES LABELS "capi;xdmf" ENVIRONMENT
  OPENBLAS_NUM_THREADS=1 FIXTURES_REQUIRED beam_tet4_mesh FIXTURES_SETUP capi_export_fortran)
add_test(NAME capi_export_fortran_xdmf COMMAND ${_xdmf_check}
  ${_xdmf_out}/fortran/xdmf_beam_tet4_plain.xdmf --bodies 1)
set_tests_properties(capi_export_fortran_xdmf PROPERTIES LABELS "capi;xdmf;postprocess"
  FIXTURES_REQUIRED capi_export_fortran)
