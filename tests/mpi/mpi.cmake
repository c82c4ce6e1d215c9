# MPI build tests (issue 12), run by the sequential build's ctest (label mpi):
#  - mpi_build (fixture): builds the MPI variant of this tree (-DFFRF_MPI=ON, no LTO, only the
#    library, the driver and the host program) into <build>/mpi with build_mpi.py; when mpicc,
#    mpif90, mpirun or Debian's MPI MUMPS are missing it records why and the tests below print
#    "skipped: <why>" (exit 77, ctest reports them as skipped). `.ci/install-deps --mpi`.
#  - mpi_modes_crank_rc{1,2,3}[_rbe2]: input/crank_rc*.nml on the lc 8 mm mesh, the sequential
#    driver and `mpirun -np 2` of the MPI driver: frequencies equal to 1e-9 (relative), the MPI
#    run writes the same files once, its results hold the peak memory of both ranks and MUMPS's
#    analysis estimates; with memory_limit_mb = 1 it is refused on every rank (exit 4).
#  - mpi_modes_crank_rc1_block, mpi_modes_crank_rc2_rbe2_block: the same with the block
#    eigensolver (&modes eigensolver = 'block') in both runs; then SIGUSR1 to mpirun inside the
#    block eigen loop (on the lc 6 mm crank.msh): the ranks stop together, exit 5, status
#    'interrupted: SIGUSR1'.
#  - every modes test: the automatic memory limit of a rank takes MemAvailable / 2 (2 ranks on
#    this node) beside its resident memory.
#  - mpi_modes_free_crank_{arpack,block}: the free-free crank (tests/mpi/free_crank_lc8.nml, its
#    rigid modes deflated, 3 modes) against the sequential driver and the first 3 of a 12-mode
#    MPI run, 1e-9; mpi_modes_crank_rc1_max_frequency: every mode below 20 kHz; every modes
#    test: the Sturm check proven with the sequential run's count.
#  - mpi_modes_crank_rc1_parpack_ranks{1,2,3,4} (issue 27): crank RC set 1 on the lc 10 mm mesh,
#    ARPACK eigensolver, the MPI driver on 1, 2, 3 and 4 ranks (oversubscribed on 2 cores): PARPACK
#    ran with each rank's block of rows (its debug line), frequencies equal the sequential
#    driver's to 1e-10 (relative), shapes to 1e-8 of their largest component (up to sign).
#  - mpi_engine: the short lc 8 mm engine of the C API tests (20 ms, 10 modes per body, h 1e-4 s)
#    under mpirun -np 2 against the sequential driver: crank angle and speed histories to 1e-9
#    of their largest value.
#  - mpi_host_program: a C MPI host (host_program.c) on 3 ranks split into communicators of 2
#    and 1 ranks, each running crank lc 8 mm RC set 2 through ffrf_case_set_mpi_comm:
#    frequencies of both groups equal the sequential driver's to 1e-9; both groups also advance
#    the mpi_engine case through the C API in two halves: final time, crank angle and speed
#    equal the sequential driver's last step to 1e-9.
set(_mpi_build "${PROJECT_BINARY_DIR}/mpi")
set(_mpi_out "${PROJECT_BINARY_DIR}/tests/mpi")
add_test(NAME mpi_build
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/mpi/build_mpi.py
    --source ${PROJECT_SOURCE_DIR} --build ${_mpi_build} --cmake ${CMAKE_COMMAND})
set_tests_properties(mpi_build PROPERTIES FIXTURES_SETUP mpi_build LABELS mpi TIMEOUT 900
  PROCESSORS 2)

set(_mpi_run ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/mpi/run_mpi_case.py)
foreach(_case crank_rc1 crank_rc2 crank_rc3 crank_rc1_rbe2 crank_rc2_rbe2 crank_rc3_rbe2)
  add_test(NAME mpi_modes_${_case}
    COMMAND ${_mpi_run} modes --mpi-build ${_mpi_build} --driver $<TARGET_FILE:ffrf>
      --case ${PROJECT_SOURCE_DIR}/input/${_case}.nml --mesh-dir ${PROJECT_BINARY_DIR}/meshes
      --set body[crank].mesh_file=crank_lc8.msh --out ${_mpi_out}/${_case} --ranks 2
      --rtol 1e-9)
  set_tests_properties(mpi_modes_${_case} PROPERTIES LABELS mpi SKIP_RETURN_CODE 77
    FIXTURES_REQUIRED "mpi_build;crank_lc8_mesh" PROCESSORS 2)
endforeach()
# the block eigensolver (eigensolver = 'block', right-hand-side blocks through the distributed
# solves): the MPI run against the sequential one with the same method, 1e-9
foreach(_case crank_rc1 crank_rc2_rbe2)
  add_test(NAME mpi_modes_${_case}_block
    COMMAND ${_mpi_run} modes --mpi-build ${_mpi_build} --driver $<TARGET_FILE:ffrf>
      --case ${PROJECT_SOURCE_DIR}/input/${_case}.nml --mesh-dir ${PROJECT_BINARY_DIR}/meshes
      --set body[crank].mesh_file=crank_lc8.msh --set modes.eigensolver=block
      --out ${_mpi_out}/${_case}_block --ranks 2 --rtol 1e-9 --signal-check)
  set_tests_properties(mpi_modes_${_case}_block PROPERTIES LABELS mpi SKIP_RETURN_CODE 77
    FIXTURES_REQUIRED "mpi_build;crank_lc8_mesh;crank_mesh" PROCESSORS 2)
endforeach()
# issue 22: the free-free crank's rigid modes deflated under MPI (3 modes, against the sequential
# run and against the first 3 of a 12-mode MPI run, both eigensolvers), and max_frequency_hz
# (crank RC set 1 below 20 kHz) against the sequential driver; the Sturm check proven with the
# sequential count
foreach(_solver arpack block)
  add_test(NAME mpi_modes_free_crank_${_solver}
    COMMAND ${_mpi_run} modes --mpi-build ${_mpi_build} --driver $<TARGET_FILE:ffrf>
      --case ${CMAKE_CURRENT_SOURCE_DIR}/mpi/free_crank_lc8.nml
      --mesh-dir ${PROJECT_BINARY_DIR}/meshes --set modes.eigensolver=${_solver}
      --out ${_mpi_out}/free_crank_${_solver} --ranks 2 --rtol 1e-9 --compare-num-modes 12)
  set_tests_properties(mpi_modes_free_crank_${_solver} PROPERTIES LABELS mpi
    SKIP_RETURN_CODE 77 FIXTURES_REQUIRED "mpi_build;crank_lc8_mesh" PROCESSORS 2)
endforeach()
add_test(NAME mpi_modes_crank_rc1_max_frequency
  COMMAND ${_mpi_run} modes --mpi-build ${_mpi_build} --driver $<TARGET_FILE:ffrf>
    --case ${PROJECT_SOURCE_DIR}/input/crank_rc1.nml --mesh-dir ${PROJECT_BINARY_DIR}/meshes
    --set body[crank].mesh_file=crank_lc8.msh --set modes.max_frequency_hz=20000
    --set modes.num_modes=10000 --out ${_mpi_out}/crank_rc1_max_frequency --ranks 2
    --rtol 1e-9)
set_tests_properties(mpi_modes_crank_rc1_max_frequency PROPERTIES LABELS mpi SKIP_RETURN_CODE 77
  FIXTURES_REQUIRED "mpi_build;crank_lc8_mesh" PROCESSORS 2)
# issue 27: PARPACK's row-distributed Lanczos vectors on 1 to 4 ranks against sequential ARPACK
foreach(_ranks 1 2 3 4)
  add_test(NAME mpi_modes_crank_rc1_parpack_ranks${_ranks}
    COMMAND ${_mpi_run} ranks --mpi-build ${_mpi_build} --driver $<TARGET_FILE:ffrf>
      --case ${PROJECT_SOURCE_DIR}/input/crank_rc1.nml --mesh-dir ${PROJECT_BINARY_DIR}/meshes
      --set body[crank].mesh_file=crank_lc10.msh --set modes.eigensolver=arpack
      --out ${_mpi_out}/crank_rc1_parpack_ranks${_ranks} --ranks ${_ranks} --rtol 1e-10
      --shape-rtol 1e-8)
  set_tests_properties(mpi_modes_crank_rc1_parpack_ranks${_ranks} PROPERTIES LABELS mpi
    SKIP_RETURN_CODE 77 FIXTURES_REQUIRED "mpi_build;crank_lc10_mesh" PROCESSORS 2)
endforeach()
add_test(NAME mpi_engine
  COMMAND ${_mpi_run} engine --mpi-build ${_mpi_build} --driver $<TARGET_FILE:ffrf>
    --case ${PROJECT_BINARY_DIR}/tests/capi/capi_engine.nml
    --mesh-dir ${PROJECT_BINARY_DIR}/meshes --out ${_mpi_out}/engine --ranks 2 --rtol 1e-9)
set_tests_properties(mpi_engine PROPERTIES LABELS mpi SKIP_RETURN_CODE 77
  FIXTURES_REQUIRED "mpi_build;crank_lc8_mesh;conrod_lc8_mesh" PROCESSORS 2)
add_test(NAME mpi_host_program
  COMMAND ${_mpi_run} host --mpi-build ${_mpi_build} --driver $<TARGET_FILE:ffrf>
    --case ${PROJECT_SOURCE_DIR}/tests/regression/crank_lc8_rc2.nml
    --engine ${PROJECT_BINARY_DIR}/tests/capi/capi_engine.nml
    --mesh-dir ${PROJECT_BINARY_DIR}/meshes --out ${_mpi_out}/host --ranks 3 --rtol 1e-9)
set_tests_properties(mpi_host_program PROPERTIES LABELS mpi SKIP_RETURN_CODE 77
  FIXTURES_REQUIRED "mpi_build;crank_lc8_mesh;conrod_lc8_mesh" PROCESSORS 2)
