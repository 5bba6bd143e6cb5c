# Warnings and sanitizers, applied to tlvlink's own targets through tlvlink_warnings.
add_library(tlvlink_warnings INTERFACE)
target_compile_options(tlvlink_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wcast-align -Wunused -Woverloaded-virtual
  -Wnull-dereference -Wdouble-promotion -Wformat=2 -Wimplicit-fallthrough)
if(TLVLINK_WERROR)
  target_compile_options(tlvlink_warnings INTERFACE -Werror)
endif()

if(TLVLINK_SANITIZE)
  add_compile_options(-fsanitize=${TLVLINK_SANITIZE} -fno-omit-frame-pointer -fno-sanitize-recover=all)
  add_link_options(-fsanitize=${TLVLINK_SANITIZE})
endif()

# The on-device code builds without exceptions or RTTI (errors are values).
add_library(tlvlink_target_code INTERFACE)
target_compile_options(tlvlink_target_code INTERFACE -fno-exceptions)
