# Builds the consumer project against Quack in MODE find_package or add_subdirectory, then
# runs it. Fails on any step's non-zero exit.
#   find_package:     installs the build under test (BUILD) into a fresh prefix, so the
#                     library is not compiled a second time; the consumer finds it there.
#   add_subdirectory: the consumer compiles Quack's sources itself, as a vendoring user's
#                     project does (slow: labelled `slow`, run by scripts/test.sh --all).
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
endfunction()
if(MODE STREQUAL "find_package")
  run(${CMAKE_COMMAND} --install ${BUILD} --prefix ${WORK}/prefix)
  run(${CMAKE_COMMAND} -S ${CONSUMER} -B ${WORK}/consumer-build -G ${GENERATOR}
      -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_PREFIX_PATH=${WORK}/prefix)
else()
  run(${CMAKE_COMMAND} -S ${CONSUMER} -B ${WORK}/consumer-build -G ${GENERATOR}
      -DCMAKE_CXX_COMPILER=${CXX} -DQUACK_VIA_SUBDIRECTORY=ON -DQUACK_SOURCE=${QUACK_SOURCE})
endif()
run(${CMAKE_COMMAND} --build ${WORK}/consumer-build -j 2)
run(${WORK}/consumer-build/consumer)
