# Compiled objects reused across builds, trees and clones: Debian's ccache, when installed, wraps
# every compiler of this tree (host, aarch64 cross, clang). Its cache lives outside the clone
# (ccache's default, ~/.cache/ccache, or CCACHE_DIR), so CI's runs on one machine share it.
# base_dir = the source root and hash_dir off make the objects of two clones (or two build trees of
# one clone) the same cache entries; -g1 line tables then hold relative paths.
option(TLVLINK_CCACHE "Compile through ccache when it is installed (cmake/ccache.cmake)" ON)
if(TLVLINK_CCACHE AND NOT CMAKE_CXX_COMPILER_LAUNCHER)
  find_program(TLVLINK_CCACHE_PROGRAM ccache)
  if(TLVLINK_CCACHE_PROGRAM)
    get_filename_component(_tlvlink_source_root "${CMAKE_CURRENT_LIST_DIR}/.." ABSOLUTE)
    set(_tlvlink_launcher env "CCACHE_BASEDIR=${_tlvlink_source_root}" CCACHE_NOHASHDIR=1
        "${TLVLINK_CCACHE_PROGRAM}")
    set(CMAKE_C_COMPILER_LAUNCHER ${_tlvlink_launcher})
    set(CMAKE_CXX_COMPILER_LAUNCHER ${_tlvlink_launcher})
  endif()
endif()
