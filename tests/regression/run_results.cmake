# cmake -DDRIVER= -DPYTHON= -DCASE= -DREFERENCE= -DMESH_DIR= -DOUT_DIR= -DSCRIPTS=
#       [-DSAME_AS=DIR] [-DTHREADS=N -DSECOND_RUN=DIR] -P run_results.cmake
# Runs one case of input/ into a fresh OUT_DIR, then
#   without SAME_AS: compares its results with the reference by value (results_values.py);
#   with SAME_AS:    checks that they equal the results in SAME_AS bitwise (bitwise.py same);
#   with SECOND_RUN: runs it again into SECOND_RUN and does both (THREADS: --threads N).
get_filename_component(name "${CASE}" NAME_WE)

function(run_case dir)
  file(REMOVE_RECURSE "${dir}")
  file(MAKE_DIRECTORY "${dir}")
  set(threads "")
  if(THREADS)
    set(threads --threads ${THREADS})
  endif()
  execute_process(COMMAND "${DRIVER}" "${CASE}" --mesh-dir "${MESH_DIR}" --output-dir "${dir}"
    --quiet ${threads} RESULT_VARIABLE code ERROR_VARIABLE err)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "ffrf ${CASE}: exit ${code}\n${err}")
  endif()
endfunction()

function(result_files dir out)
  file(GLOB files RELATIVE "${dir}" "${dir}/${name}.h5" "${dir}/${name}_*.msh"
    "${dir}/${name}_*.msh.opt")
  list(SORT files)
  set(${out} "${files}" PARENT_SCOPE)
endfunction()

function(python what dir)
  execute_process(COMMAND "${PYTHON}" ${ARGN} WORKING_DIRECTORY "${dir}" RESULT_VARIABLE code
    OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message("${out}${err}")
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "${what}")
  endif()
endfunction()

run_case("${OUT_DIR}")
result_files("${OUT_DIR}" files)
if(SAME_AS OR SECOND_RUN)
  if(SECOND_RUN)
    run_case("${SECOND_RUN}")
    set(SAME_AS "${OUT_DIR}")
    set(second "${SECOND_RUN}")
  else()
    set(second "${OUT_DIR}")
  endif()
  result_files("${SAME_AS}" first_files)
  if(NOT first_files STREQUAL files)
    message(FATAL_ERROR "the two runs of ${name} wrote different files: ${first_files} and ${files}")
  endif()
  python("two runs of ${name} differ (determinism)" "${second}" "${SCRIPTS}/bitwise.py" same
    "${SAME_AS}" "${second}" ${files})
endif()
if(NOT SAME_AS OR SECOND_RUN)
  python("results of ${name} differ from the reference beyond their tolerances" "${OUT_DIR}"
    "${SCRIPTS}/results_values.py" compare "${REFERENCE}" ${files})
endif()
