"""Chaos indicators: maximum Lyapunov exponent lambda(t), SALI(t), GALI_k(t), classification of
orbits, and the chaotic fraction over disorder realisations (paper Sec. 5, Figs. 11-14)."""
from __future__ import annotations

import inspect
import os
import time
from typing import NamedTuple

import numpy as np

from . import _lowlevel as ll
from ._arrays import as_float_array, check_memory
from ._chaos_result import CLASSES, ChaosResult, classify_orbit  # noqa: F401 (public here)
from ._engine import check_ensemble, run_calls
from ._errors import IntegrationError, Interrupted, check, last_error
from ._pacing import Pacer, first_span
from ._validate import C_U64, _int, _real
from .chaos_batch import BATCH_METHODS, lyapunov_batch
from .integrate import method_info
from .lattice import Lattice

__all__ = ["lyapunov", "chaotic_fraction", "sali", "gali", "ChaosResult", "OrbitRecord", "CLASSES",
           "classify_orbit"]


#: The default integrator of chaos ensembles (chaotic_fraction, sweeps, the study behind
#: Figs. 12-14): the fastest scheme validated (tests/python/test_study.py,
#: benchmarks/chaos_methods.py) to classify orbits as Yoshida 4 at dt = 0.01 and DOP853 on the
#: variational equations (the paper's methods) do; its energy error at dt = 0.5 is below Yoshida
#: 4's at dt = 0.01, at ~1/8 of the cost. The paper's choice stays one argument away
#: (method="dop853" or method="yoshida4", dt=0.01).
ENSEMBLE_METHOD, ENSEMBLE_DT = "srkn14a6", 0.5

#: the C defaults of the chaos options (fpl_chaos_options_init)
_C = ll.CHAOS_DEFAULTS


def _run_with_progress(lattice, method, io, t0, y, w, co, arrays, res, progress=True) -> int:
    """fpl_chaos_run through the resumable handle in segments of ~0.2 s (pauses fall on
    renormalisation times, so the numbers are those of one call; Ctrl-C is seen between
    segments), with a tqdm bar if `progress`."""
    from tqdm.auto import tqdm

    try:
        c = ll.ChaosHandle(lattice._h, method, io, t0, y, w, co)
    except IntegrationError as err:           # a numerical failure: the caller keeps what it has
        return err.status
    status = 0
    span = co.t_end - t0
    pacer = Pacer(max(first_span(io.dt or None, lattice.N, co.n_dev), co.renorm_interval))
    with tqdm(total=span, desc=f"chaos N={lattice.N}", unit="t", disable=None if progress else True,
              bar_format="{l_bar}{bar}| {n:.4g}/{total:.4g} [{elapsed}<{remaining}]") as bar:
        target = t0
        try:
            while target < co.t_end:
                target = min(co.t_end, target + pacer.span)
                before, clock = res.t_final, time.perf_counter()
                status = c.advance(target, *arrays)
                c.get_result(res)
                pacer.record(res.t_final - before, time.perf_counter() - clock)
                bar.update(res.t_final - t0 - bar.n)
                if c.done():
                    break
        except IntegrationError as err:       # NaN/Inf: the samples before it are kept
            status = err.status
    c.get_result(res)
    return status


def _chaos_options(t_end, renorm_interval, n_samples, t_first_sample, n_dev, sali_threshold,
                   stop_when_chaotic, seed, blowup_stretch):
    """A validated fpl_chaos_options (defaults from fpl_chaos_options_init)."""
    co = ll.chaos_options(_real(t_end, "t_end"))
    if renorm_interval is not None:
        co.renorm_interval = _real(renorm_interval, "renorm_interval")
    co.n_samples = _int(n_samples, "n_samples")
    co.t_first_sample = _real(t_first_sample, "t_first_sample")
    co.n_dev = _int(n_dev, "n_dev")
    co.sali_threshold = _real(sali_threshold, "sali_threshold")
    co.stop_when_chaotic = bool(stop_when_chaotic)
    seed = _int(seed, "seed", C_U64)
    if seed < 0:
        raise ValueError(f"seed must be >= 0 (got {seed})")
    co.seed = seed
    if blowup_stretch is not None:
        co.blowup_stretch = _real(blowup_stretch, "blowup_stretch")
    return co


def lyapunov(lattice: Lattice, t_end: float, *, method: str = "yoshida4", dt: float | None = None,
             rtol: float = ll.RTOL, atol: float = ll.ATOL, y0=None, w0=None,
             n_dev: int = _C["n_dev"], renorm_interval: float = _C["renorm_interval"],
             n_samples: int = _C["n_samples"], t_first_sample: float = _C["t_first_sample"],
             sali_threshold: float = _C["sali_threshold"], stop_when_chaotic: bool = False,
             seed: int = _C["seed"],
             t0: float = 0.0, progress: bool = False,
             blowup_stretch: float | None = None) -> ChaosResult:
    """Chaos indicators of one orbit: finite-time mLE λ(t), SALI(t) and GALI_k(t) (paper Sec. 5).

    Fixed-step methods carry the deviation vectors with the tangent map of the scheme;
    adaptive methods (e.g. "dop853", the paper's choice for model 3) integrate the variational
    equations.

    Parameters
    ----------
    lattice : Lattice
        The lattice.
    t_end : float
        Final time.
    method : str, optional
        Integrator name (`fputlab.methods()`); default "yoshida4" (the paper's for model 1).
    dt : float, optional
        Step of the fixed-step methods (default 0.01).
    rtol, atol : float, optional
        Tolerances of the adaptive methods.
    y0 : array_like, optional
        Initial orbit state, length 2N (default: the paper's mode-1 state, Eq. initxi).
    w0 : array_like, optional
        Initial deviation vectors, shape (n_dev, 2N) (default: Gaussian random from `seed`).
    n_dev : int, optional
        Number of deviation vectors (2 for SALI; GALI_k uses all k).
    renorm_interval : float, optional
        Time between renormalisations of the deviation vectors.
    n_samples : int, optional
        Number of log-spaced sample times.
    t_first_sample : float, optional
        First sample time (0: one renormalisation interval).
    sali_threshold : float, optional
        SALI below this marks the orbit chaotic.
    stop_when_chaotic : bool, optional
        End the run once SALI falls below the threshold.
    seed : int, optional
        Seed of the random initial deviation vectors.
    t0 : float, optional
        Initial time.
    progress : bool, optional
        A progress bar with ETA (tqdm.auto; the same computation, in segments).
    blowup_stretch : float, optional
        A bond stretch above this at a renormalisation ends the run as a blow-up (default: the
        cubic barrier 1/alpha; < 0 turns the check off).

    Returns
    -------
    ChaosResult
        ``t``, ``mle``, ``sali``, ``gali`` at the sample times, and whether and when the orbit
        was found chaotic. A blow-up ends the run cleanly: ``blew_up``, ``t_blowup`` and
        ``message`` say when and why, and the samples before it are kept. A numerical failure
        (not a blow-up) also returns, with ``completed`` False and the reason in ``message``.

    Raises
    ------
    TypeError
        `lattice` is not a `fputlab.Lattice`.
    ValueError
        An invalid option (unknown method, wrong shape of `y0` or `w0`, ...); the message
        names it.
    Interrupted
        Ctrl-C; its ``result`` holds the ChaosResult computed so far.

    Examples
    --------
    >>> import fputlab
    >>> res = lyapunov(fputlab.Lattice(16), 1e4)          # doctest: +SKIP
    >>> res.classify(), res.mle_final                     # doctest: +SKIP
    """
    if not isinstance(lattice, Lattice):
        raise TypeError(f"lattice must be a fputlab.Lattice, got {type(lattice).__name__}")
    adaptive = method_info(method)["adaptive"]
    N = lattice.N
    y = lattice.mode_state() if y0 is None else as_float_array(y0, "y0", (2 * N,))
    n_dev = _int(n_dev, "n_dev")
    w = None if w0 is None else as_float_array(w0, "w0", (n_dev, 2 * N))
    io = ll.integrator_options((0.0 if adaptive else ll.DT) if dt is None else _real(dt, "dt"),
                               _real(rtol, "rtol"), _real(atol, "atol"))
    co = _chaos_options(t_end, renorm_interval, n_samples, t_first_sample, n_dev, sali_threshold,
                        stop_when_chaotic, seed, blowup_stretch)
    S = max(co.n_samples, 1)
    check_memory(8.0 * (4 * S + 2 * N * (n_dev + 2)), f"{S} chaos samples (N = {N}, n_dev = {n_dev})")
    t, mle, sali, gali = (np.full(S, np.nan) for _ in range(4))
    res = ll.chaos_result()
    interrupted = False
    try:
        status = _run_with_progress(lattice, method, io, _real(t0, "t0"), y, w, co,
                                    (t, mle, sali, gali), res, progress)
        message = last_error() if status != 0 else ""
    except KeyboardInterrupt:            # keep what was computed (Interrupted.result)
        interrupted, status, message = True, 0, ""
    k = res.n_samples
    out = ChaosResult(t=t[:k], mle=mle[:k], sali=sali[:k], gali=gali[:k], chaotic=bool(res.chaotic),
                      t_chaotic=res.t_chaotic, t_final=res.t_final, steps=res.steps, method=method,
                      completed=bool(res.completed), message=message,
                      params={"N": N, "model": lattice.model, "tau": lattice.tau,
                              "seed": lattice.seed, "t_end": t_end, "dt": io.dt,
                              "renorm_interval": co.renorm_interval},
                      blew_up=bool(res.blew_up), t_blowup=res.t_blowup)
    if interrupted:
        out.completed, out.message = False, f"interrupted (Ctrl-C) at t = {res.t_final:.10g}"
        raise Interrupted(out.message, out)
    if status < 0:
        try:
            check(status)
        except IntegrationError as err:     # a numerical failure (not a blow-up): keep the samples
            out.completed, out.message = False, str(err)
            return out
    return out


class OrbitRecord(NamedTuple):
    """One orbit of a chaos ensemble: its lattice size, disorder seed and result, read by name."""
    N: int
    seed: int
    result: ChaosResult


def _one_realisation(args) -> OrbitRecord:
    N, tau, seed, model, alpha, t_end, method, kwargs = args
    lat = Lattice(N, alpha, model, tau=tau, seed=seed)
    res = lyapunov(lat, t_end, method=method, **kwargs)
    return OrbitRecord(N, seed, res)


def _batch_of_realisations(args) -> list[OrbitRecord]:
    """Several realisations of one N in one batched run (fputlab.chaos_batch): the same numbers
    as `_one_realisation` for each, several times cheaper per orbit for small N."""
    N, tau, seeds, model, alpha, t_end, method, kwargs = args
    if len(seeds) == 1:      # one lane gains nothing over the single-orbit path (same numbers)
        return [_one_realisation((N, tau, seeds[0], model, alpha, t_end, method, kwargs))]
    lats = [Lattice(N, alpha, model, tau=tau, seed=s) for s in seeds]
    res = lyapunov_batch(lats, t_end, method=method, **kwargs)
    return [OrbitRecord(N, s, r) for s, r in zip(seeds, res)]


def ensemble_defaults(method: str | None, kwargs: dict) -> tuple[str, dict]:
    """(method, options) of a chaos ensemble: ENSEMBLE_METHOD at ENSEMBLE_DT unless a method is
    given, and early stop of chaotic orbits unless stop_when_chaotic is given."""
    kwargs = dict(kwargs)
    if method is None:
        method = ENSEMBLE_METHOD
        kwargs.setdefault("dt", ENSEMBLE_DT)
    kwargs.setdefault("stop_when_chaotic", True)
    return method, kwargs


def chaotic_fraction(Ns=(4, 8, 16, 32, 64), realisations: int = 30, tau: float = 10.0, *,
                     t_end: float = 1e4, model: str = "nonlinear", alpha: float = 0.25,
                     method: str | None = None, first_seed: int = 1, workers: int | None = None,
                     scheduler=None, progress: bool = False, **kwargs) -> dict:
    """Percentage of chaotic orbits over disorder realisations for each lattice size (paper
    Fig. 14: tau = 10 %, model 3, t = 1e8), and how many blew up.

    An orbit counts as chaotic when SALI falls below its threshold on the finite orbit
    (`ChaosResult.classify`); a blow-up is never counted as chaotic. The realisations run on
    the ensemble engine (`fputlab.ensemble.run_calls`: local processes, or a Dask cluster with
    `scheduler`). The splitting schemes run the orbits of one N in the vector lanes of the
    batched kernel (`fputlab.chaos_batch.lyapunov_batch`: the same numbers, several times
    cheaper for N <= 16). For t = 1e8 use the resumable `fputlab.study`.

    Parameters
    ----------
    Ns : sequence of int, optional
        Lattice sizes (each >= 2).
    realisations : int, optional
        Disorder realisations per N (>= 1), seeds ``first_seed, first_seed + 1, ...``.
    tau : float, optional
        Variability in percent (the paper's 10 %).
    t_end : float, optional
        Final time of every orbit.
    model : str, optional
        Lattice model (default "nonlinear", the paper's model 3).
    alpha : float, optional
        Cubic coupling.
    method : str, optional
        Integrator name (default: `ENSEMBLE_METHOD` at ``dt = ENSEMBLE_DT``, validated to
        classify orbits as the paper's methods do).
    first_seed : int, optional
        Disorder seed of the first realisation.
    workers : int, optional
        Local worker processes (default: all cores).
    scheduler : str or dask.distributed.Client, optional
        Run on a Dask cluster instead (an address "tcp://host:port", a Client or a cluster).
    progress : bool, optional
        A progress bar over the orbits (tqdm.auto).
    **kwargs
        Passed to `lyapunov` (dt, n_samples, sali_threshold, ...); chaotic orbits stop early
        unless ``stop_when_chaotic=False`` is given.

    Returns
    -------
    dict
        ``N`` (the sizes), ``percent`` (chaotic orbits per N, in percent), ``blowups`` (blown-up
        orbits per N), ``classes`` ({N: {class: count}} over `CLASSES`) and ``results``
        ({N: [ChaosResult, ...]} in seed order).

    Raises
    ------
    ValueError
        Empty `Ns`, a size below 2, `realisations` < 1, or an invalid option of `lyapunov`.

    Examples
    --------
    >>> from fputlab.chaos import chaotic_fraction
    >>> out = chaotic_fraction(Ns=(4, 8), realisations=4, t_end=1e3)    # doctest: +SKIP
    >>> out["percent"], out["classes"][8]                                 # doctest: +SKIP
    """
    method, kwargs = ensemble_defaults(method, kwargs)
    _, Ns, realisations = check_ensemble([tau], Ns, realisations)
    Ns = [int(N) for N in Ns]
    seeds = [first_seed + r for r in range(realisations)]
    batched = method in BATCH_METHODS and set(kwargs) <= set(
        inspect.signature(lyapunov_batch).parameters)
    if batched:    # orbits of one N in the vector lanes: chunks of >= 4 orbits, one per core
        cores = workers or os.cpu_count() or 1
        per = max(4, -(-realisations // cores))
        calls = [((N, tau, seeds[i:i + per], model, alpha, t_end, method, kwargs),)
                 for N in Ns for i in range(0, realisations, per)]
        fn = _batch_of_realisations
    else:
        calls = [((N, tau, s, model, alpha, t_end, method, kwargs),) for N in Ns for s in seeds]
        fn = _one_realisation
    got: dict = {}
    from tqdm.auto import tqdm
    with tqdm(total=len(Ns) * realisations, desc="chaos", unit="orbit",
              disable=None if progress else True) as bar:
        for _, out, err in run_calls(fn, calls, workers=workers, scheduler=scheduler):
            if err is not None:
                raise err
            for orbit in (out if batched else [out]):
                got[orbit.N, orbit.seed] = orbit.result
                bar.update(1)
    results = {N: [got[N, first_seed + r] for r in range(realisations)] for N in Ns}
    classes = {N: {c: sum(r.classify() == c for r in results[N]) for c in CLASSES} for N in Ns}
    percent = [100.0 * classes[N]["chaotic"] / realisations for N in Ns]
    blowups = [classes[N]["blow-up"] for N in Ns]
    return {"N": Ns, "percent": percent, "blowups": blowups, "classes": classes,
            "results": results}


def sali(w1, w2) -> float:
    """SALI of two vectors: ``min(|w1^ - w2^|, |w1^ + w2^|)``."""
    a = as_float_array(w1, "w1")
    b = as_float_array(w2, "w2", a.shape)
    return ll.chaos_sali(a, b)


def gali(w) -> float:
    """GALI_k of the k rows of w (each normalised): the volume they span."""
    arr = as_float_array(w, "w")
    if arr.ndim != 2:
        raise ValueError(f"w has shape {arr.shape}, expected (k, len)")
    return ll.chaos_gali(arr)
