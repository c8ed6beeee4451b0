"""One place where C status codes become Python exceptions carrying the C message."""
from __future__ import annotations

from ._native import ffi, lib


class FputlabError(RuntimeError):
    """A failure reported by the C core that is not a bad argument."""

    def __init__(self, message: str, status: int):
        super().__init__(message)
        self.status = status


class IntegrationError(FputlabError):
    """The state became NaN/Inf (a blow-up, or a step too large). `result` holds every sample
    taken before the failure (all finite)."""

    def __init__(self, message: str, status: int, result=None):
        super().__init__(message, status)
        self.result = result


class Interrupted(KeyboardInterrupt):
    """Ctrl-C (SIGINT) during a long computation. Long C calls run in short segments, so this
    comes within a fraction of a second; `result` holds what was computed until then (a Run,
    ChaosResult or Blowup, marked not completed)."""

    def __init__(self, message: str, result=None):
        super().__init__(message)
        self.result = result


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
    return (dt or 0.01) * max(1.0, 1e7 / (N * (1 + n_dev)))


def last_error() -> str:
    return ffi.string(lib.fpl_last_error()).decode()


def check(status: int, handle=None) -> int:
    """Return a non-negative status; raise the matching exception for a negative one."""
    if status >= 0:
        return status
    # The thread-local message is always set by the call that just failed in this thread.
    msg = last_error()
    if not msg and handle is not None:
        msg = ffi.string(lib.fpl_lattice_errmsg(handle)).decode()
    msg = msg or ffi.string(lib.fpl_status_name(status)).decode()
    if status in (lib.FPL_ERR_ARG, lib.FPL_ERR_UNKNOWN):
        raise ValueError(msg)
    if status == lib.FPL_ERR_NOMEM:
        raise MemoryError(msg)
    if status == lib.FPL_ERR_NONFINITE:
        raise IntegrationError(msg, status)
    if status == lib.FPL_ERR_IO:
        raise OSError(msg)
    raise FputlabError(msg, status)
