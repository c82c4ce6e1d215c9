# C API tests (label capi): C99 programs against include/ffrf.h, compiled with
# -Wall -Wextra -pedantic -Werror.
#  - capi_bad_calls: every entry point's failure paths (NULL handles and pointers, bad indices,
#    calls out of order, a missing and a bad case file, small buffers), status and message;
#    again under AddressSanitizer + UBSan (capi_bad_calls_asan) and valgrind
#    (capi_bad_calls_valgrind, --leak-check=full, any error fails).
#  - capi_node_sets: interfaces on node sets (ffrf_case_add_interface_nodes) give the modes of
#    the surface interfaces with the same nodes and weights (uniform, tributary and consistent
#    area weights, to 1e-12) on a Tet10 block built from arrays.
#  - capi_sensors: ffrf_sensor_count/name/values on a crank-less slider mechanism (closed
#    forms) and the engine (crank sensors = ffrf_crank_state), failure paths included.
#  - capi_frames: marker frames (a ground &marker orientation, framed markers at flexible
#    interfaces) and a bad orientation refused through ffrf_case_open.
#  - capi_mesh_markers: a flexible body's marker at a mesh point that is no interface (the
#    cantilever's tip-face RBE3 point): counted, its state equal to its sensor, a load set on it
#    by ffrf_marker_set_load equal to the &load at it (test_capi_mesh_markers.c).
#  - capi_compare_driver: the C API's frequencies (crank lc 8 mm, RC set 2) equal the driver's
#    bitwise, and the lc 8 mm engine (flexible crank and conrod, 10 modes, h = 1e-4 s, 20 ms)
#    advanced in 1 ms chunks reaches the driver's crank angle and speed at every chunk to
#    1e-10 (compare_driver.py reads the driver's HDF5 results).
#  - capi_record_driver: that engine advanced in 1 ms chunks with an output folder writes the
#    driver's results file and animations, bitwise apart from the timings (compare_record.py).
#  - capi_values_driver: every value-returning entry point on every path (modal and mechanism,
#    with and without an output folder, after 1 ms chunks and after one run to t_end) against
#    the driver's results file, or a numpy recomputation where the file does not hold the
#    value (compare_values.py: the matrix and its tolerances).
set(_capi_out "${PROJECT_BINARY_DIR}/tests/capi")
file(MAKE_DIRECTORY "${_capi_out}")

# The short engine case: input/engine_rc1.nml on the lc 8 mm meshes, hand-set model, 20 ms
file(READ "${PROJECT_SOURCE_DIR}/input/engine_rc1.nml" _text)
ffrf_replace(_text "'crank.msh'" "'crank_lc8.msh'")
ffrf_replace(_text "'conrod.msh'" "'conrod_lc8.msh'")
ffrf_replace(_text "t_end = 2.0" "t_end = 0.02")
ffrf_replace(_text "selection = 'auto'" "selection = 'manual'")
ffrf_replace(_text "&integrator t_end" "&integrator h = 1.0e-4, t_end")
ffrf_replace(_text "type = 'flexible', modal_damping = 0.02,\n"
  "type = 'flexible', modal_damping = 0.02, num_modes = 10,\n")
ffrf_replace(_text "&run title = '" "&run output = 'capi_engine.h5', title = '")
file(WRITE "${_capi_out}/capi_engine.nml" "${_text}")
# the same engine to 5 ms for capi_values_driver (every entry point on every path)
ffrf_replace(_text "t_end = 0.02" "t_end = 0.005")
ffrf_replace(_text "output = 'capi_engine.h5'" "output = 'capi_values_engine.h5'")
file(WRITE "${_capi_out}/capi_values_engine.nml" "${_text}")
# issue 30's first variant (piston 0.9 kg, compression ratio 12) on the model with near-redundant
# equations from t = 0 (crank lc 10 mm with 4 modes, conrod with 2: regression_reactions_variant_*)
# for capi_values_variant: the API's raw multipliers equal the driver's reactions bitwise at
# every component /joints/<j>/reaction_min_norm leaves at 0
ffrf_replace(_text "output = 'capi_values_engine.h5'" "output = 'capi_values_variant.h5'")
ffrf_replace(_text "'crank_lc8.msh'" "'crank_lc10.msh'")
ffrf_replace(_text "mass = 0.45" "mass = 0.9")
ffrf_replace(_text "&pressure target_peak_pressure" "&pressure compression_ratio = 12, target_peak_pressure")
string(REGEX REPLACE "(name = 'crank'[^/]*)num_modes = 10" "\\1num_modes = 4" _text "${_text}")
string(REGEX REPLACE "(name = 'conrod'[^/]*)num_modes = 10" "\\1num_modes = 2" _text "${_text}")
file(WRITE "${_capi_out}/capi_values_variant.nml" "${_text}")

set(_capi_flags -std=c99 -Wall -Wextra -pedantic -Werror)
# linked from the fat objects' ordinary code (-fno-lto: no link-time optimisation of the whole
# library into each test, minutes per program)
set(_capi_link "$<$<C_COMPILER_ID:GNU>:-fno-lto>")
foreach(program test_capi_bad_calls test_capi_run test_capi_node_sets test_capi_record
    test_capi_values test_capi_sensors test_capi_drivers test_capi_frames test_capi_mesh_markers
    test_capi_pose)
  add_executable(${program} capi/${program}.c)
  target_link_libraries(${program} PRIVATE ffrf::ffrf m)
  target_compile_options(${program} PRIVATE ${_capi_flags})
  target_link_options(${program} PRIVATE ${_capi_link})
  set_target_properties(${program} PROPERTIES C_STANDARD 99 C_EXTENSIONS OFF)
endforeach()
add_executable(test_capi_bad_calls_asan capi/test_capi_bad_calls.c)
target_link_libraries(test_capi_bad_calls_asan PRIVATE ffrf::ffrf)
target_compile_options(test_capi_bad_calls_asan PRIVATE ${_capi_flags} -g
  -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all)
target_link_options(test_capi_bad_calls_asan PRIVATE -fsanitize=address,undefined ${_capi_link})

set(_capi_args "${PROJECT_SOURCE_DIR}/tests/regression/crank_lc8_rc2.nml"
  "${_capi_out}/capi_engine.nml" "${PROJECT_BINARY_DIR}/meshes" "${_capi_out}")
add_test(NAME capi_bad_calls COMMAND test_capi_bad_calls ${_capi_args})
add_test(NAME capi_bad_calls_asan COMMAND test_capi_bad_calls_asan ${_capi_args})
set_tests_properties(capi_bad_calls_asan PROPERTIES ENVIRONMENT
  "ASAN_OPTIONS=detect_leaks=1:abort_on_error=0;UBSAN_OPTIONS=print_stacktrace=1")
find_program(VALGRIND_EXECUTABLE valgrind)
set(_capi_tests capi_bad_calls capi_bad_calls_asan)
if(VALGRIND_EXECUTABLE)
  add_test(NAME capi_bad_calls_valgrind COMMAND ${VALGRIND_EXECUTABLE} --error-exitcode=1
    --leak-check=full --errors-for-leak-kinds=definite,indirect
    $<TARGET_FILE:test_capi_bad_calls> ${_capi_args})
  list(APPEND _capi_tests capi_bad_calls_valgrind)
endif()
set_tests_properties(${_capi_tests} PROPERTIES LABELS "capi")

# Sensors through the C API (test_capi_sensors.c): a crank-less slider mechanism against closed
# forms at every 10 ms chunk, the engine's crank sensors equal to ffrf_crank_state, bad calls
add_test(NAME capi_sensors COMMAND test_capi_sensors
  "${PROJECT_SOURCE_DIR}/tests/data/sensors/slider_wheel.nml" "${_capi_out}/capi_engine.nml"
  "${PROJECT_BINARY_DIR}/meshes")
set_tests_properties(capi_sensors PROPERTIES LABELS "capi" ENVIRONMENT "OPENBLAS_NUM_THREADS=1"
  FIXTURES_REQUIRED "crank_lc8_mesh;conrod_lc8_mesh")

# Drivers through the C API (test_capi_drivers.c): ffrf_driver_state on input/driven_crank.nml
# against the closed forms of a crank spun up under gravity, and its failure paths
add_test(NAME capi_drivers COMMAND test_capi_drivers
  "${PROJECT_SOURCE_DIR}/input/driven_crank.nml" "${PROJECT_BINARY_DIR}/meshes")
set_tests_properties(capi_drivers PROPERTIES LABELS "capi;drivers" ENVIRONMENT
  "OPENBLAS_NUM_THREADS=1")
# Marker frames through the C API (test_capi_frames.c): a rigid pendulum about a ground
# &marker orientation against energy conservation, the framed markers of a flexible pendulum
# about its links' y axis, a bad orientation refused with its place
add_test(NAME capi_frames COMMAND test_capi_frames
  "${PROJECT_SOURCE_DIR}/tests/data/frames/rigid_pendulum_oriented.nml"
  "${PROJECT_SOURCE_DIR}/tests/regression/frames_pendulum_xz.nml"
  "${PROJECT_SOURCE_DIR}/tests/data/frames/bad_marker_orientation.nml"
  "${PROJECT_BINARY_DIR}/meshes")
set_tests_properties(capi_frames PROPERTIES LABELS "capi" ENVIRONMENT "OPENBLAS_NUM_THREADS=1"
  FIXTURES_REQUIRED beam_lc6_mesh)

# The body pose through the APIs (issue 24): a rigid rod without pose keys given its pose by
# ffrf_body_set_pose and run with an output folder equals, bitwise, the driver's run with the
# pose as --set (compare_pose.py; the refusals checked by test_capi_pose.c first); the same
# through ffrf_case_t%set_pose against the pose in the namelist (test_pose_fortran.f90)
add_test(NAME capi_pose_driver
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 ${Python3_EXECUTABLE}
    ${CMAKE_CURRENT_SOURCE_DIR}/capi/compare_pose.py $<TARGET_FILE:ffrf>
    $<TARGET_FILE:test_capi_pose> "${CMAKE_CURRENT_SOURCE_DIR}/capi/pose_pendulum.nml"
    "${PROJECT_BINARY_DIR}/meshes" "${_capi_out}/pose")
set_tests_properties(capi_pose_driver PROPERTIES LABELS "capi;regression")
add_library(ffrf_api_checks OBJECT capi/api_checks.f90)
target_link_libraries(ffrf_api_checks PRIVATE ffrf::ffrf)
add_executable(test_pose_fortran capi/test_pose_fortran.f90)
target_link_libraries(test_pose_fortran PRIVATE ffrf_api_checks)
target_link_libraries(test_pose_fortran PRIVATE ffrf::ffrf)
target_link_options(test_pose_fortran PRIVATE "$<$<Fortran_COMPILER_ID:GNU>:-fno-lto>")
add_test(NAME capi_pose_fortran COMMAND test_pose_fortran
  "${CMAKE_CURRENT_SOURCE_DIR}/capi/pose_pendulum.nml"
  "${CMAKE_CURRENT_SOURCE_DIR}/capi/pose_pendulum_posed.nml" "${PROJECT_BINARY_DIR}/meshes")
set_tests_properties(capi_pose_fortran PROPERTIES LABELS "capi" ENVIRONMENT
  "OPENBLAS_NUM_THREADS=1")

add_test(NAME capi_compare_driver
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 ${Python3_EXECUTABLE}
    ${CMAKE_CURRENT_SOURCE_DIR}/capi/compare_driver.py $<TARGET_FILE:ffrf>
    $<TARGET_FILE:test_capi_run> "${PROJECT_SOURCE_DIR}/tests/regression/crank_lc8_rc2.nml"
    "${_capi_out}/capi_engine.nml" "${PROJECT_BINARY_DIR}/meshes" "${_capi_out}" 1.0e-3)
set_tests_properties(capi_compare_driver PROPERTIES LABELS "capi;regression"
  FIXTURES_REQUIRED "crank_lc8_mesh;conrod_lc8_mesh")

# distinct handles in distinct threads: two modal runs (crank lc 8 mm, one writing results) and
# two engine mechanisms (5 ms in 1 ms chunks) at once give, bitwise, what each gives alone
add_executable(test_capi_threads capi/test_capi_threads.c)
target_link_libraries(test_capi_threads PRIVATE ffrf::ffrf m)
target_compile_options(test_capi_threads PRIVATE -std=c99 -Wall -Wextra -pedantic -Werror -pthread)
target_link_options(test_capi_threads PRIVATE ${_capi_link} -pthread)
add_test(NAME capi_threads COMMAND test_capi_threads
  "${PROJECT_SOURCE_DIR}/tests/regression/crank_lc8_rc2.nml" "${_capi_out}/capi_engine.nml"
  "${PROJECT_BINARY_DIR}/meshes" "${_capi_out}")
set_tests_properties(capi_threads PROPERTIES LABELS "capi" ENVIRONMENT "OPENBLAS_NUM_THREADS=1"
  FIXTURES_REQUIRED "crank_lc8_mesh;conrod_lc8_mesh")

# The same engine advanced in 1 ms chunks with an output folder writes the driver's results
# file (bitwise, timings apart); a run closed at t_end / 2 leaves a complete file
# (compare_record.py)
add_test(NAME capi_record_driver
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 ${Python3_EXECUTABLE}
    ${CMAKE_CURRENT_SOURCE_DIR}/capi/compare_record.py $<TARGET_FILE:ffrf>
    $<TARGET_FILE:test_capi_record> "${_capi_out}/capi_engine.nml" "${PROJECT_BINARY_DIR}/meshes"
    "${_capi_out}/record" 1.0e-3)
set_tests_properties(capi_record_driver PROPERTIES LABELS "capi;regression"
  FIXTURES_REQUIRED "crank_lc8_mesh;conrod_lc8_mesh")
file(MAKE_DIRECTORY "${_capi_out}/record")

# Every value-returning entry point on every path (modal and mechanism, with and without an
# output folder, after 1 ms chunks and after a run in one call) against the driver's results
# file, or an independent recomputation where the file does not hold the value
# (compare_values.py: the matrix and its tolerances in its docstring)
add_test(NAME capi_values_driver
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 ${Python3_EXECUTABLE}
    ${CMAKE_CURRENT_SOURCE_DIR}/capi/compare_values.py $<TARGET_FILE:ffrf>
    $<TARGET_FILE:test_capi_values> "${PROJECT_SOURCE_DIR}/tests/regression/crank_lc8_rc2.nml"
    "${_capi_out}/capi_values_engine.nml" "${PROJECT_BINARY_DIR}/meshes" "${_capi_out}/values"
    1.0e-3)
set_tests_properties(capi_values_driver PROPERTIES LABELS "capi;regression"
  FIXTURES_REQUIRED "crank_lc8_mesh;conrod_lc8_mesh")
add_test(NAME capi_values_variant
  COMMAND ${CMAKE_COMMAND} -E env OPENBLAS_NUM_THREADS=1 ${Python3_EXECUTABLE}
    ${CMAKE_CURRENT_SOURCE_DIR}/capi/compare_values.py $<TARGET_FILE:ffrf>
    $<TARGET_FILE:test_capi_values> "${PROJECT_SOURCE_DIR}/tests/regression/crank_lc8_rc2.nml"
    "${_capi_out}/capi_values_variant.nml" "${PROJECT_BINARY_DIR}/meshes"
    "${_capi_out}/values_variant" 1.0e-3)
set_tests_properties(capi_values_variant PROPERTIES LABELS "capi;regression"
  FIXTURES_REQUIRED "crank_lc8_mesh;crank_lc10_mesh;conrod_lc8_mesh")

# examples/fortran_host built against the build tree (PACK's ctest builds it against the
# installed package): the host-torque loop matches the drag run within its derived bound
add_executable(example_fortran_host ${PROJECT_SOURCE_DIR}/examples/fortran_host/host.f90)
target_link_libraries(example_fortran_host PRIVATE ffrf::ffrf)
target_link_options(example_fortran_host PRIVATE "$<$<Fortran_COMPILER_ID:GNU>:-fno-lto>")
add_test(NAME capi_example_fortran_host COMMAND example_fortran_host
  "${PROJECT_SOURCE_DIR}/input" "${PROJECT_BINARY_DIR}/meshes" "${_capi_out}")
set_tests_properties(capi_example_fortran_host PROPERTIES LABELS "capi;example"
  ENVIRONMENT "OPENBLAS_NUM_THREADS=1" FIXTURES_REQUIRED "crank_lc8_mesh;conrod_lc8_mesh")

# use ffrf_c from Fortran; use ffrf / ffrf_c with only the two public module files
add_executable(test_ffrf_c capi/test_ffrf_c.f90)
target_link_libraries(test_ffrf_c PRIVATE ffrf::ffrf)
target_link_options(test_ffrf_c PRIVATE "$<$<Fortran_COMPILER_ID:GNU>:-fno-lto>")
add_test(NAME capi_ffrf_c COMMAND test_ffrf_c)
add_test(NAME capi_public_modules COMMAND ${CMAKE_COMMAND}
  -DCOMPILER=${CMAKE_Fortran_COMPILER} -DMOD_DIR=${PROJECT_BINARY_DIR}/mod
  -DWORK=${_capi_out}/public_modules -P ${CMAKE_CURRENT_SOURCE_DIR}/capi/public_modules.cmake)
set_tests_properties(capi_ffrf_c capi_public_modules PROPERTIES LABELS "capi")

# examples/c_body_arrays built against the build tree: a cantilever from arrays (Tet10), its
# mass exact and its first bending pair within 2 % of Euler-Bernoulli
add_executable(example_c_body_arrays ${PROJECT_SOURCE_DIR}/examples/c_body_arrays/body_arrays.c)
target_link_libraries(example_c_body_arrays PRIVATE ffrf::ffrf m)
target_compile_options(example_c_body_arrays PRIVATE ${_capi_flags})
target_link_options(example_c_body_arrays PRIVATE ${_capi_link})
add_test(NAME capi_example_c_body_arrays COMMAND example_c_body_arrays)
set_tests_properties(capi_example_c_body_arrays PROPERTIES LABELS "capi;example"
  ENVIRONMENT "OPENBLAS_NUM_THREADS=1")

add_test(NAME capi_node_sets COMMAND test_capi_node_sets)
set_tests_properties(capi_node_sets PROPERTIES LABELS "capi;rbe3"
  ENVIRONMENT "OPENBLAS_NUM_THREADS=1")

# Markers at mesh points through the C API (test_capi_mesh_markers.c): the cantilever of
# input/cantilever_tip_load.nml, and the same without its &load (the force set
# by ffrf_marker_set_load)
file(READ "${PROJECT_SOURCE_DIR}/input/cantilever_tip_load.nml" _text)
ffrf_replace(_text "&load name = 'tip', type = 'force', body = 'bar', marker = 'tip_face', direction = 0, -1, 0, value = 10.0 /\n" "")
file(WRITE "${_capi_out}/cantilever_tip_free.nml" "${_text}")
add_test(NAME capi_mesh_markers COMMAND test_capi_mesh_markers
  "${PROJECT_SOURCE_DIR}/input/cantilever_tip_load.nml"
  "${_capi_out}/cantilever_tip_free.nml" "${PROJECT_BINARY_DIR}/meshes")
set_tests_properties(capi_mesh_markers PROPERTIES LABELS "capi" ENVIRONMENT "OPENBLAS_NUM_THREADS=1"
  FIXTURES_REQUIRED cantilever_mesh)
