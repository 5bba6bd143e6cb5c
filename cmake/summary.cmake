message(STATUS "tlvlink ${PROJECT_VERSION} board=${TLVLINK_BOARD} xnnpack=${TLVLINK_WITH_XNNPACK} "
               "capture=${TLVLINK_WITH_CAPTURE} libcamera=${TLVLINK_WITH_LIBCAMERA} protocol=${TLVLINK_WITH_PROTOCOL} serial=${TLVLINK_WITH_SERIAL} usb=${TLVLINK_WITH_USB} trainer=${TLVLINK_BUILD_TRAINER} "
               "host_tools=${TLVLINK_BUILD_HOST_TOOLS} tests=${TLVLINK_BUILD_TESTS} "
               "benchmarks=${TLVLINK_BUILD_BENCHMARKS} fuzzers=${TLVLINK_BUILD_FUZZERS} "
               "sanitize='${TLVLINK_SANITIZE}' werror=${TLVLINK_WERROR} debug_lines=${TLVLINK_DEBUG_LINES} unity=${TLVLINK_UNITY_BUILD} ccache=${TLVLINK_CCACHE_PROGRAM}")
