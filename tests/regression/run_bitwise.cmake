# cmake -DDRIVER= -DPYTHON= -DCASE= -DREFERENCE= -DMESH_DIR= -DOUT_DIR= -DSCRIPT= -P run_bitwise.cmake
# Runs one case into a fresh OUT_DIR and compares its result files with the reference digests.
file(REMOVE_RECURSE "${OUT_DIR}")
file(MAKE_DIRECTORY "${OUT_DIR}")
execute_process(COMMAND "${DRIVER}" "${CASE}" --mesh-dir "${MESH_DIR}" --output-dir "${OUT_DIR}"
  --quiet RESULT_VARIABLE code ERROR_VARIABLE err)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "ffrf ${CASE}: exit ${code}\n${err}")
endif()
get_filename_component(name "${CASE}" NAME_WE)
file(GLOB results RELATIVE "${OUT_DIR}" "${OUT_DIR}/${name}.h5" "${OUT_DIR}/${name}_*.msh")
execute_process(COMMAND "${PYTHON}" "${SCRIPT}" compare "${REFERENCE}" ${results}
  WORKING_DIRECTORY "${OUT_DIR}" RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(NOT code EQUAL 0)
  message(FATAL_ERROR "results of ${name} differ from the reference digests")
endif()
