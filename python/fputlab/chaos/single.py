"""Chaos indicators of one orbit: maximum Lyapunov exponent lambda(t), SALI(t), GALI_k(t), MEGNO
<Y>(t) and the classification of orbits (paper Sec. 5, Fig. 11)."""
from __future__ import annotations

import time

import numpy as np

from .. import _lowlevel as ll
from .._arrays import as_float_array, check_memory
from .result import ChaosResult
from .._errors import IntegrationError, Interrupted, check, last_error
from .._pacing import Pacer, first_span
from .._validate import C_U64, _int, _real
from ..integrate import method_info
from ..lattice import Lattice

__all__ = ["lyapunov", "sali", "gali", "ENSEMBLE_METHOD", "ENSEMBLE_DT"]


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
        potential's barrier `Lattice.barrier`, 1/alpha for FPUT-alpha, none for alpha^2 <= 4 beta
        or Toda; < 0 turns the check off).

    Returns
    -------
    ChaosResult
        ``t``, ``mle``, ``sali``, ``gali`` and ``megno`` (MEGNO <Y>(t), Cincotta & Simó 2000:
        -> 2 on a quasi-periodic orbit, ~ λt/2 on a chaotic one; from the first deviation
        vector's growth, trapezoid rule on the renormalisation grid, so a `renorm_interval`
        well below the orbit's periods) at the sample times, and whether and when the orbit
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
    check_memory(8.0 * (5 * S + 2 * N * (n_dev + 2)), f"{S} chaos samples (N = {N}, n_dev = {n_dev})")
    t, mle, sali, gali, megno = (np.full(S, np.nan) for _ in range(5))
    res = ll.chaos_result()
    interrupted = False
    try:
        status = _run_with_progress(lattice, method, io, _real(t0, "t0"), y, w, co,
                                    (t, mle, sali, gali, megno), res, progress)
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
                      blew_up=bool(res.blew_up), t_blowup=res.t_blowup, megno=megno[:k])
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
