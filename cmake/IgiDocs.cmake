# The API reference: `cmake --build --preset native --target docs` runs Doxygen (Debian's doxygen)
# over include/igi/ into build/<preset>/docs/html, with docs/api_mainpage.md, the layers of the
# design, as its main page. The build fails on any Doxygen warning, above all on a public name
# without a `///` line (docs/Doxyfile.in says which names count as public), so the reference stays
# complete; tests/CMakeLists.txt runs the target as a test wherever Doxygen is installed.
find_package(Doxygen QUIET)
set(IGI_DOCS_OUTPUT_DIR "${PROJECT_BINARY_DIR}/docs")
if(DOXYGEN_FOUND)
  configure_file("${PROJECT_SOURCE_DIR}/docs/Doxyfile.in" "${IGI_DOCS_OUTPUT_DIR}/Doxyfile" @ONLY)
  add_custom_target(docs
    COMMAND Doxygen::doxygen "${IGI_DOCS_OUTPUT_DIR}/Doxyfile"
    COMMAND ${CMAKE_COMMAND} -E echo "igi: API reference in ${IGI_DOCS_OUTPUT_DIR}/html/index.html"
    WORKING_DIRECTORY "${PROJECT_SOURCE_DIR}"
    COMMENT "Doxygen: the API reference of include/igi (fails on an undocumented public name)"
    VERBATIM)
else()
  # The target still exists, so asking for it says what is missing instead of "unknown target".
  add_custom_target(docs
    COMMAND ${CMAKE_COMMAND} -E echo "igi: doxygen not found; install it (bash scripts/deps.sh, or apt-get install doxygen) and configure again"
    COMMAND ${CMAKE_COMMAND} -E false
    VERBATIM)
endif()
