"""Assembles the rig's initramfs: busybox-static (arm64), the kernel module subset, the guest's
init and helper functions, the caller's programs with the libraries they load, their data files
and the test script."""

import gzip
import io
import os
import subprocess
import tempfile

from . import cpio, debs, elf
from .errors import RigError

GUEST_DIR = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "guest")
TOOLCHAIN_LIBS = ["/usr/aarch64-linux-gnu/lib"]
BASE_DIRS = ["bin", "sbin", "usr", "usr/bin", "usr/sbin", "lib", "dev", "proc", "sys", "tmp",
             "run", "etc", "mnt", "root", "rig", "payload"]


class Payload:
    """What the caller puts into the guest. Destinations are absolute guest paths."""

    def __init__(self):
        self.programs = []   # (host path, guest path): arm64 ELF, stripped, libraries resolved
        self.files = []      # (host path, guest path): copied as they are (directories recursively)
        self.script = None   # host path of the test script, run by /init as /rig/test.sh
        self.env = {}        # exported in the guest before the script runs
        self.rootfs = []     # host directories copied onto the guest's / (a staged package root);
                             # the ELF programs in them get their libraries like --program's

    def add_program(self, spec):
        src, dest = _split(spec, "/bin")
        self.programs.append((src, dest))

    def add_rootfs(self, path):
        if not os.path.isdir(path):
            raise RigError(f"rootfs '{path}' is not a directory")
        self.rootfs.append(path)

    def rootfs_programs(self):
        """(host path, guest path) of every ELF file under the rootfs directories."""
        found = []
        for root in self.rootfs:
            for base, _, names in os.walk(root):
                for n in names:
                    host = os.path.join(base, n)
                    if os.path.isfile(host) and not os.path.islink(host) and elf.is_elf(host):
                        found.append((host, "/" + os.path.relpath(host, root)))
        return found

    def add_file(self, spec):
        src, dest = _split(spec, "/payload")
        self.files.append((src, dest))


def _split(spec, default_dir):
    src, _, dest = spec.partition(":")
    if not os.path.exists(src):
        raise RigError(f"payload '{src}' does not exist")
    return src, dest or os.path.join(default_dir, os.path.basename(src.rstrip("/")))


def busybox():
    version = debs.candidate("busybox-static")
    root = os.path.join(debs.cache_root(), f"busybox-{version.replace(':', '_')}")
    path = os.path.join(root, "bin", "busybox")
    if not os.path.exists(path):
        debs.extract(debs.download("busybox-static", version), root)
    return path


def _stripped(path):
    """The program without debug sections (the guest does not need them; images stay small)."""
    with tempfile.NamedTemporaryFile(suffix=".stripped") as tmp:
        try:
            subprocess.run(["aarch64-linux-gnu-strip", "--strip-debug", "-o", tmp.name, path],
                           check=True, capture_output=True, text=True)
        except subprocess.CalledProcessError as e:
            raise RigError(f"strip {path}: {e.stderr.strip()}")
        with open(tmp.name, "rb") as f:
            return f.read()


class _Tree:
    """Guest path -> entry; written parents-first."""

    def __init__(self):
        self.entries = {}

    def add(self, path, kind, value=None, perm=None):
        path = path.strip("/")
        parts = path.split("/")
        for i in range(1, len(parts)):
            self.entries.setdefault("/".join(parts[:i]), ("dir", None, 0o755))
        self.entries[path] = (kind, value, perm)

    def add_host(self, src, dest):
        if os.path.islink(src):  # kept as a link (a unit's wants link points at a guest path)
            self.add(dest, "symlink", os.readlink(src))
        elif os.path.isdir(src):
            for base, _, names in os.walk(src):
                for n in names:
                    host = os.path.join(base, n)
                    self.add_host(host, os.path.join(dest, os.path.relpath(host, src)))
        else:
            with open(src, "rb") as f:
                self.add(dest, "file", f.read(), os.stat(src).st_mode & 0o777)

    def write(self, out):
        w = cpio.Writer(out)
        for path in sorted(self.entries):
            kind, value, perm = self.entries[path]
            if kind == "dir":
                w.directory(path, perm)
            elif kind == "file":
                w.file(path, value, perm)
            elif kind == "symlink":
                w.symlink(path, value)
            elif kind == "chardev":
                w.chardev(path, value[0], value[1], perm)
        w.finish()


def build(out_path, kernel, payload, lib_dirs, compress=False):
    """Writes the image; returns a one-line description (size, programs, libraries)."""
    tree = _tree = _Tree()
    for d in BASE_DIRS:
        tree.add(d, "dir", perm=0o1777 if d == "tmp" else 0o755)
    tree.add("dev/console", "chardev", (5, 1), 0o600)
    tree.add("dev/null", "chardev", (1, 3), 0o666)
    tree.add_host(busybox(), "bin/busybox")
    tree.add_host(os.path.join(GUEST_DIR, "init"), "init")
    tree.add_host(os.path.join(GUEST_DIR, "rig.sh"), "rig/rig.sh")
    tree.add_host(os.path.join(GUEST_DIR, "rig"), "bin/rig")
    for base, _, names in os.walk(kernel.modules_dir):
        for n in names:
            host = os.path.join(base, n)
            tree.add_host(host, os.path.join("lib/modules", kernel.version,
                                             os.path.relpath(host, kernel.modules_dir)))

    rootfs_programs = payload.rootfs_programs()
    programs = [src for src, _ in payload.programs + rootfs_programs]
    for src in programs:
        if not elf.is_elf(src):
            raise RigError(f"{src} is not an ELF program (use --file for data and scripts)")
    libs, loader = elf.resolve(programs, lib_dirs + TOOLCHAIN_LIBS)
    for soname, host in libs.items():
        tree.add_host(host, os.path.join("lib", soname))
    for guest, host in loader.items():
        tree.add_host(host, guest)
    for src, dest in payload.programs:
        tree.add(dest, "file", _stripped(src), 0o755)
    for root in payload.rootfs:  # as they are: the package's files, already stripped
        tree.add_host(root, "/")
    for src, dest in payload.files:
        tree.add_host(src, dest)
    if payload.script:
        tree.add_host(payload.script, "rig/test.sh")
    env = "".join(f"export {k}='{v}'\n" for k, v in sorted(payload.env.items()))
    tree.add("rig/env", "file", env.encode(), 0o644)

    buf = io.BytesIO()
    _tree.write(buf)
    data = buf.getvalue()
    if compress:
        data = gzip.compress(data, compresslevel=1)
    os.makedirs(os.path.dirname(os.path.abspath(out_path)), exist_ok=True)
    with open(out_path, "wb") as f:
        f.write(data)
    return (f"{len(data) / 1048576:.1f} MB{' gzip' if compress else ''}, {len(programs)} programs, "
            f"{len(libs)} libraries, {len(tree.entries)} entries")
