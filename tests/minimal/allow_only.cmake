# Dependency provider for tests/minimal (CMAKE_PROJECT_TOP_LEVEL_INCLUDES): every find_package()
# made while configuring the board runtime must name a package it is allowed to need, or the
# configure fails naming the package. pkg-config and host-tool packages (CLI11, nlohmann_json,
# PNG, HDF5, ONNX, protobuf, torch, GTest, ...) are never on the list; XNNPACK, pthreadpool,
# cpuinfo and libsodium are plain find_library() calls, which the link-input check covers instead.
# PkgConfig joins the list when image decoding is built (libturbojpeg is found through it).
set(TLVLINK_ALLOWED_PACKAGES FlatBuffers Threads)

function(tlvlink_allow_only method package)
  if(NOT package IN_LIST TLVLINK_ALLOWED_PACKAGES)
    message(FATAL_ERROR "tlvlink minimal build: find_package(${package}) is not allowed in the "
                        "board runtime (allowed: ${TLVLINK_ALLOWED_PACKAGES}); guard it with the "
                        "option that needs it in cmake/dependencies.cmake")
  endif()
  # Not setting ${package}_FOUND hands the call back to CMake's own find_package().
endfunction()

cmake_language(SET_DEPENDENCY_PROVIDER tlvlink_allow_only SUPPORTED_METHODS FIND_PACKAGE)
