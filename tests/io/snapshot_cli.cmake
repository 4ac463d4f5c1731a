# quack run --snapshot-at / --resume (docs/determinism.md, "Snapshots"): running N steps in
# one go and running to k, snapshotting, then resuming to N write byte-identical state files,
# on sample scenes of every kind (stacking and sleep, ghost edges, bullets, sensors, concave
# bodies, two broad phases); a resumed run can snapshot again. Bad values and snapshots of
# another scene are refused with a message, exit 2.
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})
function(quack_ok)
  execute_process(COMMAND ${QUACK} run ${ARGN} --quiet RESULT_VARIABLE rc OUTPUT_VARIABLE out
                  ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "quack run ${ARGN} failed (${rc}):\n${out}\n${err}")
  endif()
endfunction()
function(quack_refused expected)
  execute_process(COMMAND ${QUACK} run ${ARGN} --quiet RESULT_VARIABLE rc ERROR_VARIABLE err)
  string(FIND "${err}" "${expected}" at)
  if(NOT rc EQUAL 2 OR at EQUAL -1)
    message(FATAL_ERROR "quack run ${ARGN}: expected exit 2 and '${expected}', got ${rc}: ${err}")
  endif()
endfunction()
foreach(scene pyramid tiles bullets sensor concave players broadphase-sap broadphase-hash)
  set(s ${SRC}/scenes/${scene}.json)
  quack_ok(${s} --steps 150 --out ${OUT}/${scene}-once.json)
  quack_ok(${s} --steps 60 --out ${OUT}/${scene}-60.json --snapshot-at 60 ${OUT}/${scene}-60.snap)
  quack_ok(${s} --steps 150 --resume ${OUT}/${scene}-60.snap --snapshot-at 100
           ${OUT}/${scene}-100.snap --out ${OUT}/${scene}-resumed.json)
  quack_ok(${s} --steps 150 --resume ${OUT}/${scene}-100.snap --out ${OUT}/${scene}-twice.json)
  foreach(other resumed twice)
    execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${OUT}/${scene}-once.json
                            ${OUT}/${scene}-${other}.json RESULT_VARIABLE differ)
    if(differ)
      message(FATAL_ERROR "${scene}: the ${other} run's state differs from the run in one go")
    endif()
  endforeach()
  # The state file after resuming really is at step 150 (not the snapshot's).
  file(READ ${OUT}/${scene}-resumed.json state)
  string(FIND "${state}" "\"steps\": 150" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "${scene}: the resumed state file is not at step 150")
  endif()
endforeach()

set(p ${SRC}/scenes/pyramid.json)
quack_refused("--snapshot-at: step 20 is after the last step (10)"
              ${p} --steps 10 --out ${OUT}/x.json --snapshot-at 20 ${OUT}/x.snap)
quack_refused("--snapshot-at: abc is not a whole number"
              ${p} --steps 10 --out ${OUT}/x.json --snapshot-at abc ${OUT}/x.snap)
quack_refused("--snapshot-at"
              ${p} --steps 10 --out ${OUT}/x.json --snapshot-at 5)
quack_refused("another static structure"
              ${SRC}/scenes/tiles.json --steps 100 --out ${OUT}/x.json --resume ${OUT}/pyramid-60.snap)
quack_refused("the snapshot is at step 60, after --steps 50"
              ${p} --steps 50 --out ${OUT}/x.json --resume ${OUT}/pyramid-60.snap)
quack_refused("--snapshot-at: step 10 is before the resumed run's first (60)"
              ${p} --steps 100 --out ${OUT}/x.json --resume ${OUT}/pyramid-60.snap
              --snapshot-at 10 ${OUT}/x.snap)
quack_refused("not a quack run snapshot"
              ${p} --steps 100 --out ${OUT}/x.json --resume ${p})
# A run snapshot of a later version (text, so that CMake can write it).
file(WRITE ${OUT}/later.snap "QUACKRUNAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAA")
quack_refused("run snapshot version 1094795585 is not this build's (2)"
              ${p} --steps 100 --out ${OUT}/x.json --resume ${OUT}/later.snap)
if(EXISTS ${OUT}/x.json OR EXISTS ${OUT}/x.snap)
  message(FATAL_ERROR "a refused run wrote output")
endif()
