#!/usr/bin/env python3
"""The emulated ARM64 board rig (see tools/rig/README.md).

  rig.py prepare [--modules GROUPS]                 fetch + cache the kernel, modules, busybox
  rig.py run --script T.sh [--program BIN] [--file F] [options]   build the initramfs, boot, report
  rig.py shell [--program BIN] [--file F] [options]               boot to a shell on this terminal
  rig.py image --out DIR [--rootfs ROOT] [--script T.sh] [options]  write the kernel, the initramfs
                                                                   and boot.sh into DIR, no boot

Exit status of `run`: 0 when every test passed or was skipped and the script returned 0;
1 on any failure, a missed bound or a guest that did not finish; 2 on bad arguments/set-up."""

import argparse
import os
import shlex
import shutil
import signal
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from riglib import initramfs, kernel, qemu  # noqa: E402
from riglib.errors import RigError  # noqa: E402
from riglib.report import print_report  # noqa: E402


def default_sysroot():
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(base, "tlvlink", "sysroot-arm64")


def parse(argv):
    p = argparse.ArgumentParser(prog="rig.py", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("command", choices=["prepare", "run", "shell", "image"])
    g = p.add_argument_group("image")
    g.add_argument("--modules", default=",".join(kernel.DEFAULT_GROUPS),
                   help=f"module groups: {', '.join(kernel.MODULE_GROUPS)} (default: all)")
    g.add_argument("--kernel-package", help="arm64 kernel package (default: what linux-image-arm64 names)")
    g.add_argument("--script", help="test script run by the guest's /init (sourced with rig.sh)")
    g.add_argument("--program", action="append", default=[], metavar="BIN[:DEST]",
                   help="arm64 program (stripped, its libraries added); default DEST /bin/NAME")
    g.add_argument("--file", action="append", default=[], metavar="PATH[:DEST]",
                   help="data file or directory, copied as is; default DEST /payload/NAME")
    g.add_argument("--rootfs", action="append", default=[], metavar="DIR",
                   help="a directory copied onto the guest's / (e.g. a board package's staged root; "
                        "its ELF programs get their libraries)")
    g.add_argument("--env", action="append", default=[], metavar="NAME=VALUE",
                   help="exported in the guest before the script runs")
    g.add_argument("--sysroot", default=default_sysroot(),
                   help="arm64 sysroot of tools/setup/make_sysroot.sh (libraries for the programs)")
    g.add_argument("--lib-dir", action="append", default=[], help="more arm64 library directories")
    g.add_argument("--gzip", action="store_true", help="compress the initramfs (slower to boot under TCG)")
    r = p.add_argument_group("run")
    r.add_argument("--out", default="build/rig", help="console.log, port recordings, the image (default build/rig)")
    r.add_argument("--cpu", default="cortex-a76", choices=["cortex-a76", "cortex-a72", "max"])
    r.add_argument("--smp", type=int, default=2)
    r.add_argument("--mem", type=int, default=1024, help="guest memory in MiB")
    r.add_argument("--append", action="append", default=[], help="extra kernel command line word")
    r.add_argument("--port", action="append", default=[], metavar="NAME",
                   help="extra virtio-serial port recorded to OUT/NAME.bin (rig.data always exists)")
    r.add_argument("--host-port", action="append", default=[], metavar="NAME",
                   help="virtio-serial port handed to --host-cmd as env RIG_PORT_<NAME> (a unix socket)")
    r.add_argument("--host-cmd", help="shell command run beside QEMU (ended with it)")
    r.add_argument("--share", metavar="DIR", help="host directory mounted at /mnt/host (9p)")
    r.add_argument("--boot-timeout", type=float, default=60)
    r.add_argument("--test-timeout", type=float, default=180)
    r.add_argument("--timeout", type=float, default=900, help="bound of the whole run in seconds")
    args = p.parse_args(argv)
    if args.command == "run" and not args.script:
        p.error("run needs --script")
    return args


def build_image(args, log):
    t = time.monotonic()
    groups = [g for g in args.modules.split(",") if g]
    if args.share and "9p" not in groups:
        groups.append("9p")
    k = kernel.prepare(kernel.modules_for(groups), args.kernel_package, log=log)
    payload = initramfs.Payload()
    for spec in args.program:
        payload.add_program(spec)
    for spec in args.file:
        payload.add_file(spec)
    for root in args.rootfs:
        payload.add_rootfs(root)
    payload.script = args.script
    for kv in args.env:
        name, eq, value = kv.partition("=")
        if not eq or not name.isidentifier():
            raise RigError(f"--env '{kv}': expected NAME=VALUE")
        payload.env[name] = value
    lib_dirs = args.lib_dir + [os.path.join(args.sysroot, d) for d in
                               ("usr/lib/aarch64-linux-gnu", "lib/aarch64-linux-gnu")]
    image = os.path.join(args.out, "initramfs.cpio" + (".gz" if args.gzip else ""))
    what = initramfs.build(image, k, payload, lib_dirs, compress=args.gzip)
    log(f"rig: kernel {k.version} ({k.package}); initramfs {what}; built in {time.monotonic() - t:.1f}s")
    return k, image


def write_boot_files(args, k, image, log):
    """`image`: the kernel beside the initramfs and a boot.sh that starts them (auto mode: the
    script's tests run and the guest powers off; `boot.sh shell` opens a shell instead)."""
    vmlinuz = os.path.join(args.out, "vmlinuz")
    shutil.copyfile(k.image, vmlinuz)
    cfg = qemu.RunConfig()
    cfg.kernel, cfg.initrd, cfg.cpu, cfg.smp, cfg.mem_mb = k, image, args.cpu, args.smp, args.mem
    cfg.append = args.append
    cfg.ports = []  # no host reader: the rig's data ports are left out
    initrd = os.path.basename(image)

    def line(interactive):
        cfg.interactive = interactive
        return " ".join(shlex.quote({k.image: "vmlinuz", image: initrd}.get(c, c))
                        for c in qemu.command(cfg, "/nonexistent"))
    boot = os.path.join(args.out, "boot.sh")
    with open(boot, "w") as f:
        f.write("#!/bin/sh\n# The emulated board (tools/rig/README.md): boots this directory's kernel and\n"
                "# initramfs under QEMU TCG. `boot.sh` runs the image's script and powers off;\n"
                "# `boot.sh shell` opens a shell on this terminal ('poweroff -f' ends it).\n"
                'cd "$(dirname "$0")"\n'
                f'[ "${{1:-}}" = shell ] && exec {line(True)}\nexec {line(False)}\n')
    os.chmod(boot, 0o755)
    log(f"rig: image in {args.out}: vmlinuz ({os.path.getsize(vmlinuz) / 1048576:.1f} MB), "
        f"{os.path.basename(image)} ({os.path.getsize(image) / 1048576:.1f} MB), boot.sh")
    return 0


def _terminate(signum, _frame):
    # SIGTERM (e.g. a CI time limit) unwinds like Ctrl-C: QEMU is stopped by its PID on the way out.
    raise SystemExit(128 + signum)


def main(argv):
    signal.signal(signal.SIGTERM, _terminate)
    args = parse(argv)
    log = lambda msg: print(msg, flush=True)  # noqa: E731
    try:
        if args.command == "prepare":
            k = kernel.prepare(kernel.modules_for(args.modules.split(",")), args.kernel_package, log=log)
            log(f"rig: kernel {k.version}: {k.image}\nrig: busybox: {initramfs.busybox()}")
            return 0
        k, image = build_image(args, log)
        if args.command == "image":
            return write_boot_files(args, k, image, log)
        cfg = qemu.RunConfig()
        cfg.kernel, cfg.initrd, cfg.cpu, cfg.smp, cfg.mem_mb = k, image, args.cpu, args.smp, args.mem
        cfg.append, cfg.ports, cfg.host_ports = args.append, ["rig.data"] + args.port, args.host_port
        cfg.host_cmd, cfg.share, cfg.out = args.host_cmd, args.share, args.out
        cfg.boot_timeout, cfg.test_timeout, cfg.total_timeout = \
            args.boot_timeout, args.test_timeout, args.timeout
        if args.command == "shell":
            cfg.interactive = True
            return qemu.interactive(cfg)
        results, seconds, console, note = qemu.run(cfg, log=log)
        return print_report(results, seconds, console, note, cfg)
    except RigError as e:
        print(f"rig: error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
