# Pipes cases.jsonl through `quack query` (on standard input) and compares the output with
# expected.jsonl; the exit status must be 1 because some lines are rejected on purpose.
# Usage: cmake -DQUACK=<exe> -DDIR=<this dir> -DOUT=<scratch file> -P run_query.cmake
execute_process(COMMAND ${QUACK} query - INPUT_FILE ${DIR}/cases.jsonl OUTPUT_FILE ${OUT}
                RESULT_VARIABLE status)
if(NOT status EQUAL 1)
  message(FATAL_ERROR "quack query exited with ${status}, expected 1 (some lines are bad)")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${OUT} ${DIR}/expected.jsonl
                RESULT_VARIABLE different)
if(different)
  file(READ ${OUT} got)
  message(FATAL_ERROR "quack query output differs from expected.jsonl:\n${got}")
endif()
