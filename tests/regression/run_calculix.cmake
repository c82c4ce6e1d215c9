# cmake -DDRIVER= -DPYTHON= -DCCX= -DCASE= -DMESH_DIR= -DOUT_DIR= -DSCRIPT= [-DWEIGHTING= -DNAME=]
#   -P run_calculix.cmake
# The case on the lc = 10 mm crank mesh, run by ffrf, then compared with CalculiX. WEIGHTING:
# RBE3 weights of every RBE3 interface of the case ('area', 'area_consistent'); NAME: the
# case's name then (default: the case file's).
file(REMOVE_RECURSE "${OUT_DIR}")
file(MAKE_DIRECTORY "${OUT_DIR}")
get_filename_component(name "${CASE}" NAME_WE)
if(NAME)
  set(name "${NAME}")
endif()
file(READ "${CASE}" text)
string(REPLACE "mesh_file = 'crank.msh'" "mesh_file = 'crank_lc10.msh'" coarse "${text}")
if(coarse STREQUAL text)
  message(FATAL_ERROR "${CASE}: no \"mesh_file = 'crank.msh'\" to replace: the case changed, "
    "update run_calculix.cmake")
endif()
if(WEIGHTING)
  set(text "${coarse}")
  string(REPLACE "mpc = 'RBE3'," "mpc = 'RBE3', weighting = '${WEIGHTING}'," coarse "${text}")
  if(coarse STREQUAL text)
    message(FATAL_ERROR "${CASE}: no \"mpc = 'RBE3',\" to give weighting = '${WEIGHTING}': "
      "the case changed, update run_calculix.cmake")
  endif()
endif()
file(WRITE "${OUT_DIR}/${name}.nml" "${coarse}")
execute_process(COMMAND "${DRIVER}" "${OUT_DIR}/${name}.nml" --mesh-dir "${MESH_DIR}"
  --output-dir "${OUT_DIR}" --quiet RESULT_VARIABLE code ERROR_VARIABLE err)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "ffrf ${name}: exit ${code}\n${err}")
endif()
execute_process(COMMAND "${PYTHON}" "${SCRIPT}" "${OUT_DIR}/${name}.h5" --ccx "${CCX}"
  --work "${OUT_DIR}/ccx" --max-hz 10000 --tolerance 1e-4 --weights-tolerance 2e-8
  RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(NOT code EQUAL 0)
  message(FATAL_ERROR "${name}: ffrf and CalculiX disagree (or ccx failed)")
endif()
