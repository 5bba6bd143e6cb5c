"""Host half of the rig.host_cmd self-test: sends "ping" to the guest over the virtio-serial port
handed over in RIG_PORT_RIG_CTRL and writes the reply to $RIG_OUT/ping.txt."""

import os
import socket
import sys
import time

deadline = time.monotonic() + 60
s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
while True:
    try:
        s.connect(os.environ["RIG_PORT_RIG_CTRL"])
        break
    except OSError:
        if time.monotonic() > deadline:
            sys.exit("ping: cannot connect to the guest's port")
        time.sleep(0.05)
s.sendall(b"ping\n")
s.settimeout(60)
reply = b""
while not reply.endswith(b"\n"):
    chunk = s.recv(64)
    if not chunk:
        break
    reply += chunk
with open(os.path.join(os.environ["RIG_OUT"], "ping.txt"), "wb") as f:
    f.write(reply)
