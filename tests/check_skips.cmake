# Checks that a missing scene makes CTest report "skipped", never "passed", and never hides a
# failure. With the scenes folder pointed to an empty directory (IGI_SCENES_DIR):
#  1. the hidden cases of tests/skip_test.cpp, run as CTest tests of a scratch CTestTestfile, get
#     the verdicts skipped / failed / skipped;
#  2. every test of the build in BUILD whose name holds "shared scene" is reported skipped.
# cmake -DCTEST=ctest -DBUILD=build-dir -DEMPTY=dir -DSKIP_CASES=exe -DSKIP_REGULAR_EXPRESSION=re -P check_skips.cmake
file(REMOVE_RECURSE ${EMPTY})
file(MAKE_DIRECTORY ${EMPTY}/scenes ${EMPTY}/ctest)

# 1. CTest's verdicts on the three hidden cases.
set(cases "skip: a missing scene skips|Skipped"
          "skip: a failure before a skip stays a failure|Failed"
          "skip: passed checks before a skip|Skipped")
set(testfile "")
set(index 0)
foreach(case ${cases})
  string(REPLACE "|" ";" case "${case}")
  list(GET case 0 name)
  string(APPEND testfile "add_test(case${index} \"${SKIP_CASES}\" \"${name}\")\n"
         "set_tests_properties(case${index} PROPERTIES SKIP_REGULAR_EXPRESSION \"${SKIP_REGULAR_EXPRESSION}\" "
         "ENVIRONMENT \"IGI_SCENES_DIR=${EMPTY}/scenes\" TIMEOUT 30)\n")
  math(EXPR index "${index} + 1")
endforeach()
file(WRITE ${EMPTY}/ctest/CTestTestfile.cmake "${testfile}")
execute_process(COMMAND ${CTEST} --test-dir ${EMPTY}/ctest --output-on-failure
                OUTPUT_VARIABLE output ERROR_VARIABLE errors TIMEOUT 100)
set(problems "")
set(index 0)
foreach(case ${cases})
  string(REPLACE "|" ";" case "${case}")
  list(GET case 0 name)
  list(GET case 1 verdict)
  if(verdict STREQUAL "Skipped")
    set(pattern "case${index} [.]+ *[*]+Skipped")
  else()
    set(pattern "case${index} [.]+ *[*]*Failed")
  endif()
  if(NOT output MATCHES "${pattern}")
    string(APPEND problems "\n  \"${name}\" was not reported ${verdict}")
  endif()
  math(EXPR index "${index} + 1")
endforeach()
if(problems)
  message(FATAL_ERROR "CTest's verdicts on tests/skip_test.cpp are wrong:${problems}\n--- ctest said:\n${output}${errors}")
endif()
message(STATUS "skip cases: skipped, failed, skipped, as they should be")

# 2. The suite's scene tests without their scenes.
execute_process(COMMAND ${CMAKE_COMMAND} -E env IGI_SCENES_DIR=${EMPTY}/scenes
                        ${CTEST} --test-dir ${BUILD} -R "shared scene" --timeout 60
                OUTPUT_VARIABLE output ERROR_VARIABLE errors RESULT_VARIABLE result TIMEOUT 110)
string(REGEX MATCHALL "Test +#[0-9]+: [^\n]*" verdicts "${output}")
list(LENGTH verdicts total)
string(REGEX MATCHALL "Test +#[0-9]+: [^\n]*[*]+Skipped" skipped "${output}")
list(LENGTH skipped skipped_count)
if(total EQUAL 0)
  message(FATAL_ERROR "no test of ${BUILD} names a \"shared scene\": the scene tests are gone or renamed\n${output}${errors}")
endif()
if(NOT skipped_count EQUAL total OR NOT result EQUAL 0)
  message(FATAL_ERROR "without the shared scenes only ${skipped_count} of ${total} scene tests were skipped:\n${output}${errors}")
endif()
message(STATUS "without the shared scenes all ${total} scene tests are reported skipped")
