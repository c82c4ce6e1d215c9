# Output suites (owner: output): HDF5 wrapper, Gmsh mode-shape writer, postprocess scripts.
# (file names start with the executable's name: the _checked variants never share a file)
ffrf_add_unit_suite(test_io_hdf5 CHECKED)
# test_io_hdf5 leaves test_io_hdf5_layout.h5 for the h5py layout check below
set_tests_properties(test_io_hdf5 PROPERTIES FIXTURES_SETUP fortran_h5_layout)
ffrf_add_unit_suite(test_io_gmsh_writer CHECKED)
set_property(TEST test_io_gmsh_writer test_io_gmsh_writer_checked APPEND PROPERTY ENVIRONMENT
  "FFRF_GMSH=${GMSH_EXECUTABLE}")

# Python postprocessing. Debian's /usr/bin/python3 sees python3-h5py/numpy/matplotlib; a pyenv
# python3 earlier on PATH may not (toolchain.md, pitfall 10), and an earlier hint-less
# find_package(Python3) may already have picked it: default to /usr/bin/python3 unless the user
# set Python3_EXECUTABLE on the command line (a cache entry).
if(NOT DEFINED CACHE{Python3_EXECUTABLE} AND EXISTS /usr/bin/python3)
  set(Python3_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "Python 3 with numpy, h5py, matplotlib")
endif()
if(DEFINED CACHE{Python3_EXECUTABLE})
  set(Python3_EXECUTABLE "$CACHE{Python3_EXECUTABLE}")
endif()
find_package(Python3 COMPONENTS Interpreter)
if(Python3_Interpreter_FOUND)
  set(_ffrf_post "${PROJECT_SOURCE_DIR}/postprocess")
  set(_ffrf_post_tests "${PROJECT_SOURCE_DIR}/tests/postprocess")
  set(_ffrf_post_out "${PROJECT_BINARY_DIR}/postprocess_tests")
  file(MAKE_DIRECTORY "${_ffrf_post_out}")
  # h5py reads what the Fortran wrapper wrote: shapes transposed, strings, series, status
  add_test(NAME postprocess_h5py_layout
    COMMAND ${Python3_EXECUTABLE} ${_ffrf_post_tests}/check_fortran_layout.py
      ${PROJECT_BINARY_DIR}/test_io_hdf5_layout.h5)
  set_tests_properties(postprocess_h5py_layout PROPERTIES LABELS "postprocess"
    FIXTURES_REQUIRED fortran_h5_layout)
  # synthetic results files (3 RC sets + a failed run) following the results schema
  add_test(NAME postprocess_make_sample
    COMMAND ${Python3_EXECUTABLE} ${_ffrf_post_tests}/make_sample.py -o ${_ffrf_post_out})
  set_tests_properties(postprocess_make_sample PROPERTIES LABELS "postprocess"
    FIXTURES_SETUP postprocess_sample)
  add_test(NAME postprocess_reader
    COMMAND ${Python3_EXECUTABLE} ${_ffrf_post_tests}/test_reader.py ${_ffrf_post_out})
  add_test(NAME postprocess_frequency_table
    COMMAND ${Python3_EXECUTABLE} ${_ffrf_post_tests}/check_frequency_table.py
      --script ${_ffrf_post}/frequency_table.py ${_ffrf_post_out})
  add_test(NAME postprocess_plot_modes
    COMMAND ${Python3_EXECUTABLE} ${_ffrf_post_tests}/check_plot_modes.py
      --script ${_ffrf_post}/plot_modes.py ${_ffrf_post_out})
  set_tests_properties(postprocess_reader postprocess_frequency_table postprocess_plot_modes
    PROPERTIES LABELS "postprocess" FIXTURES_REQUIRED postprocess_sample
    ENVIRONMENT "MPLBACKEND=Agg")
else()
  message(WARNING "no Python 3 interpreter: postprocess tests are not registered")
endif()
