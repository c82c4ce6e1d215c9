# Packaging and installation of ffrf (included by the top-level CMakeLists.txt).
#
#   <prefix>/lib/libffrf.a, or libffrf.so.0.1.0 -> .so.0 -> .so with -DBUILD_SHARED_LIBS=ON
#   <prefix>/bin/ffrf                                  the driver
#   <prefix>/include/ffrf.h                            the C API (when the source tree has it)
#   <prefix>/include/ffrf/<compiler>-<version>/*.mod   only the public Fortran modules
#   <prefix>/lib/pkgconfig/ffrf.pc                     pkg-config: --cflags, --libs, --static
#   <prefix>/lib/cmake/ffrf/                           find_package(ffrf): ffrf::ffrf, ffrf::driver
#   <prefix>/share/doc/ffrf/                           README.md and docs/*.md (the manual)
#
# Fortran module files are compiler specific (gfortran 12 cannot read another version's), hence
# the folder named after the compiler, as fortran-lang's stdlib does.
include(CMakePackageConfigHelpers)

# Library version: libffrf.so.<major> is the ABI a program records; bump the major version
# when the C API or the public Fortran modules change incompatibly.
set_target_properties(ffrf_lib PROPERTIES VERSION ${PROJECT_VERSION}
  SOVERSION ${PROJECT_VERSION_MAJOR})

# The public Fortran modules, the only ones installed: `use ffrf` (typed API) and `use ffrf_c`
# (interfaces of the C API for older Fortran). A module not built (yet) is skipped.
set(FFRF_PUBLIC_MODULES ffrf ffrf_c)
set(FFRF_INSTALL_MODULEDIR
  "${CMAKE_INSTALL_INCLUDEDIR}/ffrf/${CMAKE_Fortran_COMPILER_ID}-${CMAKE_Fortran_COMPILER_VERSION}"
  CACHE STRING "Install folder of the public Fortran module files, below the prefix")
target_include_directories(ffrf_lib PUBLIC
  "$<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>"
  "$<INSTALL_INTERFACE:${FFRF_INSTALL_MODULEDIR}>")

# A static Release build with LTO installs fat LTO objects: an outside program linked without
# -fno-lto would have gcc's linker plugin optimise the whole library again at its own link
# (minutes). Its users link the ordinary code: -fno-lto from the CMake package and ffrf.pc.
set(FFRF_NO_LTO "")
if(NOT BUILD_SHARED_LIBS AND FFRF_LTO AND CMAKE_Fortran_COMPILER_ID STREQUAL "GNU"
    AND CMAKE_BUILD_TYPE STREQUAL "Release")
  set(FFRF_NO_LTO "-fno-lto")
  target_link_options(ffrf_lib INTERFACE "$<INSTALL_INTERFACE:-fno-lto>")
endif()

# The installed driver of a shared build finds libffrf.so beside it: <prefix>/bin/../lib.
if(BUILD_SHARED_LIBS)
  file(RELATIVE_PATH _lib_from_bin "/${CMAKE_INSTALL_BINDIR}" "/${CMAKE_INSTALL_LIBDIR}")
  set_target_properties(ffrf PROPERTIES INSTALL_RPATH "$ORIGIN/${_lib_from_bin}")
endif()

install(TARGETS ffrf_lib ffrf EXPORT ffrfTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
foreach(module IN LISTS FFRF_PUBLIC_MODULES)
  install(FILES "${PROJECT_BINARY_DIR}/mod/${module}.mod" DESTINATION ${FFRF_INSTALL_MODULEDIR}
    OPTIONAL)
endforeach()
if(EXISTS "${PROJECT_SOURCE_DIR}/include/ffrf.h")
  install(FILES "${PROJECT_SOURCE_DIR}/include/ffrf.h" DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endif()
if(FFRF_MPI)   # the MPI_Comm convenience of the C API (MPI host programs)
  install(FILES "${PROJECT_SOURCE_DIR}/include/ffrf_mpi.h" DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endif()

# CMake package
install(FILES cmake/FindMUMPS.cmake cmake/FindARPACK.cmake cmake/FindMETIS.cmake
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/ffrf)
install(EXPORT ffrfTargets NAMESPACE ffrf:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/ffrf)
configure_package_config_file(cmake/ffrf-config.cmake.in
  "${PROJECT_BINARY_DIR}/ffrf-config.cmake" INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/ffrf)
write_basic_package_version_file("${PROJECT_BINARY_DIR}/ffrf-config-version.cmake"
  COMPATIBILITY SameMajorVersion)
install(FILES "${PROJECT_BINARY_DIR}/ffrf-config.cmake" "${PROJECT_BINARY_DIR}/ffrf-config-version.cmake"
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/ffrf)

# pkg-config. The libraries libffrf needs, as -L/-l flags: the dependencies found above and the
# Fortran runtime (a C program links with cc, which does not add libgfortran).
function(ffrf_link_flags out)
  set(implicit_dirs ${CMAKE_C_IMPLICIT_LINK_DIRECTORIES} ${CMAKE_Fortran_IMPLICIT_LINK_DIRECTORIES})
  set(flags "")
  foreach(lib IN LISTS ARGN)
    if(lib MATCHES "^-")                               # already a flag (-lpthread, -Wl,...)
      list(APPEND flags "${lib}")
    elseif(IS_ABSOLUTE "${lib}")
      get_filename_component(dir "${lib}" DIRECTORY)
      get_filename_component(name "${lib}" NAME)
      string(REGEX REPLACE "^lib(.*)\\.(so|a|dylib)(\\.[0-9.]*)?$" "\\1" name "${name}")
      list(FIND implicit_dirs "${dir}" found)
      if(found LESS 0)
        list(APPEND flags "-L${dir}")
      endif()
      list(APPEND flags "-l${name}")
    elseif(NOT lib MATCHES "::")
      list(APPEND flags "-l${lib}")
    endif()
  endforeach()
  list(REMOVE_DUPLICATES flags)
  list(JOIN flags " " flags)
  set(${out} "${flags}" PARENT_SCOPE)
endfunction()
set(_fortran_runtime ${CMAKE_Fortran_IMPLICIT_LINK_LIBRARIES})
if(CMAKE_C_IMPLICIT_LINK_LIBRARIES)
  list(REMOVE_ITEM _fortran_runtime ${CMAKE_C_IMPLICIT_LINK_LIBRARIES})
endif()
ffrf_link_flags(FFRF_PC_DEPENDENCIES ${HDF5_Fortran_LIBRARIES} ${HDF5_LIBRARIES}
  ${MUMPS_DMUMPS_LIBRARY} ${MUMPS_COMMON_LIBRARY} ${MUMPS_PORD_LIBRARY} ${MUMPS_MPISEQ_LIBRARY}
  ${PARPACK_LIBRARY} ${ARPACK_LIBRARY} ${METIS_LIBRARY} ${LAPACK_LIBRARIES} ${_fortran_runtime}
  ${MPI_Fortran_LIBRARIES} ${MPI_C_LIBRARIES})     # (MPI: only in the MPI build)
# A shared libffrf records its dependencies itself: `--libs` is -lffrf and `--static` adds the
# rest. A static-only install has no .so, so `--libs` must carry every library.
if(BUILD_SHARED_LIBS)
  set(FFRF_PC_LIBS "")
  set(FFRF_PC_LIBS_PRIVATE "${FFRF_PC_DEPENDENCIES}")
else()
  set(FFRF_PC_LIBS "${FFRF_PC_DEPENDENCIES} ${FFRF_NO_LTO}")
  set(FFRF_PC_LIBS_PRIVATE "")
endif()
# The .pc file finds its prefix from its own place (${pcfiledir}), so `cmake --install --prefix`
# anywhere gives a working file.
file(RELATIVE_PATH FFRF_PC_PREFIX_FROM_PCFILEDIR "/${CMAKE_INSTALL_LIBDIR}/pkgconfig" "/")
string(REGEX REPLACE "/$" "" FFRF_PC_PREFIX_FROM_PCFILEDIR "${FFRF_PC_PREFIX_FROM_PCFILEDIR}")
configure_file(cmake/ffrf.pc.in "${PROJECT_BINARY_DIR}/ffrf.pc" @ONLY)
install(FILES "${PROJECT_BINARY_DIR}/ffrf.pc" DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

# Documentation
install(FILES README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
# docs/ keeps its folder: README.md links docs/<topic>.md, and docs/README.md (the manual's index)
# must not replace the top-level README.md
install(DIRECTORY docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR}/docs FILES_MATCHING PATTERN "*.md")
