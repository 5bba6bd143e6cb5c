"""The emulated ARM64 board rig: Debian's arm64 kernel under qemu-system-aarch64 (TCG) with an
initramfs of busybox, the project's cross-built programs and a test script. See tools/rig/README.md."""
