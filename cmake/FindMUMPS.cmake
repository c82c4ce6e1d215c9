# FindMUMPS: Debian's double-precision MUMPS, which ships neither pkg-config nor a CMake config.
# Defines MUMPS::MUMPS.
#  - default: the sequential library (libmumps-seq-dev) with dmumps_struc.h and the sequential
#    stub mpif.h on the include path;
#  - COMPONENTS MPI (FFRF_MPI=ON): the MPI library (libmumps-dev: libdmumps, libmumps_common,
#    libpord, built with OpenMPI and ScaLAPACK); the caller links MPI itself.
find_path(MUMPS_INCLUDE_DIR dmumps_struc.h PATH_SUFFIXES include)
include(FindPackageHandleStandardArgs)
if("MPI" IN_LIST MUMPS_FIND_COMPONENTS)
  find_library(MUMPS_DMUMPS_LIBRARY NAMES dmumps)
  find_library(MUMPS_COMMON_LIBRARY NAMES mumps_common)
  find_library(MUMPS_PORD_LIBRARY NAMES pord)
  set(MUMPS_MPI_FOUND FALSE)
  if(MUMPS_DMUMPS_LIBRARY AND MUMPS_COMMON_LIBRARY)
    set(MUMPS_MPI_FOUND TRUE)
  endif()
  find_package_handle_standard_args(MUMPS REQUIRED_VARS MUMPS_DMUMPS_LIBRARY
    MUMPS_COMMON_LIBRARY MUMPS_PORD_LIBRARY MUMPS_INCLUDE_DIR HANDLE_COMPONENTS
    REASON_FAILURE_MESSAGE "the MPI build needs Debian's MPI MUMPS: .ci/install-deps --mpi (libmumps-dev openmpi-bin libopenmpi-dev)")
  if(MUMPS_FOUND AND NOT TARGET MUMPS::MUMPS)
    add_library(MUMPS::MUMPS INTERFACE IMPORTED)
    set_target_properties(MUMPS::MUMPS PROPERTIES
      INTERFACE_INCLUDE_DIRECTORIES "${MUMPS_INCLUDE_DIR}"
      INTERFACE_LINK_LIBRARIES "${MUMPS_DMUMPS_LIBRARY};${MUMPS_COMMON_LIBRARY};${MUMPS_PORD_LIBRARY}")
  endif()
  mark_as_advanced(MUMPS_INCLUDE_DIR MUMPS_DMUMPS_LIBRARY MUMPS_COMMON_LIBRARY MUMPS_PORD_LIBRARY)
  return()
endif()
find_path(MUMPS_SEQ_INCLUDE_DIR mpif.h PATHS /usr/include/mumps_seq PATH_SUFFIXES mumps_seq
  NO_DEFAULT_PATH)
find_path(MUMPS_SEQ_INCLUDE_DIR mpif.h PATH_SUFFIXES mumps_seq)
find_library(MUMPS_DMUMPS_LIBRARY NAMES dmumps_seq)
find_library(MUMPS_COMMON_LIBRARY NAMES mumps_common_seq)
find_library(MUMPS_PORD_LIBRARY NAMES pord_seq)
find_library(MUMPS_MPISEQ_LIBRARY NAMES mpiseq_seq)
find_package_handle_standard_args(MUMPS REQUIRED_VARS MUMPS_DMUMPS_LIBRARY MUMPS_COMMON_LIBRARY
  MUMPS_PORD_LIBRARY MUMPS_MPISEQ_LIBRARY MUMPS_INCLUDE_DIR MUMPS_SEQ_INCLUDE_DIR)
if(MUMPS_FOUND AND NOT TARGET MUMPS::MUMPS)
  add_library(MUMPS::MUMPS INTERFACE IMPORTED)
  set_target_properties(MUMPS::MUMPS PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${MUMPS_INCLUDE_DIR};${MUMPS_SEQ_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${MUMPS_DMUMPS_LIBRARY};${MUMPS_COMMON_LIBRARY};${MUMPS_PORD_LIBRARY};${MUMPS_MPISEQ_LIBRARY}")
endif()
mark_as_advanced(MUMPS_INCLUDE_DIR MUMPS_SEQ_INCLUDE_DIR MUMPS_DMUMPS_LIBRARY MUMPS_COMMON_LIBRARY
  MUMPS_PORD_LIBRARY MUMPS_MPISEQ_LIBRARY)
