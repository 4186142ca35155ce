# ctest fixture bindings_test_data: a second procedural rig, coarser than the
# capi_test_data one (other LR lattice, other checksum), so the model trained
# for p.rig does not fit it: the bindings' tests expect FACESR_ERROR_MISMATCH.
# Made once (seconds) and kept while newer than the CLI.
#   cmake -DCLI=path/to/facesr -DDATA=dir -P make_other_rig.cmake
cmake_minimum_required(VERSION 3.20)
set(rig ${DATA}/other.rig)
if(EXISTS ${rig} AND ${rig} IS_NEWER_THAN ${CLI})
  message(STATUS "${rig} is up to date")
  return()
endif()
file(MAKE_DIRECTORY ${DATA})
# Built under a temporary name and renamed, so an interrupted run leaves no
# rig that looks complete.
execute_process(
  COMMAND ${CLI} rig build --source procedural --preset coarse --lr-cell 2 --flesh-grid 0.6 --hr-max-volume 1
    -o ${rig}.partial -q
  OUTPUT_QUIET RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  file(REMOVE ${rig}.partial)
  message(FATAL_ERROR "facesr rig build (the mismatching rig) failed (${rc})")
endif()
file(RENAME ${rig}.partial ${rig})
