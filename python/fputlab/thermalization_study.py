"""Thermalization studies: the equipartition time T_eq against the nonlinearity eps for ensembles
of random-phase states, on the study engine (kind "thermalization"; CLI ``fputlab
thermalization``).

**The kind.** One task is one orbit: a random-phase state of the band of modes at the energy of
its eps (`ThermalizationSpec.energy`), integrated by a fixed-step scheme and sampled on a
log-spaced grid (t = 0, then `samples_per_doubling` samples per factor 2 around `t_first`,
the same times whatever t_end). A sample is the orbit's harmonic wave spectrum averaged over
`sub_samples` states spread over a `window` before it (two periods of the slowest mode by
default), which removes the exchange between kinetic and potential energy that the harmonic
energies of a single orbit still carry; the ensemble average does the rest. A task reports its
spectra, its entropy and n_eff series and the energy range of every sample, and its state (the
integrator's steps, t and y, and the sub-samples already taken for the samples still ahead), so
a larger t_end continues it bit for bit however the time was cut into pieces. An orbit that
crosses the alpha barrier (a blow-up) ends there and leaves the ensemble.

**The driver** (`ThermalizationStudy`). The question "when does the ensemble <eta> fall below
the threshold" is about the ensemble, not one task: the driver runs each eps as its own engine
study (in blocks of `block` orbits, so the ensemble can grow) and calls `run_study` with a
growing t_end (t_first, 2 t_first, 4 t_first, ... up to t_max) until <eta> has crossed the
threshold and 95 % of the bootstrap ensembles have too (T_eq and its interval are then defined),
or t_max. T_eq and its bootstrap interval, and the fits T_eq ~ eps^-a, are computed from the
merged labelled result (`ThermalizationStudy.dataset`, `results`); a fit takes only the points
whose T_eq is at least `MIN_WINDOWS` averaging windows (`resolved`). A killed run loses at most
the piece since the engine's last horizon; a rerun continues.

Built-in studies (`STUDIES`): "alpha" (the eps^-8 law of Onorato et al. 2015), "beta" (the
double scaling of Lvov & Onorato 2018), "beta-overlap" (its eps >= 0.1 with a window short
enough to resolve their T_eq), "toda" (the integrable control), and "disorder"
variants (models 2 and 3 at tau = 5 %, 10 %); "tiny" is a seconds-long grid for the tests.
`migrate_legacy` turns a study of the driver before the engine (one npz per orbit and segment)
into this layout with the same numbers. The parameters and the reasons for them are in
docs/thermalization.md.
"""
from __future__ import annotations

import json
import math
import time
from dataclasses import asdict, dataclass, fields, replace
from pathlib import Path

import numpy as np

from ._errors import IntegrationError
from ._validate import _int, _real
from .engine import StudyKind, grid_values, load_study, run_study
from .initial_states import random_phases, wave_energies
from .integrate import Integrator, method_info
from .lattice import Lattice
from .thermalization import equipartition_time, fit_power_law, information_entropy

__all__ = ["ThermalizationStudy", "ThermalizationSpec", "ThermalizationKind",
           "THERMALIZATION_KIND", "STUDIES", "EPS_KINDS", "FIT_RANGES", "MIN_WINDOWS",
           "check_spec", "window_of", "resolved",
           "sample_times", "migrate_legacy", "projected_cost"]

_FORMAT = "fputlab-thermalization-study-2"
_LEGACY_FORMAT = "fputlab-thermalization-study-1"
EPS_KINDS = ("alpha", "beta")
#: the phase seed of orbit o of point p: seed * _SEED_STRIDE + _POINT_STRIDE * p + o (as before
#: the engine, so a fresh run of a migrated study draws the same states); o < _POINT_STRIDE
_SEED_STRIDE, _POINT_STRIDE = 1_000_003, 1009


# ---- the kind ---------------------------------------------------------------------------------
#: the settings of the kind and their defaults; `eps_points` maps each eps (repr) to its point
#: index (the phase seeds), `legacy_times` are the sample times of a migrated study (the grid
#: then continues from the last one)
_SETTINGS = {"model": "homogeneous", "boundary": "periodic", "N": 32, "alpha": 1.0,
             "beta": 0.0, "tau": 0.0, "eps_kind": "alpha", "band": [1, 2, 3, 4], "seed": 2015,
             "method": "srkn14a6", "dt": 0.5, "t_first": 1000.0, "samples_per_doubling": 6,
             "sub_samples": 8, "window": None, "eps_points": None, "legacy_times": None}


def _energy(settings: dict, eps: float) -> float:
    if settings["eps_kind"] == "alpha":
        return settings["N"] * (eps / settings["alpha"]) ** 2
    return settings["N"] * eps / settings["beta"]


def _lattice(settings: dict, orbit: int) -> Lattice:
    """The lattice of an orbit (disordered models: one draw per orbit, seed + 7919 (orbit + 1))."""
    kw = {}
    if settings["boundary"] != "fixed":
        kw["boundary"] = settings["boundary"]
    if settings["tau"]:
        kw.update(tau=settings["tau"], seed=settings["seed"] + 7919 * (orbit + 1))
    return Lattice(settings["N"], settings["alpha"], settings["model"], beta=settings["beta"],
                   **kw)


def _window(settings: dict) -> float:
    if settings.get("window") is not None:
        return settings["window"]
    N = settings["N"]
    k1 = 2 * math.pi / N if settings["boundary"] == "periodic" else math.pi / (N + 1)
    return 2 * 2 * math.pi / (2 * math.sin(k1 / 2))     # two periods of the slowest mode


def window_of(spec: "ThermalizationSpec") -> float:
    """The averaging window of a study's samples (its `window`, or by default two periods of
    the slowest harmonic mode)."""
    return _window(asdict(spec))


#: a point enters a fit only if its T_eq is at least this many averaging windows after the
#: start: every sample averages the spectrum over the window before it, so eta(t) cannot
#: resolve crossings a few windows from the start (docs/thermalization.md, "Resolution")
MIN_WINDOWS = 4.0


def resolved(t_eq: float, window: float) -> bool:
    """Whether a T_eq is resolved by samples averaged over `window`: T_eq >= MIN_WINDOWS x
    window (False for nan)."""
    return bool(math.isfinite(t_eq) and t_eq >= MIN_WINDOWS * window)


def sample_times(settings: dict, t_end: float) -> np.ndarray:
    """The sample times up to t_end: 0, t_first 2^k for k = 1-m..0 (m = samples_per_doubling;
    the early transient, doubling), then t_first 2^(j/m), j = 1, 2, ...; a migrated study's
    `legacy_times` and then legacy[-1] 2^(j/m). The same times whatever t_end: a study run
    further keeps its samples."""
    m = settings["samples_per_doubling"]
    legacy = settings.get("legacy_times") or []
    top = t_end * (1 + 1e-12)
    if legacy:
        base = [t for t in legacy if t <= top]
        if len(base) < len(legacy):
            return np.array(base)
        t0 = legacy[-1]
    else:
        t0 = settings["t_first"]
        base = [0.0] + [t0 * 2.0 ** k for k in range(1 - m, 1)]
    n = math.floor(m * math.log2(top / t0)) + 2 if top > t0 else 0
    extra = [t0 * 2.0 ** (j / m) for j in range(1, n + 1)]
    return np.array([t for t in base + extra if t <= top])


def _n_modes(settings: dict) -> int:
    return settings["N"] if settings["boundary"] == "fixed" else settings["N"] - 1


class ThermalizationKind(StudyKind):
    """One random-phase orbit per (eps, orbit): its window-averaged wave spectrum, entropy and
    n_eff on a log-spaced grid, and its state, so a larger t_end continues it bit for bit (see
    the module docstring)."""
    name = "thermalization"
    version = 1
    dims = ("eps", "orbit")
    variables = {
        "wave_energy": (("sample", "mode"), float, "1",
                        "harmonic wave energy e_k, averaged over the sample's window"),
        "entropy": (("sample",), float, "1",
                    "information entropy S = sum_k f_k ln f_k of the orbit's spectrum"),
        "n_eff": (("sample",), float, "1", "effective fraction of modes exp(-S/M)"),
        "energy_max": (("sample",), float, "1", "largest total energy in the sample's window"),
        "energy_min": (("sample",), float, "1", "smallest total energy in the sample's window"),
        "E0": ((), float, "1", "total energy of the initial state"),
        "failed": ((), bool, "", "the orbit failed (crossed the alpha barrier): it leaves the "
                                 "ensemble"),
        "steps": ((), np.int64, "1", "integrator steps"),
        "message": ((), str, "", "how the orbit ended"),
        "cpu": ((), float, "s", "CPU seconds spent on the orbit so far"),
    }
    coord_attrs = {"eps": {"long_name": "nonlinearity eps", "units": "1"},
                   "orbit": {"long_name": "orbit of the ensemble (random phases)", "units": "1"},
                   "t": {"long_name": "sample time", "units": "1"},
                   "mode": {"long_name": "wave number index k", "units": "1"}}

    def normalise(self, grid, settings):
        eps = grid_values(grid["eps"], "eps", float, 0.0)
        if any(e <= 0 for e in eps):
            raise ValueError(f"eps must be > 0 (got {eps})")
        orbits = grid_values(grid["orbit"], "orbit", int, 0)
        if max(orbits) >= _POINT_STRIDE:
            raise ValueError(f"orbit must be < {_POINT_STRIDE} (got {max(orbits)})")
        unknown = set(settings) - set(_SETTINGS)
        if unknown:
            raise ValueError(f"{', '.join(sorted(unknown))}: not a setting of thermalization "
                             f"studies (known: {', '.join(sorted(_SETTINGS))})")
        s = {**_SETTINGS, **{k: v for k, v in settings.items() if v is not None}}
        s["N"] = _int(s["N"], "N")
        if s["N"] < 4:
            raise ValueError(f"N must be >= 4 (got {s['N']})")
        if s["eps_kind"] not in EPS_KINDS:
            raise ValueError(f"eps_kind must be one of {EPS_KINDS}, got {s['eps_kind']!r}")
        for name in ("alpha", "beta", "tau", "dt", "t_first"):
            s[name] = _real(s[name], name)
        coupling = s[s["eps_kind"]]
        if not (math.isfinite(coupling) and coupling > 0):
            raise ValueError(f"{s['eps_kind']} must be > 0 for eps_kind={s['eps_kind']!r}")
        for name in ("dt", "t_first"):
            if not (math.isfinite(s[name]) and s[name] > 0):
                raise ValueError(f"{name} must be finite and > 0 (got {s[name]:g})")
        for name in ("samples_per_doubling", "sub_samples", "seed"):
            s[name] = _int(s[name], name)
            if s[name] < (0 if name == "seed" else 1):
                raise ValueError(f"{name} must be >= 1 (got {s[name]})")
        if not isinstance(s["method"], str) or method_info(s["method"])["adaptive"]:
            raise ValueError(f"method {s['method']!r} is adaptive: a study runs a fixed-step "
                             "scheme")
        if s["window"] is not None:
            s["window"] = _real(s["window"], "window")
            if not s["window"] >= 0:
                raise ValueError("window must be >= 0")
        s["band"] = [int(k) for k in np.atleast_1d(s["band"])]
        points = dict(s["eps_points"] or {})
        s["eps_points"] = {repr(e): int(points.get(repr(e), i)) for i, e in enumerate(eps)}
        if s["legacy_times"] is not None:
            lt = [float(t) for t in s["legacy_times"]]
            if not lt or lt[0] != 0.0 or any(b <= a for a, b in zip(lt, lt[1:])):
                raise ValueError("legacy_times must ascend from 0")
            s["legacy_times"] = lt
        _lattice(s, 0)                              # model, boundary, tau checked there
        return {"eps": eps, "orbit": orbits}, s

    def cost(self, coords, settings):
        return float(settings["N"])

    def run(self, settings, coords, previous, t_end):
        return [_run_orbit(settings, c["eps"], c["orbit"], p, t_end)
                for c, p in zip(coords, previous)]

    def extra_sizes(self, settings, t_end):
        return {"sample": len(sample_times(settings, t_end)), "mode": _n_modes(settings)}

    def extra_coords(self, settings, arrays):
        n = arrays["wave_energy"].shape[-2]
        ts = sample_times(settings, _FAR)[:n]
        return {"t": ("sample", ts), "mode": ("mode", np.arange(1, _n_modes(settings) + 1))}

    def summary(self, ds):
        rows = []
        for eps in ds["eps"].values:
            r = _point_result(ds.sel(eps=eps), threshold=0.1, n_boot=100, seed=0)
            rows.append({"eps": float(eps), "n": r["orbits"], "failed": r["failed"],
                         "t_reached": r["t_reached"], "eta_last": r["eta_last"],
                         "t_eq": r["t_eq"], "t_eq_low": r["interval"][0],
                         "t_eq_high": r["interval"][1]})
        return rows


#: a time past every sample a merged result can hold (its coordinates are cut to size)
_FAR = 1e30


def _sub_times(settings: dict, ts: np.ndarray) -> np.ndarray:
    """(S, sub) times of each sample's window (t - w, t], cut at 0; after a migrated study's
    last legacy sample, cut there (its orbits' states are there; the driver before the engine
    cut its windows at the start of each segment the same way)."""
    w = _window(settings)
    sub = settings["sub_samples"]
    back = w * (np.arange(sub) + 1.0) / sub
    legacy = settings.get("legacy_times") or []
    floor = np.where(ts > legacy[-1], legacy[-1], 0.0) if legacy else np.zeros(ts.shape)
    return np.maximum(ts[:, None] - w + back[None, :], floor[:, None])


def _run_orbit(settings: dict, eps: float, orbit: int, prev, t_end: float) -> dict:
    """Advance one orbit to t_end from its previous report (None: from its random-phase state)."""
    cpu0 = time.process_time()
    lat = _lattice(settings, orbit)
    point = settings["eps_points"][repr(eps)]
    y0 = random_phases(lat, energy=_energy(settings, eps), modes=settings["band"],
                       seed=settings["seed"] * _SEED_STRIDE + _POINT_STRIDE * point + orbit)
    it = Integrator(lat, y0, method=settings["method"], dt=settings["dt"])
    M = _n_modes(settings)
    sub = settings["sub_samples"]
    ts = sample_times(settings, t_end)
    S = ts.size
    vals = {"wave_energy": np.full((S, M), np.nan), "entropy": np.full(S, np.nan),
            "n_eff": np.full(S, np.nan), "energy_max": np.full(S, np.nan),
            "energy_min": np.full(S, np.nan)}
    t_prev, n_done = -math.inf, 0
    pend_t, pend_e, pend_en = np.empty(0), np.empty((0, M)), np.empty(0)
    if prev is not None:
        for k in vals:
            v = np.asarray(prev["values"][k], float)
            vals[k][:v.shape[0]] = v[:S]
        st = prev["state"]
        it.restore(int(st["steps"]), float(st["t"]), np.asarray(st["y"], float).reshape(1, -1))
        # sub-samples at times <= taken_until were taken before (a migrated state: just below
        # its last sample, whose time the next windows start at)
        t_prev = float(st["taken_until"]) if "taken_until" in st else \
            float(prev["t"]) * (1 + 1e-12)
        n_done = int(st["n_samples"])
        pend_t = np.asarray(st["pend_t"], float)
        pend_e = np.asarray(st["pend_e"], float).reshape(-1, M)
        pend_en = np.asarray(st["pend_en"], float)
    # the samples ahead: those up to t_end are finished now; the windows of the next ones may
    # start before t_end (their early sub-samples are taken now and kept in the state)
    upto = t_end * (1 + 1e-12)                  # a sample at t_end (up to rounding) is taken
    ahead = sample_times(settings, 2 * t_end + 2 * _window(settings) + 1.0)[n_done:]
    subs = _sub_times(settings, ahead)                       # (A, sub)
    flat = subs.ravel()
    new = (flat > t_prev) & (flat <= upto)
    order = np.flatnonzero(new)[np.argsort(flat[new], kind="stable")]
    e_all = np.full((flat.size, M), np.nan)
    en_all = np.full(flat.size, np.nan)
    old = flat <= t_prev
    if not np.array_equal(flat[old], pend_t):
        raise ValueError("state: the sub-samples kept do not match the sample grid (a state "
                         "of other settings?)")
    e_all[old], en_all[old] = pend_e, pend_en
    message, failed = "", False
    try:
        if order.size:
            _, states, _, energies = it.sample(flat[order], states=True, mode_energies=False,
                                               energies=True)
            e_all[order] = wave_energies(lat, states[:, 0, :])
            en_all[order] = energies
    except IntegrationError as err:
        # an alpha-FPUT orbit can cross its barrier (blow-up): it leaves the ensemble
        message, failed = str(err), True
    complete = ahead <= upto
    for j in np.flatnonzero(complete):
        rows = slice(j * sub, (j + 1) * sub)
        i = n_done + j
        if failed or not np.all(np.isfinite(e_all[rows])):
            continue
        e = e_all[rows].mean(axis=0)
        vals["wave_energy"][i] = e
        vals["energy_max"][i] = en_all[rows].max()
        vals["energy_min"][i] = en_all[rows].min()
        S_i = float(information_entropy(e))
        vals["entropy"][i] = S_i
        vals["n_eff"][i] = math.exp(-S_i / M)
    n_new = n_done + int(complete.sum())
    keep = slice(int(complete.sum()) * sub, None)
    taken = flat[keep] <= upto
    state = None if failed else {
        "steps": np.int64(it.steps), "t": np.float64(it.t), "y": it.state[0],
        "n_samples": np.int64(n_new), "taken_until": np.float64(upto),
        "pend_t": flat[keep][taken],
        "pend_e": e_all[keep][taken], "pend_en": en_all[keep][taken]}
    cpu = time.process_time() - cpu0
    values = {**vals, "E0": float(lat.energy(y0)), "failed": failed, "steps": int(it.steps),
              "message": message,
              "cpu": cpu + (float(prev["values"]["cpu"]) if prev is not None else 0.0)}
    return {"t": t_end, "done": failed, "message": message, "cpu": cpu, "values": values,
            "state": state}


THERMALIZATION_KIND = ThermalizationKind()


# ---- the analysis of a merged result ----------------------------------------------------------
def _point_result(ds, *, threshold: float, n_boot: int, seed: int) -> dict:
    """T_eq and its bootstrap interval of one eps of a merged result (dims orbit x sample x
    mode), over the orbits that have samples and did not fail."""
    e = np.asarray(ds["wave_energy"].values, float)                    # (R, S, M)
    t = np.asarray(ds["t"].values if "t" in ds.coords else ds["t_sample"].values, float)
    failed = np.asarray(ds["failed"].values, bool)
    reached = np.asarray(ds["t_reached"].values, float)
    started = np.isfinite(reached)
    # the orbits that reached the point's time (a block still running, or stopped between the
    # engine's horizons, joins once it has caught up)
    top = np.max(reached[started & ~failed]) if np.any(started & ~failed) else 0.0
    keep = started & ~failed & (reached >= top * (1 - 1e-12))
    row = {"t_eq": math.nan, "interval": (math.nan, math.nan), "t_reached": 0.0,
           "eta_last": math.nan, "energy_error": math.nan, "orbits": int(keep.sum()),
           "failed": int((started & failed).sum()), "cpu": 0.0}
    if keep.sum() < 2:
        return row
    e = e[keep]
    # the samples every kept orbit has reached
    ok = np.all(np.isfinite(e), axis=(0, 2))
    n = int(np.argmin(ok)) if not ok.all() else ok.size
    if n < 2:
        return row
    e, t = e[:, :n], t[:n]
    res = equipartition_time(t, e, threshold=threshold, n_boot=n_boot, seed=seed)
    E0 = np.asarray(ds["E0"].values, float)[keep]
    emax = np.asarray(ds["energy_max"].values, float)[keep][:, :n]
    emin = np.asarray(ds["energy_min"].values, float)[keep][:, :n]
    err = float(np.nanmax(np.abs(np.concatenate([emax, emin], axis=1) / E0[:, None] - 1)))
    row.update(t_eq=res["t_eq"], interval=res["interval"], boot=res["boot"], t=t,
               eta=res["eta"], t_reached=float(t[-1]), eta_last=float(res["eta"][-1]),
               energy_error=err)
    return row


# ---- the driver -------------------------------------------------------------------------------
@dataclass(frozen=True)
class ThermalizationSpec:
    """What a study is: a study directory is only ever continued with the same spec (more eps
    after the stored ones, more orbits and a larger t_max are allowed).

    eps: with ``eps_kind="alpha"``, eps = alpha sqrt(E/N) (the ratio of cubic to quadratic
    bond energy); with ``"beta"``, eps = beta E/N (quartic to quadratic). E is the total energy.
    """
    label: str = "alpha"
    model: str = "homogeneous"
    boundary: str = "periodic"
    N: int = 32
    alpha: float = 1.0
    beta: float = 0.0
    tau: float = 0.0
    eps_kind: str = "alpha"
    eps: tuple = (0.2, 0.17, 0.15, 0.13)
    band: tuple = (1, 2, 3, 4)
    orbits: int = 16
    block: int = 16
    seed: int = 2015
    method: str = "srkn14a6"
    dt: float = 0.5
    t_first: float = 1000.0
    t_max: float = 1.6e7
    samples_per_doubling: int = 6
    sub_samples: int = 8
    window: float | None = None
    threshold: float = 0.1
    n_boot: int = 400

    def energy(self, eps: float) -> float:
        """Total energy E of the point eps."""
        return _energy(asdict(self), eps)

    def settings(self, point: int) -> dict:
        """The engine settings of point `point` (an engine study of its own)."""
        return {"model": self.model, "boundary": self.boundary, "N": self.N,
                "alpha": self.alpha, "beta": self.beta, "tau": self.tau,
                "eps_kind": self.eps_kind, "band": list(self.band), "seed": self.seed,
                "method": self.method, "dt": self.dt, "t_first": self.t_first,
                "samples_per_doubling": self.samples_per_doubling,
                "sub_samples": self.sub_samples, "window": self.window,
                "eps_points": {repr(float(self.eps[point])): point}}

    def to_json(self) -> str:
        d = asdict(self)
        d["eps"], d["band"] = list(d["eps"]), list(d["band"])
        return json.dumps({"format": _FORMAT, **d}, sort_keys=True)


def check_spec(spec: ThermalizationSpec) -> ThermalizationSpec:
    """The spec with its values checked (ValueError/TypeError naming the field)."""
    if not isinstance(spec, ThermalizationSpec):
        raise TypeError(f"spec must be a ThermalizationSpec, got {type(spec).__name__}")
    eps = tuple(float(_real(e, "eps")) for e in spec.eps)
    if not eps or not all(math.isfinite(e) and e > 0 for e in eps):
        raise ValueError(f"eps must be a non-empty list of values > 0 (got {spec.eps})")
    if len(set(eps)) != len(eps):
        raise ValueError(f"eps must not repeat values (got {spec.eps})")
    for name in ("orbits", "block", "n_boot"):
        if _int(getattr(spec, name), name) < (0 if name == "n_boot" else 1):
            raise ValueError(f"{name} must be >= 1 (got {getattr(spec, name)})")
    if spec.orbits < 2:
        raise ValueError(f"orbits must be >= 2 for an ensemble (got {spec.orbits})")
    if spec.orbits % spec.block:
        raise ValueError(f"orbits must be a multiple of block = {spec.block} (got "
                         f"{spec.orbits})")
    if spec.orbits > _POINT_STRIDE:
        raise ValueError(f"orbits must be <= {_POINT_STRIDE} (got {spec.orbits})")
    v = _real(spec.t_max, "t_max")
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"t_max must be finite and > 0 (got {v:g})")
    if spec.t_max < spec.t_first:
        raise ValueError(f"t_max ({spec.t_max:g}) must be >= t_first ({spec.t_first:g})")
    if not 0 < _real(spec.threshold, "threshold") < 1:
        raise ValueError(f"threshold must lie in (0, 1) (got {spec.threshold:g})")
    spec = replace(spec, eps=eps, band=tuple(int(k) for k in spec.band))
    THERMALIZATION_KIND.normalise({"eps": [eps[0]], "orbit": [0]}, spec.settings(0))
    return spec


#: the built-in studies; "tiny" is for the tests (seconds)
STUDIES = {
    # alpha-FPUT, eps = alpha sqrt(E/N): 0.05-0.11 spans ~3 decades of T_eq; above ~0.12 the
    # thermal state crosses the barrier r = -1/alpha within T_eq (orbits blow up)
    "alpha": ThermalizationSpec(eps=(0.11, 0.1, 0.09, 0.08, 0.07, 0.06, 0.05), t_max=6.4e7),
    # beta-FPUT, eps = beta E/N: both sides of the Chirikov overlap; dt = 0.2 keeps |dE/E| <
    # 1e-6 at eps = 1
    "beta": ThermalizationSpec(label="beta", alpha=0.0, beta=1.0, eps_kind="beta",
                               eps=(1.0, 0.5, 0.3, 0.2, 0.1, 0.07, 0.05, 0.03, 0.02, 0.015),
                               dt=0.2, t_first=100.0),
    # beta-FPUT past the overlap, resolved: T_eq ~ 100-1000 there, so a window of 16 (one
    # period of the slowest mode's energy exchange, half its period) sampled 16 times, and a
    # finer grid from t = 25 (the "beta" study's window 64 leaves eps >= 0.3 unresolved)
    "beta-overlap": ThermalizationSpec(label="beta-overlap", alpha=0.0, beta=1.0,
                                       eps_kind="beta", eps=(0.5, 0.3, 0.2, 0.1), orbits=64,
                                       dt=0.2, t_first=25.0, t_max=1.6e5,
                                       samples_per_doubling=8, window=16.0, sub_samples=16),
    # the integrable control at the alpha study's eps, run ~5x past the alpha T_eq there
    "toda": ThermalizationSpec(label="toda", model="toda", eps=(0.1, 0.08), t_max=1.6e6),
    "tiny": ThermalizationSpec(label="tiny", boundary="fixed", N=8, alpha=1.0,
                               eps=(0.2, 0.15), band=(1,), orbits=4, block=4, dt=0.2,
                               t_first=50.0, t_max=800.0, samples_per_doubling=4,
                               sub_samples=4, window=8.0, threshold=0.3, n_boot=50),
}


def _disorder_study(model: str, tau: float) -> tuple[str, ThermalizationSpec]:
    """Models 2 and 3 (one disorder draw per orbit) at eps of the alpha study, for T_eq and
    its exponent to set beside the homogeneous chain's."""
    label = f"disorder-{model}-{tau:g}"
    return label, ThermalizationSpec(label=label, model=model, tau=tau,
                                     eps=(0.1, 0.08, 0.07, 0.06), t_max=3.2e6)


STUDIES.update(_disorder_study(m, t) for m in ("nonlinear", "hamiltonian") for t in (5.0, 10.0))


#: eps ranges fitted on their own as well (the beta study's double scaling: its two sides of
#: the Chirikov overlap, located from the local slopes of T_eq; docs/thermalization.md)
FIT_RANGES = {"beta": ((0.0, 0.07), (0.1, 0.5))}


def _spec_from_json(text: str) -> ThermalizationSpec:
    d = json.loads(text)
    if d.pop("format", None) != _FORMAT:
        raise ValueError("study.json: not a fputlab thermalization study (of the engine)")
    names = {f.name for f in fields(ThermalizationSpec)}
    unknown = set(d) - names
    if unknown:
        raise ValueError(f"study.json: unknown fields {sorted(unknown)}")
    for k in ("eps", "band"):
        d[k] = tuple(d.get(k, ()))
    return ThermalizationSpec(**d)


def _atomic_text(path: Path, text: str) -> None:
    from .io.atomic import write_bytes_atomic
    write_bytes_atomic(path, text.encode())


class ThermalizationStudy:
    """A study in a work directory: `run` advances it in bounded pieces, `dataset` is the
    merged labelled result, `results` its analysis (T_eq per eps, fits).

    Layout: ``work_dir/study.json`` (the spec) and one engine study per eps and block of
    orbits, ``work_dir/p<point>_eps<eps>/b<block>/``.

    Parameters
    ----------
    work_dir : str or Path
        Its directory (created; an existing one must hold the same spec, or one it may grow
        into: more eps after the stored ones, more orbits, a larger t_max).
    spec : ThermalizationSpec, optional
        The study (default: the one in work_dir/study.json; a new directory needs one).
    """

    def __init__(self, work_dir, spec: ThermalizationSpec | None = None):
        self.work = Path(work_dir)
        stored = self.work / "study.json"
        if stored.exists():
            old = _spec_from_json(stored.read_text())
            if spec is not None:
                new = check_spec(spec)
                same = replace(new, eps=old.eps, t_max=old.t_max, orbits=old.orbits)
                if same.to_json() != old.to_json() or new.eps[:len(old.eps)] != old.eps:
                    raise ValueError(f"work_dir: {self.work} holds a different study; use a "
                                     "new directory (a study can only get more eps, more "
                                     "orbits or a larger t_max)")
                grown = replace(old, eps=new.eps, t_max=max(old.t_max, new.t_max),
                                orbits=max(old.orbits, new.orbits))
                if grown.to_json() != old.to_json():
                    _atomic_text(stored, grown.to_json())
                old = grown
            self.spec = old
        else:
            if spec is None:
                raise ValueError(f"work_dir: {self.work} holds no study; give a spec")
            self.spec = check_spec(spec)
            if self.work.exists() and any(self.work.iterdir()):
                raise ValueError(f"work_dir: {self.work} exists and is not a study directory")
            self.work.mkdir(parents=True, exist_ok=True)
            _atomic_text(stored, self.spec.to_json())

    # -- layout ------------------------------------------------------------------------------
    def point_dir(self, point: int) -> Path:
        return self.work / f"p{point:02d}_eps{self.spec.eps[point]!r}"

    def _block_dir(self, point: int, block: int) -> Path:
        return self.point_dir(point) / f"b{block:02d}"

    def _blocks(self, point: int) -> list[int]:
        """The blocks of the point's ensemble (those of `orbits`, and any more on disk)."""
        n = self.spec.orbits // self.spec.block
        on_disk = [int(p.name[1:]) for p in self.point_dir(point).glob("b[0-9]*")
                   if (p / "study.json").exists()]
        return sorted(set(range(n)) | set(on_disk))

    def _settings(self, point: int) -> dict:
        """The point's settings: those of its first stored block (a migrated point keeps its
        sample times), else the spec's."""
        for b in self._blocks(point):
            desc = self._block_dir(point, b) / "study.json"
            if desc.exists():
                return json.loads(desc.read_text())["settings"]
        return self.spec.settings(point)

    def _grid(self, point: int, block: int) -> dict:
        B = self.spec.block
        return {"eps": [self.spec.eps[point]], "orbit": list(range(block * B, (block + 1) * B))}

    def _reached(self, point: int, block: int) -> float:
        from .io.store import StudyStore
        d = self._block_dir(point, block)
        if not (d / "study.json").exists():
            return 0.0
        return StudyStore.reader(d).t_end() or 0.0

    # -- the merged result -------------------------------------------------------------------
    def point_dataset(self, point: int):
        """The merged result of one eps (dims eps x orbit x sample x mode), None if nothing
        has run."""
        import xarray as xr
        parts = [load_study(self._block_dir(point, b)).to_xarray() for b in self._blocks(point)
                 if (self._block_dir(point, b) / "study.json").exists()]
        if not parts:
            return None
        # a block behind the others (still catching up) has fewer samples: NaN-padded (its
        # orbits do not count until they have reached the point's time, `_point_result`)
        n = max(p.sizes["sample"] for p in parts)
        longest = next(p for p in parts if p.sizes["sample"] == n)
        parts = [p.drop_vars("t").pad(sample=(0, n - p.sizes["sample"])).assign_coords(
            t=longest["t"]) for p in parts]
        return xr.concat(parts, dim="orbit", data_vars="minimal", coords="minimal",
                         compat="override", combine_attrs="override")

    def dataset(self):
        """The merged labelled result of every eps that has run: dims eps x orbit x sample x
        mode, the sample times as ``t_sample`` (eps x sample; a migrated point has its own)."""
        import xarray as xr
        parts = []
        for p in range(len(self.spec.eps)):
            ds = self.point_dataset(p)
            if ds is not None:
                t = ds["t"].values
                ds = ds.drop_vars("t").assign(
                    t_sample=(("eps", "sample"), t[None, :], {"long_name": "sample time"}))
                parts.append(ds)
        if not parts:
            return None
        # the points reached different times: pad the sample axis (NaN) to the longest
        n = max(ds.sizes["sample"] for ds in parts)
        parts = [ds.pad(sample=(0, n - ds.sizes["sample"])) if ds.sizes["sample"] < n else ds
                 for ds in parts]
        out = xr.concat(parts, dim="eps", join="outer", data_vars="all", coords="minimal",
                        compat="override", combine_attrs="drop_conflicts",
                        fill_value={"failed": False, "finished": False, "message": "",
                                    "steps": 0, "wave_energy": np.nan})
        out.attrs.update({"study": self.spec.to_json(), "kind": "thermalization"})
        return out

    # -- running -----------------------------------------------------------------------------
    def _point_state(self, point: int) -> dict:
        ds = self.point_dataset(point)
        reached = [self._reached(point, b) for b in self._blocks(point)]
        if ds is None:
            return {"reached": reached, "finished": False, "row": None}
        row = _point_result(ds.isel(eps=0), threshold=self.spec.threshold, n_boot=100,
                            seed=self.spec.seed)
        full = min(reached) >= self.spec.t_max * (1 - 1e-12)
        crossed = (math.isfinite(row["t_eq"]) and "boot" in row
                   and np.isfinite(row["boot"]).mean() >= 0.95)
        # blocks added later (a larger ensemble) first catch up with the others
        even = min(reached) >= max(reached)
        return {"reached": reached, "row": row,
                "finished": bool(full or even and (row["orbits"] < 2 or crossed))}

    def run(self, *, t_until: float | None = None, max_seconds: float | None = None,
            workers: int = 1, points=None, progress=None) -> bool:
        """Advance the points (all, or the indices `points`), t_end doubling from t_first, up
        to `t_until` (default t_max) or for about `max_seconds` of wall time (checked between
        engine runs). Returns True when every point run is complete (crossed, or at t_max)."""
        spec = self.spec
        t_until = spec.t_max if t_until is None else _real(t_until, "t_until")
        workers = _int(workers, "workers")
        if workers < 1:
            raise ValueError(f"workers must be >= 1 (got {workers})")
        deadline = None if max_seconds is None else time.monotonic() + _real(max_seconds,
                                                                             "max_seconds")
        todo = range(len(spec.eps)) if points is None else points
        complete = True
        for p in todo:
            settings = self._settings(p)
            while True:
                st = self._point_state(p)
                if st["finished"]:
                    break
                reached = st["reached"]
                top = max(reached)
                # every block first to the time the furthest has reached; then doubling
                target = top if min(reached) < top else (
                    spec.t_first if top == 0 else min(_next_end(spec.t_first, top), spec.t_max))
                if target > t_until * (1 + 1e-12) or target <= min(reached):
                    complete = False
                    break
                if deadline is not None and time.monotonic() > deadline:
                    return False
                for b in self._blocks(p):
                    if self._reached(p, b) < target:
                        run_study("thermalization", self._grid(p, b), settings, target,
                                  work_dir=self._block_dir(p, b), workers=workers)
                        if progress:
                            progress(p, b, target)
        return complete

    # -- results -----------------------------------------------------------------------------
    def results(self, fit_ranges=None) -> dict:
        """Per point: eps, E, orbits, T_eq with its bootstrap interval, eta(t), the energy
        error, the CPU time and ``resolved`` (T_eq >= `MIN_WINDOWS` averaging windows); the
        power-law fit over the resolved points (``fit``) and one per eps range
        (``range_fits``; `fit_ranges` [(lo, hi), ...], default `FIT_RANGES` of the study's
        label). Points that crossed too early to be resolved are listed, never fitted."""
        spec = self.spec
        window = window_of(spec)
        points = []
        for p, eps in enumerate(spec.eps):
            ds = self.point_dataset(p)
            row = {"eps": eps, "E": spec.energy(eps), "t_eq": math.nan,
                   "interval": (math.nan, math.nan), "t_reached": 0.0, "eta_last": math.nan,
                   "energy_error": math.nan, "cpu": 0.0, "orbits": 0, "failed": 0}
            if ds is not None:
                r = _point_result(ds.isel(eps=0), threshold=spec.threshold, n_boot=spec.n_boot,
                                  seed=spec.seed + p)
                row.update(r)
                row["cpu"] = float(np.nansum(ds["cpu"].values))
            row["resolved"] = resolved(row["t_eq"], window)
            points.append(row)

        def fit_of(rows):
            rows = [r for r in rows if r["resolved"]]
            if len(rows) < 2:
                return None
            boot = np.array([r["boot"] for r in rows])
            return fit_power_law([r["eps"] for r in rows], [r["t_eq"] for r in rows],
                                 boot if spec.n_boot else None)

        ranges = FIT_RANGES.get(spec.label, ()) if fit_ranges is None else fit_ranges
        range_fits = []
        for lo, hi in ranges:
            f = fit_of([r for r in points if lo <= r["eps"] <= hi])
            if f is not None:
                range_fits.append({"range": (float(lo), float(hi)), **f})
        return {"spec": asdict(spec), "points": points, "fit": fit_of(points),
                "range_fits": range_fits, "window": window, "min_windows": MIN_WINDOWS}


def _next_end(t_first: float, t: float) -> float:
    """The next t_end after t: t_first 2^k (the doubling), the first one above t."""
    k = max(0, math.floor(math.log2(t / t_first)) + 1)
    end = t_first * 2.0 ** k
    return end if end > t * (1 + 1e-12) else t_first * 2.0 ** (k + 1)


def projected_cost(spec: ThermalizationSpec, seconds_per_step: float, t_eq: dict) -> dict:
    """Projected CPU time (s, one core) of each point: orbits x (time to T_eq, rounded up to
    the t_end where the driver stops, or t_max) / dt x seconds_per_step, with `t_eq` {eps:
    expected T_eq} (e.g. from a fitted law)."""
    out = {}
    for eps in spec.eps:
        target = t_eq.get(eps, math.inf)
        stop = spec.t_first
        while stop < min(2 * target, spec.t_max):
            stop = min(2 * stop, spec.t_max)
        out[eps] = spec.orbits * stop / spec.dt * seconds_per_step
    return out


# ---- migration --------------------------------------------------------------------------------
def migrate_legacy(old_dir, new_dir) -> ThermalizationStudy:
    """Turn a study of the driver before the engine (``study.json`` of format
    "fputlab-thermalization-study-1", one ``p<point>/o<orbit>_s<segment>.npz`` per orbit and
    segment) into an engine study in `new_dir` (created; must not exist) with the same numbers:
    each orbit's samples (times, window-averaged spectra, energies) become its report, its last
    state the state a larger t_end continues from, and the old sample times the point's
    `legacy_times` (the grid continues from the last one). Orbits that failed keep their
    failure. Returns the new study."""
    old_dir, new_dir = Path(old_dir), Path(new_dir)
    d = json.loads((old_dir / "study.json").read_text())
    if d.pop("format", None) != _LEGACY_FORMAT:
        raise ValueError(f"{old_dir}: not a thermalization study of the driver before the engine")
    if new_dir.exists():
        raise ValueError(f"{new_dir} exists; migrate into a new directory")
    spec = ThermalizationSpec(
        label=d["label"], model=d["model"], boundary=d["boundary"], N=d["N"], alpha=d["alpha"],
        beta=d["beta"], tau=d["tau"], eps_kind=d["eps_kind"], eps=tuple(d["eps"]),
        band=tuple(d["band"]), orbits=d["orbits"], block=d["orbits"], seed=d["seed"],
        method=d["method"], dt=d["dt"], t_first=d["t_first"], t_max=d["t_max"],
        samples_per_doubling=d["samples_per_segment"], sub_samples=d["sub_samples"],
        window=d["window"], threshold=d["threshold"], n_boot=d["n_boot"])
    study = ThermalizationStudy(new_dir, spec)
    from .io.store import StudyStore
    from .engine import StudySpec, task_id
    kind = THERMALIZATION_KIND
    M = _n_modes(spec.settings(0))
    for p, eps in enumerate(spec.eps):
        pdir = old_dir / f"p{p:02d}"
        reports = {}
        for o in range(spec.orbits):
            parts, s = [], 0
            while (pdir / f"o{o:04d}_s{s:02d}.npz").exists():
                with np.load(pdir / f"o{o:04d}_s{s:02d}.npz", allow_pickle=False) as z:
                    parts.append({k: z[k] for k in z.files})
                s += 1
            if parts:
                reports[o] = parts
        if not reports:
            continue
        # the sample times: those of the orbits that went furthest (a failed one stops early)
        ref = max(reports.values(), key=len)
        times = np.concatenate([q["t"] for q in ref])
        S = times.size
        settings = {**spec.settings(p), "legacy_times": [float(t) for t in times]}
        grid = {"eps": [eps], "orbit": list(range(spec.orbits))}
        grid, settings = kind.normalise(grid, settings)
        t_end = float(times[-1])
        sspec = StudySpec("thermalization", grid, settings, t_end)
        bdir = study._block_dir(p, 0)
        with StudyStore(bdir, {**sspec.doc(), "key": sspec.key()}) as store:
            store.set_t_end(t_end)
            for o, parts in reports.items():
                def series(name, shape):
                    out = np.full(shape, np.nan)
                    v = np.concatenate([q[name] for q in parts])
                    out[:v.shape[0]] = v
                    return out
                we = series("e", (S, M))
                fin = np.all(np.isfinite(we), axis=1)
                ent = np.full(S, np.nan)
                ent[fin] = information_entropy(we[fin])
                last = parts[-1]
                failed = bool(last["failed"])
                # CPU (process) time where the old files recorded it, else their wall time
                cpu = sum(float(q["cpu"]) if "cpu" in q else float(q["wall"]) for q in parts)
                values = {"wave_energy": we, "entropy": ent, "n_eff": np.exp(-ent / M),
                          "energy_max": series("energy", S),
                          "energy_min": series("energy_min", S), "E0": float(parts[0]["E0"]),
                          "failed": failed, "steps": int(last["steps"]),
                          "message": str(last["message"]), "cpu": cpu}
                state = None if failed else {
                    "steps": np.int64(last["steps"]), "t": np.float64(last["t_end"]),
                    "y": np.asarray(last["state"], float).reshape(-1)[:2 * spec.N],
                    "n_samples": np.int64(S),
                    "taken_until": np.nextafter(np.float64(t_end), -np.inf),
                    "pend_t": np.empty(0),
                    "pend_e": np.empty((0, M)), "pend_en": np.empty(0)}
                c = {"eps": eps, "orbit": o}
                store.write_task(task_id(c), c, {"t": t_end, "done": failed,
                                                 "message": str(last["message"]), "cpu": cpu,
                                                 "values": values, "state": state})
        # nothing left to compute: the engine merges the reports and writes result.nc
        run_study("thermalization", grid, settings, t_end, work_dir=bdir, workers=1)
    return study
