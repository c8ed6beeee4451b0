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


def last_error() -> str:
    return ffi.string(lib.fpl_last_error()).decode()


def check(status: int, handle_message=None) -> int:
    """Return a non-negative status; raise the matching exception for a negative one.
    `handle_message`: a callable giving the failing handle's own message (the fallback)."""
    if status >= 0:
        return status
    # The thread-local message is always set by the call that just failed in this thread.
    msg = last_error()
    if not msg and handle_message is not None:
        msg = handle_message()
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
