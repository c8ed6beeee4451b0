"""Fixed-step symplectic integration of a lattice with sampled mode energies."""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ._arrays import as_float_array, ptr
from ._errors import IntegrationError, check
from ._native import ffi, lib
from .lattice import Lattice, _real


def methods() -> list[str]:
    """Names of the fixed-step splitting schemes."""
    return [ffi.string(lib.fpl_splitting_name(lib.fpl_splitting_at(i))).decode()
            for i in range(lib.fpl_splitting_count())]


def _scheme(method: str):
    if not isinstance(method, str):
        raise TypeError(f"method must be a string, got {type(method).__name__}")
    out = ffi.new("const fpl_splitting **")
    check(lib.fpl_splitting_lookup(method.encode(), out))
    return out[0]


@dataclass
class Run:
    """Samples of one integration. `mode_energies[i, k-1]` is E_k at `t[i]`."""
    t: np.ndarray
    mode_energies: np.ndarray
    energy: np.ndarray
    states: np.ndarray | None
    lattice: Lattice
    method: str
    dt: float
    completed: bool = True
    message: str = ""
    y0: np.ndarray = field(default=None, repr=False)

    @property
    def relative_energy_error(self) -> np.ndarray:
        """|E(t) - E(0)| / |E(0)| at the samples (meaningful for the Hamiltonian models)."""
        e0 = self.lattice.energy(self.y0)
        return np.abs(self.energy - e0) / abs(e0)


def integrate(lattice: Lattice, t_end: float, *, dt: float = 0.01, sample_every: float | None = None,
              times=None, y0=None, method: str = "yoshida4", t0: float = 0.0,
              store_states: bool = False, on_failure: str = "raise") -> Run:
    """Integrate `lattice` from `y0` (default: the paper's mode-1 state, Eq. initxi) to t_end with a
    fixed-step splitting scheme, sampling at `times` or every `sample_every` (default: 1000
    intervals). The trajectory stays on the grid t0 + n dt; off-grid samples are exact.

    If the state becomes NaN/Inf (blow-up), on_failure="raise" raises IntegrationError whose
    `.result` holds the finite samples before it; "return" returns them with completed=False."""
    if not isinstance(lattice, Lattice):
        raise TypeError(f"lattice must be a fputlab.Lattice, got {type(lattice).__name__}")
    if on_failure not in ("raise", "return"):
        raise ValueError(f"on_failure must be 'raise' or 'return', got {on_failure!r}")
    scheme = _scheme(method)
    t0 = _real(t0, "t0")
    t_end = _real(t_end, "t_end")
    dt = _real(dt, "dt")
    if not (math.isfinite(t_end) and t_end >= t0):
        raise ValueError(f"t_end must be finite and >= t0 = {t0:g} (got {t_end:g})")
    if not (math.isfinite(dt) and dt > 0):
        raise ValueError(f"dt must be finite and > 0 (got {dt:g})")
    if times is not None:
        if sample_every is not None:
            raise ValueError("give either times or sample_every, not both")
        ts = as_float_array(times, "times")
        if ts.ndim != 1:
            raise ValueError(f"times has shape {ts.shape}, expected 1-D")
    else:
        every = (t_end - t0) / 1000 if sample_every is None else _real(sample_every, "sample_every")
        if t_end == t0:
            ts = np.array([t0])
        else:
            if not (math.isfinite(every) and every > 0):
                raise ValueError(f"sample_every must be finite and > 0 (got {every:g})")
            n = int(math.floor((t_end - t0) / every * (1 + 1e-12)))
            ts = t0 + every * np.arange(n + 1)
    N = lattice.N
    y0 = lattice.mode_state(1, 1.0) if y0 is None else as_float_array(y0, "y0", (2 * N,))
    S = ts.size
    ek = np.empty((S, N))
    en = np.empty(S)
    st = np.empty((S, 2 * N)) if store_states else None
    done = ffi.new("int *")
    status = lib.fpl_splitting_run(scheme, lattice._h, ptr(y0), t0, dt,
                                   ptr(ts) if S else ffi.NULL, S, ptr(ek) if S else ffi.NULL,
                                   ptr(en) if S else ffi.NULL,
                                   ptr(st) if store_states and S else ffi.NULL, done)
    k = done[0]
    run = Run(t=ts[:k].copy(), mode_energies=ek[:k].copy(), energy=en[:k].copy(),
              states=st[:k].copy() if store_states else None, lattice=lattice, method=method,
              dt=dt, completed=status >= 0, y0=y0.copy())
    if status < 0:
        try:
            lattice._check(status)
        except IntegrationError as err:
            run.message = str(err)
            if on_failure == "raise":
                err.result = run
                raise
            return run
    return run
