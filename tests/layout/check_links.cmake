# The floors depend downward only, checked on the targets themselves when CMake configures
# (included by tests/layout/CMakeLists.txt, run once every target of the tree exists):
#   - a target of runtime/, firmware/ or quantize/ links no target of tools/ (nor tests/);
#   - a product target (anything outside tests/) links no target of tests/, compiles no source
#     from tests/ and takes no include directory from it.
# A target's floor is the top-level folder of its SOURCE_DIR. Both LINK_LIBRARIES (what it links)
# and INTERFACE_LINK_LIBRARIES (what it passes on) count, so a PRIVATE link is caught too.
# Violations stop the configuration (SEND_ERROR: nothing is generated) and are written to
# <build>/tests/layout/link_violations.txt, which the ctest layout.links reads.

# Every build-system target under `dir`, recursively.
function(_tlvlink_targets_under dir out)
  get_property(targets DIRECTORY ${dir} PROPERTY BUILDSYSTEM_TARGETS)
  get_property(subdirs DIRECTORY ${dir} PROPERTY SUBDIRECTORIES)
  foreach(sub IN LISTS subdirs)
    _tlvlink_targets_under(${sub} more)
    list(APPEND targets ${more})
  endforeach()
  set(${out} ${targets} PARENT_SCOPE)
endfunction()

# The floor of a path inside the repository: runtime, firmware, quantize, tools, tests, or "".
function(_tlvlink_floor_of path out)
  file(RELATIVE_PATH rel ${PROJECT_SOURCE_DIR} ${path})
  string(REGEX MATCH "^[^/]+" top "${rel}")
  if(NOT top MATCHES "^(runtime|firmware|quantize|tools|tests)$")
    set(top "")
  endif()
  set(${out} "${top}" PARENT_SCOPE)
endfunction()

function(tlvlink_check_links)
  _tlvlink_targets_under(${PROJECT_SOURCE_DIR} targets)
  set(violations "")
  foreach(t IN LISTS targets)
    get_target_property(dir ${t} SOURCE_DIR)
    _tlvlink_floor_of(${dir} floor)
    if(floor STREQUAL "tests" OR floor STREQUAL "")
      continue()
    endif()
    # Links, direct and passed on. Entries can be generator expressions ($<LINK_ONLY:x>) and
    # directory markers (::@(...)) that CMake adds for links made from another directory.
    get_target_property(links ${t} LINK_LIBRARIES)
    get_target_property(ilinks ${t} INTERFACE_LINK_LIBRARIES)
    set(items "")
    foreach(item IN LISTS links ilinks)
      if(item MATCHES "^::@" OR item MATCHES "-NOTFOUND$")
        continue()
      endif()
      string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" item "${item}")
      if(TARGET ${item})
        list(APPEND items ${item})
      endif()
    endforeach()
    list(REMOVE_DUPLICATES items)
    foreach(dep IN LISTS items)
      get_target_property(imported ${dep} IMPORTED)
      if(imported)
        continue()
      endif()
      get_target_property(dep_dir ${dep} SOURCE_DIR)
      _tlvlink_floor_of(${dep_dir} dep_floor)
      if(dep_floor STREQUAL "tests")
        list(APPEND violations "${floor}/ target ${t} links ${dep} (tests/ code)")
      elseif(dep_floor STREQUAL "tools" AND floor MATCHES "^(runtime|firmware|quantize)$")
        list(APPEND violations "${floor}/ target ${t} links ${dep} (a tools/ target)")
      endif()
    endforeach()
    # Sources and include directories taken from tests/ (relative sources are the target's own).
    get_target_property(sources ${t} SOURCES)
    get_target_property(includes ${t} INCLUDE_DIRECTORIES)
    foreach(path IN LISTS sources includes)
      if(IS_ABSOLUTE "${path}" AND path MATCHES "^${PROJECT_SOURCE_DIR}/tests(/|$)")
        list(APPEND violations "${floor}/ target ${t} uses ${path} (tests/ code)")
      endif()
    endforeach()
  endforeach()
  list(LENGTH targets n_targets)
  list(LENGTH violations n_violations)
  string(REPLACE ";" "\n" text "${violations}")
  file(WRITE ${PROJECT_BINARY_DIR}/tests/layout/link_violations.txt "${text}")
  if(n_violations GREATER 0)
    message(SEND_ERROR "tlvlink: ${n_violations} link(s) against the floors' order "
                       "(tests/layout/check_links.cmake):\n${text}")
  else()
    message(STATUS "tlvlink: floors depend downward only (${n_targets} targets checked)")
  endif()
endfunction()
