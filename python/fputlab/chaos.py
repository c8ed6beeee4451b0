"""Chaos indicators: maximum Lyapunov exponent lambda(t), SALI(t), GALI_k(t), classification of
orbits, and the chaotic fraction over disorder realisations (paper Sec. 5, Figs. 11-14)."""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ._arrays import as_float_array, ptr
from ._errors import IntegrationError, check
from ._native import ffi, lib
from .integrate import method_info
from .lattice import C_U64, Lattice, _int, _real


@dataclass
class ChaosResult:
    """lambda(t), SALI(t), GALI(t) at log-spaced times for one orbit."""
    t: np.ndarray
    mle: np.ndarray
    sali: np.ndarray
    gali: np.ndarray
    chaotic: bool              # SALI fell below the threshold
    t_chaotic: float           # when it did (NaN if never)
    t_final: float
    steps: int
    method: str
    completed: bool = True
    message: str = ""
    params: dict = field(default_factory=dict)

    @property
    def mle_final(self) -> float:
        return float(self.mle[-1]) if self.mle.size else float("nan")

    def classify(self, sali_threshold: float = 1e-8) -> str:
        """'chaotic' if SALI fell below the threshold; 'blow-up' if the orbit blew up first;
        otherwise 'regular' when lambda(t) keeps following the 1/t law (lambda t bounded over the
        last decade), else 'undecided'."""
        if self.chaotic or (self.sali.size and np.nanmin(self.sali) < sali_threshold):
            return "chaotic"
        if not self.completed:
            return "blow-up"
        if self.t.size < 3:
            return "undecided"
        late = self.t >= self.t[-1] / 10
        lt = self.mle[late] * self.t[late]
        # regular: lambda*t grows at most like log t (bounded up to slow growth)
        return "regular" if lt[-1] <= 3.0 * max(lt[0], 1.0) + 2 * math.log(10) else "undecided"


def _run_with_progress(lattice, method, io, t0, y, w, co, arrays, res, progress=True) -> int:
    """fpl_chaos_run through the resumable handle in segments of ~0.2 s (pauses fall on
    renormalisation times, so the numbers are those of one call; Ctrl-C is seen between
    segments), with a tqdm bar if `progress`."""
    import time

    from tqdm import tqdm

    from ._errors import Pacer, first_span
    out = ffi.new("fpl_chaos **")
    status = lib.fpl_chaos_create(lattice._h, method.encode(), io, t0, ptr(y), w, co, out)
    if status < 0:
        return status
    c = ffi.gc(out[0], lambda h: lib.fpl_chaos_free(ffi.new("fpl_chaos **", h)))
    span = co.t_end - t0
    pacer = Pacer(max(first_span(io.dt or None, lattice.N, co.n_dev), co.renorm_interval))
    with tqdm(total=span, desc=f"chaos N={lattice.N}", unit="t", disable=None if progress else True,
              bar_format="{l_bar}{bar}| {n:.4g}/{total:.4g} [{elapsed}<{remaining}]") as bar:
        target = t0
        while target < co.t_end:
            target = min(co.t_end, target + pacer.span)
            before, clock = res.t_final, time.perf_counter()
            status = lib.fpl_chaos_advance(c, target, *(ptr(a) for a in arrays))
            lib.fpl_chaos_get_result(c, res)
            pacer.record(res.t_final - before, time.perf_counter() - clock)
            bar.update(res.t_final - t0 - bar.n)
            if status < 0 or lib.fpl_chaos_done(c):
                break
    lib.fpl_chaos_get_result(c, res)
    return status


def lyapunov(lattice: Lattice, t_end: float, *, method: str = "yoshida4", dt: float | None = None,
             rtol: float = 1e-10, atol: float = 1e-12, y0=None, w0=None, n_dev: int = 2,
             renorm_interval: float = 1.0, n_samples: int = 200, t_first_sample: float = 0.0,
             sali_threshold: float = 1e-8, stop_when_chaotic: bool = False, seed: int = 1,
             t0: float = 0.0, progress: bool = False) -> ChaosResult:
    """Follow the orbit y0 (default: the paper's mode-1 state) with n_dev deviation vectors (w0,
    shape (n_dev, 2N), default Gaussian random from `seed`) and return lambda, SALI, GALI_n_dev.

    Fixed-step methods (tangent map) use dt (default 0.01); adaptive methods (variational
    equations, e.g. method="dop853", the paper's choice for model 3) use rtol/atol.
    progress: a progress bar with ETA on a terminal (the same computation, in 100 segments)."""
    if not isinstance(lattice, Lattice):
        raise TypeError(f"lattice must be a fputlab.Lattice, got {type(lattice).__name__}")
    adaptive = method_info(method)["adaptive"]
    N = lattice.N
    y = lattice.mode_state() if y0 is None else as_float_array(y0, "y0", (2 * N,))
    n_dev = _int(n_dev, "n_dev")
    w = ffi.NULL
    if w0 is not None:
        w_arr = as_float_array(w0, "w0", (n_dev, 2 * N))
        w = ptr(w_arr)
    io = ffi.new("fpl_integrator_options *")
    lib.fpl_integrator_options_init(io)
    io.dt = (0.0 if adaptive else 0.01) if dt is None else _real(dt, "dt")
    io.rtol, io.atol = _real(rtol, "rtol"), _real(atol, "atol")
    co = ffi.new("fpl_chaos_options *")
    lib.fpl_chaos_options_init(co)
    co.t_end = _real(t_end, "t_end")
    co.renorm_interval = _real(renorm_interval, "renorm_interval")
    co.n_samples = _int(n_samples, "n_samples")
    co.t_first_sample = _real(t_first_sample, "t_first_sample")
    co.n_dev = n_dev
    co.sali_threshold = _real(sali_threshold, "sali_threshold")
    co.stop_when_chaotic = bool(stop_when_chaotic)
    seed = _int(seed, "seed", C_U64)
    if seed < 0:
        raise ValueError(f"seed must be >= 0 (got {seed})")
    co.seed = seed
    S = max(co.n_samples, 1)
    from ._arrays import check_memory
    check_memory(8.0 * (4 * S + 2 * N * (n_dev + 2)), f"{S} chaos samples (N = {N}, n_dev = {n_dev})")
    t, mle, sali, gali = (np.full(S, np.nan) for _ in range(4))
    res = ffi.new("fpl_chaos_result *")
    interrupted = False
    try:
        status = _run_with_progress(lattice, method, io, _real(t0, "t0"), y, w, co,
                                    (t, mle, sali, gali), res, progress)
    except KeyboardInterrupt:            # keep what was computed (Interrupted.result)
        interrupted, status = True, 0
    k = res.n_samples
    out = ChaosResult(t=t[:k], mle=mle[:k], sali=sali[:k], gali=gali[:k], chaotic=bool(res.chaotic),
                      t_chaotic=res.t_chaotic, t_final=res.t_final, steps=res.steps, method=method,
                      params={"N": N, "model": lattice.model, "tau": lattice.tau,
                              "seed": lattice.seed, "t_end": t_end, "dt": io.dt,
                              "renorm_interval": renorm_interval})
    if interrupted:
        from ._errors import Interrupted
        out.completed, out.message = False, f"interrupted (Ctrl-C) at t = {res.t_final:.10g}"
        raise Interrupted(out.message, out)
    if status < 0:
        try:
            check(status)
        except IntegrationError as err:     # a blow-up: keep what was computed
            out.completed, out.message = False, str(err)
            return out
    return out


def _one_realisation(args):
    N, tau, seed, model, alpha, t_end, method, kwargs = args
    lat = Lattice(N, alpha, model, tau=tau, seed=seed)
    res = lyapunov(lat, t_end, method=method, **kwargs)
    return N, seed, res


def chaotic_fraction(Ns=(4, 8, 16, 32, 64), realisations: int = 30, tau: float = 10.0, *,
                     t_end: float = 1e4, model: str = "nonlinear", alpha: float = 0.25,
                     method: str = "yoshida4", first_seed: int = 1, workers: int | None = None,
                     progress: bool = False, **kwargs) -> dict:
    """Percentage of chaotic orbits (SALI < threshold) over `realisations` disorder draws for each N
    (paper Fig. 14: tau = 10 %, model 3, DOP853, t = 1e8). Realisations run in parallel processes.
    Returns {"N": [...], "percent": [...], "results": {N: [ChaosResult, ...]}}."""
    from .ensemble import check_ensemble, process_pool
    _, Ns, realisations = check_ensemble([tau], Ns, realisations)
    tasks = [(int(N), tau, first_seed + r, model, alpha, t_end, method, kwargs)
             for N in Ns for r in range(realisations)]
    results: dict = {int(N): [] for N in Ns}
    with process_pool(workers) as pool:
        it = pool.map(_one_realisation, tasks)
        if progress:
            from tqdm import tqdm
            it = tqdm(it, total=len(tasks), desc="chaos", disable=None)
        for N, seed, res in it:
            results[N].append(res)
    percent = [100.0 * np.mean([r.classify() == "chaotic" for r in results[int(N)]]) for N in Ns]
    blowups = [int(sum(r.classify() == "blow-up" for r in results[int(N)])) for N in Ns]
    return {"N": [int(N) for N in Ns], "percent": percent, "blowups": blowups, "results": results}


def sali(w1, w2) -> float:
    """SALI of two vectors: min(|w1^ - w2^|, |w1^ + w2^|)."""
    a = as_float_array(w1, "w1")
    b = as_float_array(w2, "w2", a.shape)
    out = ffi.new("double *")
    check(lib.fpl_chaos_sali(ptr(a), ptr(b), a.size, out))
    return out[0]


def gali(w) -> float:
    """GALI_k of the k rows of w (each normalised): the volume they span."""
    arr = as_float_array(w, "w")
    if arr.ndim != 2:
        raise ValueError(f"w has shape {arr.shape}, expected (k, len)")
    out = ffi.new("double *")
    check(lib.fpl_chaos_gali(ptr(arr), arr.shape[0], arr.shape[1], out))
    return out[0]
