#!/usr/bin/env bash
# Installs everything tlvlink needs from Debian's packages. Idempotent; safe to rerun.
#   install_deps.sh [core|test|cross|rig|bench|npm|all]   (default: all: everything but bench)
# core  : compilers, cmake, ccache (cmake/ccache.cmake), XNNPACK stack, flatbuffers, libsodium (the model file's hash and
#         signatures: every build that loads a model), CLI/JSON libraries, JPEG, PNG, HDF5, ONNX,
#         libcamera (the libcamera frame source, TLVLINK_WITH_LIBCAMERA), toml++ (tlvlinkd's
#         configuration), libusb (the host side of the USB stream link, tools/listen), websocketpp
#         + standalone asio (the Foxglove WebSocket server of `tlvlink listen --foxglove`, tools/foxglove)
# test  : core + GoogleTest/Benchmark, clang (libFuzzer, sanitizers), Debian's torch + onnx
#         (the ONNX import tests export their models with /usr/bin/python3), libtorch-dev
#         (the trainer, TLVLINK_BUILD_TRAINER in the host preset); the Python stream client's
#         dependencies and test runner (python3-serial, python3-usb, python3-pytest: tools/python);
#         Debian's chromium (headless: the Foxglove live view's picture, tools/foxglove/view)
# npm   : node and npm (Debian's nodejs, npm, unless a node is on PATH) and the real Foxglove
#         clients of tests/foxglove's e2e tests (install_npm_clients.sh: `npm ci` of the pinned
#         @foxglove/ws-protocol, ws and @mcap/core, outside the tree); `test` and `all` include it
# cross : aarch64 cross compiler + qemu-user (the arm64 sysroot is tools/setup/make_sysroot.sh),
#         lintian (checks the board packages of `tlvlink flash`)
# rig   : cross + the emulated board (tools/rig): qemu-system-aarch64, kmod (depmod/modinfo for
#         the kernel module subset), python3; the arm64 kernel and busybox are fetched by the rig
#         itself with `apt-get download` (never installed)
set -euo pipefail
what=${1:-all}
export DEBIAN_FRONTEND=noninteractive
SUDO=""; [ "$(id -u)" = 0 ] || SUDO=sudo

core_pkgs=(build-essential cmake ninja-build pkg-config ccache
  libxnnpack-dev libpthreadpool-dev libcpuinfo-dev
  libflatbuffers-dev flatbuffers-compiler libsodium-dev
  libcli11-dev nlohmann-json3-dev
  libturbojpeg0-dev libpng-dev libhdf5-dev
  libonnx-dev libprotobuf-dev
  libjpeg62-turbo-dev libcamera-dev libtomlplusplus-dev libusb-1.0-0-dev
  libwebsocketpp-dev libasio-dev)
test_pkgs=(libgtest-dev libgmock-dev clang clang-format libclang-rt-14-dev llvm
  python3-torch python3-onnx python3-numpy libtorch-dev
  python3-serial python3-usb python3-pytest
  chromium)  # headless: the live view's picture (tools/foxglove/view/screenshot.sh, ctest foxglove.live_view)
npm_pkgs=(nodejs npm)
command -v node >/dev/null && command -v npm >/dev/null && npm_pkgs=()
cross_pkgs=(g++-aarch64-linux-gnu qemu-user lintian)  # lintian: the board packages (tools/boards)
rig_pkgs=(qemu-system-arm kmod python3)
# bench: the Python peer of the pipeline benchmark (OpenCV + PyTorch reading the same model).
bench_pkgs=(python3-opencv python3-flatbuffers python3-torch python3-numpy)

pkgs=("${core_pkgs[@]}")
case "$what" in
  core) ;;
  test) pkgs+=("${test_pkgs[@]}") ;;
  cross) pkgs+=("${cross_pkgs[@]}") ;;
  rig) pkgs+=("${cross_pkgs[@]}" "${rig_pkgs[@]}") ;;
  bench) pkgs+=("${bench_pkgs[@]}") ;;
  npm) ;;
  all) pkgs+=("${test_pkgs[@]}" "${cross_pkgs[@]}" "${rig_pkgs[@]}") ;;
  *) echo "install_deps.sh: unknown set '$what' (core|test|cross|rig|bench|npm|all)" >&2; exit 2 ;;
esac
case "$what" in npm|test|all) pkgs+=("${npm_pkgs[@]}") ;; esac

# The arm64 sysroot (make_sysroot.sh) needs arm64 package lists: add the architecture before the
# one `apt-get update`, so a fresh machine updates once.
if [ "$what" = cross ] || [ "$what" = rig ] || [ "$what" = all ]; then
  if ! dpkg --print-foreign-architectures | grep -qx arm64; then
    $SUDO dpkg --add-architecture arm64
    need_update=1
  fi
fi

missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ] || [ "${need_update:-0}" = 1 ]; then
  echo "install_deps: installing ${missing[*]:-(nothing; refreshing package lists for arm64)}"
  $SUDO apt-get update -qq
  if [ ${#missing[@]} -gt 0 ]; then
    $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  fi
else
  echo "install_deps: all packages for '$what' present"
fi

# The npm clients of the e2e tests (after apt: they need node and npm).
if [ "$what" = npm ] || [ "$what" = test ] || [ "$what" = all ]; then
  # Not fatal: without the registry the e2e tests say they were skipped (exit 77), nothing else needs them.
  bash "$(dirname "$0")/install_npm_clients.sh" ||
    echo "install_deps: the npm clients were not installed; tests/foxglove's e2e tests will be skipped" >&2
fi
