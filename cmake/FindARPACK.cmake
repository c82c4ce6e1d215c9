# FindARPACK: ARPACK-NG through its pkg-config file (Debian's libarpack2-dev has no CMake config
# unless libparpack2-dev is installed). Defines ARPACK::ARPACK.
find_package(PkgConfig QUIET)
if(PkgConfig_FOUND)
  pkg_check_modules(PC_ARPACK QUIET arpack)
endif()
find_library(ARPACK_LIBRARY NAMES arpack HINTS ${PC_ARPACK_LIBRARY_DIRS})
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(ARPACK REQUIRED_VARS ARPACK_LIBRARY)
if(ARPACK_FOUND AND NOT TARGET ARPACK::ARPACK)
  add_library(ARPACK::ARPACK UNKNOWN IMPORTED)
  set_target_properties(ARPACK::ARPACK PROPERTIES IMPORTED_LOCATION "${ARPACK_LIBRARY}")
endif()
mark_as_advanced(ARPACK_LIBRARY)
