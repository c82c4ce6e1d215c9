# An independent FE code in ctest (issue 13): the crank's constrained normal modes of RC sets
# 1-3, with RBE3 (uniform weights) and RBE2 interfaces, against CalculiX (ccx, Debian package
# calculix-ccx) on the same lc = 10 mm mesh. The cases are input/crank_rc*.nml with the mesh
# name changed (run_calculix.cmake fails when the replacement finds nothing to change); ccx
# gets its own deck written by postprocess/crosscheck_calculix.py from the mesh, interfaces and
# reference conditions (RBE2: *RIGID BODY, RBE3: *EQUATION from Nastran's definition
# recomputed there). Tolerance 1e-4 on every mode up to 10 kHz (measured 1.8e-5 .. 2.4e-5, the
# difference growing with frequency: see the script's docstring).
find_program(CCX_EXECUTABLE ccx)
set(_out "${PROJECT_BINARY_DIR}/tests/calculix")
foreach(_case crank_rc1 crank_rc2 crank_rc3 crank_rc1_rbe2 crank_rc2_rbe2 crank_rc3_rbe2)
  if(CCX_EXECUTABLE)
    add_test(NAME calculix_${_case}
      COMMAND ${CMAKE_COMMAND} -DDRIVER=$<TARGET_FILE:ffrf> -DPYTHON=${Python3_EXECUTABLE}
        -DCCX=${CCX_EXECUTABLE} -DCASE=${PROJECT_SOURCE_DIR}/input/${_case}.nml
        -DMESH_DIR=${PROJECT_BINARY_DIR}/meshes -DOUT_DIR=${_out}/${_case}
        -DSCRIPT=${PROJECT_SOURCE_DIR}/postprocess/crosscheck_calculix.py
        -P ${CMAKE_CURRENT_SOURCE_DIR}/regression/run_calculix.cmake)
  else()
    add_test(NAME calculix_${_case} COMMAND ${CMAKE_COMMAND} -E echo
      "CalculiX (ccx) not found: install calculix-ccx (bash .ci/install-deps), then re-run cmake")
    set_tests_properties(calculix_${_case} PROPERTIES WILL_FAIL ON)
  endif()
  set_tests_properties(calculix_${_case} PROPERTIES LABELS "regression;calculix"
    FIXTURES_REQUIRED crank_lc10_mesh ENVIRONMENT "OPENBLAS_NUM_THREADS=1;OMP_NUM_THREADS=1")
endforeach()
