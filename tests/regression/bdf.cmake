# Nastran bulk data as a mesh (issue 26, item 2; docs/input.md "Nastran bulk data").
#  - bdf_crank_pynastran: the crank written as bulk data by pyNastran (small, large and free
#    fields, continuations, INCLUDE, RBE2 and RBE3) gives the frequencies of the Gmsh path to
#    1e-12 relative for RC sets 1-3 with RBE3 and RBE2 interfaces, on the lc = 10 mm mesh of the
#    CalculiX cross-check (measured worst 5.1e-13, Ritz values to machine precision); pyNastran
#    from PyPI in a virtual environment over Debian's numpy/h5py/meshio (skip, code 77, when it
#    cannot be made).
#  - error_bdf_<name>: each deck of tests/data/bdf/bad holds one defect; ffrf stops with one line
#    naming the file, the line and the card (exit 2; 3 for the missing INCLUDE, an I/O error);
#    bdf_good_deck: the deck they are made from runs.
set(_bdf_dir "${PROJECT_SOURCE_DIR}/tests/data/bdf/bad")
set(_bdf_out "${PROJECT_BINARY_DIR}/tests/bdf")
file(MAKE_DIRECTORY "${_bdf_out}")

add_test(NAME bdf_crank_pynastran
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_bdf_crank.py
    --driver $<TARGET_FILE:ffrf> --input-dir ${PROJECT_SOURCE_DIR}/input
    --mesh-dir ${PROJECT_BINARY_DIR}/meshes --work ${_bdf_out}/crank
    --venv ${PROJECT_BINARY_DIR}/tests/pynastran_venv)
set_tests_properties(bdf_crank_pynastran PROPERTIES LABELS "regression;mesh;bdf"
  FIXTURES_REQUIRED crank_lc10_mesh SKIP_RETURN_CODE 77 TIMEOUT 300
  ENVIRONMENT "OPENBLAS_NUM_THREADS=1;OMP_NUM_THREADS=1")

# The case of each deck: a body "block" of PSOLID 1 with the interface RBE3 101.
set(_bdf_body "&body name = 'block', volumes = '1', mesh_file = '${_bdf_dir}")
set(_bdf_iface "' /\n&interface body = 'block', name = '101', rc = '123456' /\n&modes num_modes = 2 /")
file(WRITE "${_bdf_out}/good.nml" "${_bdf_body}/good.bdf${_bdf_iface}\n")
add_test(NAME bdf_good_deck COMMAND ffrf ${_bdf_out}/good.nml --output-dir ${_bdf_out})
set_tests_properties(bdf_good_deck PROPERTIES LABELS "regression;mesh;bdf" TIMEOUT 20)

# ffrf_error_case (error_cases.cmake): error_bdf_<name>, deck <name>.bdf of tests/data/bdf/bad
foreach(_entry
    "missing_grid|2|missing_grid.bdf': line 7, CTETRA 1, field 6 \\(grid\\): grid 4 is no GRID of the deck"
    "unknown_psolid|2|unknown_psolid.bdf': line 7, CTETRA 1: PID = 2 is no PSOLID of the deck"
    "bad_field|2|bad_field.bdf': line 3, GRID 2, field 3 \\(X1\\): '1.2.3' is no real"
    "unterminated|2|unterminated.bdf': line 10, RBE3 \\(card of line 10\\): unterminated continuation"
    "rbe3_no_weights|2|rbe3_no_weights.bdf': line 10, RBE3 101: no weights and grids \\(RBE3 without weights\\)"
    "include_missing|3|include_missing.bdf': line 2, INCLUDE 'not_there.bdf': included file .*not_there.bdf\" does not exist")
  string(REPLACE "|" ";" _parts "${_entry}")
  list(GET _parts 0 _name)
  list(GET _parts 1 _code)
  list(GET _parts 2 _regex)
  ffrf_error_case(bdf_${_name} ${_code} "${_regex}" "${_bdf_body}/${_name}.bdf${_bdf_iface}")
endforeach()
# an &interface that does not fit the deck: an element id it lacks, an RBE3 called RBE2
ffrf_error_case(bdf_no_element 2 "interface .103.: deck .*good.bdf' has no RBE2 or RBE3 element 103.*elements: 101"
  "${_bdf_body}/good.bdf${_bdf_iface}" --set interface[101].name=103)
ffrf_error_case(bdf_mpc_mismatch 2 "interface .101. \\(RBE3 element 101 at .*good.bdf:10\\): &interface mpc = 'RBE2' but the element is an RBE3"
  "${_bdf_body}/good.bdf${_bdf_iface}" --set interface[101].mpc=RBE2)

# bdf_hinge_pynastran: a mechanism run on a body meshed as bulk data (tests/regression/
# check_bdf_hinge.py): the conrod hinged to the ground and driven by a torque, on the lc 8 mm
# Gmsh mesh and on that mesh written by pyNastran (large-field GRIDs, RBE3 interfaces): the
# rotation angle at every step to 1e-10 rad (measured 1.6e-14), frequencies to 2e-11 (3.7e-12 to
# 5.2e-12).
# The pyNastran environment is shared with bdf_crank_pynastran (made by whichever runs first).
add_test(NAME bdf_hinge_pynastran
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_bdf_hinge.py
    --driver $<TARGET_FILE:ffrf> --mesh-dir ${PROJECT_BINARY_DIR}/meshes
    --work ${_bdf_out}/hinge --venv ${PROJECT_BINARY_DIR}/tests/pynastran_venv)
set_tests_properties(bdf_hinge_pynastran PROPERTIES LABELS "regression;mesh;bdf"
  FIXTURES_REQUIRED conrod_lc8_mesh SKIP_RETURN_CODE 77 TIMEOUT 300 RESOURCE_LOCK pynastran_venv
  ENVIRONMENT "OPENBLAS_NUM_THREADS=1;OMP_NUM_THREADS=1")
set_tests_properties(bdf_crank_pynastran PROPERTIES RESOURCE_LOCK pynastran_venv)
