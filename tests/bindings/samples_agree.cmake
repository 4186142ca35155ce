# ctest samples_agree: the C, C# and Rust samples play the same performance
# on the same rig and model (fixture capi_test_data) and write the same
# surfaces, within TOL cm (CPU inference, so nothing depends on a device).
# C and C# step synchronously, Rust pipelined (step_async + wait), which the
# header promises gives the same surfaces.
#   cmake -DPLAY_C=facesr_play_c -DMONO=mono -DPLAY_CS=FacesrPlay.exe -DPLAY_RS=facesr_play_rs
#         -DCOMPARE=compare_frames -DDATA=dir -DOUT=dir -DFRAMES=12 -DTOL=1e-5 -P samples_agree.cmake
cmake_minimum_required(VERSION 3.20)
file(MAKE_DIRECTORY ${OUT})
set(common --rig ${DATA}/p.rig --model ${DATA}/p.fsm --performance ${DATA}/talk.json --frames ${FRAMES}
  --inference cpu)

function(play name)
  file(REMOVE ${OUT}/${name}.bin)
  execute_process(COMMAND ${ARGN} OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr RESULT_VARIABLE rc)
  message(STATUS "${name}: ${stdout}${stderr}")
  if(NOT rc EQUAL 0 OR NOT EXISTS ${OUT}/${name}.bin)
    message(FATAL_ERROR "the ${name} sample failed (${rc})")
  endif()
  set(last_stdout "${stdout}" PARENT_SCOPE)
endfunction()

play(c ${PLAY_C} ${common} --out ${OUT}/c.gltf --dump-positions ${OUT}/c.bin)
if(NOT last_stdout MATCHES "([0-9]+) surface vertices")
  message(FATAL_ERROR "facesr_play_c did not print the vertex count")
endif()
math(EXPR floats_per_frame "3 * ${CMAKE_MATCH_1}")
play(csharp ${MONO} ${PLAY_CS} ${common} --out ${OUT}/csharp.bin)
play(rust ${PLAY_RS} ${common} --out ${OUT}/rust.bin --async)

# The comparison must be able to fail: its own self-test first.
execute_process(COMMAND ${COMPARE} --self-test OUTPUT_QUIET ERROR_QUIET RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "compare_frames --self-test failed: the comparison cannot be trusted")
endif()
execute_process(COMMAND ${COMPARE} ${TOL} ${floats_per_frame} ${OUT}/c.bin ${OUT}/csharp.bin ${OUT}/rust.bin
  RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the samples disagree (see above)")
endif()
file(SIZE ${OUT}/c.bin bytes)
math(EXPR frames "${bytes} / (4 * ${floats_per_frame})")
if(NOT frames EQUAL FRAMES)
  message(FATAL_ERROR "expected ${FRAMES} frames, the files hold ${frames}")
endif()
