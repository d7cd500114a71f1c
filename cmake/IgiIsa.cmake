# ISA flags belong on targets, never on the whole build: igi_use_isa(target) applies the choice
# made by the IGI_ISA cache variable (set by the presets) to one test, bench or example target.
set(IGI_ISA "native" CACHE STRING "Instruction set for igi's own programs: native, avx512, avx2, sse4.2 or none")
set_property(CACHE IGI_ISA PROPERTY STRINGS native avx512 avx2 sse4.2 none)

function(igi_use_isa target)
  if(IGI_ISA STREQUAL "native")
    target_compile_options(${target} PRIVATE -march=native)
  elseif(IGI_ISA STREQUAL "avx512")
    target_compile_options(${target} PRIVATE -march=skylake-avx512 -mprefer-vector-width=512)
  elseif(IGI_ISA STREQUAL "avx2")
    target_compile_options(${target} PRIVATE -march=haswell)
  elseif(IGI_ISA STREQUAL "sse4.2")
    target_compile_options(${target} PRIVATE -msse4.2)
  elseif(NOT IGI_ISA STREQUAL "none")
    message(FATAL_ERROR "IGI_ISA must be native, avx512, avx2, sse4.2 or none, not '${IGI_ISA}'")
  endif()
endfunction()

# Warnings for igi's own targets: -Wall -Wextra, as its users compile. -Wno-psabi: GCC notes
# that passing 32- and 64-byte vectors changed ABI in GCC 4.6, which concerns no one now.
# IGI_WARNINGS_AS_ERRORS (on in the native preset, which CI builds) makes any new warning fail
# the build: the native build prints none (GCC 12's false reports inside libstdc++'s simd are
# ignored for those headers' lines only, see igi/simd/lanes.hpp). It is off by default so that a
# newer or older compiler's new diagnostics do not stop someone building igi's programs. The
# tests in tests/warnings check the headers at other instruction sets the way a user compiles them.
option(IGI_WARNINGS_AS_ERRORS "Compile igi's own targets with -Werror" OFF)
function(igi_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wno-psabi "$<$<BOOL:${IGI_WARNINGS_AS_ERRORS}>:-Werror>")
endfunction()
