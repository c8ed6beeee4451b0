"""Sampled runs as a study: the "run" study kind.

Per (N, tau, seed) the paper's mode-1 state (Eq. initxi, as `fputlab.integrate` starts by
default) is integrated and the normal-mode energies E_k(t) and the total energy E(t) are sampled
every `sample_every`, at t = 0, sample_every, 2 sample_every, ... up to t_end. A run that crosses
the potential barrier (a bond stretched past it, `Lattice.barrier`) or becomes non-finite stops
there and counts as a blow-up. A run that has not stopped keeps its integrator state
(steps, t, y), so a larger t_end continues it: its samples are those of one run straight to the
larger t_end, bit for bit for the fixed-step methods.

    >>> from fputlab.engine import run_study
    >>> r = run_study("run", {"N": [32], "tau": [0.0, 10.0], "seed": [1, 2]},
    ...               {"sample_every": 10.0}, 1e3)                     # doctest: +SKIP
    >>> r.to_xarray()["E"].sel(mode=1)                                 # doctest: +SKIP
"""
from __future__ import annotations

import math
import time

import numpy as np

from . import _lowlevel as ll
from ._errors import FputlabError
from ._validate import _real
from .engine import DISORDER_COORD_ATTRS, StudyKind, fraction_rows, normalise_disorder
from .integrate import Integrator, method_info
from .lattice import Lattice

__all__ = ["RUN_KIND", "RunKind", "sampled_run"]

#: settings of "run" studies and their defaults (dt: C's fixed step, None for adaptive methods;
#: rtol/atol: C's; n_modes None: every mode of the largest N)
_SETTINGS = {"model": "nonlinear", "alpha": 0.25, "method": "yoshida4", "dt": None,
             "rtol": ll.RTOL, "atol": ll.ATOL, "sample_every": None, "n_modes": None}


def n_sample_times(t_end: float, every: float) -> int:
    """How many samples 0, every, 2 every, ... lie in [0, t_end] (a rounding of 1e-9 of a
    sample spacing forgiven)."""
    return int(math.floor(t_end / every + 1e-9)) + 1


def _stops(lat: Lattice) -> list:
    """The barrier criterion of the lattice (none without a barrier)."""
    lower, upper = lat.barrier
    if math.isfinite(lower) or math.isfinite(upper):
        return [("stretch", min(-lower, upper))]
    return []


def sampled_run(settings: dict, N: int, tau: float, seed: int, prev, t_end: float,
                n_modes: int | None = None) -> dict:
    """One task of the "run" kind (and of kinds built on it, `fputlab.recurrence`): the samples
    up to t_end from the start, or from `prev`'s state. Returns the engine's report with values
    E (samples x n_modes, NaN-padded), energy, t_reached (t_end, or the last sample before a
    blow-up), blew_up, message;
    the state is kept unless the run stopped."""
    cpu0 = time.process_time()
    model = settings["model"]
    lat = Lattice(N, settings["alpha"], model=model, tau=tau if model != "homogeneous" else 0.0,
                  seed=seed)
    every = settings["sample_every"]
    n = n_sample_times(t_end, every)
    M = N if n_modes is None else n_modes
    E = np.full((n, M), np.nan)
    energy = np.full(n, np.nan)
    k0 = 0
    if prev is not None and prev.get("state") is not None:
        old_E = np.asarray(prev["values"]["E"], float)
        old_en = np.asarray(prev["values"]["energy"], float)
        k0 = int(np.sum(np.isfinite(old_en)))
        E[:k0], energy[:k0] = old_E[:k0, :M], old_en[:k0]
    integ = Integrator(lat, lat.mode_state(1, 1.0), method=settings["method"],
                       dt=settings["dt"], rtol=settings["rtol"], atol=settings["atol"],
                       criteria=_stops(lat) or None)
    if k0:
        st = prev["state"]
        integ.restore(int(st["steps"]), float(st["t"]), np.asarray(st["y"], float)[None, :])
    ts = every * np.arange(k0, n)
    message, failed = "", False
    k = 0
    if ts.size:
        try:
            k, _, ek, en = integ.sample(ts)
        except FputlabError as err:         # NaN/Inf, or a back end giving up: a blow-up
            if not hasattr(err, "partial"):
                raise
            k, _, ek, en = err.partial
            message, failed = str(err), True
        m = min(M, ek.shape[1])
        E[k0:k0 + k, :m] = ek[:k, :m]
        energy[k0:k0 + k] = en[:k]
    stopped = failed or integ.event is not None
    last = k0 + k
    t_reached = (float(every * (last - 1)) if last else 0.0) if stopped else float(t_end)
    values = {"E": E, "energy": energy, "t_reached": t_reached, "blew_up": bool(stopped),
              "message": message}
    state = None if stopped else {"steps": np.int64(integ.steps), "t": np.float64(integ.t),
                                  "y": integ.state[0]}
    return {"t": float(t_end), "done": bool(stopped), "message": message,
            "cpu": time.process_time() - cpu0, "values": values, "state": state}


class RunKind(StudyKind):
    """Mode energies E_k(t) and the energy E(t) of the paper's mode-1 state per (N, tau, seed),
    sampled every `sample_every` to t_end; a blow-up ends a run; a larger t_end continues
    every run from its saved state (see the module docstring)."""
    name = "run"
    version = 1
    resumable = True
    dims = ("N", "tau", "seed")
    variables = {
        "E": (("sample", "mode"), float, "1", "energy E_k of normal mode k"),
        "energy": (("sample",), float, "1", "total energy"),
        "t_reached": ((), float, "1", "time reached: t_end, or the last sample before a "
                                      "blow-up"),
        "blew_up": ((), bool, "", "the run crossed the potential barrier or became "
                                  "non-finite"),
        "message": ((), str, "", "how the run ended"),
    }
    coord_attrs = {**DISORDER_COORD_ATTRS,
                   "t": {"long_name": "sample time", "units": "1"},
                   "mode": {"long_name": "normal mode k", "units": "1"}}

    def normalise(self, grid, settings):
        grid, s = normalise_disorder(grid, settings, _SETTINGS, "run")
        if not isinstance(s["method"], str):
            raise ValueError(f"method must be a string (got {s['method']!r})")
        adaptive = method_info(s["method"])["adaptive"]        # names an unknown method
        if s["sample_every"] is None:
            raise ValueError("sample_every: run studies need the sampling interval")
        if s["dt"] is None and not adaptive:
            s["dt"] = ll.DT
        s["alpha"] = _real(s["alpha"], "alpha")
        for name in ("sample_every", "dt", "rtol", "atol"):
            if s[name] is not None:
                s[name] = _real(s[name], name)
                if not (math.isfinite(s[name]) and s[name] > 0):
                    raise ValueError(f"{name} must be finite and > 0 (got {s[name]:g})")
        if not adaptive and s["sample_every"] < s["dt"] * (1 - 1e-9):
            raise ValueError(f"sample_every = {s['sample_every']:g} is below dt = {s['dt']:g}: a "
                             "fixed-step method only reaches multiples of dt")
        if s["n_modes"] is None:
            s["n_modes"] = max(grid["N"])
        if isinstance(s["n_modes"], bool) or int(s["n_modes"]) != s["n_modes"] or \
                s["n_modes"] < 1:
            raise ValueError(f"n_modes must be an integer >= 1 (got {s['n_modes']!r})")
        s["n_modes"] = int(s["n_modes"])
        return grid, s

    def cost(self, coords, settings):
        return float(coords["N"])

    def quantum(self, settings):
        return settings["sample_every"]

    def run(self, settings, coords, previous, t_end):
        return [sampled_run(settings, c["N"], c["tau"], c["seed"], p, t_end,
                            min(c["N"], settings["n_modes"]))
                for c, p in zip(coords, previous)]

    def extra_sizes(self, settings, t_end):
        return {"sample": n_sample_times(t_end, settings["sample_every"]),
                "mode": settings["n_modes"]}

    def extra_coords(self, settings, arrays):
        n = arrays["energy"].shape[-1]
        return {"t": ("sample", settings["sample_every"] * np.arange(n)),
                "mode": ("mode", np.arange(1, settings["n_modes"] + 1))}

    def summary(self, ds):
        return fraction_rows(ds, ds["blew_up"].values, "blew_up", "fraction_blowup")


RUN_KIND = RunKind()
