"""The shared libraries an arm64 program needs, found in the cross toolchain and the sysroot,
so the initramfs carries exactly what its programs load (there is no ld.so.cache in the guest)."""

import os
import re
import subprocess

from .errors import RigError

READELF = "aarch64-linux-gnu-readelf"


def _readelf(args, path):
    try:
        return subprocess.run([READELF, *args, path], check=True, capture_output=True, text=True).stdout
    except FileNotFoundError:
        raise RigError(f"{READELF} not found (Debian package binutils-aarch64-linux-gnu, "
                       "installed with g++-aarch64-linux-gnu)")
    except subprocess.CalledProcessError as e:
        raise RigError(f"{path}: not an ELF file readelf understands: {e.stderr.strip()}")


def is_elf(path):
    with open(path, "rb") as f:
        return f.read(4) == b"\x7fELF"


def machine(path):
    m = re.search(r"Machine:\s+(.*)", _readelf(["-h"], path))
    return m.group(1).strip() if m else "?"


def needed(path):
    return re.findall(r"\(NEEDED\)\s+Shared library: \[([^\]]+)\]", _readelf(["-d"], path))


def interpreter(path):
    m = re.search(r"Requesting program interpreter: ([^\]]+)\]", _readelf(["-l"], path))
    return m.group(1) if m else None


def resolve(programs, search_dirs):
    """{soname: host path} of every library the programs load, transitively, plus the dynamic
    loader {'/lib/ld-linux-aarch64.so.1': host path} if any program is dynamically linked."""
    libs, todo, loader = {}, list(programs), {}
    while todo:
        path = todo.pop()
        if "AArch64" not in machine(path):
            raise RigError(f"{path} is not an arm64 program (machine: {machine(path)})")
        interp = interpreter(path) if path in programs else None
        if interp and interp not in loader:
            found = _find(os.path.basename(interp), search_dirs)
            if not found:
                raise RigError(f"{path}: dynamic loader {interp} not found in {search_dirs}")
            loader[interp] = found
        for soname in needed(path):
            if soname in libs:
                continue
            found = _find(soname, search_dirs)
            if not found:
                raise RigError(f"{path} needs {soname}, not found in: {', '.join(search_dirs)}")
            libs[soname] = found
            todo.append(found)
    return libs, loader


def _find(soname, dirs):
    for d in dirs:
        candidate = os.path.join(d, soname)
        if os.path.exists(candidate):
            return os.path.realpath(candidate)
    return None
