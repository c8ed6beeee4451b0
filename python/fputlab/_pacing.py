"""Segments of long C calls: how far the next call may go so that Python sees signals (Ctrl-C)
and updates progress bars about every 0.2 s."""
from __future__ import annotations

from ._lowlevel import DT


class Pacer:
    """How far (in units of t) the next C call may go so that it returns within about
    `seconds` of wall time (measured as the run goes): between calls Python sees signals, so
    Ctrl-C takes effect promptly. Pausing a fixed-step method between grid points changes
    nothing; adaptive methods are only paused where they stop anyway (samples)."""

    def __init__(self, first_span: float, seconds: float = 0.2):
        self.seconds, self._span = seconds, float(first_span)

    @property
    def span(self) -> float:
        return self._span

    def record(self, advanced: float, elapsed: float) -> None:
        if advanced > 0 and elapsed > 1e-4:
            want = advanced / elapsed * self.seconds
            self._span = min(max(want, self._span / 4), self._span * 4)   # smooth, no wild jumps


def first_span(dt: float | None, N: int, n_dev: int = 0) -> float:
    """A first segment of about 1e7 site-steps (~0.05 s) before the speed is measured."""
    return (dt or DT) * max(1.0, 1e7 / (N * (1 + n_dev)))
