# A copy of facesr.h with one field more at the end of facesr_frame_stats
# (64-bit, so that the struct grows whatever padding its end has),
# as a careless header change would add it: the consistency check's
# self-test compiles a layout program from it and expects the check to fail.
#   cmake -DIN=facesr.h -DOUT=doctored/facesr.h -P doctor_header.cmake
cmake_minimum_required(VERSION 3.20)
file(READ ${IN} text)
string(REPLACE "} facesr_frame_stats;" "  int64_t doctored_field;\n} facesr_frame_stats;" doctored "${text}")
if(doctored STREQUAL text)
  message(FATAL_ERROR "${IN} has no '} facesr_frame_stats;' to doctor: update doctor_header.cmake")
endif()
get_filename_component(dir ${OUT} DIRECTORY)
file(MAKE_DIRECTORY ${dir})
file(WRITE ${OUT}.tmp "${doctored}")
file(RENAME ${OUT}.tmp ${OUT})
