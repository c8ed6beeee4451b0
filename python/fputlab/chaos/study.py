"""The paper's chaos study (Sec. 5, Figs. 12-14) at full length: a chaos study of the study
engine (`fputlab.engine`, kind "chaos") with the paper's set-up and a fixed sample grid.

For each N and disorder realisation (seed) one orbit of model 3 at tau = 10 % (the paper's
mode-1 initial state, two deviation vectors) is followed with the chaos indicators lambda(t)
and SALI(t) up to t_end = 1e8, sampled at n_samples log-spaced times up to t_end. The work
directory is the engine's (`fputlab.io.store`): one task file per orbit (its samples and its
state in the single-orbit checkpoint format), replaced atomically as the orbit reports, so a
rerun continues bit for bit. The study advances in horizons (1e4, 2e4, 5e4, 1e5, ... up to
t_until):
every orbit reaches a horizon before any goes further, so after a bounded piece of work the
classes are known for every orbit at the same time:

    >>> from fputlab.chaos.study import ChaosStudy
    >>> study = ChaosStudy("fig14.d")                     # the paper's set-up, fast defaults
    >>> study.run(t_until=1e6)                            # a piece (all local cores); rerun later
    >>> study.run(t_until=1e8, scheduler="tcp://h:8786")  # the rest, on a Dask cluster
    >>> study.table()                                     # class counts per N at 1e6, 1e7, 1e8

An orbit stops early when its class is decided: chaotic (SALI < 1e-8 on the finite orbit,
confirmed one renormalisation later) or blow-up (the bond-stretch barrier 1/alpha or a
non-finite state); regular orbits run to t_end.

Method: the default is srkn14a6 at dt = 0.5, validated against Yoshida 4 at dt = 0.01 (the
paper's tangent-map choice) and DOP853 on the variational equations (the paper's choice for
model 3) in tests/python/test_study.py and benchmarks/chaos_methods.py; method="dop853" gives
the paper's own integrator (about 30x slower).

A study directory of the format before the engine (one orbit_N*_seed*.npz per orbit) is
converted by `migrate_legacy(old, new)`, which only reads the old one.
"""
from __future__ import annotations

import json
import math
import shutil
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from .. import _lowlevel as ll
from ..engine import HORIZONS, run_study  # noqa: F401 (HORIZONS: public here)
from ..integrate import method_info
from ..lattice import MODELS
from .ensemble import CHAOS_KIND, ChaoticFraction, _lattice, _report, chaos_accumulators

__all__ = ["ChaosStudy", "StudySpec", "HORIZONS", "migrate_legacy"]

_FORMAT = "fputlab-chaos-study-1"

@dataclass(frozen=True)
class StudySpec:
    """What every orbit of a study shares (stored in work_dir/study.json; a study directory is
    only ever continued with the same spec)."""
    Ns: tuple = (4, 8, 16, 32, 64)
    realisations: int = 30
    tau: float = 10.0
    model: str = "nonlinear"
    alpha: float = 0.25
    first_seed: int = 1
    t_end: float = 1e8
    method: str = "srkn14a6"
    dt: float = 0.5
    rtol: float = ll.RTOL
    atol: float = ll.ATOL
    renorm_interval: float = 1.0
    n_samples: int = 400
    sali_threshold: float = 1e-8
    stop_when_chaotic: bool = True

    def validate(self) -> "StudySpec":
        Ns = tuple(int(n) for n in self.Ns)
        if not Ns or min(Ns) < 2 or len(set(Ns)) != len(Ns):
            raise ValueError(f"Ns must be distinct integers >= 2 (got {list(self.Ns)})")
        if isinstance(self.realisations, bool) or int(self.realisations) != self.realisations \
                or self.realisations < 1:
            raise ValueError(f"realisations must be an integer >= 1 (got {self.realisations!r})")
        if self.model not in MODELS:
            raise ValueError(f"model {self.model!r} is unknown (known: {', '.join(MODELS)})")
        if self.model == "homogeneous" and self.tau != 0:
            raise ValueError("tau: the homogeneous model has no disorder (use tau=0)")
        for name in ("tau", "alpha", "t_end", "renorm_interval", "sali_threshold"):
            v = getattr(self, name)
            if not isinstance(v, (int, float)) or not math.isfinite(v):
                raise ValueError(f"{name} must be a finite number (got {v!r})")
        if self.tau < 0:
            raise ValueError(f"tau must be >= 0 (got {self.tau})")
        if not self.t_end > 0:
            raise ValueError(f"t_end must be > 0 (got {self.t_end})")
        if not self.renorm_interval > 0:
            raise ValueError(f"renorm_interval must be > 0 (got {self.renorm_interval})")
        if int(self.first_seed) != self.first_seed or self.first_seed < 0:
            raise ValueError(f"first_seed must be an integer >= 0 (got {self.first_seed!r})")
        if int(self.n_samples) != self.n_samples or self.n_samples < 2:
            raise ValueError(f"n_samples must be an integer >= 2 (got {self.n_samples!r})")
        adaptive = method_info(self.method)["adaptive"]     # ValueError names an unknown method
        if not adaptive and not (self.dt > 0 and math.isfinite(self.dt)):
            raise ValueError(f"dt must be finite and > 0 (got {self.dt})")
        return StudySpec(**{**asdict(self), "Ns": Ns, "realisations": int(self.realisations),
                            "first_seed": int(self.first_seed), "n_samples": int(self.n_samples),
                            "tau": float(self.tau), "alpha": float(self.alpha),
                            "t_end": float(self.t_end), "dt": float(self.dt)})

    def to_json(self) -> str:
        return json.dumps({"format": _FORMAT, **asdict(self), "Ns": list(self.Ns)},
                          sort_keys=True)

    @classmethod
    def from_json(cls, text: str) -> "StudySpec":
        d = json.loads(text)
        if d.pop("format", None) != _FORMAT:
            raise ValueError("not a fputlab chaos-study description")
        d["Ns"] = tuple(d["Ns"])
        return cls(**d).validate()


def _engine_study(spec: StudySpec) -> tuple[dict, dict]:
    """(grid, settings) of the engine's chaos study that is this study."""
    grid = {"N": list(spec.Ns), "tau": [spec.tau],
            "seed": [spec.first_seed + r for r in range(spec.realisations)]}
    settings = {"model": spec.model, "alpha": spec.alpha, "method": spec.method, "dt": spec.dt,
                "rtol": spec.rtol, "atol": spec.atol, "renorm_interval": spec.renorm_interval,
                "sali_threshold": spec.sali_threshold,
                "stop_when_chaotic": spec.stop_when_chaotic,
                "sample_grid_end": spec.t_end, "n_samples": spec.n_samples}
    return grid, settings


def _spec_of(work: Path) -> StudySpec | None:
    """The StudySpec of the engine study in `work` (None if there is none)."""
    desc = work / "study.json"
    if not desc.exists():
        return None
    try:
        d = json.loads(desc.read_text())
        g, s = d["grid"], d["settings"]
        seeds = g["seed"]
        return StudySpec(Ns=tuple(g["N"]), realisations=len(seeds), tau=g["tau"][0],
                         model=s["model"], alpha=s["alpha"], first_seed=seeds[0],
                         t_end=s["sample_grid_end"], method=s["method"], dt=s["dt"],
                         rtol=s["rtol"], atol=s["atol"], renorm_interval=s["renorm_interval"],
                         n_samples=s["n_samples"], sali_threshold=s["sali_threshold"],
                         stop_when_chaotic=s["stop_when_chaotic"]).validate()
    except (OSError, ValueError, KeyError, TypeError, IndexError) as err:
        if json.loads(desc.read_text()).get("format") == _FORMAT:
            raise ValueError(f"{work} holds a chaos study of the format before the study engine: "
                             "convert it with fputlab.chaos.study.migrate_legacy(old, new)") \
                from None
        raise ValueError(f"{desc}: not a readable chaos study ({err})") from None


class ChaosStudy:
    """A resumable chaos study in `work_dir` (see the module docstring): the paper's set-up as
    a study of the engine.

    Parameters
    ----------
    work_dir : path
        Directory of the study (the engine's layout). An existing directory is continued; its
        parameters must match the ones given (only the ones given are compared; the rest are
        taken from it).
    batched : bool, optional
        Kept for compatibility: the engine runs the orbits of one N in the vector lanes when
        the method allows it; the numbers are the same either way.
    **params
        StudySpec fields: Ns, realisations, tau, model, alpha, first_seed, t_end, method, dt,
        rtol, atol, renorm_interval, n_samples, sali_threshold, stop_when_chaotic.
    """

    def __init__(self, work_dir, *, batched: bool = True, **params):
        self.work = Path(work_dir)
        self.batched = bool(batched)
        unknown = set(params) - set(StudySpec.__dataclass_fields__)
        if unknown:
            raise TypeError(f"unknown study parameter(s): {', '.join(sorted(unknown))} "
                            f"(known: {', '.join(StudySpec.__dataclass_fields__)})")
        if self.work.exists() and not self.work.is_dir():
            raise ValueError(f"work_dir {self.work} exists and is not a directory")
        old = _spec_of(self.work)
        if old is not None:
            given = StudySpec(**{**asdict(old), **params}).validate()
            if given != old:
                diff = [k for k in params if getattr(given, k) != getattr(old, k)]
                raise ValueError(f"{self.work} holds a study with other parameters "
                                 f"({', '.join(f'{k}={getattr(old, k)!r}' for k in diff)}); "
                                 f"use another work directory")
            self.spec = old
        else:
            self.spec = StudySpec(**params).validate()
            _create(self.work, self.spec)

    def orbits(self) -> list[tuple[int, int]]:
        s = self.spec
        return [(N, s.first_seed + r) for N in s.Ns for r in range(s.realisations)]

    def _study(self, t_until: float, **run) -> ChaoticFraction:
        grid, settings = _engine_study(self.spec)
        reached = _reached_t_end(self.work)
        t = max(t_until, reached or 0.0)
        r = run_study("chaos", grid, settings, t, work_dir=self.work, **run)
        return ChaoticFraction(r.kind, r.dataset, r.work_dir, r.computed, r.resumed, r.reused)

    def run(self, t_until: float | None = None, *, workers: int | None = None, scheduler=None,
            progress: bool = True, save_every: float | None = None) -> dict:
        """Advance every orbit to t_until (default t_end), horizon by horizon, on a local
        process pool (`workers`, default all cores) or a Dask cluster (`scheduler`). Safe to
        interrupt at any moment: rerun to continue. Returns `status()`. (`save_every` is kept
        for compatibility: every horizon piece is saved as it reports.)"""
        t_until = self.spec.t_end if t_until is None else float(t_until)
        if not (math.isfinite(t_until) and t_until > 0):
            raise ValueError(f"t_until must be finite and > 0 (got {t_until})")
        t_until = min(t_until, self.spec.t_end)
        reached = _reached_t_end(self.work)
        if reached is not None and reached > t_until:
            # orbits beyond t_until stay where they are; only the ones behind move
            t_until = reached
        self._study(t_until, workers=workers, scheduler=scheduler, progress=progress)
        return self.status()

    def _loaded(self) -> ChaoticFraction:
        """The study as its files hold it now (merged, nothing computed)."""
        if _spec_of(self.work) is None:
            return ChaoticFraction("chaos", _empty(self.spec), None)
        from ..engine import load_study
        from ..io.store import StudyStore
        key = StudyStore.reader(self.work).fingerprint()
        if getattr(self, "_cache", (None,))[0] != key:      # files changed: merge again
            r = load_study(self.work)
            self._cache = (key, ChaoticFraction(r.kind, r.dataset, r.work_dir))
        return self._cache[1]

    # -- reading ---------------------------------------------------------------------------
    def result(self) -> ChaoticFraction:
        """The study's labelled result as its files hold it now (`to_xarray()`, `summary()`);
        nothing is computed."""
        return self._loaded()

    def results(self) -> dict[int, list]:
        """{N: [ChaosResult per realisation]} as far as computed (None where not started)."""
        r = self._loaded()
        return {N: r.orbits(N) for N in self.spec.Ns}

    def reached(self) -> float:
        """The time every orbit has reached or been decided by: the study's honest horizon
        (t_end once every orbit is done)."""
        ds = self._loaded().dataset
        t = ds["t_reached"].values
        fin = ds["finished"].values
        open_ = np.where(fin, np.inf, np.nan_to_num(t, nan=0.0))
        m = float(open_.min()) if open_.size else math.inf
        return self.spec.t_end if not math.isfinite(m) else min(m, self.spec.t_end)

    def classes(self, t_eval: float) -> dict[int, dict[str, int]]:
        """{N: {class: count}} at time t_eval; orbits that have not reached t_eval (and were not
        decided before it) are counted as 'not reached'."""
        return self._loaded().classes_at(t_eval)

    def table(self, t_evals=(1e6, 1e7, 1e8)) -> list[dict]:
        """Rows {t, N, chaotic, regular, blow-up, undecided, not reached} for each t in t_evals
        up to t_end."""
        rows = []
        for te in t_evals:
            if te > self.spec.t_end * (1 + 1e-12):
                continue
            for N, counts in self.classes(te).items():
                rows.append({"t": te, "N": N, **counts})
        return rows

    def status(self) -> dict:
        ds = self._loaded().dataset
        t = np.nan_to_num(ds["t_reached"].values, nan=0.0)
        fin = ds["finished"].values
        t_orbit = np.where(fin & ds["blew_up"].values, ds["t_blowup"].values,
                           np.where(fin, ds["t_final"].values, t))
        return {"work_dir": str(self.work), "orbits": int(t.size), "done": int(fin.sum()),
                "reached": self.reached(), "t_min": float(t_orbit.min()),
                "t_max": float(t_orbit.max())}


def _engine_spec(spec: StudySpec):
    from ..engine import StudySpec as EngineSpec
    g, s = CHAOS_KIND.normalise(*_engine_study(spec))
    return EngineSpec("chaos", g, s, spec.t_end)


def _create(work: Path, spec: StudySpec) -> None:
    """The study's directory and description (atomic; a racing creator of another study is
    refused by the store)."""
    from ..io.store import StudyStore
    es = _engine_spec(spec)
    StudyStore(work, {**es.doc(), "key": es.key()}).close()


def _reached_t_end(work: Path) -> float | None:
    try:
        return float(json.loads((work / "progress.json").read_text())["t_end"])
    except (OSError, ValueError, KeyError, TypeError):
        return None


def _empty(spec: StudySpec):
    """The labelled result of a study not started (nothing computed)."""
    from ..engine import _merge
    es = _engine_spec(spec)
    return _merge(CHAOS_KIND, es, es.tasks(), None, {})


# ---- the format before the engine ---------------------------------------------------------------

def migrate_legacy(old_dir, new_dir) -> ChaoticFraction:
    """Convert a chaos study of the format before the study engine (study.json
    "fputlab-chaos-study-1" and one orbit_N<N>_seed<seed>.npz per orbit: step count, time,
    state, fpl_chaos_save accumulators, samples) into an engine study in `new_dir`, which must
    not exist. `old_dir` is only read. Every orbit keeps its state, so the new study continues
    bit for bit; its classes at every time are those of the old one.

    Returns
    -------
    ChaoticFraction
        The migrated study's result (as `ChaosStudy(new_dir)` reads it).
    """
    old, new = Path(old_dir), Path(new_dir)
    if new.exists():
        raise ValueError(f"new_dir {str(new)!r} exists: migrate into a new directory")
    d = json.loads((old / "study.json").read_text())
    if d.pop("format", None) != _FORMAT:
        raise ValueError(f"{old}/study.json is not a chaos study of the old format")
    d["Ns"] = tuple(d["Ns"])
    spec = StudySpec(**d).validate()
    from ..engine import task_id
    from ..io.store import StudyStore
    es = _engine_spec(spec)
    s = es.settings
    reached = 0.0
    try:
        with StudyStore(new, {**es.doc(), "key": es.key()}) as store:
            for c in es.tasks():
                path = old / f"orbit_N{c['N']}_seed{c['seed']}.npz"
                if not path.exists():
                    continue
                rep = _legacy_report(path, s, c)
                store.write_task(task_id(c), c, rep)
                reached = max(reached, rep["t"])
            store.set_t_end(reached)
    except BaseException:            # never leave half a study: new_dir did not exist before
        shutil.rmtree(new, ignore_errors=True)
        raise
    result = ChaosStudy(new)._loaded()
    StudyStore.reader(new).write_result(result.dataset)
    return result


def _legacy_report(path: Path, settings: dict, c: dict) -> dict:
    """An old orbit file as an engine report: C restores the orbit (integrator and
    accumulators) and reports its result, so nothing here reads the accumulators."""
    with np.load(path, allow_pickle=False) as z:
        f = {k: z[k] for k in z.files}
    lat = _lattice(settings, c["N"], c["tau"], c["seed"])
    io = ll.integrator_options(0.0 if method_info(settings["method"])["adaptive"]
                               else settings["dt"], settings["rtol"], settings["atol"])
    co = {"renorm_interval": settings["renorm_interval"], "n_samples": settings["n_samples"],
          "sali_threshold": settings["sali_threshold"],
          "stop_when_chaotic": settings["stop_when_chaotic"]}
    h = ll.ChaosHandle(lat._h, settings["method"], io, 0.0, lat.mode_state(), None,
                       ll.chaos_options(settings["sample_grid_end"], **co))
    ih = h.integrator()
    acc = chaos_accumulators(f["acc"])
    steps, t_saved = int(f["steps"]), float(f["t"])
    if settings["dt"] and steps * settings["dt"] != t_saved:
        # an orbit that blew up was saved at its last renormalisation with the step count of
        # the step it blew up in: it never continues, so the integrator is put on that time
        steps = round(t_saved / settings["dt"])
    ih.restore(steps, t_saved, np.ascontiguousarray(f["state"], float))
    try:
        h.restore(acc)
    except ValueError:
        # an orbit that blew up keeps the state of the interval it blew up in, one
        # renormalisation after its accumulators (m, the first of fpl_chaos_save's): it never
        # continues, and C reports its result from the accumulators at their own time
        t_acc = acc[0] * settings["renorm_interval"]
        steps = int(f["steps"]) if not settings["dt"] else round(t_acc / settings["dt"])
        ih.restore(steps, t_acc, np.ascontiguousarray(f["state"], float))
        h.restore(acc)
    res = h.get_result()
    arrays = [np.asarray(f["s_" + k], float) for k in ("t", "mle", "sali", "gali")]
    arrays.append(np.full(arrays[0].size, np.nan))      # old orbit files have no MEGNO
    state = {"steps": np.int64(f["steps"]), "t": np.float64(f["t"]), "y": ih.get_state(),
             "acc": h.save()}
    failed = bool(f.get("failed", False))
    t = float(f["t"])
    rep = _report(settings, t, res, *arrays, str(f["message"]), state, float(f["wall"]),
                  h.done(), failed)
    rep["values"]["steps"] = int(f["steps"])        # the orbit's own count (see above)
    return rep
