# Warnings for libwave's own targets only (dependency headers come in as SYSTEM).
function(libwave_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow
    -Wconversion -Wno-sign-conversion -Wnon-virtual-dtor -Wold-style-cast)
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
