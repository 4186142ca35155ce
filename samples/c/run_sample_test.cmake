# ctest capi_sample_c_*: plays the fixture's performance through
# facesr_play_c, then validates the glTF it wrote; also checks that a failing
# run exits non-zero and leaves no file behind.
#   cmake -DPLAY=... -DCHECK=... -DDATA=dir -DOUT=x.gltf [-DFLAGS=--async] -P run_sample_test.cmake
cmake_minimum_required(VERSION 3.20)
set(frames 12)
file(REMOVE ${OUT})
execute_process(
  COMMAND ${PLAY} --rig ${DATA}/p.rig --model ${DATA}/p.fsm --performance ${DATA}/talk.json --out ${OUT}
    --frames ${frames} --inference cpu ${FLAGS}
  OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc)
message(STATUS "${out}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "facesr_play_c failed (${rc})")
endif()
if(NOT out MATCHES "FPS")
  message(FATAL_ERROR "facesr_play_c did not print its frame rate")
endif()
execute_process(COMMAND ${CHECK} ${OUT} ${frames} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${OUT} is not a valid animation glTF")
endif()

set(bad ${OUT}.bad.gltf)
file(REMOVE ${bad})
execute_process(
  COMMAND ${PLAY} --rig ${DATA}/p.fsm --model ${DATA}/p.fsm --performance ${DATA}/talk.json --out ${bad}
  OUTPUT_QUIET ERROR_VARIABLE err RESULT_VARIABLE rc)
if(rc EQUAL 0 OR EXISTS ${bad} OR EXISTS ${bad}.partial OR NOT err MATCHES "FACESR_ERROR_FILE")
  message(FATAL_ERROR "a model passed as the rig should fail with FACESR_ERROR_FILE and write nothing (rc ${rc}): ${err}")
endif()
