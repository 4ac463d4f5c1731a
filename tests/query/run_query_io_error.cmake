# `quack query` must fail loudly when it cannot read its input or write its answers.
# Usage: cmake -DQUACK=<exe> -DDIR=<tests/query> -DCASE=directory|full -P run_query_io_error.cmake
#   directory: `quack query <a directory>` exits 2 saying "cannot read <dir>: Is a directory";
#   full:      `quack query cases.jsonl > /dev/full` exits 2 saying "No space left on device".
if(CASE STREQUAL "directory")
  execute_process(COMMAND ${QUACK} query ${DIR} RESULT_VARIABLE status OUTPUT_VARIABLE out
                  ERROR_VARIABLE err)
  set(expected "quack query: cannot read ${DIR}: Is a directory")
elseif(CASE STREQUAL "full")
  execute_process(COMMAND ${QUACK} query ${DIR}/cases.jsonl OUTPUT_FILE /dev/full
                  RESULT_VARIABLE status ERROR_VARIABLE err)
  set(expected "quack query: cannot write the answers to standard output: No space left on device")
else()
  message(FATAL_ERROR "unknown CASE '${CASE}'")
endif()
if(NOT status EQUAL 2)
  message(FATAL_ERROR "quack query exited with '${status}', expected 2; stderr:\n${err}")
endif()
string(FIND "${err}" "${expected}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "stderr lacks \"${expected}\":\n${err}")
endif()
