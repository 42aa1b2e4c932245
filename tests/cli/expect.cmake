# Runs one wavevcm command line and checks its exit code and output.
#   cmake -DCOMMAND="a;b;c" -DEXIT_CODE=N [-DOUTPUT_MATCHES=regex] [-DWORKDIR=dir] -P expect.cmake
# OUTPUT_MATCHES is matched against stdout and stderr together.
if(NOT DEFINED WORKDIR)
  set(WORKDIR ${CMAKE_CURRENT_BINARY_DIR})
endif()
execute_process(COMMAND ${COMMAND}
  WORKING_DIRECTORY ${WORKDIR}
  RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 300)
message("exit code: ${code}\nstdout:\n${out}\nstderr:\n${err}")
if(NOT "${code}" STREQUAL "${EXIT_CODE}")
  message(FATAL_ERROR "expected exit code ${EXIT_CODE}, got ${code}")
endif()
if(DEFINED OUTPUT_MATCHES AND NOT "${out}${err}" MATCHES "${OUTPUT_MATCHES}")
  message(FATAL_ERROR "output does not match: ${OUTPUT_MATCHES}")
endif()
