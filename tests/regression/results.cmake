# Regression references by value, and determinism run against run (issue 21, tests/TOLERANCES.md
# "Regression references"). Every case of input/ that has a reference
# tests/data/references/<case>.json is run by the driver on its full meshes:
#   results_<case>[_<kernel>]      its results file and Gmsh views compared with the reference by
#                                  value, each dataset with the tolerance of its rule
#                                  (results_values.py RULES): portable across processors and BLAS
#                                  kernels;
#   determinism_<case>[_<kernel>]  a second run, bitwise equal to the first (bitwise.py same): the
#                                  same machine, build and kernel give the same bits;
#   determinism_threads_<case>     two runs with 2 BLAS threads, bitwise equal to each other and
#                                  within the reference's tolerances.
# <kernel> forces OpenBLAS's kernel (OPENBLAS_CORETYPE) to one that runs on every x86-64 processor
# with its instruction set (checked in /proc/cpuinfo), so that one machine proves the references
# hold on others; without a suffix, the kernel OpenBLAS picks for this processor.
# A change that alters results ON PURPOSE regenerates the references in the same commit and says
# by how much each moved (results_values.py spread OLD_DIR NEW_DIR FILES):
#   build/release/driver/ffrf input/<case>.nml --mesh-dir build/release/meshes --output-dir out
#   cd out && python3 ../tests/regression/results_values.py reference <case>.h5 <case>_*.msh* \
#     > ../tests/data/references/<case>.json
set(_out "${PROJECT_BINARY_DIR}/tests/results")
file(MAKE_DIRECTORY "${_out}")
set(_kernels native)
if(EXISTS /proc/cpuinfo)
  file(STRINGS /proc/cpuinfo _flags REGEX "^flags" LIMIT_COUNT 1)
  foreach(_kernel "haswell:Haswell:avx2" "sandybridge:Sandybridge:avx" "nehalem:Nehalem:sse4_2")
    string(REGEX MATCH "[^:]+$" _flag "${_kernel}")
    string(REGEX REPLACE ":[^:]+$" "" _kernel "${_kernel}")
    if(_flags MATCHES " ${_flag}( |$)")
      list(APPEND _kernels "${_kernel}")
    else()
      message(STATUS "results_*: this processor lacks ${_flag}; no test with OpenBLAS forced to "
        "the ${_kernel} kernel")
    endif()
  endforeach()
endif()
set(_fixtures "crank_mesh;crank_lc10_mesh;crank_lc8_mesh;conrod_mesh;conrod_lc8_mesh")
set(_script "${CMAKE_CURRENT_SOURCE_DIR}/regression/run_results.cmake")
file(GLOB _references "${PROJECT_SOURCE_DIR}/tests/data/references/*.json")
foreach(_reference IN LISTS _references)
  get_filename_component(_case "${_reference}" NAME_WE)
  set(_common -DDRIVER=$<TARGET_FILE:ffrf> -DPYTHON=${Python3_EXECUTABLE}
    -DCASE=${PROJECT_SOURCE_DIR}/input/${_case}.nml -DREFERENCE=${_reference}
    -DMESH_DIR=${PROJECT_BINARY_DIR}/meshes -DSCRIPTS=${CMAKE_CURRENT_SOURCE_DIR}/regression)
  foreach(_kernel IN LISTS _kernels)
    if(_kernel STREQUAL "native")
      set(_suffix "")
      set(_environment "OPENBLAS_NUM_THREADS=1")
    else()
      string(REGEX REPLACE ":.*$" "" _name "${_kernel}")
      string(REGEX REPLACE "^.*:" "" _coretype "${_kernel}")
      set(_suffix "_${_name}")
      set(_environment "OPENBLAS_NUM_THREADS=1;OPENBLAS_CORETYPE=${_coretype}")
    endif()
    set(_first "${_out}/${_case}${_suffix}/run1")
    add_test(NAME results_${_case}${_suffix}
      COMMAND ${CMAKE_COMMAND} ${_common} -DOUT_DIR=${_first} -P ${_script})
    add_test(NAME determinism_${_case}${_suffix}
      COMMAND ${CMAKE_COMMAND} ${_common} -DOUT_DIR=${_out}/${_case}${_suffix}/run2
        -DSAME_AS=${_first} -P ${_script})
    set_tests_properties(results_${_case}${_suffix} PROPERTIES LABELS "regression;results"
      ENVIRONMENT "${_environment}" FIXTURES_REQUIRED "${_fixtures}"
      FIXTURES_SETUP "results_${_case}${_suffix}")
    set_tests_properties(determinism_${_case}${_suffix} PROPERTIES
      LABELS "regression;determinism" ENVIRONMENT "${_environment}"
      FIXTURES_REQUIRED "${_fixtures};results_${_case}${_suffix}")
  endforeach()
endforeach()
# Two BLAS threads: bitwise run against run, and within the references' tolerances.
foreach(_case crank_rc1 engine_rc1_manual)
  set(_reference "${PROJECT_SOURCE_DIR}/tests/data/references/${_case}.json")
  set(_common -DDRIVER=$<TARGET_FILE:ffrf> -DPYTHON=${Python3_EXECUTABLE}
    -DCASE=${PROJECT_SOURCE_DIR}/input/${_case}.nml -DREFERENCE=${_reference}
    -DMESH_DIR=${PROJECT_BINARY_DIR}/meshes -DSCRIPTS=${CMAKE_CURRENT_SOURCE_DIR}/regression
    -DTHREADS=2)
  add_test(NAME determinism_threads_${_case}
    COMMAND ${CMAKE_COMMAND} ${_common} -DOUT_DIR=${_out}/${_case}_threads/run1
      -DSECOND_RUN=${_out}/${_case}_threads/run2 -P ${_script})
  set_tests_properties(determinism_threads_${_case} PROPERTIES LABELS "regression;determinism"
    FIXTURES_REQUIRED "${_fixtures}" PROCESSORS 2)
endforeach()
# The comparison itself can fail: faults planted in a copy of results_crank_rc1's files (a moved
# frequency, shape entry and view number, NaN and large residuals, datasets removed and added, a
# changed status and view text) must fail it, a flipped mode sign and round-off must pass.
add_test(NAME results_values_faults
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_results_values.py
    ${PROJECT_SOURCE_DIR}/tests/data/references/crank_rc1.json ${_out}/crank_rc1/run1 crank_rc1)
set_tests_properties(results_values_faults PROPERTIES LABELS "regression;results"
  FIXTURES_REQUIRED results_crank_rc1)
