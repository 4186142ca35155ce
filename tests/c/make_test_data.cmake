# ctest fixture capi_test_data: a tiny procedural rig, a one-epoch model and a
# performance, made with the facesr CLI into DATA once (about a minute) and
# reused while they are newer than the CLI.
#   cmake -DCLI=path/to/facesr -DDATA=dir -P make_test_data.cmake
cmake_minimum_required(VERSION 3.20)
set(stamp ${DATA}/complete.stamp)
if(EXISTS ${stamp} AND ${stamp} IS_NEWER_THAN ${CLI})
  message(STATUS "capi test data in ${DATA} is up to date")
  return()
endif()
file(REMOVE_RECURSE ${DATA})
file(MAKE_DIRECTORY ${DATA})

function(run)
  string(REPLACE ";" " " shown "${ARGN}")
  message(STATUS "facesr ${shown}")
  execute_process(COMMAND ${CLI} ${ARGN} WORKING_DIRECTORY ${DATA} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "facesr ${shown} failed (${rc})")
  endif()
endfunction()

run(rig build --source procedural --preset coarse -o p.rig)
run(dataset --rig p.rig -o dataset --builtin pain,anger --frames 6 -q)
run(train --rig p.rig --dataset dataset -o p.fsm --epochs 1 --encoder-dims 8,8 --recon-hidden 16 --weight-hidden 8
  --pe-dim 8 -q)
run(perf write --rig p.rig --builtin talk -o talk.json)
file(REMOVE_RECURSE ${DATA}/dataset ${DATA}/p.fsm.ckpt)
file(TOUCH ${stamp})
