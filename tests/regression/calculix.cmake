# An independent FE code in ctest (issue 13): the crank's constrained normal modes of RC sets
# 1-3, with RBE3 (uniform weights) and RBE2 interfaces, and of RC set 2 with RBE3 area weights
# of both definitions ('area': tributary, 'area_consistent': int N_i dA), against CalculiX (ccx,
# Debian package calculix-ccx) on the same lc = 10 mm mesh. The cases are input/crank_rc*.nml
# with the mesh name changed and, for the area-weighted ones, weighting = '...' added to every
# RBE3 interface (run_calculix.cmake fails when a replacement finds nothing to change); ccx gets
# its own deck written by postprocess/crosscheck_calculix.py from the mesh, interfaces and
# reference conditions (RBE2: *RIGID BODY, RBE3: *EQUATION from Nastran's definition with the
# weights recomputed there from the Tet10 faces, ffrf's weights checked against them to 2e-8 of
# the largest: measured 2.2e-9 'area', 3.8e-9 'area_consistent'). Tolerance 1e-4 on every mode
# up to 10 kHz (measured 1.8e-5 .. 3.0e-5, the difference growing with frequency: see the
# script's docstring).
find_program(CCX_EXECUTABLE ccx)
set(_out "${PROJECT_BINARY_DIR}/tests/calculix")
# <test name>:<input case>[:<weighting>]
foreach(_entry crank_rc1:crank_rc1 crank_rc2:crank_rc2 crank_rc3:crank_rc3
    crank_rc1_rbe2:crank_rc1_rbe2 crank_rc2_rbe2:crank_rc2_rbe2 crank_rc3_rbe2:crank_rc3_rbe2
    crank_rc2_area:crank_rc2:area crank_rc2_area_consistent:crank_rc2:area_consistent)
  string(REPLACE ":" ";" _parts "${_entry}")
  list(GET _parts 0 _case)
  list(GET _parts 1 _input)
  set(_weighting "")
  list(LENGTH _parts _n)
  if(_n GREATER 2)
    list(GET _parts 2 _weighting)
  endif()
  if(CCX_EXECUTABLE)
    add_test(NAME calculix_${_case}
      COMMAND ${CMAKE_COMMAND} -DDRIVER=$<TARGET_FILE:ffrf> -DPYTHON=${Python3_EXECUTABLE}
        -DCCX=${CCX_EXECUTABLE} -DCASE=${PROJECT_SOURCE_DIR}/input/${_input}.nml
        -DNAME=${_case} -DWEIGHTING=${_weighting}
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
