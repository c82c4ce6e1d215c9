# The manual (issue 25): label `docs` (`ctest --preset release -L docs`).
#   docs_citations            every section of docs/<file>.md or of the README and every
#                             `theory.md N.M` cited in the tree resolves to a heading; the Markdown
#                             links of README.md and docs/ resolve (check_citations.py)
#   docs_developer_modules    docs/developer.md's module map names every module of src/
#                             (check_module_map.py)
#   example_own_part_commands the four commands of docs/own_part.md (also in README.md) run as
#                             written; the lever's mass against rho V, its two lowest frequencies
#                             against the Euler-Bernoulli cantilever; then its mechanism command,
#                             the swing against the rigid pendulum's half period (own_part_commands.py)
add_test(NAME docs_citations
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/docs/check_citations.py
    ${PROJECT_SOURCE_DIR})
add_test(NAME docs_developer_modules
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/docs/check_module_map.py
    ${PROJECT_SOURCE_DIR})
set_tests_properties(docs_citations docs_developer_modules PROPERTIES LABELS "docs" TIMEOUT 60)
add_test(NAME example_own_part_commands
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/docs/own_part_commands.py)
set_tests_properties(example_own_part_commands PROPERTIES LABELS "docs;examples" TIMEOUT 300
  ENVIRONMENT "OPENBLAS_NUM_THREADS=1;FFRF_SOURCE_DIR=${PROJECT_SOURCE_DIR};FFRF_DRIVER=$<TARGET_FILE:ffrf>;GMSH=${GMSH_EXECUTABLE};PYTHON=${Python3_EXECUTABLE};FFRF_WORK_DIR=${PROJECT_BINARY_DIR}/tests/own_part")
#   docs_key_tables           the `&group key` tables of docs/input.md, docs/mechanisms.md and
#                             docs/sensors.md name every key of the readers' key specs and
#                             nothing else, and a choice key's row every accepted word and no
#                             other (list_keys prints the specs; check_key_tables.py)
add_executable(docs_list_keys docs/list_keys.f90)
target_link_libraries(docs_list_keys PRIVATE ffrf_lib)
add_test(NAME docs_key_tables
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/docs/check_key_tables.py
    $<TARGET_FILE:docs_list_keys> ${PROJECT_SOURCE_DIR})
set_tests_properties(docs_key_tables PROPERTIES LABELS "docs" TIMEOUT 60)
