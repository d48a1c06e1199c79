# One command-line test of an example (ctest, label "cli"), run as
#   cmake -D PROGRAM=<exe> -D ARGS=<arguments, separated by |> -D CODE=<exit code>
#         -D REGEX=<regular expression> -P cli_test.cmake
# Passes when the program exits with CODE and its output (stdout and stderr) matches REGEX.
# (PASS_REGULAR_EXPRESSION alone would ignore the exit code.)
foreach(var PROGRAM CODE REGEX)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "cli_test.cmake: ${var} is not set")
  endif()
endforeach()
string(REPLACE "|" ";" args "${ARGS}")
execute_process(COMMAND "${PROGRAM}" ${args}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 30)
if(NOT rc STREQUAL CODE)
  message(FATAL_ERROR "'${PROGRAM} ${args}' exited with ${rc}, expected ${CODE}; its output:\n${out}${err}")
endif()
if(NOT "${out}${err}" MATCHES "${REGEX}")
  message(FATAL_ERROR "the output of '${PROGRAM} ${args}' does not match '${REGEX}':\n${out}${err}")
endif()
message(STATUS "exit code ${rc}: ${out}${err}")
