# Compiler flags shared by every Fulcrum target.
function(fulcrum_set_warnings target)
  if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
    target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion)
    # Determinism: never let the compiler fuse a*b+c into an FMA behind our back
    # (GCC does by default when FMA is enabled, e.g. -march=native), so scalar and
    # SIMD paths, and builds with different flags, round identically.
    target_compile_options(${target} PRIVATE -ffp-contract=off)
    if(FULCRUM_WARNINGS_AS_ERRORS)
      target_compile_options(${target} PRIVATE -Werror)
    endif()
  endif()
endfunction()

if(FULCRUM_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
endif()
