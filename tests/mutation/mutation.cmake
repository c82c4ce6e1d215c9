# Mutation check (issue 13, item 1; tests/mutation/README.md): `cmake --build --preset mutation`
# copies the sources to build/<preset>/mutation, builds them once (-O2, no LTO) and runs the
# related tests of every mutation in tests/mutation/mutations.toml. Not part of ctest or CI
# (28 mutations: 7 min from scratch on 2 busy cores, 3.5 min again); fails when a mutation
# survives or an entry is broken.
add_custom_target(mutation
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_LIST_DIR}/run_mutations.py
    --source ${PROJECT_SOURCE_DIR} --work ${PROJECT_BINARY_DIR}/mutation
    --cmake ${CMAKE_COMMAND} --ctest ${CMAKE_CTEST_COMMAND}
  USES_TERMINAL VERBATIM
  COMMENT "Mutation check: tests/mutation/mutations.toml")
# Every entry of the list still applies (issue 25: files split into submodules move the lines
# the entries find): its file, its find text exactly once, a test for its regex. Seconds.
add_test(NAME mutation_list_applies
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_LIST_DIR}/run_mutations.py
    --source ${PROJECT_SOURCE_DIR} --check-list ${PROJECT_BINARY_DIR}
    --ctest ${CMAKE_CTEST_COMMAND})
set_tests_properties(mutation_list_applies PROPERTIES LABELS "unit")
