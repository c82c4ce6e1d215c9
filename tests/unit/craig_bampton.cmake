# Craig-Bampton mode basis suite (owner: study). Mesh fixture beam_lc40: input/beam.geo at
# lc = 40 mm, Tet10, 242 nodes (gmsh 4.8.4): small enough for the dense LAPACK references of
# the complete basis; the crank tests use the crank_lc8 fixture of input/CMakeLists.txt.
set(FFRF_MESH_DIR "${PROJECT_BINARY_DIR}/meshes")
ffrf_add_mesh(beam_lc40 beam 0.040 2)
ffrf_add_unit_suite(test_modes_craig_bampton CHECKED FIXTURES beam_lc40_mesh crank_lc8_mesh
  LABELS modes)
# The study scripts that chart the CB basis among the other speed/accuracy choices
include(${CMAKE_CURRENT_LIST_DIR}/study_scripts.cmake)
