# fe and sparse suites (owner: fe). gmsh meshes tests/data/fe/*.geo as ctest fixtures (fixture
# fe_meshes) into ${PROJECT_BINARY_DIR}/meshes/test_fe/ ($FFRF_MESH_DIR/test_fe), MSH 2.2 ASCII
# (test_fe_assembly reads them with a small private reader).
#   name          geo     options                  nodes (gmsh 4.8.4)
#   box_tet4      box     -order 1 -clscale 0.5      291   (patch test needs interior nodes)
#   box_tet10     box     -order 2                   454
#   onetet_tet10  onetet  -order 2                    10   (Gmsh's Tet10 edge-node order)
#   cylinder_lc10 cylinder -order 2                  819   (curved Tet10/Tri6)
#   cylinder_lc5  cylinder -order 2 -clscale 0.5    4431
set(FFRF_TEST_FE_SOURCE "${PROJECT_SOURCE_DIR}/tests/data/fe")
set(FFRF_TEST_FE_DIR "${PROJECT_BINARY_DIR}/meshes/test_fe")
file(MAKE_DIRECTORY "${FFRF_TEST_FE_DIR}")

# ffrf_test_fe_mesh(<output name> <geo name> <gmsh options...>): one gmsh run, fixture fe_meshes.
function(ffrf_test_fe_mesh name geo)
  add_test(NAME test_fe_gmsh_${name}
    COMMAND ${GMSH_EXECUTABLE} "${FFRF_TEST_FE_SOURCE}/${geo}.geo" -3 ${ARGN} -format msh22 -v 2
      -o "${FFRF_TEST_FE_DIR}/${name}.msh")
  set_tests_properties(test_fe_gmsh_${name} PROPERTIES FIXTURES_SETUP fe_meshes
    LABELS "unit;fe" FAIL_REGULAR_EXPRESSION "Error *:")
endfunction()

ffrf_test_fe_mesh(box_tet4 box -order 1 -clscale 0.5)
ffrf_test_fe_mesh(box_tet10 box -order 2)
ffrf_test_fe_mesh(onetet_tet10 onetet -order 2)
ffrf_test_fe_mesh(cylinder_lc10 cylinder -order 2)
ffrf_test_fe_mesh(cylinder_lc5 cylinder -order 2 -clscale 0.5)

ffrf_add_unit_suite(test_la_sparse CHECKED LABELS la)
ffrf_add_unit_suite(test_fe_elements CHECKED LABELS fe)
ffrf_add_unit_suite(test_fe_assembly CHECKED FIXTURES fe_meshes LABELS fe)
