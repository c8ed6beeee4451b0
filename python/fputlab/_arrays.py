"""Checked conversion of user arrays to C-contiguous float64 buffers for the C core."""
from __future__ import annotations

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


def ptr(arr: np.ndarray):
    """double* view of a C-contiguous float64 array (no copy)."""
    if arr.dtype != np.float64 or not arr.flags.c_contiguous:
        raise TypeError("internal: buffer must be C-contiguous float64")
    return ffi.cast("double *", ffi.from_buffer(arr))
