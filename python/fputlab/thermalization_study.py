"""Thermalization studies: the equipartition time T_eq against the nonlinearity eps for ensembles
of random-phase states, resumable in bounded pieces (CLI: ``fputlab thermalization``).

A study is a `ThermalizationSpec` (one model, boundary, N, band of initial modes, a list of
eps, an ensemble of orbits) kept in ``work_dir/study.json``. Each orbit of each eps is
integrated in segments that double in length (t_first, 2 t_first, 4 t_first, ... up to t_max).
A task is one (point, orbit, segment); `run_segment` is a pure function of the spec, the task
and the segment's start (the previous segment's end state), returning arrays; the driver
writes each task's result to its own file, atomically (temporary name, fsync, rename), so a
killed run loses at most the tasks in flight and a rerun continues bit for bit. After every
segment of a point the driver computes the ensemble eta(t) (`fputlab.thermalization`) and
stops the point once eta stays below the threshold (or at t_max): T_eq is never paid for twice.

Samples: at each sample time the spectrum is the average over `sub_samples` states spread
over a `window` (two periods of the slowest mode by default), which removes the exchange
between kinetic and potential energy that the harmonic energies of a single orbit still
carry; the ensemble average does the rest.

Built-in studies (`STUDIES`): "alpha" (the eps^-8 law of Onorato et al. 2015), "beta" (the
double scaling of Lvov & Onorato 2018), "toda" (the integrable control), and "disorder"
variants (models 2 and 3 at tau = 5 %, 10 %); "tiny" is a seconds-long grid for the tests.
The parameters and the reasons for them are in docs/thermalization.md.
"""
from __future__ import annotations

import json
import math
import os
import time
from dataclasses import asdict, dataclass, field, fields, replace
from pathlib import Path

import numpy as np

from ._validate import _int, _real
from .initial_states import boundary_of, random_phases, wave_energies
from ._errors import IntegrationError
from .integrate import Integrator, method_info
from .lattice import Lattice
from .thermalization import equipartition_time, fit_power_law

__all__ = ["ThermalizationStudy", "ThermalizationSpec", "STUDIES", "EPS_KINDS", "FIT_RANGES",
           "check_spec", "run_segment", "spec_from_json", "load_summary", "projected_cost"]

_FORMAT = "fputlab-thermalization-study-1"
EPS_KINDS = ("alpha", "beta")


@dataclass(frozen=True)
class ThermalizationSpec:
    """What a study is: a study directory is only ever continued with the same spec.

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
    seed: int = 2015
    method: str = "srkn14a6"
    dt: float = 0.5
    t_first: float = 1000.0
    t_max: float = 1.6e7
    samples_per_segment: int = 6
    sub_samples: int = 8
    window: float | None = None
    threshold: float = 0.1
    n_boot: int = 400
    #: the t_max values a study had before it was extended (ascending): the segments ended
    #: there, so they still do (`segment_ends`)
    earlier_t_max: tuple = ()

    def energy(self, eps: float) -> float:
        """Total energy E of the point eps."""
        if self.eps_kind == "alpha":
            return self.N * (eps / self.alpha) ** 2
        return self.N * eps / self.beta

    def lattice(self, orbit: int) -> Lattice:
        """The lattice of an orbit (disordered models: one draw per orbit, seed + orbit)."""
        kw = {}
        if self.boundary != "fixed":
            kw["boundary"] = self.boundary
        if self.tau:
            kw.update(tau=self.tau, seed=self.seed + 7919 * (orbit + 1))
        return Lattice(self.N, self.alpha, self.model, beta=self.beta, **kw)

    def segment_ends(self) -> list[float]:
        # doubling from t_first, each (earlier) t_max an end of its own, so a study extended
        # to a larger t_max keeps the segments it has and continues doubling from there
        ends = [self.t_first]
        for cap in tuple(self.earlier_t_max) + (self.t_max,):
            while ends[-1] < cap * (1 - 1e-12):
                ends.append(min(2 * ends[-1], cap))
        return ends

    def window_length(self) -> float:
        if self.window is not None:
            return self.window
        k1 = 2 * math.pi / self.N if self.boundary == "periodic" else math.pi / (self.N + 1)
        return 2 * 2 * math.pi / (2 * math.sin(k1 / 2))     # two periods of the slowest mode

    def to_json(self) -> str:
        return json.dumps({"format": _FORMAT, **asdict(self)}, sort_keys=True)


def check_spec(spec: ThermalizationSpec) -> ThermalizationSpec:
    """The spec with its values checked (ValueError/TypeError naming the field)."""
    if not isinstance(spec, ThermalizationSpec):
        raise TypeError(f"spec must be a ThermalizationSpec, got {type(spec).__name__}")
    N = _int(spec.N, "N")
    if N < 4:
        raise ValueError(f"N must be >= 4 (got {N})")
    if spec.eps_kind not in EPS_KINDS:
        raise ValueError(f"eps_kind must be one of {EPS_KINDS}, got {spec.eps_kind!r}")
    coupling = spec.alpha if spec.eps_kind == "alpha" else spec.beta
    if not (math.isfinite(_real(coupling, spec.eps_kind)) and coupling > 0):
        raise ValueError(f"{spec.eps_kind} must be > 0 for eps_kind={spec.eps_kind!r}")
    eps = tuple(float(_real(e, "eps")) for e in spec.eps)
    if not eps or not all(math.isfinite(e) and e > 0 for e in eps):
        raise ValueError(f"eps must be a non-empty list of values > 0 (got {spec.eps})")
    for name in ("orbits", "samples_per_segment", "sub_samples", "n_boot"):
        if _int(getattr(spec, name), name) < (0 if name == "n_boot" else 1):
            raise ValueError(f"{name} must be >= 1 (got {getattr(spec, name)})")
    if spec.orbits < 2:
        raise ValueError(f"orbits must be >= 2 for an ensemble (got {spec.orbits})")
    for name in ("dt", "t_first", "t_max"):
        v = _real(getattr(spec, name), name)
        if not (math.isfinite(v) and v > 0):
            raise ValueError(f"{name} must be finite and > 0 (got {v:g})")
    if spec.t_max < spec.t_first:
        raise ValueError(f"t_max ({spec.t_max:g}) must be >= t_first ({spec.t_first:g})")
    earlier = tuple(float(_real(t, "earlier_t_max")) for t in spec.earlier_t_max)
    if any(not spec.t_first <= a < b for a, b in zip(earlier, earlier[1:] + (spec.t_max,))):
        raise ValueError("earlier_t_max must ascend from t_first to below t_max")
    if not 0 < _real(spec.threshold, "threshold") < 1:
        raise ValueError(f"threshold must lie in (0, 1) (got {spec.threshold:g})")
    if method_info(spec.method)["adaptive"]:
        raise ValueError(f"method {spec.method!r} is adaptive: a study runs a fixed-step scheme")
    if spec.window is not None and not (_real(spec.window, "window") >= 0):
        raise ValueError("window must be >= 0")
    spec.lattice(0)                                   # model, boundary, tau checked there
    return replace(spec, eps=eps, band=tuple(int(k) for k in spec.band), earlier_t_max=earlier)


#: the built-in studies; "tiny" is for the tests (seconds)
STUDIES = {
    # alpha-FPUT, eps = alpha sqrt(E/N): 0.06-0.11 spans ~2 decades of T_eq; above ~0.12 the
    # thermal state crosses the barrier r = -1/alpha within T_eq (orbits blow up)
    "alpha": ThermalizationSpec(eps=(0.11, 0.1, 0.09, 0.08, 0.07, 0.06, 0.05), t_max=3.2e7),
    # beta-FPUT, eps = beta E/N: both sides of the Chirikov overlap; dt = 0.2 keeps |dE/E| <
    # 1e-6 at eps = 1
    "beta": ThermalizationSpec(label="beta", alpha=0.0, beta=1.0, eps_kind="beta",
                               eps=(1.0, 0.5, 0.3, 0.2, 0.1, 0.07, 0.05, 0.03, 0.02, 0.015),
                               dt=0.2, t_first=100.0),
    # the integrable control at the alpha study's eps, run ~5x past the alpha T_eq there
    "toda": ThermalizationSpec(label="toda", model="toda", eps=(0.1, 0.08), t_max=1.6e6),
    "tiny": ThermalizationSpec(label="tiny", boundary="fixed", N=8, alpha=1.0,
                               eps=(0.2, 0.15), band=(1,), orbits=4, dt=0.2, t_first=50.0,
                               t_max=800.0, samples_per_segment=4, sub_samples=4,
                               threshold=0.3, n_boot=50),
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


# -- one task: pure ----------------------------------------------------------------------------
def _sample_times(spec: ThermalizationSpec, segment: int) -> np.ndarray:
    """Sample times of a segment: log-spaced up to its end (segment 0 starts with t = 0)."""
    ends = spec.segment_ends()
    hi = ends[segment]
    lo = ends[segment - 1] if segment else hi / 2 ** spec.samples_per_segment
    ts = np.geomspace(lo, hi, spec.samples_per_segment + 1)[1:]
    return np.concatenate([[0.0], ts]) if segment == 0 else ts


def run_segment(spec: ThermalizationSpec, point: int, orbit: int, segment: int,
                start: dict | None) -> dict:
    """One task: integrate orbit `orbit` of point `point` through segment `segment` from
    `start` (None: the random-phase initial state; else the previous segment's ``steps``,
    ``t``, ``state``). Returns the samples' times ``t`` (S,), window-averaged wave energies
    ``e`` (S, M), the energies ``energy`` (S,) and the end ``steps``, ``t_end``, ``state``."""
    lat = spec.lattice(orbit)
    E = spec.energy(spec.eps[point])
    y0 = random_phases(lat, energy=E, modes=spec.band,
                       seed=spec.seed * 1_000_003 + 1009 * point + orbit)
    it = Integrator(lat, y0, method=spec.method, dt=spec.dt)
    if start is not None:
        it.restore(int(start["steps"]), float(start["t"]), start["state"])
    ts = _sample_times(spec, segment)
    seg_start = spec.segment_ends()[segment - 1] if segment else 0.0
    # each sample averages `sub_samples` states over the window (t - w, t], cut at the
    # segment's start (the integrator only moves forward)
    w = spec.window_length()
    back = w * (np.arange(spec.sub_samples) + 1.0) / spec.sub_samples
    raw = np.maximum(ts[:, None] - w + back[None, :], seg_start).ravel()
    order = np.argsort(raw, kind="stable")
    try:
        _, st, _, en_sorted = it.sample(raw[order], states=True, mode_energies=False,
                                        energies=True)
    except IntegrationError as err:
        # an alpha-FPUT orbit can cross its barrier (blow-up): it leaves the ensemble, and
        # the study reports how many did and when
        nan = np.full(ts.size, np.nan)
        return {"t": ts, "e": np.full((ts.size, len(wave_energies(lat, y0))), np.nan),
                "energy": nan, "energy_min": nan, "E0": np.float64(lat.energy(y0)),
                "steps": np.int64(it.steps), "t_end": np.float64(it.t), "state": it.state,
                "failed": np.bool_(True), "message": np.array(str(err))}
    e_sorted = wave_energies(lat, st[:, 0, :])
    e = np.empty_like(e_sorted)
    e[order] = e_sorted
    en = np.empty_like(en_sorted)
    en[order] = en_sorted
    e = e.reshape(ts.size, spec.sub_samples, -1).mean(axis=1)
    en = en.reshape(ts.size, spec.sub_samples)
    return {"t": ts, "e": e, "energy": en.max(axis=1), "energy_min": en.min(axis=1),
            "E0": np.float64(lat.energy(y0)), "steps": np.int64(it.steps),
            "t_end": np.float64(it.t), "state": it.state, "failed": np.bool_(False),
            "message": np.array("")}


# -- files ---------------------------------------------------------------------------------
def _atomic_savez(path: Path, **arrays) -> None:
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    with open(tmp, "wb") as f:
        np.savez(f, **arrays)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)


def _atomic_text(path: Path, text: str) -> None:
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    with open(tmp, "w") as f:
        f.write(text)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)


def _task_path(work: Path, point: int, orbit: int, segment: int) -> Path:
    return work / f"p{point:02d}" / f"o{orbit:04d}_s{segment:02d}.npz"


def _load_task(path: Path) -> dict | None:
    if not path.exists():
        return None
    try:
        with np.load(path, allow_pickle=False) as z:
            return {k: z[k] for k in z.files}
    except Exception as err:   # a damaged file is reported, never silently replaced
        raise ValueError(f"{path}: unreadable task result ({type(err).__name__}: {err}); "
                         "remove it to recompute that task") from None


def _run_task(spec_json: str, work: str, point: int, orbit: int, segment: int) -> float:
    """Worker entry: run one task (its start read from the previous segment's file) and write
    its result file; returns the wall time."""
    spec = spec_from_json(spec_json)
    work = Path(work)
    t0, c0 = time.perf_counter(), time.process_time()
    start = None
    if segment:
        prev = _load_task(_task_path(work, point, orbit, segment - 1))
        start = {"steps": prev["steps"], "t": prev["t_end"], "state": prev["state"]}
    res = run_segment(spec, point, orbit, segment, start)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    path = _task_path(work, point, orbit, segment)
    path.parent.mkdir(parents=True, exist_ok=True)
    _atomic_savez(path, wall=np.float64(wall), cpu=np.float64(cpu), **res)
    if res["failed"]:
        _atomic_text(_failed_path(work, point, orbit),
                     json.dumps({"segment": segment, "message": str(res["message"])}))
    return wall


def _failed_path(work: Path, point: int, orbit: int) -> Path:
    return work / f"p{point:02d}" / f"o{orbit:04d}_failed.json"


def spec_from_json(text: str) -> ThermalizationSpec:
    d = json.loads(text)
    if d.pop("format", None) != _FORMAT:
        raise ValueError("study.json: not a fputlab thermalization study")
    names = {f.name for f in fields(ThermalizationSpec)}
    unknown = set(d) - names
    if unknown:
        raise ValueError(f"study.json: unknown fields {sorted(unknown)}")
    for k in ("eps", "band", "earlier_t_max"):
        d[k] = tuple(d.get(k, ()))
    return ThermalizationSpec(**d)


class ThermalizationStudy:
    """A study in a work directory: `run` advances it in bounded pieces, `results` analyses
    what is there.

    Parameters
    ----------
    work_dir : str or Path
        Its directory (created; an existing one must hold the same spec).
    spec : ThermalizationSpec, optional
        The study (default: the one in work_dir/study.json; a new directory needs one).
    """

    def __init__(self, work_dir, spec: ThermalizationSpec | None = None):
        self.work = Path(work_dir)
        stored = self.work / "study.json"
        if stored.exists():
            old = spec_from_json(stored.read_text())
            if spec is not None and check_spec(spec).to_json() != old.to_json():
                new = check_spec(spec)
                # a study may grow: more eps after the stored ones (the stored points and
                # their orbits' seeds, which depend on the point's index, are kept) and a larger
                # t_max (the segments so far are kept; the old t_max stays a segment end); a
                # smaller t_max than stored changes nothing
                same = replace(new, eps=old.eps, t_max=old.t_max,
                               earlier_t_max=old.earlier_t_max)
                if same.to_json() != old.to_json() or new.eps[:len(old.eps)] != old.eps:
                    raise ValueError(f"work_dir: {self.work} holds a different study; use a "
                                     "new directory (a study can only get more eps or a "
                                     "larger t_max)")
                grown = replace(old, eps=new.eps)
                if new.t_max > old.t_max:
                    grown = replace(grown, t_max=new.t_max,
                                    earlier_t_max=old.earlier_t_max + (old.t_max,))
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
        self._json = self.spec.to_json()

    # -- progress ----------------------------------------------------------------------------
    def _segments_done(self, point: int) -> int:
        """Segments every orbit of the point has finished."""
        n = 0
        failed = self._failed(point)
        for s in range(len(self.spec.segment_ends())):
            if all(o in failed or _task_path(self.work, point, o, s).exists()
                   for o in range(self.spec.orbits)):
                n = s + 1
            else:
                break
        return n

    def _failed(self, point: int) -> set:
        """Orbits of the point that blew up (they leave the ensemble)."""
        return {o for o in range(self.spec.orbits) if _failed_path(self.work, point, o).exists()}

    def point_data(self, point: int) -> dict | None:
        """The point's samples so far: ``t`` (S,), ``e`` (R, S, M), relative energy error."""
        done = self._segments_done(point)
        if not done:
            return None
        ts, es, err = None, [], 0.0
        failed = self._failed(point)
        walls = cpus = 0.0
        for o in range(self.spec.orbits):
            parts = [_load_task(_task_path(self.work, point, o, s)) for s in range(done)
                     if _task_path(self.work, point, o, s).exists()]
            walls += sum(float(p["wall"]) for p in parts)
            # CPU time (process time; files written before it was recorded have none: nan)
            cpus += sum(float(p["cpu"]) if "cpu" in p else math.nan for p in parts)
            if o in failed:
                continue
            es.append(np.concatenate([p["e"] for p in parts]))
            if ts is None:
                ts = np.concatenate([p["t"] for p in parts])
            E0 = float(parts[0]["E0"])
            for p in parts:
                err = max(err, float(np.max(np.abs(np.concatenate(
                    [p["energy"], p["energy_min"]]) / E0 - 1))))
        # fewer than 2 orbits left (the rest blew up): no ensemble, e is None
        return {"t": ts, "e": np.stack(es) if len(es) >= 2 else None, "energy_error": err,
                "segments": done, "wall": walls, "cpu": cpus, "failed": len(failed)}

    def _point_finished(self, point: int) -> bool:
        d = self.point_data(point)
        if d is None:
            return False
        if d["segments"] == len(self.spec.segment_ends()) or d["e"] is None:
            return True
        res = equipartition_time(d["t"], d["e"], threshold=self.spec.threshold, n_boot=100,
                                 seed=self.spec.seed)
        # stop once eta has crossed and so have 95 % of the bootstrap ensembles: the
        # interval is then defined (a crossing at the last sample alone would leave it open)
        return bool(np.isfinite(res["t_eq"]) and np.isfinite(res["boot"]).mean() >= 0.95)

    # -- running -----------------------------------------------------------------------------
    def run(self, *, t_until: float | None = None, max_seconds: float | None = None,
            workers: int = 1, progress=None) -> bool:
        """Advance every point, segment by segment, up to `t_until` (default t_max) or for
        about `max_seconds` of wall time (checked between tasks). Returns True when the study
        is complete (every point has crossed or reached t_max)."""
        spec = self.spec
        ends = spec.segment_ends()
        t_until = spec.t_max if t_until is None else _real(t_until, "t_until")
        workers = _int(workers, "workers")
        if workers < 1:
            raise ValueError(f"workers must be >= 1 (got {workers})")
        deadline = None if max_seconds is None else time.monotonic() + _real(max_seconds,
                                                                             "max_seconds")
        for p in range(len(spec.eps)):
            while not self._point_finished(p):
                s = self._segments_done(p)
                if s >= len(ends) or ends[s] > t_until * (1 + 1e-12):
                    break
                todo = [(self._json, str(self.work), p, o, s) for o in range(spec.orbits)
                        if not _task_path(self.work, p, o, s).exists()]
                if deadline is not None and time.monotonic() > deadline:
                    return False
                if workers == 1:
                    for call in todo:
                        _run_task(*call)
                        if progress:
                            progress(p, call[3], s)
                        if deadline is not None and time.monotonic() > deadline:
                            return False
                else:
                    from ._engine import run_calls
                    for call, _r, err in run_calls(_run_task, todo, workers=workers):
                        if err is not None:
                            raise err
                        if progress:
                            progress(p, call[3], s)
                self.write_summary()
        self.write_summary()
        return all(self._point_finished(p) for p in range(len(spec.eps)))

    # -- results -----------------------------------------------------------------------------
    def results(self, fit_ranges=None) -> dict:
        """Per point: eps, E, T_eq with its bootstrap interval, eta(t), the energy error and
        the compute; the power-law fit over the points that crossed (``fit``) and one per eps
        range (``range_fits``; `fit_ranges` [(lo, hi), ...], default `FIT_RANGES` of the
        study's label)."""
        spec = self.spec
        points = []
        for p, eps in enumerate(spec.eps):
            d = self.point_data(p)
            row = {"eps": eps, "E": spec.energy(eps), "t_eq": math.nan,
                   "interval": (math.nan, math.nan), "t_reached": 0.0, "eta_last": math.nan,
                   "energy_error": math.nan, "wall": 0.0, "cpu": 0.0, "orbit_time": 0.0,
                   "failed": 0}
            if d is not None and d["e"] is None:
                row.update(failed=d["failed"], wall=d["wall"], cpu=d["cpu"])
            elif d is not None:
                res = equipartition_time(d["t"], d["e"], threshold=spec.threshold,
                                         n_boot=spec.n_boot, seed=spec.seed + p)
                row.update(t_eq=res["t_eq"], interval=res["interval"], boot=res["boot"],
                           t=d["t"], eta=res["eta"], t_reached=float(d["t"][-1]),
                           eta_last=float(res["eta"][-1]), energy_error=d["energy_error"],
                           wall=d["wall"], cpu=d["cpu"],
                           orbit_time=float(d["t"][-1]) * spec.orbits,
                           failed=d["failed"],
                           finished=self._point_finished(p))
            points.append(row)
        def fit_of(rows):
            rows = [r for r in rows if np.isfinite(r["t_eq"])]
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
                "range_fits": range_fits}

    def write_summary(self) -> None:
        """(Re)write ``work_dir/summary.json`` from the task files (`load_summary` reads it)."""
        res = self.results()
        # everything the table and the figure need (`load_summary` reads it back), without
        # the bootstrap replicates
        plain = {"format": _FORMAT, "spec": res["spec"], "fit": res["fit"],
                 "range_fits": res["range_fits"],
                 "points": [{k: v for k, v in r.items() if k != "boot"}
                            for r in res["points"]]}
        _atomic_text(self.work / "summary.json",
                     json.dumps(plain, indent=1, default=_json_default, allow_nan=True))


def load_summary(path) -> dict:
    """A study's ``summary.json`` (written after every segment) as `ThermalizationStudy.results`
    gives it, without the bootstrap replicates: enough for the table and the figure."""
    d = json.loads(Path(path).read_text())
    if d.get("format") != _FORMAT:
        raise ValueError(f"{path}: not a fputlab thermalization study summary")
    for r in d["points"]:
        r["interval"] = tuple(r["interval"])
        for k in ("t", "eta"):
            if k in r:
                r[k] = np.asarray(r[k], dtype=float)
    return d


def _json_default(o):
    if isinstance(o, (np.floating, np.integer)):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    raise TypeError(type(o).__name__)


def projected_cost(spec: ThermalizationSpec, seconds_per_step: float, t_eq: dict) -> dict:
    """Projected wall time (s, one core) of each point: orbits x (time to T_eq, rounded up to
    the segment end where the driver stops, or t_max) / dt x seconds_per_step, with
    `t_eq` {eps: expected T_eq} (e.g. from a fitted law)."""
    ends = spec.segment_ends()
    out = {}
    for eps in spec.eps:
        target = t_eq.get(eps, math.inf)
        stop = next((e for e in ends if e >= 2 * target), ends[-1])
        out[eps] = spec.orbits * stop / spec.dt * seconds_per_step
    return out
