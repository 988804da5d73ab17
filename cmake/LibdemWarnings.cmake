# Warning and optimisation flags shared by every target of the project (not exported).
add_library(libdem_flags INTERFACE)
target_compile_options(libdem_flags INTERFACE -Wall -Wextra -Wpedantic -Wshadow)
# GCC 12 reports false -Wrestrict positives inside libstdc++ string concatenation at -O2/-O3
# (GCC bug 105329); it is not about our code.
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  target_compile_options(libdem_flags INTERFACE -Wno-restrict)
endif()
# The library never reads errno or floating-point exception flags. Without -fno-math-errno GCC
# guards every sqrt with a compare, a branch and a libm call for negative arguments; without
# -fno-trapping-math it will not compute a select's both sides (a square root or a quotient "could
# trap"), which keeps the contact loop out of SIMD lanes (contact/lanes.hpp). Neither changes a
# result: no -ffast-math reassociation, no FMA contraction beyond the default.
target_compile_options(libdem_flags INTERFACE -fno-math-errno -fno-trapping-math)
if(LIBDEM_WERROR)
  target_compile_options(libdem_flags INTERFACE -Werror)
endif()
if(LIBDEM_NATIVE)
  target_compile_options(libdem_flags INTERFACE -march=native)
endif()
if(LIBDEM_SANITIZE)
  target_compile_options(libdem_flags INTERFACE -fsanitize=address,undefined -fno-omit-frame-pointer
                                                -fno-sanitize-recover=undefined)
  target_link_options(libdem_flags INTERFACE -fsanitize=address,undefined)
  # GCC 12 with -fsanitize and optimisation reports false -Wmaybe-uninitialized inside <regex>
  # (std::function in Catch2's main); it is not about our code. Only the Catch2 test executable
  # is exempted, so the library still builds with this warning as an error.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    target_compile_options(libdem_flags INTERFACE
                           $<$<STREQUAL:$<TARGET_PROPERTY:NAME>,dem_tests>:-Wno-maybe-uninitialized>)
  endif()
endif()
