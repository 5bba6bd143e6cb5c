"""Unit tests of the rig's host side that need no QEMU: console marker parsing and the newc
writer. Run: python3 tools/rig/test_riglib.py"""

import io
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from riglib import cpio  # noqa: E402
from riglib.markers import Results  # noqa: E402


class Markers(unittest.TestCase):
    def feed(self, lines):
        r = Results()
        for i, line in enumerate(lines):
            r.feed(line, float(i))
        return r

    def test_normal_run(self):
        r = self.feed(["[    1.0] booting", "RIG-INIT 1.50", "RIG-BEGIN a", "noise", "RIG-NOTE a: 3 fps",
                       "RIG-PASS a", "RIG-BEGIN b", "RIG-SKIP b: no camera here", "RIG-BEGIN c",
                       "RIG-FAIL c: exit status 1", "RIG-DONE 1"])
        self.assertEqual(r.init_at, 1.0)
        self.assertEqual(r.guest_uptime, 1.5)
        self.assertEqual([(t.name, t.status) for t in r.tests], [("a", "PASS"), ("b", "SKIP"), ("c", "FAIL")])
        self.assertEqual(r.tests[0].notes, ["3 fps"])
        self.assertEqual(r.tests[1].reason, "no camera here")
        self.assertEqual(r.tests[0].seconds, 3.0)
        self.assertEqual(r.done_rc, 1)
        self.assertEqual(r.errors, [])

    def test_marker_after_kernel_text_on_the_same_line(self):
        r = self.feed(["RIG-INIT 2", "[   3.2] vivid-000: disconnectRIG-BEGIN x", "RIG-PASS x", "RIG-DONE 0"])
        self.assertEqual([(t.name, t.status) for t in r.tests], [("x", "PASS")])

    def test_a_test_without_result_fails(self):
        r = self.feed(["RIG-INIT 1", "RIG-BEGIN a", "RIG-BEGIN b", "RIG-PASS b", "RIG-BEGIN c", "RIG-DONE 0"])
        self.assertEqual([t.status for t in r.tests], ["FAIL", "PASS", "FAIL"])
        self.assertIn("no result", r.tests[0].reason)

    def test_result_without_begin_is_a_protocol_error(self):
        r = self.feed(["RIG-INIT 1", "RIG-PASS ghost", "RIG-DONE 0"])
        self.assertEqual(len(r.errors), 1)
        self.assertEqual(r.count("PASS"), 1)

    def test_no_done(self):
        r = self.feed(["RIG-INIT 1", "RIG-BEGIN a"])
        self.assertIsNone(r.done_rc)
        self.assertEqual(r.current.name, "a")


def parse_newc(data):
    """(name, mode, size, rdevmajor, rdevminor, body) entries of a newc archive."""
    out, pos = [], 0
    while True:
        head = data[pos:pos + 110]
        assert head[:6] == b"070701", head[:6]
        f = [int(head[6 + 8 * i:14 + 8 * i], 16) for i in range(13)]
        namesize, size = f[11], f[6]
        name = data[pos + 110:pos + 110 + namesize - 1].decode()
        pos += 110 + namesize
        pos += (4 - pos % 4) % 4
        body = data[pos:pos + size]
        pos += size + (4 - size % 4) % 4
        if name == "TRAILER!!!":
            return out, pos
        out.append((name, f[1], size, f[9], f[10], body))


class Newc(unittest.TestCase):
    def test_round_trip(self):
        buf = io.BytesIO()
        w = cpio.Writer(buf)
        w.directory("dev")
        w.chardev("dev/console", 5, 1)
        w.file("init", b"#!/bin/sh\n", 0o755)
        w.file("odd", b"x" * 5)
        w.symlink("bin/sh", "busybox")
        w.finish()
        data = buf.getvalue()
        self.assertEqual(len(data) % 512, 0)
        entries, end = parse_newc(data)
        self.assertEqual([e[0] for e in entries], ["dev", "dev/console", "init", "odd", "bin/sh"])
        self.assertEqual(entries[1][1], 0o020600)
        self.assertEqual(entries[1][3:5], (5, 1))
        self.assertEqual(entries[2][5], b"#!/bin/sh\n")
        self.assertEqual(entries[2][1] & 0o777, 0o755)
        self.assertEqual(entries[3][5], b"xxxxx")
        self.assertEqual(entries[4][5], b"busybox")
        self.assertTrue(all(b == 0 for b in data[end:]))


if __name__ == "__main__":
    unittest.main()
