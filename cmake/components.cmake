# tlvlink_component(NAME [PUBLIC_DEPS ...] [PRIVATE_DEPS ...]) declares one runtime component:
# a static library tlvlink_<NAME> whose public headers are <dir>/include (included as
# "tlvlink/..."), whose private headers live in <dir>/src and are guarded by
# TLVLINK_<NAME>_PRIVATE (defined only while compiling the component itself, so another
# component that includes them fails to compile), built as on-device code (no exceptions).
function(tlvlink_component name)
  cmake_parse_arguments(arg "" "" "PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  set(target tlvlink_${name})
  add_library(${target} STATIC)
  string(TOUPPER ${name} upper)
  target_include_directories(${target}
    PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include
    PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src)
  target_compile_definitions(${target} PRIVATE TLVLINK_${upper}_PRIVATE=1)
  target_link_libraries(${target} PUBLIC ${arg_PUBLIC_DEPS}
                                  PRIVATE ${arg_PRIVATE_DEPS} tlvlink_warnings tlvlink_target_code)
endfunction()
