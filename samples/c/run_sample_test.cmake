# ctest capi_sample_c_*: plays the fixture's performance through
# facesr_play_c and validates the glTF it wrote; plays a hand-written sparse
# keyframe file (sampling as the engine does: 0.2 s at 30 fps is 7 frames);
# and checks that failing runs exit non-zero, say why, and write nothing.
#   cmake -DPLAY=... -DCHECK=... -DDATA=dir -DOUT=x.gltf [-DFLAGS=--async] -P run_sample_test.cmake
cmake_minimum_required(VERSION 3.20)

function(play perf out)
  file(REMOVE ${out})
  execute_process(
    COMMAND ${PLAY} --rig ${DATA}/p.rig --model ${DATA}/p.fsm --performance ${perf} --out ${out} --inference cpu
      ${FLAGS} ${ARGN}
    OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr RESULT_VARIABLE rc)
  message(STATUS "${stdout}${stderr}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "facesr_play_c failed (${rc})")
  endif()
  if(NOT stdout MATCHES "FPS")
    message(FATAL_ERROR "facesr_play_c did not print its frame rate")
  endif()
endfunction()

function(check out targets)
  execute_process(COMMAND ${CHECK} ${out} ${targets} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${out} is not a valid animation glTF with ${targets} frames")
  endif()
endfunction()

# Fails with `expected` in its message and leaves no file.
function(play_fails rig perf expected)
  set(bad ${OUT}.bad.gltf)
  file(REMOVE ${bad})
  execute_process(COMMAND ${PLAY} --rig ${rig} --model ${DATA}/p.fsm --performance ${perf} --out ${bad}
    OUTPUT_QUIET ERROR_VARIABLE stderr RESULT_VARIABLE rc)
  if(rc EQUAL 0 OR EXISTS ${bad} OR EXISTS ${bad}.partial OR NOT stderr MATCHES "${expected}")
    message(FATAL_ERROR "expected a failure naming '${expected}' and no output file (rc ${rc}): ${stderr}")
  endif()
endfunction()

play(${DATA}/talk.json ${OUT} --frames 12)
check(${OUT} 12)

get_filename_component(dir ${OUT} DIRECTORY)
set(sparse ${dir}/sparse_${FLAGS}.json)
file(WRITE ${sparse} [=[
{"format": "facesr-performance", "version": 1, "fps": 30, "extra": [1, {"x": null}],
 "keyframes": [{"time": 0, "weights": {"jawOpen": 0}},
               {"time": 0.1, "weights": {"jawOpen": 0.5, "mouthSmile_L": 1e-1}},
               {"time": 0.2, "weights": {}}]}
]=])
play(${sparse} ${OUT}.sparse.gltf)
check(${OUT}.sparse.gltf 7)

play_fails(${DATA}/p.fsm ${DATA}/talk.json "FACESR_ERROR_FILE")
file(WRITE ${sparse}.broken "{\"format\": \"facesr-performance\", \"keyframes\": [")
play_fails(${DATA}/p.rig ${sparse}.broken "not valid JSON")
file(WRITE ${sparse}.unknown
  "{\"format\":\"facesr-performance\",\"version\":1,\"fps\":30,\"keyframes\":[{\"time\":0,\"weights\":{\"jawopen\":1}}]}")
play_fails(${DATA}/p.rig ${sparse}.unknown "no blendshape named 'jawopen'")
