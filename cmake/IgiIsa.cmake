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

# Warnings for igi's own targets. Designated initializers that leave members at their defaults
# (igi::Material{.name = ..., .metallic = ...}) are C++20's way to name a few fields; GCC 12's
# -Wmissing-field-initializers flags every member of class type they omit (hundreds of lines).
function(igi_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wno-psabi -Wno-missing-field-initializers)
endfunction()
