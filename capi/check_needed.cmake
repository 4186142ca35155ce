# ctest capi_needed_libraries: libfacesr.so depends on runtime libraries
# only. A game ships it with the OpenCL ICD loader and the C/C++ and OpenMP
# runtimes; a NEEDED entry for anything else (TetGen, GMP, Embree, CGAL,
# LibTorch...) means offline code leaked into engine/'s facesr_runtime.
#   cmake -DLIB=libfacesr.so -DOBJDUMP=objdump -P check_needed.cmake
cmake_minimum_required(VERSION 3.20)
foreach(var LIB OBJDUMP)
  if(NOT ${var})
    message(FATAL_ERROR "check_needed.cmake: -D${var}=... is required")
  endif()
endforeach()
execute_process(COMMAND ${OBJDUMP} -p ${LIB} OUTPUT_VARIABLE out RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${OBJDUMP} -p ${LIB} failed (${rc})")
endif()
# The sanitizer runtimes appear in scripts/sanitize.sh's builds only.
set(allowed "^(libOpenCL|libgomp|libstdc\\+\\+|libm|libgcc_s|libc|libpthread|libdl|librt|ld-linux-x86-64|ld-linux-aarch64|libasan|libubsan|libtsan)\\.so")
string(REGEX MATCHALL "NEEDED +[^\n]+" entries "${out}")
set(needed "")
set(offending "")
foreach(entry IN LISTS entries)
  string(REGEX REPLACE "NEEDED +" "" name "${entry}")
  string(STRIP "${name}" name)
  list(APPEND needed "${name}")
  if(NOT name MATCHES "${allowed}")
    list(APPEND offending "${name}")
  endif()
endforeach()
if(NOT needed)
  message(FATAL_ERROR "${LIB}: no NEEDED entries found in `${OBJDUMP} -p` (not an ELF shared library?)")
endif()
if(offending)
  string(REPLACE ";" ", " offending "${offending}")
  message(FATAL_ERROR "${LIB} needs libraries a game should not ship: ${offending}. "
    "Something in engine/'s facesr_runtime calls offline code; move it out of the runtime.")
endif()
string(REPLACE ";" ", " needed "${needed}")
message(STATUS "${LIB} needs only: ${needed}")
