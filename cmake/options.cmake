# All tlvlink build options, declared once. A board preset (boards/*.cmake, CMakePresets.json)
# sets these; the minimal runtime needs only XNNPACK, pthreadpool, cpuinfo and flatbuffers.
option(TLVLINK_WITH_XNNPACK   "Build the XNNPACK executor (otherwise only the portable reference executor)" ON)
option(TLVLINK_WITH_LIBCAMERA "Build the libcamera capture backend (needs libcamera-dev)" OFF)
# The prediction stream (issue 14): protocol, transports, the board's sender, `tlvlink listen`.
option(TLVLINK_WITH_PROTOCOL  "Build the stream protocol library tlvlink_protocol (runtime/protocol; needs only flatbuffers)" ON)
option(TLVLINK_WITH_SERIAL    "Build tlvlink_transport: the link interface, the serial transports (termios: UART, CDC-ACM, pty) and the board's sender (runtime/transport); with host tools, `tlvlink listen` (tools/listen)" ON)
option(TLVLINK_WITH_USB       "Add the USB bulk transport: the FunctionFS device side to tlvlink_transport and, with host tools, the libusb host side to tools/listen (needs libusb-1.0)" OFF)
option(TLVLINK_BUILD_TRAINER  "Build the libtorch trainer (needs libtorch-dev)" OFF)
option(TLVLINK_BUILD_HOST_TOOLS "Build the host CLI, model writer and quantizer" ON)
option(TLVLINK_WITH_ONNX     "Build `tlvlink convert` (ONNX import; host tools only, needs libonnx-dev, libprotobuf-dev)" ON)
option(TLVLINK_BUILD_BENCHMARKS "Build Google Benchmark micro-benchmarks" OFF)
option(TLVLINK_BUILD_TESTS    "Build the GoogleTest suites" ON)
option(TLVLINK_BUILD_FUZZERS  "Build libFuzzer targets (needs clang)" OFF)
option(TLVLINK_WERROR         "Treat compiler warnings as errors (CI sets this)" OFF)
set(TLVLINK_SANITIZE "" CACHE STRING "Sanitizers to build with, e.g. address,undefined (empty = none)")
set(TLVLINK_BOARD "host" CACHE STRING "Board definition this build targets (see boards/)")

if(TLVLINK_WITH_SERIAL AND NOT TLVLINK_WITH_PROTOCOL)
  message(FATAL_ERROR "tlvlink: TLVLINK_WITH_SERIAL needs TLVLINK_WITH_PROTOCOL=ON "
                      "(the transports carry the stream protocol's frames)")
endif()
if(TLVLINK_WITH_USB AND NOT TLVLINK_WITH_SERIAL)
  message(FATAL_ERROR "tlvlink: TLVLINK_WITH_USB needs TLVLINK_WITH_SERIAL=ON (the USB transport "
                      "joins the serial ones in tlvlink_transport, beside the sender)")
endif()
