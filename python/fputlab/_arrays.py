"""Checked conversion of user arrays to C-contiguous float64 buffers for the C core."""
from __future__ import annotations

import os

import numpy as np

from ._native import ffi


def as_float_array(a, name: str, shape: tuple | None = None, *, last: int | None = None) -> np.ndarray:
    """Return `a` as a C-contiguous float64 array (a copy only if needed).

    Raises TypeError for non-real input (strings, objects, complex) and ValueError naming `name`
    for a wrong shape. `shape` fixes the whole shape; `last` only the length of the last axis."""
    arr = np.asarray(a)
    if arr.dtype.kind not in "fiub":
        raise TypeError(f"{name} must be a real numeric array, got dtype {arr.dtype}")
    arr = np.ascontiguousarray(arr, dtype=np.float64)
    if shape is not None and arr.shape != tuple(shape):
        raise ValueError(f"{name} has shape {arr.shape}, expected {tuple(shape)}")
    if last is not None and (arr.ndim == 0 or arr.shape[-1] != last):
        raise ValueError(f"{name} has shape {arr.shape}, expected last axis of length {last}")
    return arr


def available_memory() -> int | None:
    """Bytes of memory available to a new allocation (Linux MemAvailable; else physical memory);
    None if unknown."""
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return None


def _gb(n: float) -> str:
    return f"{n / 1e9:.3g} GB" if n >= 1e8 else f"{n / 1e6:.3g} MB"


def check_memory(nbytes: float, what: str) -> None:
    """Refuse (MemoryError naming `what` and the bytes) what cannot fit in the memory available,
    before anything is allocated: the kernel's OOM killer gives no message at all."""
    avail = available_memory()
    if avail is not None and nbytes > avail:
        raise MemoryError(f"{what} needs about {_gb(nbytes)} ({nbytes:.3g} bytes), more than the "
                          f"{_gb(avail)} of memory available")


def ptr(arr: np.ndarray):
    """double* view of a C-contiguous float64 array (no copy)."""
    if arr.dtype != np.float64 or not arr.flags.c_contiguous:
        raise TypeError("internal: buffer must be C-contiguous float64")
    return ffi.cast("double *", ffi.from_buffer(arr))
