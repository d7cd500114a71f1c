# Fails unless every relative link of the user-facing Markdown pages (README.md, docs/*.md,
# bench/README.md) names a file or folder that exists: pages moved between folders, or images
# renamed, otherwise break silently. Anchors (#section) and links out of the repository are not
# checked.
# cmake -DSOURCE=source-dir -P check_doc_links.cmake
file(GLOB pages "${SOURCE}/docs/*.md")
list(APPEND pages "${SOURCE}/README.md" "${SOURCE}/bench/README.md")
set(problems "")
set(count 0)
foreach(page ${pages})
  get_filename_component(folder "${page}" DIRECTORY)
  file(READ "${page}" text)
  # Fenced code may hold text that only looks like a link.
  string(REGEX REPLACE "```[^`]*```" "" text "${text}")
  string(REGEX MATCHALL "\\]\\([^) \t\n]+\\)" links "${text}")
  # CMake lists do not split inside square brackets: the "](" and ")" go before the list is read.
  string(REPLACE "](" "" links "${links}")
  string(REPLACE ")" "" links "${links}")
  foreach(link ${links})
    string(REGEX REPLACE "#.*$" "" target "${link}")
    if(target STREQUAL "" OR target MATCHES "^[a-z]+:")
      continue()  # a link within the page, or to the web
    endif()
    get_filename_component(absolute "${folder}/${target}" ABSOLUTE)
    file(RELATIVE_PATH inside "${SOURCE}" "${absolute}")
    if(inside MATCHES "^\\.\\./")
      continue()  # beside the repository (the project's shared folder), which a clone may lack
    endif()
    math(EXPR count "${count} + 1")
    if(NOT EXISTS "${absolute}")
      file(RELATIVE_PATH shown "${SOURCE}" "${page}")
      string(APPEND problems "\n  ${shown}: ${target}")
    endif()
  endforeach()
endforeach()
if(problems)
  message(FATAL_ERROR "links to files that do not exist:${problems}")
endif()
message(STATUS "${count} links, each to an existing file")
