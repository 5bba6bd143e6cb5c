"""Debian arm64 packages for the rig: resolved with apt-cache, fetched with `apt-get download`
into a cache directory and unpacked with `dpkg-deb -x`. Nothing is installed into the host."""

import os
import shutil
import subprocess

from .errors import RigError


def cache_root():
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(base, "tlvlink", "rig")


def _run(cmd, what):
    try:
        return subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    except FileNotFoundError:
        raise RigError(f"{what}: '{cmd[0]}' not found (tools/setup/install_deps.sh rig installs it)")
    except subprocess.CalledProcessError as e:
        raise RigError(f"{what} failed: {' '.join(cmd)}\n{e.stderr.strip()}")


def candidate(package):
    """The candidate version of an arm64 package, e.g. ('busybox-static', '1:1.35.0-4+deb12u1+b1')."""
    out = _run(["apt-cache", "policy", f"{package}:arm64"], f"apt-cache policy {package}:arm64")
    for line in out.splitlines():
        line = line.strip()
        if line.startswith("Candidate:"):
            version = line.split(":", 1)[1].strip()
            if version and version != "(none)":
                return version
    raise RigError(f"no arm64 candidate for '{package}': run `dpkg --add-architecture arm64 && "
                   f"apt-get update` (tools/setup/install_deps.sh rig does this)")


def kernel_package():
    """The arm64 kernel image package the linux-image-arm64 metapackage currently points to."""
    out = _run(["apt-cache", "depends", "linux-image-arm64:arm64"], "apt-cache depends linux-image-arm64")
    for line in out.splitlines():
        line = line.strip()
        if line.startswith("Depends:") and "linux-image-" in line:
            return line.split(":", 1)[1].strip().split(":")[0]
    raise RigError("cannot tell which kernel linux-image-arm64:arm64 depends on")


def download(package, version=None):
    """Path of the cached .deb of package:arm64 (downloaded if missing)."""
    version = version or candidate(package)
    debs = os.path.join(cache_root(), "debs")
    os.makedirs(debs, exist_ok=True)
    name = f"{package}_{version.replace(':', '%3a')}_arm64.deb"
    path = os.path.join(debs, name)
    if os.path.exists(path):
        return path
    cmd = ["apt-get", "download", "-q", f"{package}:arm64={version}"]
    if os.geteuid() == 0:  # as root apt drops to _apt, which cannot write our cache
        cmd[2:2] = ["-o", "APT::Sandbox::User=root"]
    try:
        subprocess.run(cmd, check=True, cwd=debs, capture_output=True, text=True)
    except subprocess.CalledProcessError as e:
        raise RigError(f"apt-get download {package}:arm64={version} failed:\n{e.stderr.strip()}")
    if not os.path.exists(path):
        raise RigError(f"apt-get download did not produce {path}")
    return path


def extract(deb, dest):
    """Unpacks a .deb into dest (created; an existing dest is replaced)."""
    if os.path.exists(dest):
        shutil.rmtree(dest)
    os.makedirs(dest)
    _run(["dpkg-deb", "-x", deb, dest], f"dpkg-deb -x {os.path.basename(deb)}")
