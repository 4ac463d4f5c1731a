# Builds the consumer project against Quack in MODE find_package (install first) or
# add_subdirectory, then runs it. Fails on any step's non-zero exit.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
endfunction()
if(MODE STREQUAL "find_package")
  run(${CMAKE_COMMAND} -S ${QUACK_SOURCE} -B ${WORK}/quack-build -G ${GENERATOR}
      -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_BUILD_TYPE=Release -DQUACK_BUILD_TESTS=OFF
      -DQUACK_BUILD_BENCHMARKS=OFF -DQUACK_BUILD_APPS=OFF -DCMAKE_INSTALL_PREFIX=${WORK}/prefix)
  run(${CMAKE_COMMAND} --build ${WORK}/quack-build -j 2)
  run(${CMAKE_COMMAND} --install ${WORK}/quack-build)
  run(${CMAKE_COMMAND} -S ${CONSUMER} -B ${WORK}/consumer-build -G ${GENERATOR}
      -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_PREFIX_PATH=${WORK}/prefix)
else()
  run(${CMAKE_COMMAND} -S ${CONSUMER} -B ${WORK}/consumer-build -G ${GENERATOR}
      -DCMAKE_CXX_COMPILER=${CXX} -DQUACK_VIA_SUBDIRECTORY=ON -DQUACK_SOURCE=${QUACK_SOURCE})
endif()
run(${CMAKE_COMMAND} --build ${WORK}/consumer-build -j 2)
run(${WORK}/consumer-build/consumer)
