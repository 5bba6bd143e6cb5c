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
