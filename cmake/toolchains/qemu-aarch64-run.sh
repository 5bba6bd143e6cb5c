#!/bin/sh
# ctest's emulator for the aarch64 trees: qemu-aarch64 (user mode) under the tree's CPU model, or
# under the one TLVLINK_TEST_CPU names, so one tree's tests run under several CPU models
# (tools/setup/cross_test.sh: the Cortex-A72 build under -cpu cortex-a72, then cortex-a76, where
# XNNPACK picks its dot-product kernels at run time).
#   qemu-aarch64-run.sh QEMU CPU LIBC LIBDIR PROGRAM [ARG...]
qemu=$1 cpu=$2 libc=$3 libdir=$4
shift 4
exec "$qemu" -cpu "${TLVLINK_TEST_CPU:-$cpu}" -L "$libc" -E "LD_LIBRARY_PATH=$libdir" "$@"
