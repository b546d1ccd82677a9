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
endfunction()

# libFuzzer's coverage instrumentation (LIBWAVE_FUZZ) for the given sources only: the
# readers the fuzzers explore (tests/fuzz) and the fuzzers' own files. The rest of the
# library, which the test suite runs from the same tree, is left without it: with it
# everywhere the suite under ASan ran about twice as long (breaking-beach.json's first 12
# frames: 9.3 s, against 4.5–5.4 s with the readers only). Call from the directory that
# adds the sources' target.
function(libwave_fuzz_coverage)
  if(LIBWAVE_FUZZ)
    set_property(SOURCE ${ARGN} APPEND PROPERTY COMPILE_OPTIONS -fsanitize=fuzzer-no-link)
  endif()
endfunction()
