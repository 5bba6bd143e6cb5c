# ctest layout.links: the result of check_links.cmake for this tree (empty file = no violation).
#   cmake -DVIOLATIONS=<build>/tests/layout/link_violations.txt -P read_link_violations.cmake
if(NOT EXISTS "${VIOLATIONS}")
  message(FATAL_ERROR "${VIOLATIONS} is missing: check_links.cmake did not run at configure time")
endif()
file(READ "${VIOLATIONS}" text)
if(NOT text STREQUAL "")
  message(FATAL_ERROR "links against the floors' order:\n${text}")
endif()
message(STATUS "floors depend downward only")
