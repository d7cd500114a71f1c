# Script mode (cmake -P): runs one example program and checks what it wrote. Lists are passed
# with '|' between items (ctest would split ';').
#   WORK            folder emptied first; the program writes its images there
#   REQUIRE         programs that must be on PATH, else the test is skipped (prints SKIPPED)
#   SCENE           a scene file that must exist, else the test is skipped (../shared/scenes missing)
#   PACKAGE_BINARY  if set: install igi from this build into WORK/prefix, then configure and build
#                   PACKAGE_SOURCE against it with find_package(igi) (generator GENERATOR)
#   COMMAND         the program and its arguments
#   EXPECT          regular expressions its standard output must match
#   CHECKER         igi-image-check, run on each of IMAGES with CHECK_ARGS
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "failed (${code}): ${ARGN}\n${out}\n${err}")
  endif()
  message(STATUS "${ARGN}\n${out}${err}")
  set(run_output "${out}" PARENT_SCOPE)
endfunction()

foreach(list COMMAND EXPECT IMAGES CHECK_ARGS REQUIRE)
  string(REPLACE "|" ";" ${list} "${${list}}")
endforeach()
foreach(program ${REQUIRE})
  find_program(_found_${program} ${program})
  if(NOT _found_${program})
    message("SKIPPED: ${program} is not installed")
    return()
  endif()
endforeach()

if(SCENE AND NOT EXISTS "${SCENE}")
  message("SKIPPED: ${SCENE} is missing (../shared/scenes not present)")
  return()
endif()

file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
if(PACKAGE_BINARY)
  run(${CMAKE_COMMAND} --install ${PACKAGE_BINARY} --prefix ${WORK}/prefix)
  run(${CMAKE_COMMAND} -S ${PACKAGE_SOURCE} -B ${WORK}/build -G ${GENERATOR} -DCMAKE_BUILD_TYPE=Release
      -DCMAKE_PREFIX_PATH=${WORK}/prefix)
  run(${CMAKE_COMMAND} --build ${WORK}/build)
endif()
run(${COMMAND})
foreach(regex ${EXPECT})
  if(NOT run_output MATCHES "${regex}")
    message(FATAL_ERROR "the output does not match '${regex}':\n${run_output}")
  endif()
endforeach()
foreach(image ${IMAGES})
  if(NOT EXISTS ${image})
    message(FATAL_ERROR "${image} was not written")
  endif()
  run(${CHECKER} ${image} ${CHECK_ARGS})
endforeach()
