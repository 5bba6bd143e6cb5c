# Warnings and sanitizers, applied to tlvlink's own targets through tlvlink_warnings.
# Not -Wnull-dereference: g++ 12 reports it from inlined flatbuffers and libstdc++ code after a
# null check was done (false positives that -Werror would turn into build failures).
add_library(tlvlink_warnings INTERFACE)
target_compile_options(tlvlink_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wcast-align -Wunused -Woverloaded-virtual
  -Wdouble-promotion -Wformat=2 -Wimplicit-fallthrough)
if(TLVLINK_WERROR)
  target_compile_options(tlvlink_warnings INTERFACE -Werror)
endif()
# g++ 12 with -fsanitize reports -Wmaybe-uninitialized inside libstdc++ (<regex>'s std::function
# moves): sanitizer instrumentation defeats its flow analysis. Plain builds keep the warning.
if(TLVLINK_SANITIZE AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  target_compile_options(tlvlink_warnings INTERFACE -Wno-maybe-uninitialized)
endif()

# Line tables only: added after CMAKE_<LANG>_FLAGS_RELWITHDEBINFO's -g, so g++'s last -g level
# wins. Measured on 15 of the host tree's heaviest sources, one at a time: 79.6 s against
# 107.2 s with -g (tools/setup/README.md, "Wall time of the whole test command").
if(TLVLINK_DEBUG_LINES)
  add_compile_options($<$<CONFIG:RelWithDebInfo>:-g1>)
endif()

# Unity build: CMAKE_UNITY_BUILD gives every target created after this its UNITY_BUILD property.
# Names in anonymous namespaces must then differ between the files of one target (a clash is a
# compile error, never a silent change; tools/setup/README.md says how to resolve one). A build
# without it compiles every file on its own: the minimal and fuzz trees of the test command do.
if(TLVLINK_UNITY_BUILD)
  set(CMAKE_UNITY_BUILD ON)
  set(CMAKE_UNITY_BUILD_BATCH_SIZE 8)
endif()

if(TLVLINK_SANITIZE)
  add_compile_options(-fsanitize=${TLVLINK_SANITIZE} -fno-omit-frame-pointer -fno-sanitize-recover=all)
  add_link_options(-fsanitize=${TLVLINK_SANITIZE})
endif()

# The on-device code builds without exceptions (errors are values). RTTI stays on: nothing uses
# it, but the tests' doubles derive from runtime interfaces and need their typeinfo.
add_library(tlvlink_target_code INTERFACE)
target_compile_options(tlvlink_target_code INTERFACE -fno-exceptions)

# Fuzz builds instrument all of tlvlink's code for coverage (not only the fuzz target), or the
# fuzzer cannot see into the loader it is fuzzing.
if(TLVLINK_BUILD_FUZZERS)
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
endif()
