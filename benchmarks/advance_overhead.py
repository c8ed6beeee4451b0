"""Per-call cost of `Integrator.advance` and where it goes (issue 22, item 4).

N = 16, yoshida4, no deviation vectors. `advance(t)` to the current time (no step: the pure
overhead of one call) is split into its parts: the C call alone through cffi with a ready pointer,
the copy of the returned state, `_validate._real`, and, for comparison, the path before issue 22
(a fresh `np.empty` output, its pointer made by `ffi.from_buffer` + `ffi.cast` on every call, and
`_real`'s isinstance checks). Also `advance` by one step (dt = 0.01) per call. Cost = process CPU
time per call, best of 15 repeats of 50,000 calls (wall time on a loaded machine counts other
processes too). Usage: python benchmarks/advance_overhead.py
"""
from __future__ import annotations

import time
import timeit

import numpy as np

import fputlab
from fputlab._native import lib
from fputlab._validate import _real


def _real_before(value, name):
    """`_validate._real` before issue 22 (isinstance checks first)."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a real number")
    return float(value)


def main() -> None:
    lat = fputlab.Lattice(16)
    y0 = lat.mode_state(1, 1.0)
    at_rest = fputlab.Integrator(lat, y0, method="yoshida4")
    h = at_rest._h
    shape = at_rest._shape
    buffer, pointer, handle_ptr = h._out, h._out_ptr, h.ptr

    def advance():
        at_rest.advance(0.0)

    def c_call():
        lib.fpl_integrator_advance(handle_ptr, 0.0, pointer)

    def copy():
        buffer.copy()

    def validate():
        _real(0.0, "t")

    def before():
        y = np.empty(shape)
        h.advance(_real_before(0.0, "t"), y)

    stepping = fputlab.Integrator(lat, y0, method="yoshida4")
    t = [0.0]

    def one_step():
        t[0] += 0.01
        stepping.advance(t[0])

    print(f"fputlab {fputlab.__version__}, load average {open('/proc/loadavg').read().split()[:3]}")
    for name, f in (("Integrator.advance (no step)", advance), ("  C call via cffi", c_call),
                    ("  copy of the state", copy), ("  _validate._real", validate),
                    ("before issue 22 (no step)", before), ("Integrator.advance (1 step)", one_step)):
        n = 50_000
        best = min(timeit.repeat(f, number=n, repeat=15, timer=time.process_time)) / n
        print(f"{name:32s} {best * 1e6:7.3f} us")


if __name__ == "__main__":
    main()
