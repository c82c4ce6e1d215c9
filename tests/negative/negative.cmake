# Negative suite (issue 10, part 5): generated bad meshes and case files, each run through the
# driver and checked for its verdict (tests/negative/README.md). Label `negative`.
#   negative_mesh_msh41, negative_mesh_msh41_binary, negative_mesh_msh22: 300 mutated meshes
#     each (from the block of input/fuzz_block.geo, Tet4 and Tet10), every one run as a real
#     modal analysis (no --check) inside a small case: the meshes are tiny (0.1-0.3 s a run).
#   negative_namelist: ~400 mutated copies of input/*.nml, run with --check (read and check the
#     case and its meshes, then exit) against the built crank/conrod meshes.
# Fixtures: negative_base_meshes (gmsh on fuzz_block.geo, 6 files) -> negative_<class>_inputs
# (generate.py) -> negative_<class> (run.py, 2 workers, 10 s and 1 GB per run).
set(_neg_src "${CMAKE_CURRENT_SOURCE_DIR}/negative")
set(_neg_out "${PROJECT_BINARY_DIR}/tests/negative")
set(_neg_meshes "${PROJECT_BINARY_DIR}/meshes")

# Base meshes: the real gmsh, MSH 4.1 ASCII, 4.1 binary and 2.2 ASCII, Tet4 and Tet10
foreach(order 1 2)
  if(order EQUAL 1)
    set(_kind tet4)
  else()
    set(_kind tet10)
  endif()
  foreach(format msh41 msh41_binary msh22)
    set(_flags -format msh41)
    if(format STREQUAL "msh41_binary")
      set(_flags -format msh41 -bin)
    elseif(format STREQUAL "msh22")
      set(_flags -format msh22)
    endif()
    add_test(NAME negative_base_${_kind}_${format}
      COMMAND ${GMSH_EXECUTABLE} -3 -setnumber order ${order} ${_flags}
        -o ${_neg_meshes}/fuzz_block_${_kind}_${format}.msh ${PROJECT_SOURCE_DIR}/input/fuzz_block.geo)
    set_tests_properties(negative_base_${_kind}_${format} PROPERTIES
      FIXTURES_SETUP negative_base_meshes FIXTURES_REQUIRED mesh_dir LABELS "negative;mesh"
      TIMEOUT 60 FAIL_REGULAR_EXPRESSION "Error *:")
  endforeach()
endforeach()

# ffrf_negative_suite(<test name> <class> [ARGS run.py args...] [FIXTURES fixture...])
function(ffrf_negative_suite name class)
  cmake_parse_arguments(ARG "" "" "ARGS;FIXTURES" ${ARGN})
  if(class STREQUAL "namelist")
    set(_gen_args --input-dir ${PROJECT_SOURCE_DIR}/input)
    set(_gen_fixtures "")
  else()
    set(_gen_args --base-dir ${_neg_meshes})
    set(_gen_fixtures negative_base_meshes)
  endif()
  add_test(NAME negative_generate_${class}
    COMMAND ${Python3_EXECUTABLE} ${_neg_src}/generate.py ${_gen_args} --out ${_neg_out}
      --class ${class})
  set_tests_properties(negative_generate_${class} PROPERTIES LABELS negative TIMEOUT 120
    FIXTURES_SETUP negative_${class}_inputs FIXTURES_REQUIRED "${_gen_fixtures}")
  add_test(NAME ${name}
    COMMAND ${Python3_EXECUTABLE} ${_neg_src}/run.py
      --manifest ${_neg_out}/${class}/manifest.json --driver $<TARGET_FILE:ffrf> --jobs 2
      --timeout 10 --memory-mb 1024 --work-dir ${_neg_out}/${class}-runs ${ARG_ARGS})
  set_tests_properties(${name} PROPERTIES LABELS negative TIMEOUT 300 PROCESSORS 2
    ENVIRONMENT "OPENBLAS_NUM_THREADS=1"
    FIXTURES_REQUIRED "negative_${class}_inputs;${ARG_FIXTURES}")
endfunction()

ffrf_negative_suite(negative_mesh_msh41 msh41)
ffrf_negative_suite(negative_mesh_msh41_binary msh41_binary)
ffrf_negative_suite(negative_mesh_msh22 msh22)
ffrf_negative_suite(negative_namelist namelist
  ARGS --mesh-dir ${_neg_meshes} --check-flag=--check
  FIXTURES crank_mesh conrod_mesh crank_lc10_mesh crank_lc8_mesh conrod_lc8_mesh)

# Input rules of issue 23 (items 4 and 5): generated variants per class, each run through the
# driver with its exact exit code and message (input_rules.py, docs/input.md "Input rules").
#   negative_rules_<class>: bounded (2 GB sparse meshes, counts beyond the file), options (empty
#   values), characters (control characters everywhere), file_kinds (FIFO, folder, device as
#   every file argument), sweep (duplicate keys, byte-order marks), task (long job-array
#   variables), echo (the echo reads back), sets (20 000 --set in linear time), restart (an
#   earlier t_end), surfaces (a surface across two bodies, names equal up to blanks).
foreach(_class sparse bounded options characters file_kinds sweep task echo sets restart surfaces)
  add_test(NAME negative_rules_${_class}
    COMMAND ${Python3_EXECUTABLE} ${_neg_src}/input_rules.py --driver $<TARGET_FILE:ffrf>
      --work ${_neg_out}/rules --class ${_class} --mesh-dir ${_neg_meshes}
      --input-dir ${PROJECT_SOURCE_DIR}/input --gmsh ${GMSH_EXECUTABLE})
  set_tests_properties(negative_rules_${_class} PROPERTIES LABELS "negative;input"
    TIMEOUT 60 ENVIRONMENT "OPENBLAS_NUM_THREADS=1")
endforeach()
set_tests_properties(negative_rules_bounded negative_rules_file_kinds PROPERTIES
  FIXTURES_REQUIRED negative_base_meshes)
# a quadratic reading of 2 GB or of 20 000 --set options would exceed these by far (the 2 GB
# files read whole took 24-33 s, 20 000 --set over 300 s); measured 0.1 s and 0.7 s
set_tests_properties(negative_rules_sparse PROPERTIES TIMEOUT 10)
set_tests_properties(negative_rules_sets PROPERTIES TIMEOUT 20)
