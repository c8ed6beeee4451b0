"""Finite-time blow-up: stopping criteria found by root-finding, blow-up times, and sweeps of the
blow-up probability over disorder realisations (paper Sec. 3, Fig. 3 and Sec. 4)."""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from . import _lowlevel as ll
from ._display import ResultMixin
from ._arrays import as_float_array
from ._engine import check_ensemble, run_calls
from ._errors import Interrupted
from ._pacing import Pacer, first_span
from ._validate import _positive_real, _real, _renamed
# CRITERIA stays importable from here (fputlab.blowup.CRITERIA)
from .integrate import CRITERIA, Integrator, check_steps, method_info  # noqa: F401
from .lattice import Lattice
from .reduction import realisation_quadratics

__all__ = ["blowup_time", "blowup_sweep", "Blowup", "BlowupRecord", "default_criteria",
           "realisation_tau_c", "CRITERIA"]

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


def _one(args):
    N, tau, seed, model, alpha, t_max, method, kwargs = args
    lat = Lattice(N, alpha, model, tau=tau, seed=seed)
    res = blowup_time(lat, t_max, method=method, **kwargs)
    return BlowupRecord(tau, N, seed, res.blew_up, res.time, realisation_tau_c(N, seed, alpha))


def blowup_sweep(tau=None, Ns=(64,), realisations: int = 20, *, t_end: float = 1e4,
                 model: str = "nonlinear", alpha: float = 0.25, method: str = "yoshida4",
                 first_seed: int = 1, workers: int | None = None, scheduler=None,
                 progress: bool = False, taus=None, t_max: float | None = None,
                 **kwargs) -> dict:
    """Probability of blow-up before `t_end` versus tau (and N) over disorder realisations, run
    in parallel processes.

    Parameters
    ----------
    tau : float or sequence of float
        Tolerances (percent). (`taus`: its old spelling, deprecated.)
    Ns : sequence of int, optional
        Lattice sizes.
    realisations : int, optional
        Disorder draws per (tau, N), seeds ``first_seed, first_seed + 1, ...``.
    t_end : float, optional
        Longest time per run. (`t_max`: its old spelling, deprecated.)
    model : str, optional
        Lattice model (default "nonlinear", the paper's).
    alpha : float, optional
        Cubic coupling.
    method : str, optional
        Integrator name.
    first_seed : int, optional
        Seed of the first realisation.
    workers : int, optional
        Worker processes (default: all cores).
    scheduler : str or dask.distributed.Client, optional
        Run on a Dask cluster instead (the ensemble engine, `fputlab.ensemble.run_calls`).
    progress : bool, optional
        A progress bar over the runs (tqdm.auto).
    taus : sequence of float, optional
        Deprecated spelling of `tau` (warns; removed in the next release).
    t_max : float, optional
        Deprecated spelling of `t_end` (warns; removed in the next release).
    **kwargs
        Passed to `blowup_time` (dt, rtol, atol, criteria).

    Returns
    -------
    dict
        ``tau``, ``N``, ``probability`` (len(taus) x len(Ns)), the per-realisation ``records``
        (`BlowupRecord`: tau, N, seed, blew_up, time, tau_c, in the order tau, N, seed) where
        tau_c is the realisation's own two-mode threshold (B~ < 0 above it), and
        ``prediction_accuracy``: the share of runs where "tau > tau_c" agrees with "blew up
        before t_end" (``t_end``; ``t_max`` too, deprecated). Plot with `fputlab.plotting.plot_blowup_sweep_figure` or
        `fputlab.plotting.plot_blowup_sweep`.
    """
    from tqdm.auto import tqdm

    taus = _renamed(tau, taus, "tau", "taus")
    t_max = _renamed(t_end, t_max, "t_end", "t_max")
    if taus is None:
        raise TypeError("blowup_sweep() needs tau, the tolerances in percent")
    taus, Ns, realisations = check_ensemble(taus, Ns, realisations)
    tasks = [(N, tau, first_seed + r, model, alpha, t_max, method, kwargs)
             for tau in taus for N in Ns for r in range(realisations)]
    done = {}
    with tqdm(total=len(tasks), desc="blow-up sweep", disable=None if progress else True) as bar:
        for (task,), rec, err in run_calls(_one, [(t,) for t in tasks], workers=workers,
                                           scheduler=scheduler):
            if err is not None:
                raise err
            done[task[:3]] = rec
            bar.update(1)
    records = [done[t[:3]] for t in tasks]          # in the order tau, N, seed
    prob = np.zeros((len(taus), len(Ns)))
    for i, tau in enumerate(taus):
        for j, N in enumerate(Ns):
            hits = [r.blew_up for r in records if r.tau == tau and r.N == N]
            prob[i, j] = np.mean(hits)
    agree = [(r.tau > r.tau_c) == r.blew_up for r in records if np.isfinite(r.tau_c)]
    return {"tau": np.array(taus), "N": np.array(Ns), "probability": prob, "records": records,
            "t_end": t_max, "t_max": t_max, "realisations": realisations,
            "prediction_accuracy": float(np.mean(agree)) if agree else float("nan")}
