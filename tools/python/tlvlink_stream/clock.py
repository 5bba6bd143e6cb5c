"""The board's clock offset from Ping/TimeSync exchanges (runtime/protocol/README.md "Clock
offset"; the same algorithm as tlvlink/protocol/clock.h): t1 host send, t2 board receive,
t3 board send, t4 host receive; offset = ((t2 - t1) + (t3 - t4)) / 2, delay = (t4 - t1) - (t3 - t2);
the least-delayed of the last 8 exchanges wins; its bound is delay/2 plus 100 ppm of its age."""

from __future__ import annotations

from dataclasses import dataclass
from typing import List, Tuple

WINDOW = 8
DRIFT_PPM = 100


def _half(v: int) -> int:
    """Integer division truncating toward zero, as C++ does."""
    return -((-v) // 2) if v < 0 else v // 2


@dataclass
class ClockEstimate:
    valid: bool = False
    offset_ns: int = 0       # board clock - host clock
    uncertainty_ns: int = 0
    delay_ns: int = 0
    samples: int = 0


class ClockSync:
    """A ring of the last WINDOW exchanges, as the C++ ClockSync keeps them (ties between equally
    delayed exchanges resolve the same way)."""

    def __init__(self) -> None:
        self.reset()

    def add(self, t1: int, t2: int, t3: int, t4: int) -> bool:
        if t4 < t1 or t3 < t2:
            return False
        delay = (t4 - t1) - (t3 - t2)
        if delay < 0:
            return False
        self._slots[self._next] = (_half(t2 - t1) + _half(t3 - t4), delay, t4)
        self._next = (self._next + 1) % WINDOW
        self._count = min(self._count + 1, WINDOW)
        return True

    def _best(self):
        best = None
        for i in range(self._count):
            if best is None or self._slots[i][1] < best[1]:
                best = self._slots[i]
        return best

    def estimate(self, now_ns: int) -> ClockEstimate:
        b = self._best()
        if b is None:
            return ClockEstimate()
        offset, delay, t4 = b
        age = now_ns - t4 if now_ns > t4 else 0
        return ClockEstimate(True, offset, delay // 2 + 1 + age // 1_000_000 * DRIFT_PPM, delay, self._count)

    def board_to_host(self, board_ns: int) -> int:
        b = self._best()
        return board_ns - b[0] if b else board_ns

    def host_to_board(self, host_ns: int) -> int:
        b = self._best()
        return host_ns + b[0] if b else host_ns

    def reset(self) -> None:
        self._slots: List[Tuple[int, int, int]] = [(0, 0, 0)] * WINDOW
        self._next = 0
        self._count = 0
