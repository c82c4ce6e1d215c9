# FindGmsh: the gmsh program, used to mesh the .geo sources in input/. Sets GMSH_EXECUTABLE.
find_program(GMSH_EXECUTABLE NAMES gmsh)
if(GMSH_EXECUTABLE)
  execute_process(COMMAND ${GMSH_EXECUTABLE} --version OUTPUT_VARIABLE _gmsh_out
    ERROR_VARIABLE _gmsh_out OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_STRIP_TRAILING_WHITESPACE)
  string(REGEX MATCH "[0-9]+\\.[0-9]+\\.[0-9]+" GMSH_VERSION "${_gmsh_out}")
endif()
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(Gmsh REQUIRED_VARS GMSH_EXECUTABLE VERSION_VAR GMSH_VERSION)
mark_as_advanced(GMSH_EXECUTABLE)
