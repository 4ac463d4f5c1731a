# quack run on a sample scene (exit 0, state, SVG and replay written), on a bad scene
# (exit 2, the message names file and JSON path, nothing written) and on bad arguments.
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})
execute_process(COMMAND ${QUACK} run ${SRC}/scenes/pyramid.json --steps 30 --out ${OUT}/state.json
                        --svg ${OUT}/last.svg --html ${OUT}/replay.html
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "quack run failed (${rc}):\n${out}\n${err}")
endif()
foreach(f state.json last.svg replay.html)
  if(NOT EXISTS ${OUT}/${f})
    message(FATAL_ERROR "quack run did not write ${f}")
  endif()
endforeach()
foreach(line "bodies    211 (210 dynamic)" "steps     30" "awake     210 of 210 non-static bodies at the end"
             "replay    ")
  string(FIND "${out}" "${line}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "summary lacks '${line}':\n${out}")
  endif()
endforeach()
execute_process(COMMAND ${QUACK} run ${SRC}/tests/io/bad_scenes/bad_radius.json --steps 30
                        --out ${OUT}/bad.json RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 2)
  message(FATAL_ERROR "a bad scene should exit 2, got ${rc}")
endif()
string(FIND "${err}" "bad_radius.json: bodies[1].shapes[0].radius: must be > 0" at)
if(at EQUAL -1)
  message(FATAL_ERROR "unexpected message: ${err}")
endif()
file(GLOB bad_parts ${OUT}/bad.json.part*)
if(EXISTS ${OUT}/bad.json OR bad_parts)
  message(FATAL_ERROR "a failed run wrote output")
endif()
# An unwritable output is refused before running, and the earlier state file survives.
execute_process(COMMAND ${QUACK} run ${SRC}/scenes/pyramid.json --steps 5 --out ${OUT}/state.json
                        --svg ${OUT}/no/such/dir/x.svg RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 2)
  message(FATAL_ERROR "an unwritable output should exit 2, got ${rc}")
endif()
file(READ ${OUT}/state.json state)
string(FIND "${state}" "\"steps\": 30" at)
if(at EQUAL -1)
  message(FATAL_ERROR "the earlier state file was overwritten")
endif()
# Issue 12: `--steps abc` said "Value abc not in range"; a usage error exits 2 and says what
# is wrong with the value.
execute_process(COMMAND ${QUACK} run ${SRC}/scenes/pyramid.json --steps abc --out ${OUT}/s.json
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 2)
  message(FATAL_ERROR "--steps abc should exit 2, got ${rc}")
endif()
string(FIND "${err}" "--steps: abc is not a whole number" at)
if(at EQUAL -1)
  message(FATAL_ERROR "unexpected message for --steps abc: ${err}")
endif()
execute_process(COMMAND ${QUACK} run ${SRC}/scenes/pyramid.json --steps 100000001 --out ${OUT}/s.json
                RESULT_VARIABLE rc ERROR_VARIABLE err)
string(FIND "${err}" "--steps: 100000001 is more than 100000000 steps" at)
if(NOT rc EQUAL 2 OR at EQUAL -1)
  message(FATAL_ERROR "unexpected answer to --steps 100000001 (${rc}): ${err}")
endif()
# Issue 12: a scene path that is a directory said "unexpected end of input".
execute_process(COMMAND ${QUACK} run ${SRC}/scenes --out ${OUT}/s.json RESULT_VARIABLE rc
                ERROR_VARIABLE err)
string(FIND "${err}" "scenes: is a directory, not a scene file" at)
if(NOT rc EQUAL 2 OR at EQUAL -1)
  message(FATAL_ERROR "unexpected answer to a directory scene (${rc}): ${err}")
endif()
# Issue 9: `--out DIR` is refused before running, and leaves no DIR.part.
file(MAKE_DIRECTORY ${OUT}/dir)
execute_process(COMMAND ${QUACK} run ${SRC}/scenes/pyramid.json --out ${OUT}/dir
                RESULT_VARIABLE rc ERROR_VARIABLE err)
string(FIND "${err}" "dir: is a directory" at)
if(NOT rc EQUAL 2 OR at EQUAL -1)
  message(FATAL_ERROR "unexpected answer to --out DIR (${rc}): ${err}")
endif()
file(GLOB parts ${OUT}/*.part*)
if(parts)
  message(FATAL_ERROR "temporaries left behind: ${parts}")
endif()

# --threads: 1..64, refused by name otherwise.
foreach(bad 0 65 two)
  execute_process(COMMAND ${QUACK} run ${SRC}/scenes/pyramid.json --threads ${bad} --out ${OUT}/s.json
                  RESULT_VARIABLE rc ERROR_VARIABLE err OUTPUT_QUIET)
  string(FIND "${err}" "--threads: ${bad} is not" at)
  if(NOT rc EQUAL 2 OR at EQUAL -1)
    message(FATAL_ERROR "unexpected answer to --threads ${bad} (${rc}): ${err}")
  endif()
endforeach()

# A 3D scene: the 3D state file and the WebGL replay.
execute_process(COMMAND ${QUACK} run ${SRC}/scenes/cards-3d.json --steps 10 --out ${OUT}/state3.json
                        --html ${OUT}/replay3.html
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "quack run on a 3D scene failed (${rc}):\n${out}\n${err}")
endif()
file(READ ${OUT}/state3.json state)
file(READ ${OUT}/replay3.html replay)
string(FIND "${state}" "{\"dim\": 3," at_dim)
string(FIND "${replay}" "getContext(\"webgl\"" at_gl)
string(FIND "${out}" "cards-3d.json (3D)" at_summary)
if(at_dim EQUAL -1 OR at_gl EQUAL -1 OR at_summary EQUAL -1)
  message(FATAL_ERROR "a 3D run wrote the wrong files or summary:\n${out}\n${state}")
endif()
