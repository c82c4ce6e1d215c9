# Batch command line (issue 12, item 3): --set, --sweep, --task and the job-array variables,
# --output templates, --threads, --print-input, --version on the small crank (lc = 8 mm, RC set
# 2), read back by check_batch.py (h5py) against the edited case file, the 8-mode run and the
# constraint theorem; and their bad uses: exit 2 (input) or 1 (command line), ONE line in our
# words, the namelist's own message after the override's origin for a bad value.
if(NOT Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
  set(Python3_EXECUTABLE /usr/bin/python3)
endif()
set(_batch "${PROJECT_BINARY_DIR}/tests/batch")
file(MAKE_DIRECTORY "${_batch}")
set(_case "${CMAKE_CURRENT_SOURCE_DIR}/regression/crank_lc8_rc2.nml")
add_test(NAME batch_runs
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/check_batch.py
    $<TARGET_FILE:ffrf> ${_case} ${PROJECT_BINARY_DIR}/meshes ${_batch}/runs)
set_tests_properties(batch_runs PROPERTIES LABELS "regression;batch"
  FIXTURES_REQUIRED crank_lc8_mesh TIMEOUT 120 ENVIRONMENT OPENBLAS_NUM_THREADS=1)

file(WRITE "${_batch}/table.csv" "modes.num_modes,interface[B2].rc\n4,Tx\n8,Tx Ty Tz\n")
file(WRITE "${_batch}/ragged.csv" "modes.num_modes,interface[B2].rc\n4,Tx\n8\n")
file(WRITE "${_batch}/unknown_key.csv" "modes.num_modez\n4\n")
file(WRITE "${_batch}/bad_value.csv" "modes.num_modes\nfour\n")
set(_expect "${CMAKE_CURRENT_SOURCE_DIR}/regression/expect_input.cmake")
# ffrf_batch_error(<name> <exit code> <message regex> <driver args after the case...>)
function(ffrf_batch_error name code regex)
  add_test(NAME batch_error_${name}
    COMMAND ${CMAKE_COMMAND}
      "-DCOMMAND=$<TARGET_FILE:ffrf>;${_case};--mesh-dir;${PROJECT_BINARY_DIR}/meshes;--output-dir;${_batch};${ARGN}"
      -DEXIT_CODE=${code} "-DMESSAGE=${regex}" -P ${_expect})
  set_tests_properties(batch_error_${name} PROPERTIES LABELS "regression;errors;batch"
    FIXTURES_REQUIRED crank_lc8_mesh TIMEOUT 30
    ENVIRONMENT "OPENBLAS_NUM_THREADS=1;SLURM_ARRAY_TASK_ID=;PBS_ARRAY_INDEX=;LSB_JOBINDEX=")
endfunction()

# --set: unknown group or key, name not found, group kind, bad values in the namelist's words
ffrf_batch_error(unknown_key 2 "--set modes.num_modez: unknown key num_modez of &modes. the keys of &modes are num_modes, shift_hz"
  --set modes.num_modez=4)
ffrf_batch_error(unknown_group 2 "--set mode.num_modes: unknown namelist group &mode. groups are &run, &body"
  --set mode.num_modes=4)
ffrf_batch_error(name_not_found 2 "--set interface\\[B9\\].rc: no &interface named \"B9\" in .*crank_lc8_rc2\\.nml \\(names: B1, B2, B3\\)"
  --set interface[B9].rc=Tx)
ffrf_batch_error(body_not_found 2 "--set body\\[conrod\\].mesh_file: no &body named \"conrod\" in .*crank_lc8_rc2\\.nml \\(names: crank\\)"
  --set body[conrod].mesh_file=conrod_lc8.msh)
ffrf_batch_error(repeatable_without_name 2 "--set interface.rc: &interface is a repeatable group. choose one by its name, interface\\[NAME\\].rc=VALUE"
  --set interface.rc=Tx)
ffrf_batch_error(no_equals 2 "--set modes.num_modes: no \"=\". write GROUP.KEY=VALUE"
  --set modes.num_modes)
# the messages of input_integer_is_string, input_h_huge... after "--set GROUP.KEY = VALUE:"
ffrf_batch_error(bad_integer 2 "--set modes.num_modes = four: not an integer. give an integer in 1\\.\\.10000"
  --set modes.num_modes=four)
ffrf_batch_error(bad_real 2 "--set body\\[crank\\].young = steel: not a number. give a finite real in \\(0, 1E\\+13\\] Pa"
  --set body[crank].young=steel)
ffrf_batch_error(bad_choice 2 "--set interface\\[B2\\].mpc = RBE9: not allowed. mpc is one of"
  --set interface[B2].mpc=RBE9)
# a value the group reader checks (the dof words of rc): its message, the override's origin
ffrf_batch_error(bad_rc 2 "--set interface\\[B2\\].rc = Tq: unknown dof \"tq\""
  --set interface[B2].rc=Tq)
ffrf_batch_error(output_outside 2 "--output = \\.\\./x\\.h5: a '\\.\\.' component leaves the output folder"
  --output ../x.h5)
# --sweep and --task
ffrf_batch_error(row_out_of_range 2 "table\\.csv: row 3 asked \\(the task index\\), the table has 2 rows \\(1\\.\\.2\\)"
  --sweep ${_batch}/table.csv --task 3)
ffrf_batch_error(row_zero 2 "table\\.csv: row 0 asked" --sweep ${_batch}/table.csv --task 0)
ffrf_batch_error(ragged_row 2 "ragged\\.csv:3: 1 values, the header names 2 keys"
  --sweep ${_batch}/ragged.csv --task 1)
ffrf_batch_error(sweep_unknown_key 2 "unknown_key\\.csv:2 modes\\.num_modez: unknown key num_modez of &modes"
  --sweep ${_batch}/unknown_key.csv --task 1)
ffrf_batch_error(sweep_bad_value 2 "bad_value\\.csv:2 modes\\.num_modes = four: not an integer. give an integer in 1\\.\\.10000"
  --sweep ${_batch}/bad_value.csv --task 1)
ffrf_batch_error(sweep_without_task 2 "--sweep .*table\\.csv: which row\\? give --task N or run as a job array"
  --sweep ${_batch}/table.csv)
ffrf_batch_error(sweep_missing 3 "--sweep table \".*missing\\.csv\" does not exist" --sweep ${_batch}/missing.csv --task 1)
ffrf_batch_error(task_without_source 2 "--output '\\{case\\}_\\{task\\}\\.h5': \\{task\\} needs a task index"
  --output {case}_{task}.h5)
ffrf_batch_error(unknown_field 2 "--output '\\{run\\}\\.h5': unknown field \\{run\\}. the fields are \\{case\\} and \\{task\\}"
  --output {run}.h5)
ffrf_batch_error(task_not_number 1 "--task x: not a whole number" --task x)
ffrf_batch_error(threads_zero 1 "--threads 0: give 1 or more" --threads 0)
ffrf_batch_error(threads_not_number 1 "--threads two: not a whole number" --threads two)
# a job-array variable that is not an index
add_test(NAME batch_error_slurm_not_index
  COMMAND ${CMAKE_COMMAND}
    "-DCOMMAND=$<TARGET_FILE:ffrf>;${_case};--output;{task}.h5;--print-input"
    -DEXIT_CODE=2 "-DMESSAGE=SLURM_ARRAY_TASK_ID = \"1-3\" \\(3 characters\\): not a task index" -P ${_expect})
set_tests_properties(batch_error_slurm_not_index PROPERTIES LABELS "regression;errors;batch"
  TIMEOUT 30 ENVIRONMENT "OPENBLAS_NUM_THREADS=1;SLURM_ARRAY_TASK_ID=1-3")
# a cross-key check of a group reader (h against the run) names the override; a named joint
set(_engine "${PROJECT_SOURCE_DIR}/input/engine_rigid.nml")
add_test(NAME batch_error_cross_key
  COMMAND ${CMAKE_COMMAND} "-DCOMMAND=$<TARGET_FILE:ffrf>;${_engine};--check;--set;integrator.h=5"
    -DEXIT_CODE=2 "-DMESSAGE=--set integrator.h = 5: longer than the run, t_end - t_start = 2 s"
    -P ${_expect})
add_test(NAME batch_error_joint_not_found
  COMMAND ${CMAKE_COMMAND}
    "-DCOMMAND=$<TARGET_FILE:ffrf>;${_engine};--check;--set;joint[crank_main].body1=crank"
    -DEXIT_CODE=2 "-DMESSAGE=--set joint\\[crank_main\\].body1: no &joint named \"crank_main\" in .*engine_rigid\\.nml \\(names: main_bearing_B1, main_bearing_B3, flywheel"
    -P ${_expect})
# --help names the batch options
add_test(NAME batch_help
  COMMAND ${CMAKE_COMMAND} "-DCOMMAND=$<TARGET_FILE:ffrf>;--help" -DWORKING_DIRECTORY=${_batch}
    "-DREGEX=--set G\\[NAME\\]\\.KEY=V.*--sweep TABLE\\.csv.*--task N.*--output NAME.*--threads N.*--print-input.*--version"
    -P ${CMAKE_CURRENT_SOURCE_DIR}/regression/expect_output.cmake)
set_tests_properties(batch_error_cross_key batch_error_joint_not_found PROPERTIES
  LABELS "regression;errors;batch" TIMEOUT 30 ENVIRONMENT OPENBLAS_NUM_THREADS=1)
set_tests_properties(batch_help PROPERTIES LABELS "regression;batch" TIMEOUT 30)
