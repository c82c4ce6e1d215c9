# Speed-against-accuracy scripts (owner: study): postprocess/study_run.py, study_chart.py,
# study_outputs.py and namelist.py on synthetic data with known answers, then one tiny real study
# (tests/postprocess/study_tiny.nml: the crank alone at lc 12, 10, 8 mm and a 0.3 s engine on
# coarse meshes, about 10 s). Included from unit/craig_bampton.cmake.
if(Python3_Interpreter_FOUND)
  set(_ffrf_study_out "${PROJECT_BINARY_DIR}/postprocess_tests/study")
  file(MAKE_DIRECTORY "${_ffrf_study_out}")
  add_test(NAME postprocess_study_synthetic
    COMMAND ${Python3_EXECUTABLE} ${PROJECT_SOURCE_DIR}/tests/postprocess/check_study.py
      synthetic --postprocess-dir ${PROJECT_SOURCE_DIR}/postprocess
      --work ${_ffrf_study_out}/synthetic)
  set_tests_properties(postprocess_study_synthetic PROPERTIES LABELS "postprocess"
    ENVIRONMENT "MPLBACKEND=Agg")
  add_test(NAME postprocess_study_tiny
    COMMAND ${Python3_EXECUTABLE} ${PROJECT_SOURCE_DIR}/tests/postprocess/check_study.py
      tiny --postprocess-dir ${PROJECT_SOURCE_DIR}/postprocess --work ${_ffrf_study_out}/tiny
      --study ${PROJECT_SOURCE_DIR}/tests/postprocess/study_tiny.nml --ffrf $<TARGET_FILE:ffrf>
      --gmsh ${GMSH_EXECUTABLE} --input-dir ${PROJECT_SOURCE_DIR}/input)
  set_tests_properties(postprocess_study_tiny PROPERTIES LABELS "postprocess;regression"
    ENVIRONMENT "MPLBACKEND=Agg;OPENBLAS_NUM_THREADS=1" TIMEOUT 300)
else()
  message(WARNING "no Python 3 interpreter: study script tests are not registered")
endif()
