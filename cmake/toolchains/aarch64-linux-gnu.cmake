# Cross build for 64-bit ARM Linux boards with Debian's cross toolchain (g++-aarch64-linux-gnu).
#
# Where things come from:
#   compilers, libc, libstdc++  /usr/bin/aarch64-linux-gnu-*, /usr/aarch64-linux-gnu (the toolchain)
#   XNNPACK, pthreadpool, cpuinfo, flatbuffers, GoogleTest
#                               TLVLINK_SYSROOT: arm64 .debs unpacked by tools/setup/make_sysroot.sh
#   flatc and other build-time programs: the host's (/usr/bin/flatc), never the sysroot's
#
# No CMAKE_SYSROOT (it would also work: Debian's cross gcc finds its libc relative to its own
# prefix). The unpacked packages are only a find root, so compile lines stay the toolchain's
# defaults plus the found -isystem paths, and the linker gets -rpath-link for their .so deps.
#
# Cache variables (set them with -D or in a board preset, boards/*.json):
#   TLVLINK_SYSROOT     the unpacked arm64 packages (default: the make_sysroot.sh default)
#   TLVLINK_TARGET_CPU  -mcpu= for tlvlink and everything built here (default: generic armv8-a)
#   TLVLINK_QEMU_CPU    qemu-aarch64 -cpu for running tests (default cortex-a76: NEON + sdot;
#                       TLVLINK_TEST_CPU in ctest's environment overrides it)
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)

set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)

if(DEFINED ENV{XDG_CACHE_HOME} AND NOT "$ENV{XDG_CACHE_HOME}" STREQUAL "")
  set(_tlvlink_cache_home "$ENV{XDG_CACHE_HOME}")
else()
  set(_tlvlink_cache_home "$ENV{HOME}/.cache")
endif()
set(TLVLINK_SYSROOT "${_tlvlink_cache_home}/tlvlink/sysroot-arm64" CACHE PATH
    "arm64 packages unpacked by tools/setup/make_sysroot.sh")
set(TLVLINK_TARGET_CPU "" CACHE STRING "-mcpu for the target (empty: generic armv8-a)")
set(TLVLINK_QEMU_CPU "cortex-a76" CACHE STRING "qemu-aarch64 -cpu used to run tests")
# try_compile projects re-read this file without the cache: hand the values down.
list(APPEND CMAKE_TRY_COMPILE_PLATFORM_VARIABLES TLVLINK_SYSROOT TLVLINK_TARGET_CPU)

set(_tlvlink_toolchain_libc /usr/aarch64-linux-gnu)
set(_tlvlink_sysroot_libdir "${TLVLINK_SYSROOT}/usr/lib/aarch64-linux-gnu")
if(NOT EXISTS "${TLVLINK_SYSROOT}/.tlvlink-sysroot-stamp")
  message(FATAL_ERROR "tlvlink: no arm64 sysroot at '${TLVLINK_SYSROOT}'. "
                      "Run tools/setup/make_sysroot.sh [DIR] (and -DTLVLINK_SYSROOT=DIR if not default).")
endif()

if(TLVLINK_TARGET_CPU)
  set(CMAKE_C_FLAGS_INIT "-mcpu=${TLVLINK_TARGET_CPU}")
  set(CMAKE_CXX_FLAGS_INIT "-mcpu=${TLVLINK_TARGET_CPU}")
endif()
# Shared libraries in the sysroot need each other (libXNNPACK.so -> libcpuinfo.so.0 ...).
set(CMAKE_EXE_LINKER_FLAGS_INIT "-Wl,-rpath-link,${_tlvlink_sysroot_libdir}")
set(CMAKE_SHARED_LINKER_FLAGS_INIT "-Wl,-rpath-link,${_tlvlink_sysroot_libdir}")

# No build-tree RPATH: binaries copied to a board must not point into this machine's sysroot.
# Under qemu the libraries are found through LD_LIBRARY_PATH (below).
set(CMAKE_SKIP_BUILD_RPATH ON)

# Libraries, headers and CMake packages only from the sysroot / toolchain; programs only from
# the host (find_program(flatc) must find /usr/bin/flatc, which runs here).
set(CMAKE_FIND_ROOT_PATH "${TLVLINK_SYSROOT}" "${_tlvlink_toolchain_libc}")
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
# pkg-config, if a later option uses it, must read the sysroot's .pc files, not the host's.
set(ENV{PKG_CONFIG_LIBDIR} "${_tlvlink_sysroot_libdir}/pkgconfig:${TLVLINK_SYSROOT}/usr/share/pkgconfig")
set(ENV{PKG_CONFIG_SYSROOT_DIR} "${TLVLINK_SYSROOT}")
set(ENV{PKG_CONFIG_PATH} "")
# The sysroot's multiarch headers (libjpeg's jconfig.h lives there); the cross compiler only
# searches its own.
set(CMAKE_C_STANDARD_INCLUDE_DIRECTORIES "${TLVLINK_SYSROOT}/usr/include/aarch64-linux-gnu")
set(CMAKE_CXX_STANDARD_INCLUDE_DIRECTORIES "${TLVLINK_SYSROOT}/usr/include/aarch64-linux-gnu")

# Tests (ctest, gtest_discover_tests) run through qemu user mode. binfmt_misc is not assumed:
# qemu is always called explicitly, by qemu-aarch64-run.sh (TLVLINK_TEST_CPU in the environment
# runs the tree under another -cpu). -L serves the toolchain's ld.so and libc; LD_LIBRARY_PATH
# finds the sysroot's shared libraries (XNNPACK, pthreadpool, cpuinfo).
find_program(TLVLINK_QEMU_AARCH64 qemu-aarch64)
if(TLVLINK_QEMU_AARCH64)
  set(CMAKE_CROSSCOMPILING_EMULATOR
      "sh;${CMAKE_CURRENT_LIST_DIR}/qemu-aarch64-run.sh;${TLVLINK_QEMU_AARCH64};${TLVLINK_QEMU_CPU};${_tlvlink_toolchain_libc};${_tlvlink_sysroot_libdir}")
else()
  message(WARNING "tlvlink: qemu-aarch64 not found (apt package qemu-user): cross-built tests cannot run here")
endif()

