"""The chaotic fraction over disorder realisations (paper Sec. 5, Figs. 12-14): many orbits of
`fputlab.chaos.lyapunov` (or of the batched kernel) on the ensemble engine."""
from __future__ import annotations

import json
import math
import time
import warnings
from typing import NamedTuple

import numpy as np

from .. import _lowlevel as ll
from .._errors import FputlabError, last_error
from .._validate import C_INT, C_U64, _int, _real
from .._engine import check_ensemble
from ..engine import (DISORDER_COORD_ATTRS, StudyKind, StudyResult, normalise_disorder,
                      run_study, wilson_interval)
from ..integrate import method_info
from ..lattice import Lattice
from .batch import BATCH_METHODS, lyapunov_batch
from .result import CLASSES, ChaosResult
from .single import ENSEMBLE_DT, ENSEMBLE_METHOD, lyapunov

__all__ = ["chaotic_fraction", "ChaoticFraction", "OrbitRecord", "ensemble_defaults"]


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
    """Several realisations of one N in one batched run (fputlab.chaos.batch): the same numbers
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



# ---- the chaos study kind ---------------------------------------------------------------------
# The sample grid is log-spaced at `samples_per_decade` from t_first_sample, independent of t_end:
# the C options get a grid end t_first * 10^K beyond t_end (K decades, n = K*spd + 1 samples:
# the same times for every K), so a study run further keeps its samples and continues every orbit
# bit for bit from its saved state, and every orbit shares one sequence of sample times.

#: samples per decade of the chaos studies' log-spaced grid
SAMPLES_PER_DECADE = 40


def _grid_options(settings: dict, t_end: float) -> tuple[float, int]:
    """(C t_end, C n_samples) whose log-spaced grid holds t_end with samples_per_decade, or the
    fixed grid (sample_grid_end, n_samples) of a study that set one (the studies of Figs. 12-14
    made before the engine: their grid ends at their t_end)."""
    if settings.get("sample_grid_end") is not None:
        return settings["sample_grid_end"], settings["n_samples"]
    t_first = settings["t_first_sample"] or settings["renorm_interval"]
    K = max(1, math.floor(math.log10(t_end / t_first)) + 1)
    return t_first * 10.0 ** K, K * settings["samples_per_decade"] + 1


def _c_options(settings: dict, t_end: float) -> dict:
    T, n = _grid_options(settings, t_end)
    co = {"renorm_interval": settings["renorm_interval"], "n_samples": n,
          "t_first_sample": settings["t_first_sample"], "n_dev": settings["n_dev"],
          "sali_threshold": settings["sali_threshold"],
          "stop_when_chaotic": settings["stop_when_chaotic"], "seed": settings["deviation_seed"]}
    if settings["blowup_stretch"] is not None:
        co["blowup_stretch"] = settings["blowup_stretch"]
    return T, co


def _lattice(settings: dict, N: int, tau: float, seed: int) -> Lattice:
    if settings["model"] == "homogeneous":
        return Lattice(N, settings["alpha"], "homogeneous")
    return Lattice(N, settings["alpha"], settings["model"], tau=tau, seed=seed)


def _initial(settings: dict, lat: Lattice) -> np.ndarray:
    """The orbit's initial state: settings["y0"], or the paper's mode-1 state (Eq. initxi)."""
    if settings["y0"] is not None:
        return np.ascontiguousarray(settings["y0"], dtype=float)
    return lat.mode_state()


def _report(settings, t_end, res, t, mle, sali, gali, megno, message, state, cpu, ended: bool,
            failed=False) -> dict:
    """One orbit's report: its values (class at the end, final indicators, the samples) and, if
    it can go on, its state in the single-orbit checkpoint format."""
    k = int(res.n_samples)
    t, mle, sali, gali, megno = (np.array(a[:k]) for a in (t, mle, sali, gali, megno))
    cls = ll.chaos_classify(bool(res.chaotic), float(res.t_chaotic), bool(res.blew_up),
                            float(res.t_blowup), float(res.t_final), t, mle, math.nan)
    # decided (chaotic with early stop, blown up), at the end of a fixed grid, or failed
    done = bool(ended) or failed
    values = {"orbit_class": cls, "mle": float(res.mle), "sali": float(res.sali),
              "chaotic": bool(res.chaotic), "t_chaotic": float(res.t_chaotic),
              "blew_up": bool(res.blew_up), "t_blowup": float(res.t_blowup),
              "t_final": float(res.t_final), "steps": int(res.steps), "message": message,
              "megno": float(res.megno),
              "t_sample": t, "mle_t": mle, "sali_t": sali, "gali_t": gali, "megno_t": megno}
    return {"t": t_end, "done": done, "message": message, "cpu": cpu, "values": values,
            "state": None if done else state}


#: fpl_chaos_save's accumulators before MEGNO (fputlab <= the chaos subpackage's first study
#: engine): states saved then continue with MEGNO unknown (NaN)
_ACCUMULATORS_BEFORE_MEGNO = 15


def chaos_accumulators(acc) -> np.ndarray:
    """An orbit's saved fpl_chaos accumulators, as fpl_chaos_restore takes them: a state saved
    before MEGNO (15 numbers) gets MEGNO's four as NaN, so it continues bit for bit in every
    other number and reports MEGNO as NaN."""
    acc = np.ascontiguousarray(acc, dtype=float)
    if acc.size == _ACCUMULATORS_BEFORE_MEGNO:
        acc = np.concatenate([acc, np.full(ll.CHAOS_N_ACCUMULATORS - acc.size, np.nan)])
    return acc


def _samples(prev, S: int, rows: int = 1):
    """Sample arrays (t, mle, sali, gali, megno) of length S, holding a previous report's
    samples."""
    out = [np.full(S, np.nan) for _ in range(5)]
    if prev is not None:
        for a, name in zip(out, ("t_sample", "mle_t", "sali_t", "gali_t", "megno_t")):
            if name in prev["values"]:       # a report from before MEGNO has no megno_t
                v = np.asarray(prev["values"][name], float)
                a[:v.size] = v
    return out


def _run_single(settings, N, tau, seed, prev, t_end) -> dict:
    """One orbit through fpl_chaos (any method), from its saved state if any."""
    cpu0 = time.process_time()
    lat = _lattice(settings, N, tau, seed)
    T, co = _c_options(settings, t_end)
    adaptive = method_info(settings["method"])["adaptive"]
    io = ll.integrator_options(0.0 if adaptive else settings["dt"], settings["rtol"],
                               settings["atol"])
    c = ll.ChaosHandle(lat._h, settings["method"], io, 0.0, _initial(settings, lat), None,
                       ll.chaos_options(T, **co))
    ih = c.integrator()
    arrays = _samples(prev, co["n_samples"])
    if prev is not None:
        st = prev["state"]
        ih.restore(int(st["steps"]), float(st["t"]), np.ascontiguousarray(st["y"], float))
        c.restore(chaos_accumulators(st["acc"]))
    message, failed = (prev["message"] if prev is not None else ""), False
    try:
        if c.advance(t_end, *arrays) > 0:
            message = last_error()              # a blow-up: when and why
    except (FputlabError, ValueError) as err:   # a numerical failure: the orbit ends here
        message, failed = str(err), True
    res = c.get_result()
    state = {"steps": np.int64(ih.steps()), "t": np.float64(ih.time()), "y": ih.get_state(),
             "acc": c.save()}
    return _report(settings, t_end, res, *arrays, message, state,
                   time.process_time() - cpu0, c.done(), failed)


def _run_lanes(settings, N, tau, seeds, prevs, t_end) -> list[dict]:
    """Orbits of one N (all at one step) in the vector lanes of the batched kernel: the numbers
    of `_run_single` for each, bit for bit, several times cheaper for small N."""
    cpu0 = time.process_time()
    R = len(seeds)
    lats = [_lattice(settings, N, tau, s) for s in seeds]
    T, co = _c_options(settings, t_end)
    io = ll.integrator_options(settings["dt"])
    y0 = np.ascontiguousarray(np.stack([_initial(settings, lat) for lat in lats]))
    b = ll.ChaosBatchHandle([lat._h for lat in lats], settings["method"], io, 0.0, y0, None,
                            ll.chaos_batch_options(T, **co))
    S = co["n_samples"]
    rows = [_samples(p, S) for p in prevs]
    arrays = [np.ascontiguousarray(np.stack([r[i] for r in rows])) for i in range(5)]
    if prevs[0] is not None:
        st = [p["state"] for p in prevs]
        b.set_orbits([int(x["steps"]) for x in st], [float(x["t"]) for x in st],
                     # a state saved by a single-orbit call is (1 + n_dev, 2N), by lanes flat:
                     # the same numbers in the same order
                     np.stack([np.asarray(x["y"], float).ravel() for x in st]),
                     np.stack([chaos_accumulators(x["acc"]) for x in st]))
    b.advance(t_end, *arrays)
    cpu = (time.process_time() - cpu0) / R
    lane = 2 * N * (settings["n_dev"] + 1)
    out = []
    for r in range(R):
        steps, t, y, acc = b.get_orbit(r, lane)
        res = b.get_result(r)
        state = {"steps": np.int64(steps), "t": np.float64(t), "y": y, "acc": acc}
        out.append(_report(settings, t_end, res, *(a[r] for a in arrays), b.message(r), state,
                           cpu, bool(res.done)))
    return out


def orbit_method(s: dict, given: dict, taus: list) -> bool:
    """The checks the chaos and spectrum kinds share once their settings are completed (`s`,
    from the settings as `given`): no disorder in the homogeneous model, the method a string
    (None: ENSEMBLE_METHOD at ENSEMBLE_DT, unless a dt is given), set in `s`. Returns whether
    the method is adaptive (ValueError naming an unknown one)."""
    if s["model"] == "homogeneous" and any(t != 0 for t in taus):
        raise ValueError("tau: the homogeneous model has no disorder (use tau=0)")
    if s["method"] is None:
        s["method"] = ENSEMBLE_METHOD
        s["dt"] = ENSEMBLE_DT if given.get("dt") is None else given["dt"]
    if not isinstance(s["method"], str):
        raise ValueError(f"method must be a string (got {s['method']!r})")
    return method_info(s["method"])["adaptive"]      # names an unknown method


class ChaosKind(StudyKind):
    """Chaos indicators of one orbit per (N, tau, seed): lambda(t), SALI(t), GALI(t) on a
    log-spaced grid, the class at t_end; the orbit state in the single-orbit checkpoint format,
    so a larger t_end continues it bit for bit. Batchable methods run the orbits of one N in
    the vector lanes."""
    name = "chaos"
    version = 1         # MEGNO added (megno, megno_t): no other number changed, and states
                        # saved before it continue (chaos_accumulators)
    dims = ("N", "tau", "seed")
    batch = 4
    resumable = True
    variables = {
        "orbit_class": ((), str, "", "class of the orbit at t_end (chaotic, regular, blow-up, "
                                     "undecided)"),
        "mle": ((), float, "1", "finite-time maximum Lyapunov exponent at the end"),
        "sali": ((), float, "1", "smaller alignment index at the end"),
        "megno": ((), float, "1", "MEGNO <Y> at the end (-> 2 regular, ~ lambda t/2 chaotic)"),
        "chaotic": ((), bool, "", "SALI fell below its threshold on the finite orbit"),
        "t_chaotic": ((), float, "1", "time SALI fell below its threshold"),
        "blew_up": ((), bool, "", "the orbit blew up"),
        "t_blowup": ((), float, "1", "blow-up time"),
        "t_final": ((), float, "1", "time of the last renormalisation"),
        "steps": ((), np.int64, "1", "integrator steps"),
        "message": ((), str, "", "how the run ended"),
        "t_sample": (("sample",), float, "1", "sample time of the orbit"),
        "mle_t": (("sample",), float, "1", "finite-time maximum Lyapunov exponent"),
        "sali_t": (("sample",), float, "1", "smaller alignment index"),
        "gali_t": (("sample",), float, "1", "generalised alignment index"),
        "megno_t": (("sample",), float, "1", "MEGNO <Y>(t)"),
    }
    coord_attrs = {**DISORDER_COORD_ATTRS,
                   "t": {"long_name": "sample time", "units": "1"}}

    def normalise(self, grid, settings):
        grid, s = normalise_disorder(grid, settings, _CHAOS_SETTINGS, "chaos")
        adaptive = orbit_method(s, settings, grid["tau"])
        for name in ("alpha", "dt", "rtol", "atol", "renorm_interval", "t_first_sample",
                     "sali_threshold"):
            s[name] = _real(s[name], name)
        for name in ("dt", "rtol", "atol", "renorm_interval"):
            if not s[name] > 0 and not (name == "dt" and adaptive):
                raise ValueError(f"{name} must be > 0 (got {s[name]:g})")
        if s["t_first_sample"] < 0:
            raise ValueError(f"t_first_sample must be >= 0 (got {s['t_first_sample']:g})")
        for name, low in (("n_dev", 1), ("samples_per_decade", 1), ("deviation_seed", 0)):
            s[name] = _int(s[name], name, C_U64 if name == "deviation_seed" else C_INT)
            if s[name] < low:
                raise ValueError(f"{name} must be >= {low} (got {s[name]})")
        s["stop_when_chaotic"] = bool(s["stop_when_chaotic"])
        if s["sample_grid_end"] is not None:      # a fixed grid: t_end can not pass its end
            s["sample_grid_end"] = _real(s["sample_grid_end"], "sample_grid_end")
            s["n_samples"] = _int(s["n_samples"], "n_samples")
            if not s["sample_grid_end"] > 0 or s["n_samples"] < 2:
                raise ValueError("a fixed sample grid needs sample_grid_end > 0 and n_samples "
                                 f">= 2 (got {s['sample_grid_end']}, {s['n_samples']})")
        elif s["n_samples"] is not None:
            raise ValueError("n_samples: only with sample_grid_end (a fixed grid); chaos "
                             "studies sample at samples_per_decade")
        if s["y0"] is not None:
            y0 = np.asarray(s["y0"], dtype=float).ravel()
            bad = [N for N in grid["N"] if y0.size != 2 * N]
            if bad or not np.all(np.isfinite(y0)):
                raise ValueError(f"y0 must hold 2N finite values for every N (got {y0.size} "
                                 f"values, N = {grid['N']})")
            s["y0"] = [float(v) for v in y0]
        if s["blowup_stretch"] is not None:
            s["blowup_stretch"] = _real(s["blowup_stretch"], "blowup_stretch")
        return grid, s

    def group(self, coords, settings, previous):
        if settings["method"] not in BATCH_METHODS:
            return None
        steps = int(previous["state"]["steps"]) if previous is not None else 0
        return (coords["N"], coords["tau"], steps)

    def cost(self, coords, settings):
        return float(coords["N"])

    def quantum(self, settings):
        # a call cut short ends on a renormalisation (and a step of the fixed-step methods)
        return max(settings["renorm_interval"], settings["dt"] or 0.0)

    def run(self, settings, coords, previous, t_end):
        if len(coords) == 1 or settings["method"] not in BATCH_METHODS:
            return [_run_single(settings, c["N"], c["tau"], c["seed"], p, t_end)
                    for c, p in zip(coords, previous)]
        c0 = coords[0]
        return _run_lanes(settings, c0["N"], c0["tau"], [c["seed"] for c in coords], previous,
                          t_end)

    def extra_sizes(self, settings, t_end):
        return {"sample": _grid_options(settings, t_end)[1]}

    def extra_coords(self, settings, arrays):
        """The sample times every orbit shares (those of the orbit sampled furthest; an
        orbit stopped as chaotic has one last sample of its own, in t_sample)."""
        ts = arrays["t_sample"]
        if ts.size == 0:
            return {"t": ("sample", np.empty(ts.shape[-1]))}
        ts = ts.reshape(-1, ts.shape[-1])
        t = ts[int(np.argmax(np.sum(np.isfinite(ts), axis=1)))]
        return {"t": ("sample", t)}

    def summary(self, ds):
        rows = []
        cls = ds["orbit_class"].values
        for i, N in enumerate(ds["N"].values):
            for j, tau in enumerate(ds["tau"].values):
                c = cls[i, j]
                n = int(c.size)
                row = {"N": int(N), "tau": float(tau), "n": n}
                row.update({name: int(np.sum(c == name)) for name in CLASSES})
                k = row["chaotic"]
                lo, hi = wilson_interval(k, n)
                row.update({"fraction_chaotic": k / n if n else math.nan,
                            "fraction_chaotic_low": lo, "fraction_chaotic_high": hi})
                b = row["blow-up"]
                lo, hi = wilson_interval(b, n)
                row.update({"fraction_blowup": b / n if n else math.nan,
                            "fraction_blowup_low": lo, "fraction_blowup_high": hi})
                rows.append(row)
        return rows


_C = ll.CHAOS_DEFAULTS
#: the settings of chaos studies and their defaults (C's, from fpl_chaos_options_init; method
#: None: ENSEMBLE_METHOD at ENSEMBLE_DT)
_CHAOS_SETTINGS = {
    "model": "nonlinear", "alpha": 0.25, "method": None, "dt": ll.DT, "rtol": ll.RTOL,
    "atol": ll.ATOL, "renorm_interval": _C["renorm_interval"],
    "t_first_sample": _C["t_first_sample"], "samples_per_decade": SAMPLES_PER_DECADE,
    "n_dev": _C["n_dev"], "sali_threshold": _C["sali_threshold"], "stop_when_chaotic": True,
    "deviation_seed": _C["seed"], "blowup_stretch": None, "y0": None,
    "sample_grid_end": None, "n_samples": None,
}

CHAOS_KIND = ChaosKind()


class ChaoticFraction(StudyResult):
    """The result of `chaotic_fraction`: a `StudyResult` (``to_xarray()``, ``summary()``, a
    one-line repr) that also answers the keys of the dict it used to be ("N", "percent",
    "blowups", "classes", "results"), with a DeprecationWarning."""

    _OLD = ("N", "percent", "blowups", "classes", "results")

    def __getitem__(self, key):
        if key not in self._OLD:
            raise KeyError(key)
        warnings.warn(f"chaotic_fraction(...)[{key!r}] is deprecated: use .summary() or "
                      ".to_xarray()", DeprecationWarning, stacklevel=2)
        return self._legacy()[key]

    def keys(self):
        return list(self._OLD)

    def _legacy(self) -> dict:
        ds = self.dataset
        Ns = [int(n) for n in ds["N"].values]
        rows = {r["N"]: r for r in self.summary() if r["tau"] == float(ds["tau"].values[0])}
        return {"N": Ns,
                "percent": [100.0 * rows[N]["fraction_chaotic"] for N in Ns],
                "blowups": [rows[N]["blow-up"] for N in Ns],
                "classes": {N: {c: rows[N][c] for c in CLASSES} for N in Ns},
                "results": {N: self.orbits(N) for N in Ns}}

    def classes_at(self, t_eval: float, tau: float | None = None) -> dict[int, dict[str, int]]:
        """{N: {class: count}} at time t_eval (and tau: default the first); orbits that have
        not reached t_eval (and were not decided before it) count as 'not reached'."""
        ds = self.dataset
        tau = float(ds["tau"].values[0]) if tau is None else tau
        grid_end = json.loads(ds.attrs["settings"]).get("sample_grid_end") or math.inf
        out = {}
        for N in ds["N"].values:
            counts = dict.fromkeys((*CLASSES, "not reached"), 0)
            finished = ds["finished"].sel(N=N, tau=tau).values
            for r, fin in zip(self.orbits(int(N), tau), finished):
                if r is None:
                    counts["not reached"] += 1
                    continue
                cls = r.classify(t_eval=t_eval)
                t_at = r.t_blowup if r.blew_up else r.t_final
                if cls not in ("chaotic", "blow-up") and t_at < t_eval * (1 - 1e-12) and not (
                        fin and r.t_final >= grid_end):
                    counts["not reached"] += 1
                else:
                    counts[cls] += 1
            out[int(N)] = counts
        return out

    def orbits(self, N: int, tau: float | None = None) -> list:
        """The ChaosResult of every seed at one N (and tau: default the first), in seed order
        (None for an orbit not started)."""
        ds = self.dataset
        sel = ds.sel(N=N, tau=float(ds["tau"].values[0]) if tau is None else tau)
        settings = json.loads(ds.attrs["settings"])
        out = []
        for seed in ds["seed"].values:
            o = sel.sel(seed=seed)
            if not np.isfinite(float(o["t_reached"])):      # not started
                out.append(None)
                continue
            t = o["t_sample"].values
            k = int(np.sum(np.isfinite(t)))
            out.append(ChaosResult(
                t=t[:k], mle=o["mle_t"].values[:k], sali=o["sali_t"].values[:k],
                gali=o["gali_t"].values[:k], chaotic=bool(o["chaotic"]),
                t_chaotic=float(o["t_chaotic"]), t_final=float(o["t_final"]),
                steps=int(o["steps"]), method=settings["method"],
                completed=bool(o["finished"]) or float(o["t_reached"]) >= ds.attrs["t_end"],
                message=str(o["message"].values),
                params={"N": int(N), "model": settings["model"], "tau": float(o["tau"]),
                        "seed": int(seed), "t_end": ds.attrs["t_end"], "dt": settings["dt"],
                        "renorm_interval": settings["renorm_interval"]},
                blew_up=bool(o["blew_up"]), t_blowup=float(o["t_blowup"]),
                megno=o["megno_t"].values[:k] if "megno_t" in o else None))
        return out


def chaotic_fraction(Ns=(4, 8, 16, 32, 64), realisations: int = 30, tau=10.0, *,
                     t_end: float = 1e4, model: str = "nonlinear", alpha: float = 0.25,
                     method: str | None = None, first_seed: int = 1, work_dir=None,
                     overwrite: bool = False, workers: int | None = None, scheduler=None,
                     progress: bool = False, **kwargs) -> ChaoticFraction:
    """Share of chaotic orbits over disorder realisations for each lattice size (paper Fig. 14:
    tau = 10 %, model 3, t = 1e8), and how many blew up: a chaos study of the study engine
    (`fputlab.engine.run_study`, kind "chaos").

    An orbit counts as chaotic when SALI falls below its threshold on the finite orbit
    (`ChaosResult.classify`); a blow-up is never counted as chaotic. The orbits run on the
    ensemble engine (local processes, or a Dask cluster with `scheduler`); the splitting schemes
    run the orbits of one N in the vector lanes of the batched kernel (the same numbers, several
    times cheaper for N <= 16). lambda(t), SALI(t), GALI(t) are sampled log-spaced at
    `samples_per_decade` (default 40) from the first renormalisation, the same times whatever
    t_end.

    Parameters
    ----------
    Ns : sequence of int, optional
        Lattice sizes (each >= 2).
    realisations : int, optional
        Disorder realisations per N (>= 1), seeds ``first_seed, first_seed + 1, ...``.
    tau : float or sequence of float, optional
        Variability in percent (the paper's 10 %); several: a grid over tau.
    t_end : float, optional
        Final time of every orbit. With `work_dir`, a larger t_end than the last run's continues
        every orbit from its saved state (bit for bit).
    model : str, optional
        Lattice model (default "nonlinear", the paper's model 3).
    alpha : float, optional
        Cubic coupling.
    method : str, optional
        Integrator name (default: `ENSEMBLE_METHOD` at ``dt = ENSEMBLE_DT``, validated to
        classify orbits as the paper's methods do).
    first_seed : int, optional
        Disorder seed of the first realisation.
    work_dir : path, optional
        Keep the study on disk: each orbit's result and state written as it finishes; a rerun
        continues, a changed study is refused (default: in memory).
    overwrite : bool, optional
        Discard another study found in `work_dir` instead of refusing.
    workers : int, optional
        Local worker processes (default: all cores).
    scheduler : str or dask.distributed.Client, optional
        Run on a Dask cluster instead (an address "tcp://host:port", a Client or a cluster).
    progress : bool, optional
        A progress bar with a cost-weighted ETA.
    **kwargs
        Chaos settings: dt, rtol, atol, renorm_interval, t_first_sample, samples_per_decade,
        n_dev, sali_threshold, stop_when_chaotic (default True), blowup_stretch, y0 (one
        initial state for every orbit, default the paper's mode-1 state), seed (of the random
        deviation vectors); n_samples (samples up to t_end) is converted to samples per decade.

    Returns
    -------
    ChaoticFraction
        A `fputlab.engine.StudyResult`: ``to_xarray()`` (dims N x tau x seed x sample, the class
        as the string variable ``orbit_class``), ``summary()`` (counts per class, fractions with
        Wilson 95 % intervals), ``orbits(N)`` (ChaosResult per seed).

    Raises
    ------
    ValueError
        Empty `Ns`, a size below 2, `realisations` < 1, an invalid setting (named), or another
        study in `work_dir`.

    Examples
    --------
    >>> from fputlab.chaos import chaotic_fraction
    >>> out = chaotic_fraction(Ns=(4, 8), realisations=4, t_end=1e3)    # doctest: +SKIP
    >>> out.summary()                                                    # doctest: +SKIP
    """
    taus = [float(t) for t in np.atleast_1d(np.asarray(tau, dtype=float))]
    _, Ns, realisations = check_ensemble(taus, Ns, realisations)
    first_seed = _int(first_seed, "first_seed", C_U64)
    settings = dict(kwargs)
    if "seed" in settings:
        settings["deviation_seed"] = settings.pop("seed")
    if "n_samples" in settings:
        n = _int(settings.pop("n_samples"), "n_samples")
        if n < 2:
            raise ValueError(f"n_samples must be >= 2 (got {n})")
        t_first = settings.get("t_first_sample") or settings.get("renorm_interval") or \
            _C["renorm_interval"]
        decades = max(1.0, math.log10(max(_real(t_end, "t_end"), t_first) / t_first))
        settings.setdefault("samples_per_decade", max(1, math.ceil((n - 1) / decades)))
    if "y0" in settings and settings["y0"] is not None:
        settings["y0"] = [float(v) for v in np.asarray(settings["y0"], float).ravel()]
    settings.update(model=model, alpha=alpha, method=method)
    grid = {"N": Ns, "tau": taus, "seed": [first_seed + r for r in range(realisations)]}
    r = run_study("chaos", grid, settings, t_end, work_dir=work_dir, overwrite=overwrite,
                  workers=workers, scheduler=scheduler, progress=progress)
    return ChaoticFraction(r.kind, r.dataset, r.work_dir, r.computed, r.resumed, r.reused)



