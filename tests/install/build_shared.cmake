# A shared build of this source tree, as a user makes one, installed into a fresh prefix: only
# the library and the driver (no tests, no link-time optimisation), so it costs one library build
# (again only what changed when the folder is kept). Configured once; later runs rebuild.
# cmake -DSOURCE_DIR= -DBUILD_DIR= -DPREFIX= -DGENERATOR= -DFortran_COMPILER= -DC_COMPILER=
#       -DPYTHON= -P build_shared.cmake
function(run)
  execute_process(COMMAND ${ARGV} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "failed (${code}): ${ARGV}\n${out}\n${err}")
  endif()
  string(LENGTH "${out}" length)          # the build's log is long: its end only
  if(length GREATER 4000)
    math(EXPR start "${length} - 4000")
    string(SUBSTRING "${out}" ${start} -1 out)
  endif()
  message(STATUS "${out}${err}")
endfunction()
if(NOT EXISTS "${BUILD_DIR}/CMakeCache.txt")
  run(${CMAKE_COMMAND} -S "${SOURCE_DIR}" -B "${BUILD_DIR}" -G "${GENERATOR}"
    -DCMAKE_BUILD_TYPE=Release -DBUILD_SHARED_LIBS=ON -DFFRF_BUILD_TESTS=OFF -DFFRF_LTO=OFF
    "-DCMAKE_Fortran_COMPILER=${Fortran_COMPILER}" "-DCMAKE_C_COMPILER=${C_COMPILER}"
    "-DPython3_EXECUTABLE=${PYTHON}")
endif()
run(${CMAKE_COMMAND} --build "${BUILD_DIR}")
file(REMOVE_RECURSE "${PREFIX}")
run(${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${PREFIX}")
