# Dependency discovery for every option. A missing dependency for an enabled option is a
# configure error that names the Debian package to install.
function(tlvlink_require found what package)
  if(NOT ${found})
    message(FATAL_ERROR "tlvlink: ${what} not found; install Debian package '${package}' "
                        "(tools/setup/install_deps.sh does this)")
  endif()
endfunction()

find_package(FlatBuffers CONFIG REQUIRED)
find_program(TLVLINK_FLATC flatc REQUIRED)
find_package(Threads REQUIRED)

# libsodium: the model file's BLAKE2b-256 hash and optional ed25519 signature
# (runtime/model "Integrity trailer"); every build that loads a model needs it.
find_path(SODIUM_INCLUDE_DIR sodium.h)
find_library(SODIUM_LIBRARY sodium)
tlvlink_require(SODIUM_INCLUDE_DIR "sodium.h" libsodium-dev)
tlvlink_require(SODIUM_LIBRARY "libsodium" libsodium-dev)
add_library(tlvlink::sodium INTERFACE IMPORTED)
target_include_directories(tlvlink::sodium INTERFACE ${SODIUM_INCLUDE_DIR})
target_link_libraries(tlvlink::sodium INTERFACE ${SODIUM_LIBRARY})

if(TLVLINK_WITH_XNNPACK)
  find_path(XNNPACK_INCLUDE_DIR xnnpack.h)
  find_library(XNNPACK_LIBRARY XNNPACK)
  find_library(PTHREADPOOL_LIBRARY pthreadpool)
  find_library(CPUINFO_LIBRARY cpuinfo)
  tlvlink_require(XNNPACK_INCLUDE_DIR "xnnpack.h" libxnnpack-dev)
  tlvlink_require(XNNPACK_LIBRARY "libXNNPACK" libxnnpack-dev)
  tlvlink_require(PTHREADPOOL_LIBRARY "libpthreadpool" libpthreadpool-dev)
  tlvlink_require(CPUINFO_LIBRARY "libcpuinfo" libcpuinfo-dev)
  add_library(tlvlink::xnnpack INTERFACE IMPORTED)
  target_include_directories(tlvlink::xnnpack INTERFACE ${XNNPACK_INCLUDE_DIR})
  target_link_libraries(tlvlink::xnnpack INTERFACE
    ${XNNPACK_LIBRARY} ${PTHREADPOOL_LIBRARY} ${CPUINFO_LIBRARY} Threads::Threads)
endif()

if(TLVLINK_WITH_IMAGE OR TLVLINK_BUILD_HOST_TOOLS)
  # JPEG: runtime/image wraps libturbojpeg for the whole project.
  find_package(PkgConfig REQUIRED)
  pkg_check_modules(TURBOJPEG IMPORTED_TARGET libturbojpeg)
  tlvlink_require(TURBOJPEG_FOUND "libturbojpeg (TurboJPEG API)" libturbojpeg0-dev)
  # The libjpeg API of the same library (cropped, DCT-scaled decodes: runtime/image).
  pkg_check_modules(LIBJPEG IMPORTED_TARGET libjpeg)
  tlvlink_require(LIBJPEG_FOUND "libjpeg (libjpeg-turbo's libjpeg API)" libjpeg62-turbo-dev)
  add_library(tlvlink::libjpeg ALIAS PkgConfig::LIBJPEG)
endif()

if(TLVLINK_WITH_LIBCAMERA)
  if(NOT TLVLINK_WITH_CAPTURE)
    message(FATAL_ERROR "tlvlink: TLVLINK_WITH_LIBCAMERA needs TLVLINK_WITH_CAPTURE=ON (the libcamera source lives in runtime/capture)")
  endif()
  find_package(PkgConfig REQUIRED)
  pkg_check_modules(LIBCAMERA IMPORTED_TARGET libcamera)
  tlvlink_require(LIBCAMERA_FOUND "libcamera" libcamera-dev)
endif()
# USB: the board's FunctionFS side needs only the kernel headers; libusb is the host side's
# (tools/listen), built with the host tools or the tests.
if(TLVLINK_WITH_USB AND TLVLINK_WITH_SERIAL AND (TLVLINK_BUILD_HOST_TOOLS OR TLVLINK_BUILD_TESTS))
  find_package(PkgConfig REQUIRED)
  pkg_check_modules(LIBUSB IMPORTED_TARGET libusb-1.0)
  tlvlink_require(LIBUSB_FOUND "libusb-1.0" libusb-1.0-0-dev)
endif()
if(TLVLINK_BUILD_TRAINER)
  find_package(Torch QUIET)
  tlvlink_require(Torch_FOUND "libtorch" libtorch-dev)
endif()
if(TLVLINK_BUILD_HOST_TOOLS)
  find_package(CLI11 CONFIG REQUIRED)
  find_package(nlohmann_json CONFIG REQUIRED)
  # HDF5 (the Feel dataset format, tools/datasets).
  find_package(PkgConfig REQUIRED)
  pkg_check_modules(HDF5 IMPORTED_TARGET hdf5)
  tlvlink_require(HDF5_FOUND "HDF5 C library" libhdf5-dev)
  # The Foxglove WebSocket server of `tlvlink listen --foxglove` (tools/foxglove): websocketpp
  # (header-only) on standalone asio.
  find_path(WEBSOCKETPP_INCLUDE_DIR websocketpp/server.hpp)
  tlvlink_require(WEBSOCKETPP_INCLUDE_DIR "websocketpp (websocketpp/server.hpp)" libwebsocketpp-dev)
  find_path(ASIO_INCLUDE_DIR asio.hpp)
  tlvlink_require(ASIO_INCLUDE_DIR "standalone asio (asio.hpp)" libasio-dev)
  add_library(tlvlink::websocketpp INTERFACE IMPORTED)
  target_include_directories(tlvlink::websocketpp SYSTEM INTERFACE ${WEBSOCKETPP_INCLUDE_DIR} ${ASIO_INCLUDE_DIR})
  target_compile_definitions(tlvlink::websocketpp INTERFACE ASIO_STANDALONE)
  # PNG images (tools/io/png.cc: calibration folders).
  find_package(PNG QUIET)
  tlvlink_require(PNG_FOUND "libpng" libpng-dev)
endif()
if(TLVLINK_BUILD_HOST_TOOLS AND TLVLINK_WITH_ONNX)
  # ONNX's config imports onnx_proto, which links protobuf::libprotobuf: find protobuf first.
  find_package(Protobuf QUIET)
  tlvlink_require(Protobuf_FOUND "protobuf" libprotobuf-dev)
  find_package(ONNX CONFIG QUIET)
  tlvlink_require(ONNX_FOUND "ONNX (onnx_proto)" libonnx-dev)
endif()
if(TLVLINK_BUILD_TESTS)
  find_package(GTest REQUIRED)
  # Tests parse JSON outputs (the daemon's records) also in board builds without host tools.
  find_package(nlohmann_json CONFIG REQUIRED)
endif()

