# Mesh reader suite (owner: mesh). gmsh meshes the .geo files of tests/data/mesh as fixtures into
# ${PROJECT_BINARY_DIR}/meshes/test_mesh/ ($FFRF_MESH_DIR/test_mesh); the hand-written .msh files
# are read from tests/data/mesh ($FFRF_TEST_DATA_DIR/mesh).
set(FFRF_TEST_MESH_SOURCE "${PROJECT_SOURCE_DIR}/tests/data/mesh")
set(FFRF_TEST_MESH_DIR "${PROJECT_BINARY_DIR}/meshes/test_mesh")
file(MAKE_DIRECTORY "${FFRF_TEST_MESH_DIR}")

# ffrf_test_mesh(<output name> <geo name> <gmsh options...>): one gmsh run, fixture test_mesh.
function(ffrf_test_mesh name geo)
  add_test(NAME test_mesh_gmsh_${name}
    COMMAND ${GMSH_EXECUTABLE} "${FFRF_TEST_MESH_SOURCE}/${geo}.geo" -3 ${ARGN} -v 2
      -o "${FFRF_TEST_MESH_DIR}/${name}.msh")
  set_tests_properties(test_mesh_gmsh_${name} PROPERTIES FIXTURES_SETUP test_mesh
    LABELS "unit;mesh")
endfunction()

ffrf_test_mesh(box_o1_41 box -order 1 -format msh41)
ffrf_test_mesh(box_o2_41 box -order 2 -format msh41)
ffrf_test_mesh(box_o2_41b box -order 2 -format msh41 -bin)
ffrf_test_mesh(box_o2_22 box -order 2 -format msh22)
ffrf_test_mesh(two_blocks_o2_41 two_blocks -order 2 -format msh41)
ffrf_test_mesh(surface_only_41 surface_only -order 1 -format msh41)

ffrf_add_unit_suite(test_mesh_gmsh CHECKED FIXTURES "test_mesh;crank_lc8_mesh" LABELS mesh)
ffrf_add_unit_suite(test_mesh_bulk_data CHECKED LABELS mesh)
# Physical curves and points (box.geo's x_edge and origin): their nodes in every format, in a
# body, and the mesh points (marker locations) at their centre (issue 24 item 1)
ffrf_add_unit_suite(test_mesh_groups FIXTURES test_mesh LABELS mesh)
