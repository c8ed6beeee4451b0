"""Finite-time blow-up: stopping criteria found by root-finding, blow-up times, and sweeps of the
blow-up probability over disorder realisations (paper Sec. 3, Fig. 3 and Sec. 4).

The sweeps are studies of the study engine (`fputlab.engine`), kind "blowup" (`BLOWUP_KIND`):
one run per (N, tau, seed), kept on disk with ``work_dir``; a larger t_end continues every run
that has not blown up from its saved state (bit for bit for the fixed-step methods)."""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from . import _lowlevel as ll
from ._display import ResultMixin
from ._arrays import as_float_array
from ._engine import check_ensemble
from ._errors import Interrupted
from ._pacing import Pacer, first_span
from ._validate import C_U64, _int, _positive_real, _real, _renamed
from .engine import DISORDER_COORD_ATTRS, StudyKind, fraction_rows, normalise_disorder, run_study
# CRITERIA stays importable from here (fputlab.blowup.CRITERIA)
from .integrate import CRITERIA, Integrator, check_steps, criteria_events, method_info  # noqa: F401
from .lattice import Lattice
from .reduction import realisation_quadratics

__all__ = ["blowup_time", "blowup_sweep", "Blowup", "BlowupRecord", "default_criteria",
           "realisation_tau_c", "CRITERIA", "BLOWUP_KIND", "BlowupKind"]

def default_criteria(lattice: Lattice) -> list[tuple]:
    """The bond potential's barrier: a bond stretched beyond its nearer top (`Lattice.barrier`,
    the nearest non-zero root of V': 1/alpha for FPUT-alpha) has escaped; a potential without a
    barrier (alpha^2 <= 4 beta, the Toda lattice) cannot blow up that way: ``|x_j| > 100``."""
    lower, upper = lattice.barrier
    stretch = min(-lower, upper)
    if np.isfinite(stretch):
        return [("stretch", stretch)]
    return [("displacement", 100.0)]


@dataclass(repr=False)
class Blowup(ResultMixin):
    """Outcome of one run with stopping criteria."""
    blew_up: bool
    time: float                 # event time (NaN if no event)
    criterion: str              # which criterion fired ("" if none)
    t_reached: float            # time reached (the event time, or t_max)
    state: np.ndarray           # last finite state (the state at the event)
    method: str
    message: str = ""
    params: dict = field(default_factory=dict)


def blowup_time(lattice: Lattice, t_end: float | None = None, *, method: str = "yoshida4",
                dt: float | None = None, rtol: float = ll.RTOL, atol: float = ll.ATOL, y0=None,
                criteria=None, progress: bool = False, t_max: float | None = None) -> Blowup:
    """Integrate until a stopping criterion fires (a blow-up) or `t_end`.

    Parameters
    ----------
    lattice : Lattice
        The lattice (typically model 3 with tau above tau_c).
    t_end : float
        Longest time to integrate (finite, > 0). (`t_max`: its old spelling, deprecated.)
    method : str, optional
        Integrator name; the splitting schemes locate the crossing inside the step, ARKODE and
        CVODE by root-finding ("gsl-rk8pd" refuses criteria).
    dt : float, optional
        Step of the fixed-step methods (default 0.01).
    rtol, atol : float, optional
        Tolerances of the adaptive methods.
    y0 : array_like, optional
        Initial state, length 2N (default: the paper's mode-1 state).
    criteria : list of tuple, optional
        Stopping criteria such as ``[("stretch", 4.0)]``, ``("energy", E)``,
        ``("displacement", X)`` or ``("mode_energy", E)`` (default: a bond stretched beyond the
        potential's barrier, 1/alpha for FPUT-alpha, `default_criteria`).
    progress : bool, optional
        A progress bar with ETA (tqdm.auto).
    t_max : float, optional
        Deprecated spelling of `t_end` (warns; removed in the next release).

    Returns
    -------
    Blowup
        Whether it blew up, when, by which criterion, and the state there.

    Raises
    ------
    IntegrationError
        The state became NaN/Inf without a criterion firing: an integration failure, not a
        located blow-up.
    """
    t_end = _renamed(t_end, t_max, "t_end", "t_max")
    if t_end is None:
        raise TypeError("blowup_time() needs t_end, the longest time to integrate")
    t_max = _positive_real(t_end, "t_end")
    crit = default_criteria(lattice) if criteria is None else criteria
    y = lattice.mode_state() if y0 is None else as_float_array(y0, "y0", (2 * lattice.N,))
    if dt is None and not method_info(method)["adaptive"]:
        dt = ll.DT
    if not method_info(method)["adaptive"]:
        check_steps(t_max, _real(dt, "dt"), "t_end", t_max)
    # the criteria belong to this run (the lattice stays untouched)
    integ = Integrator(lattice, y, method=method, dt=dt, rtol=rtol, atol=atol, criteria=crit)
    from tqdm.auto import tqdm

    # in segments: fixed-step ones of ~0.2 s (pausing changes nothing), adaptive ones in 100
    # equal parts (deterministic); Ctrl-C is seen between them
    pacer = Pacer(first_span(dt, lattice.N)) if not integ.adaptive else None
    target, status = 0.0, 0
    with tqdm(total=t_max, desc=f"blow-up N={lattice.N}", unit="t",
              disable=None if progress else True,
              bar_format="{l_bar}{bar}| {n:.4g}/{total:.4g} [{elapsed}<{remaining}]") as bar:
        try:
            while target < t_max and status == 0:
                step = pacer.span if pacer else t_max / 100
                target = min(t_max, target + step)
                before, clock = integ.t, time.perf_counter()
                # a failure without an event is not a blow-up: it raises
                status = integ._h.advance(target)
                if pacer:
                    pacer.record(integ.t - before, time.perf_counter() - clock)
                bar.update(integ.t - bar.n)
        except KeyboardInterrupt:
            msg = f"interrupted (Ctrl-C) at t = {integ.t:.10g}"
            raise Interrupted(msg, Blowup(False, float("nan"), "", integ.t, integ.state[0],
                                          method, msg)) from None
    event = integ.event
    message = integ._h.errmsg()
    state = integ.state[0]
    params = {"N": lattice.N, "model": lattice.model, "tau": lattice.tau, "seed": lattice.seed}
    if event:
        return Blowup(True, event["time"], event["criterion"], event["time"], state,
                      method, message, params)
    return Blowup(False, float("nan"), "", t_max, state, method, "", params)


def realisation_tau_c(N: int, seed: int, alpha: float = 0.25, disorder: str = "gaussian") -> float:
    """The realisation's own two-mode threshold: the smallest tau > 0 where its B~(tau) = 0
    (same standard draws z for every tau; NaN if B~ never vanishes)."""
    return float(realisation_quadratics(N, alpha, R=1, seed0=seed, kind=disorder).critical_tolerances()[0])


class BlowupRecord(NamedTuple):
    """One realisation of a blow-up sweep (`blowup_sweep`'s ``records``), read by name.

    Still a tuple, so ``np.array(records, dtype=float)`` gives the (runs, 6) array of the CLI's
    HDF5 files and `BlowupRecord.to_array` a structured array with these field names."""
    tau: float          #: variability (percent)
    N: int              #: lattice size
    seed: int           #: disorder seed
    blew_up: bool       #: a stopping criterion fired before t_max
    time: float         #: blow-up time (NaN if none)
    tau_c: float        #: the realisation's own two-mode threshold (`realisation_tau_c`)

    @staticmethod
    def to_array(records) -> np.ndarray:
        """The records as a structured numpy array (fields tau, N, seed, blew_up, time, tau_c)."""
        dtype = [("tau", float), ("N", np.int64), ("seed", np.int64), ("blew_up", bool),
                 ("time", float), ("tau_c", float)]
        return np.array([tuple(r) for r in records], dtype=dtype)


# ---- the blow-up study kind -------------------------------------------------------------------

#: settings of blow-up studies and their defaults (dt: C's fixed step, None for the adaptive
#: methods; rtol/atol: C's; criteria None: `default_criteria` of each lattice; y0 None: the
#: paper's mode-1 state)
_SETTINGS = {"model": "nonlinear", "alpha": 0.25, "method": "yoshida4", "dt": None,
             "rtol": ll.RTOL, "atol": ll.ATOL, "criteria": None, "y0": None}


def _study_lattice(settings: dict, N: int, tau: float, seed: int) -> Lattice:
    return Lattice(N, settings["alpha"], settings["model"], tau=tau, seed=seed)


class BlowupKind(StudyKind):
    """The blow-up time of one run per (N, tau, seed) (`blowup_time`'s numbers), and the
    realisation's own two-mode threshold tau_c. A run that has not blown up keeps its
    integrator state (steps, t, y), so a larger t_end continues it: bit for bit for the
    fixed-step methods."""
    name = "blowup"
    version = 1
    resumable = True
    dims = ("N", "tau", "seed")
    variables = {
        "blew_up": ((), bool, "", "a stopping criterion fired before t_end"),
        "time": ((), float, "1", "blow-up time (NaN: none before t_end)"),
        "criterion": ((), str, "", "the stopping criterion that fired (empty: none)"),
        "t_reached": ((), float, "1", "time reached (the blow-up time, or t_end)"),
        "tau_c": ((), float, "percent", "the realisation's own two-mode threshold tau_c"),
    }
    coord_attrs = DISORDER_COORD_ATTRS

    def normalise(self, grid, settings):
        grid, s = normalise_disorder(grid, settings, _SETTINGS, "blow-up")
        if s["model"] == "homogeneous" and any(t != 0 for t in grid["tau"]):
            raise ValueError("tau: the homogeneous model has no disorder (use tau=[0])")
        if not isinstance(s["method"], str):
            raise ValueError(f"method must be a string (got {s['method']!r})")
        adaptive = method_info(s["method"])["adaptive"]        # names an unknown method
        s["alpha"] = _real(s["alpha"], "alpha")
        if not math.isfinite(s["alpha"]):
            raise ValueError(f"alpha must be finite (got {s['alpha']:g})")
        if s["dt"] is None and not adaptive:
            s["dt"] = ll.DT
        for name in ("dt", "rtol", "atol"):
            if s[name] is not None:
                s[name] = _real(s[name], name)
                if not s[name] > 0:
                    raise ValueError(f"{name} must be > 0 (got {s[name]:g})")
        if s["criteria"] is not None:
            criteria_events(s["criteria"])                # names a bad criterion
            s["criteria"] = [[c[0], float(c[1]), *(int(x) for x in c[2:])]
                             for c in s["criteria"]]
        if s["y0"] is not None:
            y0 = np.asarray(s["y0"], dtype=float).ravel()
            if any(y0.size != 2 * N for N in grid["N"]) or not np.all(np.isfinite(y0)):
                raise ValueError(f"y0 must hold 2N finite values for every N (got {y0.size} "
                                 f"values, N = {grid['N']})")
            s["y0"] = [float(v) for v in y0]
        return grid, s

    def cost(self, coords, settings):
        return float(coords["N"])

    def run(self, settings, coords, previous, t_end):
        return [_blowup_task(settings, c["N"], c["tau"], c["seed"], p, t_end)
                for c, p in zip(coords, previous)]

    def summary(self, ds):
        return fraction_rows(ds, ds["blew_up"].values, "blew_up", "probability")


def _blowup_task(settings, N, tau, seed, prev, t_end) -> dict:
    """One run from the start (or from its saved state) to t_end, or to its blow-up."""
    cpu0 = time.process_time()
    try:
        lat = _study_lattice(settings, N, tau, seed)
        crit = default_criteria(lat) if settings["criteria"] is None else \
            [tuple(c) for c in settings["criteria"]]
        y = lat.mode_state() if settings["y0"] is None else np.asarray(settings["y0"], float)
        if prev is not None and prev["state"] is not None:
            tau_c = float(prev["values"]["tau_c"])
        elif settings["model"] == "homogeneous":
            tau_c = math.nan
        else:
            tau_c = realisation_tau_c(N, seed, settings["alpha"])
        if settings["dt"] is not None and not method_info(settings["method"])["adaptive"]:
            check_steps(t_end, settings["dt"], "t_end", t_end)
        integ = Integrator(lat, y, method=settings["method"], dt=settings["dt"],
                           rtol=settings["rtol"], atol=settings["atol"], criteria=crit)
        if prev is not None and prev["state"] is not None:
            st = prev["state"]
            integ.restore(int(st["steps"]), float(st["t"]), np.asarray(st["y"], float)[None, :])
        integ._h.advance(t_end)     # a failure without an event is not a blow-up: it raises
    except Exception as err:        # reported, not stored: the next run tries it again
        return {"error": f"{type(err).__name__}: {err}"}
    event = integ.event
    if event:
        values = {"blew_up": True, "time": float(event["time"]),
                  "criterion": event["criterion"], "t_reached": float(event["time"]),
                  "tau_c": tau_c}
        state = None
    else:
        values = {"blew_up": False, "time": math.nan, "criterion": "",
                  "t_reached": float(t_end), "tau_c": tau_c}
        state = {"steps": np.int64(integ.steps), "t": np.float64(integ.t),
                 "y": integ.state[0]}
    return {"t": float(t_end), "done": bool(event), "message": integ._h.errmsg() if event else "",
            "cpu": time.process_time() - cpu0, "values": values, "state": state}


BLOWUP_KIND = BlowupKind()


def _records(ds) -> list:
    """The BlowupRecords of a blow-up study's dataset, in the order tau, N, seed (finished
    tasks only)."""
    out = []
    blew, times = ds["blew_up"].values, ds["time"].values
    tauc, reached = ds["tau_c"].values, ds["t_reached"].values
    for j, tau in enumerate(ds["tau"].values):
        for i, N in enumerate(ds["N"].values):
            for r, seed in enumerate(ds["seed"].values):
                if not np.isfinite(reached[i, j, r]):
                    continue
                out.append(BlowupRecord(float(tau), int(N), int(seed), bool(blew[i, j, r]),
                                        float(times[i, j, r]), float(tauc[i, j, r])))
    return out


def blowup_sweep(tau=None, Ns=(64,), realisations: int = 20, *, t_end: float = 1e4,
                 model: str = "nonlinear", alpha: float = 0.25, method: str = "yoshida4",
                 first_seed: int = 1, work_dir=None, overwrite: bool = False,
                 workers: int | None = None, scheduler=None, progress: bool = False,
                 taus=None, t_max: float | None = None, **kwargs) -> dict:
    """Probability of blow-up before `t_end` versus tau (and N) over disorder realisations: a
    blow-up study of the study engine (`fputlab.engine.run_study`, kind "blowup"), run in
    parallel processes or on a Dask cluster.

    Parameters
    ----------
    tau : float or sequence of float
        Tolerances (percent). (`taus`: its old spelling, deprecated.)
    Ns : sequence of int, optional
        Lattice sizes.
    realisations : int, optional
        Disorder draws per (tau, N), seeds ``first_seed, first_seed + 1, ...``.
    t_end : float, optional
        Longest time per run. (`t_max`: its old spelling, deprecated.) With `work_dir`, a
        larger t_end than the last run's continues every run that has not blown up from its
        saved state (bit for bit for the fixed-step methods).
    model : str, optional
        Lattice model (default "nonlinear", the paper's).
    alpha : float, optional
        Cubic coupling.
    method : str, optional
        Integrator name.
    first_seed : int, optional
        Seed of the first realisation.
    work_dir : path, optional
        Keep the study on disk (`fputlab.io.store`): each run written as it finishes, a rerun
        continues, a changed study is refused (default: in memory).
    overwrite : bool, optional
        Discard another study found in `work_dir` instead of refusing.
    workers : int, optional
        Worker processes (default: all cores).
    scheduler : str or dask.distributed.Client, optional
        Run on a Dask cluster instead (the ensemble engine, `fputlab.ensemble.run_calls`).
    progress : bool, optional
        The study engine's progress bar (tasks, cost-weighted ETA).
    taus : sequence of float, optional
        Deprecated spelling of `tau` (warns; removed in the next release).
    t_max : float, optional
        Deprecated spelling of `t_end` (warns; removed in the next release).
    **kwargs
        Settings of the runs, as `blowup_time` takes them: dt, rtol, atol, criteria, y0.

    Returns
    -------
    dict
        ``tau``, ``N``, ``probability`` (len(taus) x len(Ns)), the per-realisation ``records``
        (`BlowupRecord`: tau, N, seed, blew_up, time, tau_c, in the order tau, N, seed) where
        tau_c is the realisation's own two-mode threshold (B~ < 0 above it), and
        ``prediction_accuracy``: the share of runs where "tau > tau_c" agrees with "blew up
        before t_end" (``t_end``; ``t_max`` too, deprecated); ``study``: the
        `fputlab.engine.StudyResult` (``to_xarray()``, ``summary()`` with Wilson 95 %
        intervals). Plot with `fputlab.plotting.plot_blowup_sweep_figure` or
        `fputlab.plotting.plot_blowup_sweep`.

    Raises
    ------
    ValueError
        An invalid argument or setting (named), or another study in `work_dir`.
    IntegrationError
        A run became NaN/Inf without a criterion firing (not stored as finished: a rerun
        tries it again).
    """
    taus = _renamed(tau, taus, "tau", "taus")
    t_max = _renamed(t_end, t_max, "t_end", "t_max")
    if taus is None:
        raise TypeError("blowup_sweep() needs tau, the tolerances in percent")
    taus, Ns, realisations = check_ensemble(taus, Ns, realisations)
    first_seed = _int(first_seed, "first_seed", C_U64)
    settings = dict(kwargs, model=model, alpha=alpha, method=method)
    grid = {"N": Ns, "tau": taus, "seed": [first_seed + r for r in range(realisations)]}
    study = run_study("blowup", grid, settings, t_max, work_dir=work_dir, overwrite=overwrite,
                      workers=workers, scheduler=scheduler, progress=progress)
    if study.failed:     # as the run raised it (the kind reports "<type>: <message>")
        from ._errors import IntegrationError
        c, msg = study.failed[0]
        text = (f"{len(study.failed)} run(s) failed; the first (N = {c['N']}, tau = "
                f"{c['tau']:g}, seed = {c['seed']}): {msg}")
        if msg.startswith(("ValueError", "TypeError")):
            raise (TypeError if msg.startswith("TypeError") else ValueError)(text)
        raise IntegrationError(text, ll.ERR_NONFINITE, None)
    records = _records(study.dataset)
    p = study.dataset["blew_up"].mean("seed").values          # (N, tau)
    agree = [(r.tau > r.tau_c) == r.blew_up for r in records if np.isfinite(r.tau_c)]
    return {"tau": np.array(taus), "N": np.array(Ns), "probability": np.asarray(p, float).T,
            "records": records, "t_end": study.dataset.attrs["t_end"],
            "t_max": study.dataset.attrs["t_end"], "realisations": realisations,
            "prediction_accuracy": float(np.mean(agree)) if agree else float("nan"),
            "study": study}
