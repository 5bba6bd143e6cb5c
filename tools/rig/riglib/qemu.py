"""Boots the rig under qemu-system-aarch64 (virt machine, TCG), watches the console for markers
with bounded waits, records the virtio-serial ports, and always ends QEMU by its own PID."""

import ctypes
import os
import select
import shutil
import signal
import socket
import subprocess
import tempfile
import time

from .errors import RigError
from .markers import Results


class RunConfig:
    def __init__(self):
        self.kernel = None          # riglib.kernel.Kernel
        self.initrd = None          # path of the initramfs
        self.cpu = "cortex-a76"     # or cortex-a72 (Pi 4: no dot product)
        self.smp = 2
        self.mem_mb = 1024
        self.append = []            # extra kernel command line words
        self.ports = ["rig.data"]   # virtio-serial ports; each recorded to <out>/<name>.bin
        self.host_ports = []        # ports left to a --host-cmd (not recorded)
        self.host_cmd = None        # runs beside QEMU with RIG_PORT_<NAME>=socket in its env
        self.share = None           # host directory mounted in the guest at /mnt/host (9p)
        self.boot_timeout = 60      # seconds until RIG-INIT
        self.test_timeout = 180     # seconds one test may run (RIG-BEGIN to its result)
        self.total_timeout = 900    # seconds for the whole run
        self.out = "build/rig"
        self.interactive = False


def command(cfg, sockdir):
    append = ["console=ttyAMA0", "panic=-1", "loglevel=4",
              "rig.mode=shell" if cfg.interactive else "rig.mode=auto"]
    if cfg.share:
        append.append("rig.share=1")
    cmd = ["qemu-system-aarch64", "-M", "virt", "-cpu", cfg.cpu, "-accel", "tcg",
           "-smp", str(cfg.smp), "-m", str(cfg.mem_mb), "-nographic", "-no-reboot", "-nic", "none",
           "-kernel", cfg.kernel.image, "-initrd", cfg.initrd,
           "-append", " ".join(append + cfg.append), "-device", "virtio-serial-device"]
    for i, name in enumerate(cfg.ports + cfg.host_ports):
        path = os.path.join(sockdir, f"p{i}.sock")
        cmd += ["-chardev", f"socket,id=port{i},path={path},server=on,wait=off",
                "-device", f"virtserialport,chardev=port{i},name={name}"]
    if cfg.share:
        cmd += ["-fsdev", f"local,id=fs0,path={os.path.abspath(cfg.share)},security_model=none",
                "-device", "virtio-9p-device,fsdev=fs0,mount_tag=host0"]
    if not cfg.interactive:
        cmd[cmd.index("-nographic") + 1:cmd.index("-nographic") + 1] = ["-monitor", "none"]
    return cmd


def _connect(path, deadline):
    while time.monotonic() < deadline:
        if os.path.exists(path):
            s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
            try:
                s.connect(path)
                s.setblocking(False)
                return s
            except OSError:
                s.close()
        time.sleep(0.02)
    raise RigError(f"QEMU did not create {path}")


def _die_with_parent():
    """In the child before exec: QEMU gets SIGKILL if the runner dies without cleaning up."""
    PR_SET_PDEATHSIG = 1
    ctypes.CDLL(None, use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGKILL)


def _stop(proc):
    """Ends this QEMU only: SIGTERM to its PID, SIGKILL if it has not exited within 5 s."""
    if proc.poll() is None:
        proc.send_signal(signal.SIGTERM)
        try:
            proc.wait(timeout=5)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


def interactive(cfg):
    if not shutil.which("qemu-system-aarch64"):
        raise RigError("qemu-system-aarch64 not found (Debian package qemu-system-arm)")
    with tempfile.TemporaryDirectory(prefix="tlvrig-") as sockdir:
        return subprocess.call(command(cfg, sockdir))


def run(cfg, log=print):
    """Boots, runs the guest's tests, returns (Results, seconds, console log path, note)."""
    if not shutil.which("qemu-system-aarch64"):
        raise RigError("qemu-system-aarch64 not found (Debian package qemu-system-arm; "
                       "tools/setup/install_deps.sh rig)")
    os.makedirs(cfg.out, exist_ok=True)
    console_path = os.path.join(cfg.out, "console.log")
    results, note = Results(), ""
    # Unix socket paths are limited to 108 bytes: keep them in a short temporary directory.
    sockdir = tempfile.mkdtemp(prefix="tlvrig-")
    proc = helper = None
    t0 = time.monotonic()
    try:
        cmd = command(cfg, sockdir)
        with open(os.path.join(cfg.out, "qemu-command.txt"), "w") as f:
            f.write(" ".join(cmd) + "\n")
        proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                stderr=subprocess.STDOUT, start_new_session=True,
                                preexec_fn=_die_with_parent)
        socks = {}
        for i, name in enumerate(cfg.ports):
            s = _connect(os.path.join(sockdir, f"p{i}.sock"), t0 + 10)
            socks[s] = open(os.path.join(cfg.out, f"{name}.bin"), "wb")
        if cfg.host_cmd:
            env = dict(os.environ)
            for j, name in enumerate(cfg.host_ports):
                env["RIG_PORT_" + name.upper().replace(".", "_").replace("-", "_")] = \
                    os.path.join(sockdir, f"p{len(cfg.ports) + j}.sock")
            helper = subprocess.Popen(cfg.host_cmd, shell=True, env=env, start_new_session=True,
                                      preexec_fn=_die_with_parent)
        note = _watch(proc, socks, console_path, results, cfg, t0)
        for f in socks.values():
            f.close()
    finally:
        if proc:
            _stop(proc)
        if helper:
            _stop(helper)
            if helper.returncode not in (0, -signal.SIGTERM) and not note:
                note = f"host command exited with status {helper.returncode}"
        shutil.rmtree(sockdir, ignore_errors=True)
    return results, time.monotonic() - t0, console_path, note


def _watch(proc, socks, console_path, results, cfg, t0):
    """Reads console and ports until QEMU exits or a bound is hit; returns a note on a bound."""
    fd = proc.stdout.fileno()
    os.set_blocking(fd, False)
    pending = b""
    with open(console_path, "wb") as console:
        while True:
            now = time.monotonic() - t0
            if results.init_at is None and now > cfg.boot_timeout:
                return f"no RIG-INIT within {cfg.boot_timeout}s (kernel or init did not start)"
            cur = results.current
            if cur and now - cur.start > cfg.test_timeout:
                results._finish(cur, "FAIL", f"no result within {cfg.test_timeout}s", now)
                return f"test {cur.name} ran longer than {cfg.test_timeout}s"
            if now > cfg.total_timeout:
                return f"the run took longer than {cfg.total_timeout}s"
            if results.done_at is not None and now - results.done_at > 15:
                return "QEMU did not power off within 15s of RIG-DONE"
            ready, _, _ = select.select([fd] + list(socks), [], [], 0.2)
            for r in ready:
                if r in socks:
                    try:
                        data = r.recv(65536)
                    except BlockingIOError:
                        continue
                    if data:
                        socks[r].write(data)
                    else:  # the guest closed the port
                        socks.pop(r).close()
                        r.close()
                    continue
                try:
                    data = os.read(fd, 65536)
                except BlockingIOError:
                    continue
                if not data:  # QEMU exited
                    if pending:
                        results.feed(pending.decode(errors="replace"), time.monotonic() - t0)
                    proc.wait()
                    return ""
                console.write(data)
                console.flush()
                pending += data
                *lines, pending = pending.split(b"\n")
                for line in lines:
                    results.feed(line.decode(errors="replace").rstrip("\r"), time.monotonic() - t0)
