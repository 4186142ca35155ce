# ctest csharp_sample / rust_sample: the C# or Rust playback sample (the same
# options and formats) plays the fixture's performance to .bin and .obj, sync
# and pipelined with the same result, samples a hand-written sparse keyframe
# file as the engine does (0.2 s at 30 fps is 7 frames), and fails cleanly on
# bad input: exit non-zero, say why, write nothing.
#   cmake "-DPLAY=mono;FacesrPlay.exe" -DDATA=dir -DOUT=dir -P run_play_sample.cmake
cmake_minimum_required(VERSION 3.20)
file(MAKE_DIRECTORY ${OUT})

function(play perf out)
  file(REMOVE ${out})
  execute_process(
    COMMAND ${PLAY} --rig ${DATA}/p.rig --model ${DATA}/p.fsm --performance ${perf} --out ${out} --inference cpu
      ${ARGN}
    OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr RESULT_VARIABLE rc)
  message(STATUS "${stdout}${stderr}")
  if(NOT rc EQUAL 0 OR NOT EXISTS ${out})
    message(FATAL_ERROR "the sample failed (${rc})")
  endif()
  if(NOT stdout MATCHES "FPS")
    message(FATAL_ERROR "the sample did not print its frame rate")
  endif()
  if(EXISTS ${out}.partial)
    message(FATAL_ERROR "${out}.partial was left behind")
  endif()
endfunction()

# The number of "o frame_NNNN" objects in an OBJ file.
function(obj_frames file var)
  file(STRINGS ${file} objects REGEX "^o frame_[0-9]+$")
  list(LENGTH objects n)
  set(${var} ${n} PARENT_SCOPE)
endfunction()

# Fails with `expected` on stderr, exit code `code` (if given), and no file.
function(play_fails rig perf out expected)
  file(REMOVE ${out})
  execute_process(COMMAND ${PLAY} --rig ${rig} --model ${DATA}/p.fsm --performance ${perf} --out ${out} ${ARGN}
    OUTPUT_QUIET ERROR_VARIABLE stderr RESULT_VARIABLE rc)
  if(rc EQUAL 0 OR EXISTS ${out} OR EXISTS ${out}.partial OR NOT stderr MATCHES "${expected}")
    message(FATAL_ERROR "expected a failure naming '${expected}' and no output file (rc ${rc}): ${stderr}")
  endif()
endfunction()

play(${DATA}/talk.json ${OUT}/talk.bin --frames 6)
play(${DATA}/talk.json ${OUT}/talk_async.bin --frames 6 --async)
file(SIZE ${OUT}/talk.bin bytes)
math(EXPR rest "${bytes} % (6 * 12)")
if(bytes EQUAL 0 OR NOT rest EQUAL 0)
  message(FATAL_ERROR "talk.bin has ${bytes} bytes: not 6 frames of 3-float vertices")
endif()
file(SHA256 ${OUT}/talk.bin sync_hash)
file(SHA256 ${OUT}/talk_async.bin async_hash)
if(NOT sync_hash STREQUAL async_hash)
  message(FATAL_ERROR "pipelined playback wrote other surfaces than synchronous playback")
endif()
play(${DATA}/talk.json ${OUT}/talk.obj --frames 3)
obj_frames(${OUT}/talk.obj n)
if(NOT n EQUAL 3)
  message(FATAL_ERROR "talk.obj has ${n} frame objects, not 3")
endif()

set(sparse ${OUT}/sparse.json)
file(WRITE ${sparse} [=[
{"format": "facesr-performance", "version": 1, "fps": 30, "extra": [1, {"x": null}],
 "keyframes": [{"time": 0, "weights": {"jawOpen": 0}},
               {"time": 0.1, "weights": {"jawOpen": 0.5, "mouthSmile_L": 1e-1}},
               {"time": 0.2, "weights": {}}]}
]=])
play(${sparse} ${OUT}/sparse.obj)
obj_frames(${OUT}/sparse.obj n)
if(NOT n EQUAL 7)
  message(FATAL_ERROR "sparse.obj has ${n} frame objects, not 7")
endif()

play_fails(${DATA}/p.fsm ${DATA}/talk.json ${OUT}/bad.bin "FACESR_ERROR_FILE")
file(WRITE ${sparse}.broken "{\"format\": \"facesr-performance\", \"keyframes\": [")
play_fails(${DATA}/p.rig ${sparse}.broken ${OUT}/bad.bin "not valid JSON")
file(WRITE ${sparse}.unknown
  "{\"format\":\"facesr-performance\",\"version\":1,\"fps\":30,\"keyframes\":[{\"time\":0,\"weights\":{\"jawopen\":1}}]}")
play_fails(${DATA}/p.rig ${sparse}.unknown ${OUT}/bad.bin "no blendshape named 'jawopen'")
file(WRITE ${sparse}.range
  "{\"format\":\"facesr-performance\",\"version\":1,\"fps\":30,\"keyframes\":[{\"time\":0,\"weights\":{\"jawOpen\":1.5}}]}")
play_fails(${DATA}/p.rig ${sparse}.range ${OUT}/bad.bin "weight 'jawOpen' is not a number in \\[0, 1\\]")
play_fails(${DATA}/p.rig ${DATA}/missing.json ${OUT}/bad.bin "cannot read")
play_fails(${DATA}/p.rig ${DATA}/talk.json ${OUT}/bad.gltf "must end in .bin or .obj")
play_fails(${DATA}/p.rig ${DATA}/talk.json ${OUT}/bad.bin "--frames wants a positive number" --frames 0)
play_fails(${DATA}/p.rig ${DATA}/talk.json ${OUT}/bad.bin "unknown option" --fast)
