"""Recurrence against disorder: the "recurrence" study kind and its measures.

The ordered FPUT chain started in mode 1 gives its energy away to the higher modes and takes
almost all of it back at the recurrence time t_r (t_r ~ 5.6e4 at N = 64, alpha = 0.25: the
paper's Fig. 1). Disorder spoils the return (Fig. 2). Per realisation this kind integrates the
paper's mode-1 state to t_end and samples the share of the first four modes,

    s_k(t) = E_k(t) / sum_j E_j(t),    k = 1..4,

every `sample_every` (the share, not E_1 / E(0): model 3 is not Hamiltonian and its energy
drifts). `recurrence_quality` reduces one run to two numbers: the largest s_1 in
[t_r / 2, 3 t_r / 2] (how much comes back at the ordered chain's first recurrence) and the
smallest s_1 before t_r / 2 (how much was given away). A run that crosses the potential barrier
(a bond stretched past it, `Lattice.barrier`) stops there and is counted as a blow-up.

A task is the "run" kind's (`fputlab.sampled`: the same samples, bit for bit) reduced to the
shares. It is cheap (about a second at N = 64), so a larger t_end runs it again from the start
rather than keeping its state (the stored recurrence studies hold none).
"""
from __future__ import annotations

import math

import numpy as np

from . import _lowlevel as ll
from ._validate import _real
from .engine import StudyKind, normalise_disorder
from .sampled import RUN_KIND, n_sample_times, sampled_run

__all__ = ["RECURRENCE_KIND", "RecurrenceKind", "recurrence_quality", "recurrence_time"]

_SETTINGS = {"model": "nonlinear", "alpha": 0.25, "method": "srkn14a6", "dt": 0.25,
             "sample_every": 20.0}


def recurrence_time(t, share) -> float:
    """The time of the largest mode-1 share after its deepest sharing (the first recurrence of
    an ordered chain's run)."""
    t = np.asarray(t, float)
    s1 = np.asarray(share, float)[:, 0]
    ok = np.isfinite(s1)
    t, s1 = t[ok], s1[ok]
    after = t > t[np.argmin(s1)]
    if not after.any():
        raise ValueError("the run ends at its deepest sharing: no recurrence in it")
    return float(t[after][np.argmax(s1[after])])


def recurrence_quality(t, share, t_recurrence: float) -> tuple[float, float]:
    """(peak, dip): the largest mode-1 share in [t_r/2, 3t_r/2] and the smallest before t_r/2
    (NaN where the run has no sample there)."""
    t = np.asarray(t, float)
    s1 = np.asarray(share, float)[:, 0]
    late = (t >= 0.5 * t_recurrence) & (t <= 1.5 * t_recurrence) & np.isfinite(s1)
    early = (t < 0.5 * t_recurrence) & np.isfinite(s1)
    peak = float(s1[late].max()) if late.any() else math.nan
    dip = float(s1[early].min()) if early.any() else math.nan
    return peak, dip


class RecurrenceKind(StudyKind):
    """Mode shares s_1..s_4 of the paper's mode-1 state per (N, tau, seed), sampled every
    `sample_every` to t_end; a blow-up ends a run (see the module docstring)."""
    name = "recurrence"
    version = 1
    dims = ("N", "tau", "seed")
    variables = {
        "share": (("sample", "mode"), float, "1",
                  "share E_k / sum_j E_j of normal modes k = 1..4"),
        "t_stop": ((), float, "1", "time the run reached (before t_end: a blow-up)"),
        "blew_up": ((), bool, "", "the run crossed the potential barrier"),
        "message": ((), str, "", "how the run ended"),
    }
    coord_attrs = RUN_KIND.coord_attrs       # the run kind's samples and modes

    def normalise(self, grid, settings):
        grid, s = normalise_disorder(grid, settings, _SETTINGS, "recurrence")
        for name in ("alpha", "dt", "sample_every"):
            s[name] = _real(s[name], name)
            if not s[name] > 0 and name != "alpha":
                raise ValueError(f"{name} must be > 0 (got {s[name]:g})")
        return grid, s

    def cost(self, coords, settings):
        return float(coords["N"])

    def run(self, settings, coords, previous, t_end):
        return [_run_one(settings, c["N"], c["tau"], c["seed"], t_end) for c in coords]

    def extra_sizes(self, settings, t_end):
        return {"sample": n_sample_times(t_end, settings["sample_every"]), "mode": 4}

    def extra_coords(self, settings, arrays):
        n = arrays["share"].shape[-2]
        return {"t": ("sample", settings["sample_every"] * np.arange(n)),
                "mode": ("mode", np.arange(1, 5))}

    def summary(self, ds):
        return []


def _run_one(settings, N, tau, seed, t_end) -> dict:
    """The "run" kind's task from the start (all N modes), reduced to the shares of modes 1-4."""
    run = sampled_run({**settings, "rtol": ll.RTOL, "atol": ll.ATOL}, N, tau, seed, None, t_end)
    E = run["values"]["E"]
    share = E[:, :4] / E.sum(axis=1, keepdims=True)      # NaN after a blow-up
    v = run["values"]
    values = {"share": share, "t_stop": v["t_reached"] if v["blew_up"] else
              float(settings["sample_every"] * (E.shape[0] - 1)),
              "blew_up": v["blew_up"], "message": v["message"]}
    return {"t": t_end, "done": v["blew_up"], "message": v["message"], "cpu": run["cpu"],
            "values": values, "state": None}


RECURRENCE_KIND = RecurrenceKind()
