# ctest script: `use ffrf` and `use ffrf_c` compile with only ffrf.mod and ffrf_c.mod in the
# include folder (what the installation ships), so no internal module file is needed.
# -DCOMPILER=<Fortran compiler> -DMOD_DIR=<build mod folder> -DWORK=<scratch folder>
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}/include")
file(COPY "${MOD_DIR}/ffrf.mod" "${MOD_DIR}/ffrf_c.mod" DESTINATION "${WORK}/include")
file(WRITE "${WORK}/outside.f90" "program outside
   use ffrf, only: ffrf_case_t, error_t, dp
   use ffrf_c, only: ffrf_version, FFRF_OK
   implicit none
   type(ffrf_case_t) :: engine
   type(error_t), allocatable :: error
   real(dp) :: angle, speed
   call engine%open('engine.nml', error)
   if (.not. allocated(error)) call engine%advance(1.0e-3_dp, error)
   if (.not. allocated(error)) call engine%crank_state(angle, speed, error)
   call engine%close()
end program outside
")
execute_process(COMMAND "${COMPILER}" -c -I "${WORK}/include" outside.f90
  WORKING_DIRECTORY "${WORK}" RESULT_VARIABLE status ERROR_VARIABLE messages)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "use ffrf with only ffrf.mod and ffrf_c.mod failed:\n${messages}")
endif()
message(STATUS "use ffrf and use ffrf_c compile with only ffrf.mod and ffrf_c.mod")
