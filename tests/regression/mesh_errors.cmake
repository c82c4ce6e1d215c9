# Mesh validation through the driver (issue 10, part 4): each hand-made mesh of tests/data/mesh/bad
# (made by make_bad_meshes.py there) holds one defect; ffrf must stop with exit 2 (3 for a file
# that is not a regular file) and one line "ffrf: error: ..." naming the file and the entity.
# Every case but inverted_tet ran to the end (or failed elsewhere, or hung) before the checks.
set(_mesh_dir "${PROJECT_SOURCE_DIR}/tests/data/mesh/bad")
set(_mesh_case_dir "${PROJECT_BINARY_DIR}/tests/mesh_errors")
file(MAKE_DIRECTORY "${_mesh_case_dir}")

# ffrf_mesh_error(<name> <exit code> <message regex> <mesh file> [surface]): a body "block" of the
# physical volume "block" with an interface on the physical surface "face" (or [surface]).
function(ffrf_mesh_error name code regex mesh)
  set(surface face)
  if(ARGC GREATER 4)
    set(surface ${ARGV4})
  endif()
  file(WRITE "${_mesh_case_dir}/${name}.nml"
    "&body name = 'block', mesh_file = '${mesh}', volumes = 'block' /\n&interface body = 'block', name = '${surface}', rc = '123456' /\n")
  add_test(NAME mesh_error_${name}
    COMMAND ${CMAKE_COMMAND}
      "-DCOMMAND=$<TARGET_FILE:ffrf>;${_mesh_case_dir}/${name}.nml;--mesh-dir;${_mesh_dir};--output-dir;${_mesh_case_dir}"
      -DEXIT_CODE=${code} "-DMESSAGE=${regex}" -P ${CMAKE_CURRENT_SOURCE_DIR}/regression/expect_error.cmake)
  set_tests_properties(mesh_error_${name} PROPERTIES LABELS "regression;errors;mesh" TIMEOUT 20)
endfunction()

# Volume elements other than Tet4/Tet10 in the body (a half-hex body gave 0.262 kg for 0.628 kg)
ffrf_mesh_error(hex_in_body 2
  "hex_in_body.msh.: the body's volumes hold 1 Hex8 \\(Gmsh type 5, first element 4, physical volume 'block'.*tetrahedra only.*Recombine"
  hex_in_body.msh)
ffrf_mesh_error(prism_in_body_22 2 "prism_in_body_22.msh.*1 Prism6 \\(Gmsh type 6.*'block'"
  prism_in_body_22.msh)
ffrf_mesh_error(pyramid_in_body_bin 2 "pyramid_in_body_bin.msh.*1 Pyramid5 \\(Gmsh type 7.*'block'"
  pyramid_in_body_bin.msh)
ffrf_mesh_error(unknown_type 2 "unknown_type.msh.: .Elements, line 31: .*curve entity 1 has element type 200"
  unknown_type.msh)
ffrf_mesh_error(type_dimension 2 "type_dimension.msh.*entity dimension 2 \\(entity 1\\) holds Tet4"
  type_dimension.msh)
# Tags and counts
ffrf_mesh_error(node_tag_zero 2 "node_tag_zero.msh.: .Nodes, line 17: node tag 0 is not allowed"
  node_tag_zero.msh)
ffrf_mesh_error(node_tag_zero_22 2 "node_tag_zero_22.msh.: .Nodes, line 11: node tag 0"
  node_tag_zero_22.msh)
ffrf_mesh_error(element_count 2 "element_count.msh.*element blocks hold 3 elements, the header announced 4"
  element_count.msh)
ffrf_mesh_error(node_range 2 "node_range.msh.*header gives node tags 1..6, the nodes have tags 1..5"
  node_range.msh)
ffrf_mesh_error(node_count_22 2 "node_count_22.msh.*Nodes announces 6 nodes, the section ends after 5"
  node_count_22.msh)
ffrf_mesh_error(huge_nodes 2 "huge_nodes.msh.*number of nodes = 2000000000 cannot be right: the 164 bytes left"
  huge_nodes.msh)
ffrf_mesh_error(huge_block 2 "huge_block.msh.*elements in block = 2000000000 cannot be right"
  huge_block.msh)
# Coordinates: a missing one where it is missing, a NaN as a NaN, naming the node
ffrf_mesh_error(missing_coordinate 2 "missing_coordinate.msh.: .Nodes, line 24: node 3: the line holds 2 of the node's 3 coordinates"
  missing_coordinate.msh)
ffrf_mesh_error(nan_coordinate 2 "nan_coordinate.msh.*node 4 has the coordinate 'nan', which is not a finite number"
  nan_coordinate.msh)
ffrf_mesh_error(nan_coordinate_bin 2 "nan_coordinate_bin.msh.*node 4 has a non-finite coordinate.*NaN"
  nan_coordinate_bin.msh)
# Groups
ffrf_mesh_error(duplicate_names 2 "duplicate_names.msh.*two physical volumes are named 'block' \\(tags 1 and 3\\)"
  duplicate_names.msh)
ffrf_mesh_error(surface_outside 2 "surface_outside.msh.: physical surface 'far' has no triangles in the body of physical volume\\(s\\) 'block'"
  surface_outside.msh far)
# Body checks: duplicate, non-conforming Tet10, disconnected, a triangle that is not a face
ffrf_mesh_error(duplicate_tet 2 "duplicate_tet.msh.: tetrahedra 2 and 4 of physical volume\\(s\\) 'block' have the same corner nodes"
  duplicate_tet.msh)
ffrf_mesh_error(tet10_crack 2 "tet10_crack.msh.: edge \\(2, 3\\) has two mid-side nodes, 7 \\(tetrahedron 2\\) and 15 \\(tetrahedron 3\\)"
  tet10_crack.msh)
ffrf_mesh_error(tet10_crack_22 2 "tet10_crack_22.msh.: edge \\(2, 3\\) has two mid-side nodes"
  tet10_crack_22.msh)
ffrf_mesh_error(tet10_midside_corner 2 "tet10_midside_corner.msh.: node 5 is a mid-side node of tetrahedron 2 and a corner of another one"
  tet10_midside_corner.msh)
ffrf_mesh_error(tet10_midside_two_edges 2 "tet10_midside_two_edges.msh.: node 6 is the mid-side node of edge \\(3, 5\\) of tetrahedron 3 and of edge \\(1, 2\\)"
  tet10_midside_two_edges.msh)
ffrf_mesh_error(two_pieces 2 "two_pieces.msh.: the body of physical volume\\(s\\) 'block' is in 2 pieces.*piece 2 has 4 nodes and 1 tetrahedra \\(first 4\\), box \\(3, 0, 0\\)"
  two_pieces.msh)
ffrf_mesh_error(not_a_face 2 "not_a_face.msh.: triangle 1 of physical surface 'face' \\(surface entity 1; nodes \\(1, 2, 5\\)\\) is not a face"
  not_a_face.msh)
# Not a regular file: exit 3 before anything is read (a FIFO hung forever)
ffrf_mesh_error(folder 3 "mesh file \".*bad/\\.\" is a folder" .)
add_test(NAME mesh_error_fifo_setup
  COMMAND sh -c "rm -f '${_mesh_case_dir}/fifo.msh' && mkfifo '${_mesh_case_dir}/fifo.msh'")
set_tests_properties(mesh_error_fifo_setup PROPERTIES FIXTURES_SETUP mesh_error_fifo
  LABELS "regression;errors;mesh")
ffrf_mesh_error(fifo 3 "mesh file \".*fifo.msh\" is a FIFO" "${_mesh_case_dir}/fifo.msh")
set_tests_properties(mesh_error_fifo PROPERTIES FIXTURES_REQUIRED mesh_error_fifo)
