# cmake -DMAP=<linker map> -DEXE=<program> -DALLOWED=<lib;names> -P check_link.cmake
# Fails when the program linked, or loads at run time, a library that is neither in ALLOWED nor
# part of the C/C++ toolchain. Two views, because each misses something the other sees: the
# linker map lists every input, static archives included (ldd never sees those); ldd lists the
# shared libraries the allowed ones pull in transitively.
set(toolchain "c|m|mvec|dl|rt|pthread|gcc|gcc_s|gcc_eh|stdc\\+\\+|c_nonshared")
list(JOIN ALLOWED "|" allowed)
set(lib_re "^lib(${toolchain}|${allowed})(-[0-9.]+)?\\.(a|so)(\\.[0-9]+)*$")
set(other_re
    "^([A-Za-z]?crt[a-zA-Z0-9]*\\.o|ld-linux[-a-z0-9_]*\\.so\\.[0-9]+|linux-vdso\\.so\\.[0-9]+)$")
set(bad "")

file(STRINGS "${MAP}" loads REGEX "^LOAD ")
list(LENGTH loads n_loads)
if(n_loads EQUAL 0)
  message(FATAL_ERROR "${MAP} has no LOAD lines (not a GNU ld map?)")
endif()
foreach(line IN LISTS loads)
  string(REGEX REPLACE "^LOAD " "" path "${line}")
  get_filename_component(name "${path}" NAME)
  if(name MATCHES "\\.cc\\.o$" OR name MATCHES "^libtlvlink_[a-z_]+\\.a$" OR name MATCHES "${lib_re}"
     OR name MATCHES "${other_re}")
    continue()
  endif()
  list(APPEND bad "linked: ${path}")
endforeach()

execute_process(COMMAND ldd "${EXE}" OUTPUT_VARIABLE ldd_out RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "ldd ${EXE} failed (${rc})")
endif()
string(REPLACE "\n" ";" ldd_lines "${ldd_out}")
set(loaded "")
foreach(line IN LISTS ldd_lines)
  string(STRIP "${line}" line)
  if(line STREQUAL "")
    continue()
  endif()
  string(REGEX REPLACE "[ \t].*" "" first "${line}")
  get_filename_component(name "${first}" NAME)
  list(APPEND loaded ${name})
  if(NOT name MATCHES "${lib_re}" AND NOT name MATCHES "${other_re}")
    list(APPEND bad "loaded at run time: ${line}")
  endif()
endforeach()

list(JOIN loaded " " loaded_text)
message(STATUS "${n_loads} link inputs; run-time libraries: ${loaded_text}")
if(bad)
  list(JOIN bad "\n  " bad_text)
  message(FATAL_ERROR "libraries outside the board runtime's allowed set (${ALLOWED} and the "
                      "toolchain's):\n  ${bad_text}")
endif()
