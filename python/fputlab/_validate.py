"""Checked conversion of scalar arguments (the shared validation of every module): a wrong type
is a TypeError, a value out of range a ValueError, and both name the parameter."""
from __future__ import annotations

import math
import os

import numpy as np

#: ranges of C integer parameters
C_INT = (-2**31, 2**31 - 1)
C_LONG = (-2**63, 2**63 - 1)
C_U64 = (-2**63, 2**64 - 1)     # seeds (negative values get their own "must be >= 0" errors)


def _path(value, name: str) -> str:
    """A file-name parameter (str, bytes or path-like) as str. Refused: other types, the empty
    name, and a NUL byte (C would end the name there and write another file)."""
    if not isinstance(value, (str, bytes, os.PathLike)):
        raise TypeError(f"{name} must be a file name (str, bytes or path-like), got "
                        f"{type(value).__name__}")
    path = os.fsdecode(os.fspath(value))
    if "\0" in path:
        raise ValueError(f"{name}: the file name {path!r} contains a NUL byte")
    if not path:
        raise ValueError(f"{name}: empty file name")
    return path


def _real(value, name: str) -> float:
    """A real-number parameter as a float (bools, non-numbers and numpy times refused)."""
    if isinstance(value, (bool, np.timedelta64, np.datetime64)) or \
            not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a real number, got {type(value).__name__}")
    return float(value)


def _finite_real(value, name: str) -> float:
    """A real-number parameter that must be finite."""
    x = _real(value, name)
    if not math.isfinite(x):
        raise ValueError(f"{name} must be finite (got {x})")
    return x


def _positive_real(value, name: str) -> float:
    """A real-number parameter that must be finite and > 0 (times, steps, intervals)."""
    x = _real(value, name)
    if not (math.isfinite(x) and x > 0):
        raise ValueError(f"{name} must be finite and > 0 (got {x:g})")
    return x


def _size(value, name: str = "N") -> int:
    """A lattice size: an integer >= 2 (the smallest chain with two modes)."""
    value = _int(value, name)
    if value < 2:
        raise ValueError(f"{name} must be >= 2 (got {value})")
    return value


def _seed(value, name: str = "seed") -> int:
    """A random seed: an integer in [0, 2**64) (the C seeds are unsigned 64-bit)."""
    value = _int(value, name, C_U64)
    if value < 0:
        raise ValueError(f"{name} must be >= 0 (got {value})")
    return value


def _int(value, name: str, bounds: tuple = C_INT) -> int:
    """An integer parameter, checked against the range of the C type it goes to (int by
    default): out of range is a ValueError naming it, not cffi's anonymous OverflowError."""
    if isinstance(value, (bool, np.timedelta64, np.datetime64)) or \
            not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an integer, got {type(value).__name__}")
    value = int(value)
    lo, hi = bounds
    if not lo <= value <= hi:
        raise ValueError(f"{name} = {value} is out of range (it must lie in [{lo}, {hi}])")
    return value


def _renamed(value, old_value, name: str, old: str):
    """One name per idea: `old` is the deprecated spelling of `name`; given, it warns
    (DeprecationWarning, for one release) and its value is used."""
    if old_value is None:
        return value
    import warnings
    warnings.warn(f"{old} is deprecated: use {name}", DeprecationWarning, stacklevel=3)
    return old_value
