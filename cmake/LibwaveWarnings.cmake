# Warnings and code generation for libwave's own targets (dependency headers come in as SYSTEM).
function(libwave_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow
    -Wconversion -Wno-sign-conversion -Wnon-virtual-dtor -Wold-style-cast)
  # No errno from libm and no FP traps assumed: lets per-vertex loops with sqrt and
  # selects vectorise (core/vector_clones.h). Our public functions are not interposed
  # (the shared libraries call their own): a per-vertex loop may inline one. None of
  # these changes a computed value.
  target_compile_options(${target} PRIVATE -fno-math-errno -fno-trapping-math -fno-semantic-interposition)
  if(LIBWAVE_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
  if(LIBWAVE_SANITIZE)
    target_compile_options(${target} PRIVATE -fsanitize=address,undefined
      -fno-sanitize-recover=undefined -fno-omit-frame-pointer)
    target_link_options(${target} PRIVATE -fsanitize=address,undefined)
  endif()
  if(LIBWAVE_FUZZ)  # coverage for libFuzzer in every target the fuzzers reach
    target_compile_options(${target} PRIVATE -fsanitize=fuzzer-no-link)
  endif()
endfunction()
