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
    # The sloppiness lets ccache cache what compiles against a precompiled header (the tests'
    # gtest, the CLI's CLI11: ~100 of ~200 objects of the host tree): without it every one of
    # them is "could_not_use_precompiled_header" and recompiles in every run (ccache manual,
    # "Precompiled headers"). Nothing here expands __DATE__/__TIME__.
    set(_tlvlink_launcher env "CCACHE_BASEDIR=${_tlvlink_source_root}" CCACHE_NOHASHDIR=1
        "CCACHE_SLOPPINESS=pch_defines,time_macros,include_file_mtime,include_file_ctime"
        "${TLVLINK_CCACHE_PROGRAM}")
    set(CMAKE_C_COMPILER_LAUNCHER ${_tlvlink_launcher})
    set(CMAKE_CXX_COMPILER_LAUNCHER ${_tlvlink_launcher})
    # GCC names the .gch it used only in preprocessed output with -fpch-preprocess (ccache's
    # preprocessor mode, the fallback of its direct mode, needs it to hash the header).
    if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
      add_compile_options($<$<COMPILE_LANGUAGE:CXX>:-fpch-preprocess>)
    endif()
  endif()
endif()
