"""Debian's arm64 kernel for the rig: the image and a subset of its modules with a modules.dep,
prepared once per (kernel package version, module set) under ~/.cache/tlvlink/rig/kernels/."""

import glob
import hashlib
import os
import shutil
import subprocess
import tempfile

from . import debs
from .errors import RigError

# Named module groups; dependencies are added from each module's modinfo. Load order inside the
# guest comes from modules.dep (busybox modprobe), so only the top-level modules are named here.
MODULE_GROUPS = {
    "virtio": ["virtio_mmio", "virtio_console"],
    "9p": ["9pnet_virtio", "9p"],
    "v4l2": ["vivid"],
    "usb": ["dummy_hcd", "libcomposite", "usb_f_acm", "usb_f_fs", "usb_f_ss_lb", "cdc-acm"],
}
DEFAULT_GROUPS = ["virtio", "9p", "v4l2", "usb"]


class Kernel:
    def __init__(self, root, version, package):
        self.root = root            # contains vmlinuz and lib/modules/<version>
        self.version = version      # e.g. 6.1.0-56-arm64
        self.package = package      # e.g. linux-image-6.1.0-56-arm64 6.1.192-2
        self.image = os.path.join(root, "vmlinuz")
        self.modules_dir = os.path.join(root, "lib", "modules", version)


def _tool(name):
    for d in (None, "/usr/sbin", "/sbin"):
        path = shutil.which(name, path=d) if d else shutil.which(name)
        if path:
            return path
    raise RigError(f"'{name}' not found (Debian package kmod; tools/setup/install_deps.sh rig)")


def _norm(name):
    return name.replace("-", "_")


def _module_index(tree):
    index = {}
    for path in glob.glob(os.path.join(tree, "kernel", "**", "*.ko*"), recursive=True):
        index[_norm(os.path.basename(path).split(".ko")[0])] = path
    return index


def _closure(names, index, modinfo):
    """Every module needed to load `names`, resolved with modinfo's depends= field."""
    wanted, todo = {}, [_norm(n) for n in names]
    while todo:
        name = todo.pop()
        if name in wanted:
            continue
        if name not in index:
            raise RigError(f"kernel module '{name}' is not in this kernel package")
        wanted[name] = index[name]
        out = subprocess.run([modinfo, "-F", "depends", index[name]], check=True,
                             capture_output=True, text=True).stdout.strip()
        todo.extend(_norm(d) for d in out.split(",") if d)
    return wanted


def modules_for(groups):
    mods = []
    for g in groups:
        if g not in MODULE_GROUPS:
            raise RigError(f"unknown module group '{g}' (known: {', '.join(MODULE_GROUPS)})")
        mods.extend(MODULE_GROUPS[g])
    return mods


def prepare(modules, package=None, log=print):
    """The kernel image and the module subset (with dependencies and modules.dep)."""
    package = package or debs.kernel_package()
    version = debs.candidate(package)
    key = hashlib.sha256(" ".join(sorted(set(map(_norm, modules)))).encode()).hexdigest()[:10]
    kernels = os.path.join(debs.cache_root(), "kernels")
    dest = os.path.join(kernels, f"{package}_{version.replace(':', '_')}_{key}")
    stamp = os.path.join(dest, ".rig-stamp")
    if os.path.exists(stamp):
        kver = open(stamp).read().strip()
        return Kernel(dest, kver, f"{package} {version}")

    log(f"rig: preparing {package} {version} with {len(modules)} top-level modules")
    deb = debs.download(package, version)
    os.makedirs(kernels, exist_ok=True)
    work = tempfile.mkdtemp(prefix="prep-", dir=kernels)
    try:
        full = os.path.join(work, "full")
        debs.extract(deb, full)
        trees = glob.glob(os.path.join(full, "lib", "modules", "*"))
        images = glob.glob(os.path.join(full, "boot", "vmlinuz-*"))
        if len(trees) != 1 or len(images) != 1:
            raise RigError(f"unexpected layout in {os.path.basename(deb)} (modules: {trees}, images: {images})")
        kver = os.path.basename(trees[0])
        wanted = _closure(modules, _module_index(trees[0]), _tool("modinfo"))

        out = os.path.join(work, "out")
        out_tree = os.path.join(out, "lib", "modules", kver)
        os.makedirs(out_tree)
        shutil.copy2(images[0], os.path.join(out, "vmlinuz"))
        for f in ("modules.builtin", "modules.builtin.modinfo", "modules.order"):
            if os.path.exists(os.path.join(trees[0], f)):
                shutil.copy2(os.path.join(trees[0], f), out_tree)
        for path in wanted.values():
            rel = os.path.relpath(path, trees[0])
            os.makedirs(os.path.dirname(os.path.join(out_tree, rel)), exist_ok=True)
            shutil.copy2(path, os.path.join(out_tree, rel))
        # Debian's System.map is a stub: no -F (symbol versions are checked at load time anyway).
        subprocess.run([_tool("depmod"), "-b", out, kver], check=True, capture_output=True, text=True)
        with open(os.path.join(out, ".rig-stamp"), "w") as f:
            f.write(kver + "\n")
        try:
            os.rename(out, dest)
        except OSError:  # another rig run finished the same preparation first: use theirs
            if not os.path.exists(stamp):
                raise
    except subprocess.CalledProcessError as e:
        raise RigError(f"{' '.join(e.cmd)} failed: {e.stderr.strip()}")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    log(f"rig: kernel {kver}: {len(wanted)} modules in {dest}")
    return Kernel(dest, kver, f"{package} {version}")
