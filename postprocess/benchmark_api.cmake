# benchmark_api (not part of `all`, not a test; needs the C API, include/ffrf.h):
#   (a) crank RC set 1 (RBE3, 12 modes) by the driver and by examples/c_modal through the C API
#   (b) engine_rc1_manual through the C API: one call to t_end against 1 ms chunks with the
#       host's drag torque; both programs link the library as the driver does (static, LTO)
# cmake --build --preset benchmark-api; CSV in build/release/benchmark/benchmark_api.csv
if(EXISTS ${PROJECT_SOURCE_DIR}/include/ffrf.h)
  add_executable(benchmark_api_modal EXCLUDE_FROM_ALL
    ${PROJECT_SOURCE_DIR}/examples/c_modal/c_modal.c)
  add_executable(benchmark_api_engine EXCLUDE_FROM_ALL
    ${CMAKE_CURRENT_SOURCE_DIR}/benchmark_api_engine.c)
  foreach(program benchmark_api_modal benchmark_api_engine)
    target_link_libraries(${program} PRIVATE ffrf::ffrf)
    target_link_options(${program} PRIVATE ${FFRF_LTO_FLAGS})
  endforeach()
  add_custom_target(benchmark_api
    COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 ${Python3_EXECUTABLE}
      ${CMAKE_CURRENT_SOURCE_DIR}/benchmark_api.py --driver $<TARGET_FILE:ffrf>
      --modal-program $<TARGET_FILE:benchmark_api_modal>
      --modal-case ${PROJECT_SOURCE_DIR}/input/crank_rc1.nml
      --engine-program $<TARGET_FILE:benchmark_api_engine>
      --engine-case ${PROJECT_SOURCE_DIR}/input/engine_rc1_manual.nml
      --mesh-dir ${PROJECT_BINARY_DIR}/meshes --runs 5 --work ${PROJECT_BINARY_DIR}/benchmark/api
      --csv ${PROJECT_BINARY_DIR}/benchmark/benchmark_api.csv
    WORKING_DIRECTORY ${PROJECT_BINARY_DIR}
    COMMENT "benchmark: C API against the driver (modal), 1 ms chunks against one call (engine)"
    VERBATIM USES_TERMINAL)
  add_dependencies(benchmark_api ffrf benchmark_api_modal benchmark_api_engine meshes)
endif()
