# Precompiles <torch/torch.h> for the sources of a target that include it
# (directly or through engine/train or the tests' sr_fixtures.h). Parsing that
# header took about 25 s per source on 2 cores, most of the build; every
# other source of the target skips the precompiled header, so it pays
# nothing for it. A source whose includes change between configures still
# builds either way, only more slowly.
function(facesr_torch_pch TARGET)
  get_target_property(sources ${TARGET} SOURCES)
  set(users 0)
  foreach(src ${sources})
    file(STRINGS ${src} torch_includes REGEX "#include [<\"](torch/|train/|sr_fixtures\\.h)")
    if(torch_includes)
      math(EXPR users "${users} + 1")
    else()
      set_source_files_properties(${src} TARGET_DIRECTORY ${TARGET} PROPERTIES SKIP_PRECOMPILE_HEADERS ON)
    endif()
  endforeach()
  if(users GREATER 1)
    target_precompile_headers(${TARGET} PRIVATE <torch/torch.h>)
  endif()
endfunction()
