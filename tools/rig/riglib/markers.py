"""Parses the guest's console markers (written by tools/rig/guest/rig.sh) into test results,
timed on the host's clock as the lines arrive."""

import re

MARKER = re.compile(r"RIG-(INIT|BEGIN|PASS|FAIL|SKIP|NOTE|DONE)(?: ([^\s:]+)(?:: (.*))?)?")


class Test:
    def __init__(self, name, start):
        self.name, self.start, self.end = name, start, None
        self.status, self.reason = "RUNNING", ""
        self.notes = []

    @property
    def seconds(self):
        return (self.end or self.start) - self.start


class Results:
    def __init__(self):
        self.init_at = None        # host seconds since QEMU start when /init announced itself
        self.guest_uptime = None   # the guest kernel's uptime at that moment
        self.done_rc = None
        self.done_at = None
        self.tests = []            # in order of RIG-BEGIN
        self.errors = []           # protocol problems (a result without a begin, ...)

    @property
    def current(self):
        return self.tests[-1] if self.tests and self.tests[-1].status == "RUNNING" else None

    def feed(self, line, now):
        m = MARKER.search(line)
        if not m:
            return
        kind, name, reason = m.group(1), m.group(2), (m.group(3) or "").strip()
        if kind == "INIT":
            self.init_at = now
            try:
                self.guest_uptime = float(name)
            except (TypeError, ValueError):
                pass
        elif kind == "BEGIN":
            if self.current:
                self._finish(self.current, "FAIL", "no result before the next test began", now)
            self.tests.append(Test(name, now))
        elif kind in ("PASS", "FAIL", "SKIP"):
            test = self.current
            if not test or test.name != name:
                self.errors.append(f"RIG-{kind} {name} without RIG-BEGIN {name}")
                test = Test(name, now)
                self.tests.append(test)
            self._finish(test, kind, reason, now)
        elif kind == "NOTE":
            for t in reversed(self.tests):
                if t.name == name:
                    t.notes.append(reason)
                    break
        elif kind == "DONE":
            self.done_rc = int(name) if name and name.lstrip("-").isdigit() else -1
            self.done_at = now
            if self.current:
                self._finish(self.current, "FAIL", "no result before RIG-DONE", now)

    @staticmethod
    def _finish(test, status, reason, now):
        test.status, test.reason, test.end = status, reason, now

    def count(self, status):
        return sum(1 for t in self.tests if t.status == status)
