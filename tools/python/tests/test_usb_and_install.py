"""USB device selection (no device needed), source strings, a USB link with no board, and the
package installing offline from the repository the way its README says."""

import os
import shutil
import subprocess
import sys
import venv

import pytest

from conftest import REPO
from tlvlink_stream.transports import (LinkUnavailable, SerialLink, UsbCandidate, UsbLink, open_source,
                                       select_usb_device)


def board(serial, stream=True, accessible=True):
    return UsbCandidate(0x1D6B, 0x0104, serial, 1, 2, stream, accessible)


def test_selection_rules():
    assert select_usb_device([board("A")], 0x1D6B, 0x0104) == 0
    with pytest.raises(ValueError, match="2 boards match"):
        select_usb_device([board("A"), board("B")], 0x1D6B, 0x0104)
    assert select_usb_device([board("A"), board("B")], 0x1D6B, 0x0104, "B") == 1
    with pytest.raises(LinkUnavailable, match="no tlvlink stream interface"):
        select_usb_device([board("A", stream=False)], 0x1D6B, 0x0104)
    with pytest.raises(LinkUnavailable, match="no permission"):
        select_usb_device([board("A", accessible=False)], 0x1D6B, 0x0104)


def test_sources():
    s = open_source("serial:/dev/ttyACM0,baud=921600,flow=rtscts")
    assert isinstance(s, SerialLink) and (s.baud, s.rtscts) == (921600, True)
    u = open_source("usb:0c45:636d,serial=X")
    assert isinstance(u, UsbLink) and (u.vendor, u.product, u.serial) == (0x0C45, 0x636D, "X")
    assert open_source("usb").vendor == 0x1D6B
    for bad in ("tcp:1.2.3.4", "serial:", "serial:/dev/x,parity=even", "usb:12345", "usb:1d6b:0104,speed=high"):
        with pytest.raises(ValueError):
            open_source(bad)


def test_usb_link_without_a_board():
    with pytest.raises(LinkUnavailable):
        UsbLink(0x1D6B, 0x0104, "no-such-board").open()


def test_installs_offline_as_the_readme_says(tmp_path):
    env_dir = tmp_path / "venv"
    venv.EnvBuilder(system_site_packages=True, with_pip=True).create(env_dir)
    py = env_dir / "bin" / "python"
    # From a copy: setuptools builds in the source tree (build/, *.egg-info), which must stay clean.
    source = tmp_path / "python"
    shutil.copytree(REPO / "tools" / "python", source, ignore=shutil.ignore_patterns("build", "*.egg-info", "__pycache__"))
    subprocess.run([py, "-m", "pip", "install", "--quiet", "--no-build-isolation", "--no-index", str(source)],
                   check=True, cwd=tmp_path)
    out = subprocess.run([py, "-c", "import tlvlink_stream, serial; print(tlvlink_stream.__version__)"],
                         capture_output=True, text=True, check=True, cwd=tmp_path)
    assert out.stdout.strip() == "1.0.0"
    assert (env_dir / "bin" / "tlvlink-stream").exists()
