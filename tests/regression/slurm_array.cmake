# The Slurm array script postprocess/slurm_array.sh (docs/batch.md "Batch runs", issue 12 part 5)
# run without Slurm by slurm_array.py: a fake array task with stub scontrol/sbatch on PATH, SIGUSR1
# to the batch shell mid-run -> ffrf exit 5 -> `scontrol requeue 4242_1`; the requeued task
# continues with --restart and its time history equals the uninterrupted run bit for bit.
add_test(NAME regression_slurm_array
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/regression/slurm_array.py
    $<TARGET_FILE:ffrf> ${PROJECT_SOURCE_DIR}/postprocess/slurm_array.sh
    ${PROJECT_BINARY_DIR}/meshes ${PROJECT_BINARY_DIR}/tests/engine
    ${PROJECT_BINARY_DIR}/tests/slurm_array)
set_tests_properties(regression_slurm_array PROPERTIES
  LABELS "regression;engine;output" TIMEOUT 600
  FIXTURES_REQUIRED "crank_lc8_mesh;conrod_lc8_mesh")
