"""The rig's report: one line per test with its time, boot and total times, and the guest's
console log when anything failed."""


def _tail(path, lines):
    with open(path, "rb") as f:
        text = f.read().decode(errors="replace").splitlines()
    return text[-lines:], len(text)


def print_report(results, seconds, console, note, cfg, log_lines=300):
    """Prints the report; returns the exit status (0 all passed or skipped, 1 otherwise)."""
    r = results
    if r.init_at is not None:
        up = f" (guest kernel uptime {r.guest_uptime:.2f}s)" if r.guest_uptime is not None else ""
        print(f"rig: boot to init {r.init_at:.1f}s{up}")
    for t in r.tests:
        reason = f": {t.reason}" if t.reason and t.status != "PASS" else ""
        print(f"  {t.status:<7} {t.name}  {t.seconds:.2f}s{reason}")
        for text in t.notes:
            print(f"            {text}")
    for e in r.errors:
        print(f"rig: marker problem: {e}")
    passed, failed, skipped = r.count("PASS"), r.count("FAIL") + r.count("RUNNING"), r.count("SKIP")
    tests_s = (r.tests[-1].end or seconds) - r.tests[0].start if r.tests else 0.0
    problems = []
    if note:
        problems.append(note)
    if r.done_rc is None and not note:
        problems.append("the guest never printed RIG-DONE")
    elif r.done_rc not in (None, 0):
        problems.append(f"the test script ended with status {r.done_rc}")
    if not r.tests:
        problems.append("no tests ran")
    ok = not problems and failed == 0 and not r.errors
    print(f"rig: tests {passed} passed, {failed} failed, {skipped} skipped; tests {tests_s:.1f}s, "
          f"total {seconds:.1f}s (qemu-system-aarch64 -M virt -cpu {cfg.cpu} -smp {cfg.smp}, TCG)")
    for p in problems:
        print(f"rig: FAIL: {p}")
    if not ok:
        tail, total = _tail(console, log_lines)
        print(f"rig: guest console (last {len(tail)} of {total} lines; full log {console}):")
        for line in tail:
            print(f"  | {line}")
    print("rig: PASS" if ok else "rig: FAIL")
    return 0 if ok else 1
