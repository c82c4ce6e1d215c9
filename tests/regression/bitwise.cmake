# Bitwise stability: every case of input/ run by the driver on its full meshes, its results
# (HDF5 datasets and attributes, Gmsh views) compared digest by digest with the results of the
# same case made before the layer redesign of issue 11 (tests/data/bitwise/<case>.json, made with
# `bitwise.py digest` from revision 68abc00). A change that alters a number, even in the last
# bit, fails here; a change that alters results ON PURPOSE regenerates the digests in the same
# commit and says so:
#   build/release/driver/ffrf input/<case>.nml --mesh-dir build/release/meshes --output-dir out
#   python3 tests/regression/bitwise.py digest out/<case>.h5 out/<case>_*.msh > tests/data/bitwise/<case>.json
set(_out "${PROJECT_BINARY_DIR}/tests/bitwise")
file(MAKE_DIRECTORY "${_out}")
file(GLOB _references "${PROJECT_SOURCE_DIR}/tests/data/bitwise/*.json")
foreach(_reference IN LISTS _references)
  get_filename_component(_case "${_reference}" NAME_WE)
  add_test(NAME bitwise_${_case}
    COMMAND ${CMAKE_COMMAND} -DDRIVER=$<TARGET_FILE:ffrf> -DPYTHON=${Python3_EXECUTABLE}
      -DCASE=${PROJECT_SOURCE_DIR}/input/${_case}.nml -DREFERENCE=${_reference}
      -DMESH_DIR=${PROJECT_BINARY_DIR}/meshes -DOUT_DIR=${_out}/${_case}
      -DSCRIPT=${CMAKE_CURRENT_SOURCE_DIR}/regression/bitwise.py
      -P ${CMAKE_CURRENT_SOURCE_DIR}/regression/run_bitwise.cmake)
  set_tests_properties(bitwise_${_case} PROPERTIES LABELS "regression;bitwise"
    ENVIRONMENT OPENBLAS_NUM_THREADS=1
    FIXTURES_REQUIRED "crank_mesh;crank_lc10_mesh;crank_lc8_mesh;conrod_mesh;conrod_lc8_mesh")
endforeach()
