# ctest bindings_consistency[_selftest]: collects the three layouts (the C
# compiler's, C#'s, Rust's) and runs binding_check on them.
# With -DSELFTEST=ON it instead feeds binding_check doctored inputs, one
# defect each, and requires every one to fail naming the defect, so that a
# check that silently passes everything cannot go unnoticed.
#   cmake -DCHECK=binding_check -DHEADER=facesr.h -DC_LAYOUT=exe -DC_LAYOUT_DOCTORED=exe
#         -DHEADER_DOCTORED=doctored/facesr.h -DMONO=mono
#         -DCS_LAYOUT=CsharpLayout.exe -DFACESR_DLL=Facesr.dll -DRUST_LAYOUT=print_layout
#         -DRUST_SYS=facesr-sys/src/lib.rs -DOUT=dir [-DSELFTEST=ON] -P run_check.cmake
cmake_minimum_required(VERSION 3.20)
file(MAKE_DIRECTORY ${OUT})

# Runs a layout printer into OUT/<name>.txt.
function(collect name)
  execute_process(COMMAND ${ARGN} OUTPUT_FILE ${OUT}/${name}.txt ERROR_VARIABLE err RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${ARGN} failed (${rc}): ${err}")
  endif()
endfunction()

collect(c ${C_LAYOUT})
collect(csharp ${MONO} ${CS_LAYOUT} ${FACESR_DLL})
collect(rust ${RUST_LAYOUT})

# binding_check on the given files (defaults: the real ones).
function(run_check result_var output_var)
  cmake_parse_arguments(A "" "HEADER;C;CSHARP;RUST;RUST_SYS" "" ${ARGN})
  foreach(k HEADER C CSHARP RUST RUST_SYS)
    if(NOT A_${k})
      set(A_${k} ${DEFAULT_${k}})
    endif()
  endforeach()
  execute_process(COMMAND ${CHECK} check --header ${A_HEADER} --c ${A_C} --csharp ${A_CSHARP} --rust ${A_RUST}
    --rust-sys ${A_RUST_SYS} OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc)
  set(${result_var} ${rc} PARENT_SCOPE)
  set(${output_var} "${out}${err}" PARENT_SCOPE)
endfunction()
set(DEFAULT_HEADER ${HEADER})
set(DEFAULT_C ${OUT}/c.txt)
set(DEFAULT_CSHARP ${OUT}/csharp.txt)
set(DEFAULT_RUST ${OUT}/rust.txt)
set(DEFAULT_RUST_SYS ${RUST_SYS})

if(NOT SELFTEST)
  run_check(rc output)
  message(STATUS "${output}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "facesr.h and its bindings disagree (see above)")
  endif()
  return()
endif()

# ------------------------------------------------------------- self-test

# The check passes on the real inputs (else the failures below prove nothing).
run_check(rc output)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the real inputs already fail:\n${output}")
endif()

set(failures 0)
# One doctored case: binding_check must exit 1 and print every `expect`
# (CMake regexes, ';'-separated).
function(expect_failure case expect)
  run_check(rc output ${ARGN})
  set(ok TRUE)
  if(NOT rc EQUAL 1)
    set(ok FALSE)
  endif()
  foreach(e IN LISTS expect)
    if(NOT output MATCHES "${e}")
      set(ok FALSE)
    endif()
  endforeach()
  if(ok)
    message(STATUS "self-test '${case}': failed as it should")
  else()
    message(STATUS "self-test '${case}': expected exit 1 and '${expect}', got ${rc}:\n${output}")
    math(EXPR n "${failures} + 1")
    set(failures ${n} PARENT_SCOPE)
  endif()
endfunction()

# Writes OUT/<name> as `file` with `from` replaced by `to`; fails if absent.
function(doctor name file from to)
  file(READ ${file} text)
  string(REPLACE "${from}" "${to}" doctored "${text}")
  if(doctored STREQUAL text)
    message(FATAL_ERROR "self-test: '${from}' is not in ${file}; update run_check.cmake")
  endif()
  file(WRITE ${OUT}/${name} "${doctored}")
endfunction()

# A C# field at another offset (e.g. a field reordered in the C# struct).
doctor(cs_offset.txt ${OUT}/csharp.txt "field facesr_rig_info checksum offset 24" "field facesr_rig_info checksum offset 28")
expect_failure("C# offset" "C#: facesr_rig_info.checksum is at offset 28" CSHARP ${OUT}/cs_offset.txt)

# A C# field of another size (int where the header has int64_t).
doctor(cs_size.txt ${OUT}/csharp.txt "field facesr_frame_stats frame offset 8 size 8"
  "field facesr_frame_stats frame offset 8 size 4")
expect_failure("C# field size" "C#: facesr_frame_stats.frame .*size 4" CSHARP ${OUT}/cs_size.txt)

# A C# DllImport with the wrong calling convention.
doctor(cs_conv.txt ${OUT}/csharp.txt "function facesr_step ptr i32 Cdecl facesr" "function facesr_step ptr i32 StdCall facesr")
expect_failure("C# calling convention" "facesr_step uses CallingConvention.StdCall" CSHARP ${OUT}/cs_conv.txt)

# A C# struct and a C# DllImport missing altogether.
file(READ ${OUT}/csharp.txt text)
string(REGEX REPLACE "[^\n]*facesr_model_info[^\n]*\n" "" no_struct "${text}")
file(WRITE ${OUT}/cs_no_struct.txt "${no_struct}")
expect_failure("C# missing struct" "C#: no binding of struct facesr_model_info" CSHARP ${OUT}/cs_no_struct.txt)
string(REGEX REPLACE "function facesr_wait [^\n]*\n" "" no_wait "${text}")
file(WRITE ${OUT}/cs_no_wait.txt "${no_wait}")
expect_failure("C# missing function" "C#: no binding of facesr_wait" CSHARP ${OUT}/cs_no_wait.txt)

# A Rust struct missing a field, and one of another size.
doctor(rust_field.txt ${OUT}/rust.txt "field facesr_sphere_def radius offset 16 size 4\n" "")
expect_failure("Rust missing field" "Rust: facesr_sphere_def.radius has no binding" RUST ${OUT}/rust_field.txt)
doctor(rust_size.txt ${OUT}/rust.txt "struct facesr_spring_def size 24" "struct facesr_spring_def size 28")
expect_failure("Rust struct size" "Rust: sizeof facesr_spring_def is 28" RUST ${OUT}/rust_size.txt)

# A function facesr-sys does not declare.
doctor(lib_no_step.rs ${RUST_SYS} "pub fn facesr_step(context: *mut facesr_context) -> facesr_status;" "")
expect_failure("Rust missing function" "Rust: no binding of facesr_step" RUST_SYS ${OUT}/lib_no_step.rs)

# A header function with no binding anywhere, a parameter whose type changed,
# and a new constant.
doctor(header_fn.h ${HEADER} "#ifdef __cplusplus\n}"
  "FACESR_API facesr_status facesr_doctored_function(facesr_context* context, int32_t n);\n#ifdef __cplusplus\n}")
expect_failure("header function without bindings"
  "C#: no binding of facesr_doctored_function;Rust: no binding of facesr_doctored_function" HEADER ${OUT}/header_fn.h)
doctor(header_param.h ${HEADER} "facesr_get_normals(const facesr_context* context, float* xyz, int64_t count)"
  "facesr_get_normals(const facesr_context* context, float* xyz, int32_t count)")
expect_failure("header parameter type"
  "C#: facesr_get_normals is declared \\(ptr,ptr,i64 i32\\); facesr.h has \\(ptr,ptr,i32 i32\\);Rust: facesr_get_normals"
  HEADER ${OUT}/header_param.h)
doctor(header_const.h ${HEADER} "#define FACESR_ERROR_INTERNAL 10"
  "#define FACESR_ERROR_INTERNAL 10\n#define FACESR_ERROR_DOCTORED 11")
expect_failure("header constant" "C#: no constant FACESR_ERROR_DOCTORED;Rust: no constant FACESR_ERROR_DOCTORED"
  HEADER ${OUT}/header_const.h)

# A struct field added to the header, compiled (facesr_layout_c_doctored).
collect(c_doctored ${C_LAYOUT_DOCTORED})
expect_failure("header struct field"
  "C#: facesr_frame_stats.doctored_field has no binding;Rust: facesr_frame_stats.doctored_field has no binding;sizeof facesr_frame_stats"
  HEADER ${HEADER_DOCTORED} C ${OUT}/c_doctored.txt)

if(failures GREATER 0)
  message(FATAL_ERROR "${failures} doctored input(s) did not fail the check as they should")
endif()
message(STATUS "binding_check fails on each of the doctored inputs")
