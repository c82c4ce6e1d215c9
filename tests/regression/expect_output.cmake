# cmake "-DCOMMAND=prog;arg;..." -DWORKING_DIRECTORY=dir "-DREGEX=..." -P expect_output.cmake
# Runs COMMAND: it must exit 0 and its standard output + error must match REGEX.
execute_process(COMMAND ${COMMAND} WORKING_DIRECTORY "${WORKING_DIRECTORY}"
  RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "exit code ${code} (expected 0)\n${out}\n${err}")
endif()
if(NOT "${out}${err}" MATCHES "${REGEX}")
  message(FATAL_ERROR "output does not match \"${REGEX}\":\n${out}\n${err}")
endif()
message(STATUS "exit 0, output matches \"${REGEX}\"")
