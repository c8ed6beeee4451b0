"""The paper's chaos study (Sec. 5, Figs. 12-14) at full length, resumable in bounded pieces.

For each N and disorder realisation (seed) one orbit of model 3 at tau = 10 % (the paper's
mode-1 initial state, two deviation vectors) is followed with the chaos indicators lambda(t)
and SALI(t) up to t_end = 1e8. Every orbit has its own state file in the work directory (the
integrator's step count, time and state with the deviation vectors, the chaos accumulators and
the log-spaced samples so far), written atomically every few minutes and whenever a piece
ends, so a kill loses minutes, not hours, and the continuation is bit for bit the
uninterrupted run. The study advances in horizons (1e4, 1e5, ... up to t_until): every orbit
reaches a horizon before any goes further, so after a bounded piece of work the classes are
known for every orbit at the same time and the table of the paper can be drawn honestly:

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
the paper's own integrator (about 30x slower). The work directory must be reachable by the
workers (local pool: always; Dask: a shared file system).
"""
from __future__ import annotations

import json
import math
import os
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from .. import _lowlevel as ll
from .._engine import run_calls
from .._errors import FputlabError, last_error
from .result import ChaosResult
from .batch import BATCH_METHODS
from ..integrate import method_info
from ..lattice import MODELS, Lattice

__all__ = ["ChaosStudy", "StudySpec", "OrbitState", "advance_orbit", "advance_group", "HORIZONS"]

_FORMAT = "fputlab-chaos-study-1"
#: the horizons every orbit reaches before any goes further
HORIZONS = (1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10)


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


@dataclass
class OrbitState:
    """One orbit's progress (what its state file holds)."""
    N: int
    seed: int
    t: float = 0.0                 # time reached
    done: bool = False             # class decided or t_end reached
    result: ChaosResult | None = None
    wall: float = 0.0              # CPU seconds spent on it so far
    extra: dict = field(default_factory=dict)


def _orbit_path(work: Path, N: int, seed: int) -> Path:
    return work / f"orbit_N{N}_seed{seed}.npz"


def _handle(spec: StudySpec, N: int, seed: int):
    """(lattice, chaos handle, integrator handle) at t = 0 for one orbit of the study."""
    lat = Lattice(N, spec.alpha, spec.model, tau=spec.tau, seed=seed if spec.tau else None)
    io = ll.integrator_options(0.0 if method_info(spec.method)["adaptive"] else spec.dt,
                               spec.rtol, spec.atol)
    co = ll.chaos_options(spec.t_end, renorm_interval=spec.renorm_interval,
                          n_samples=spec.n_samples, sali_threshold=spec.sali_threshold,
                          stop_when_chaotic=spec.stop_when_chaotic)
    c = ll.ChaosHandle(lat._h, spec.method, io, 0.0, lat.mode_state(), None, co)
    return lat, c, c.integrator()


def _save(path: Path, spec_json: str, c, ih, arrays, message: str, wall: float,
          failed: bool) -> None:
    """The orbit's state file, written under a temporary name and renamed (never half-written)."""
    acc = c.save()
    state = ih.get_state().reshape(arrays["state_len"])
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    with open(tmp, "wb") as f:
        np.savez(f, spec=np.array(spec_json), steps=np.int64(ih.steps()),
                 t=np.float64(ih.time()), state=state, acc=acc,
                 s_t=arrays["t"], s_mle=arrays["mle"], s_sali=arrays["sali"],
                 s_gali=arrays["gali"], s_megno=arrays["megno"], message=np.array(message),
                 wall=np.float64(wall),
                 failed=np.bool_(failed))
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)


def _load(path: Path, spec_json: str) -> dict | None:
    """The orbit's state file as a dict, None if there is none; ValueError if it belongs to
    another study or cannot be read (a corrupt file is never silently replaced)."""
    if not path.exists():
        return None
    try:
        with np.load(path, allow_pickle=False) as z:
            d = {k: z[k] for k in z.files}
    except Exception as err:     # zipfile/OSError/ValueError: a damaged file
        raise ValueError(f"{path}: unreadable orbit state ({type(err).__name__}: {err}); "
                         f"remove it to recompute that orbit") from None
    if str(d.get("spec")) != spec_json:
        raise ValueError(f"{path}: belongs to another study (other parameters)")
    if np.size(d.get("acc")) != ll.CHAOS_N_ACCUMULATORS:     # fpl_chaos_save grew (MEGNO)
        raise ValueError(f"{path}: written by an older fputlab ({np.size(d.get('acc'))} chaos "
                         f"accumulators, this version keeps {ll.CHAOS_N_ACCUMULATORS}); remove it "
                         "to recompute that orbit")
    return d


def advance_orbit(spec_json: str, N: int, seed: int, t_until: float, work_dir: str,
                  save_every: float = 120.0) -> dict:
    """Advance one orbit of the study to t_until (or until its class is decided), resuming
    from its state file and saving it every `save_every` seconds and at the end. Runs in a
    worker process; returns a small summary {N, seed, t, done, class, wall}."""
    spec = StudySpec.from_json(spec_json)
    path = _orbit_path(Path(work_dir), N, seed)
    lat, c, ih = _handle(spec, N, seed)
    S = spec.n_samples
    arrays = {"t": np.full(S, np.nan), "mle": np.full(S, np.nan), "sali": np.full(S, np.nan),
              "gali": np.full(S, np.nan), "megno": np.full(S, np.nan), "state_len": 2 * N * 3}
    saved = _load(path, spec_json)
    message, wall = "", 0.0
    if saved is not None:
        ih.restore(int(saved["steps"]), float(saved["t"]),
                   np.ascontiguousarray(saved["state"], float))
        c.restore(np.ascontiguousarray(saved["acc"], float))
        for k in ("t", "mle", "sali", "gali", "megno"):
            arrays[k][:] = saved["s_" + k]
        message, wall = str(saved["message"]), float(saved["wall"])
    # pieces of ~1e5 force evaluations per particle between clock checks
    seg = spec.renorm_interval * max(1, round(2e4 / spec.renorm_interval))
    started = last_save = time.monotonic()
    cpu0 = time.process_time()
    t_now = ih.time()
    failed = bool(saved is not None and saved.get("failed", False))
    while not failed and not c.done() and t_now < t_until:
        try:
            if c.advance(min(t_now + seg, t_until),
                         *(arrays[k] for k in ("t", "mle", "sali", "gali", "megno"))) > 0:
                message = last_error()          # a blow-up: when and why
        except (FputlabError, ValueError, MemoryError, OSError):
            message, failed = last_error(), True    # a numerical failure: stop this orbit here
        t_now = ih.time()
        if time.monotonic() - last_save > save_every:
            _save(path, spec_json, c, ih, arrays, message, wall + time.process_time() - cpu0,
                  failed)
            last_save = time.monotonic()
    wall += time.process_time() - cpu0
    _save(path, spec_json, c, ih, arrays, message, wall, failed)
    res = c.get_result()
    done = c.done() or failed
    del lat
    return {"N": N, "seed": seed, "t": float(res.t_final if not res.blew_up else res.t_blowup),
            "done": done, "wall": wall, "elapsed": time.monotonic() - started}


# ---- batched pieces: the orbits of one N in the vector lanes (fputlab.chaos.batch) -----------
# fpl_chaos_save accumulators: m, logsum, next, n_samples, chaotic, t_chaotic, mle, sali, gali,
# t_final, done, blew_up, t_blowup, completed, t_pending, MEGNO's ell_int, y_int, y_prev, megno;
# a batch lane (fpl_chaos_batch_save):
# logsum, next, pending, n_samples, t_final, mle, sali, gali, chaotic, t_chaotic, blew_up,
# t_blowup, blowup_reason, event_index, steps, done, running, MEGNO's ell_int, y_int, y_prev,
# megno. A lane computes exactly what
# fpl_chaos computes for its orbit, so an orbit file moves in and out of a lane losslessly.
_LANE_ACC, _BATCH_HEADER = 21, 8


def _lane_from_orbit(acc, steps):
    chaotic, t_pending = bool(acc[4]), float(acc[14])
    pending = not chaotic and t_pending == t_pending
    t_chaotic = float(acc[5]) if chaotic else (t_pending if pending else math.nan)
    return [acc[1], acc[2], float(pending), acc[3], acc[9], acc[6], acc[7], acc[8],
            float(chaotic), t_chaotic, 0.0, math.nan, 0.0, -1.0, float(steps), 0.0, 1.0,
            acc[15], acc[16], acc[17], acc[18]]


def _orbit_from_lane(lane, renorm_interval):
    chaotic, pending, blew_up, done = (bool(lane[i]) for i in (8, 2, 10, 15))
    t_final = float(lane[4])
    t_pending = float(lane[9]) if (pending or chaotic) else math.nan
    return np.array([round(t_final / renorm_interval), lane[0], lane[1], lane[3],
                     float(chaotic), lane[9] if chaotic else math.nan, lane[5], lane[6], lane[7],
                     t_final, float(done), float(blew_up), lane[11],
                     float(done and not blew_up), t_pending, lane[17], lane[18], lane[19],
                     lane[20]])


def advance_group(spec_json: str, N: int, seeds, t_until: float, work_dir: str,
                  save_every: float = 120.0) -> list[dict]:
    """Advance several orbits of one N (all at the same step, e.g. a horizon) together in the
    batched kernel to t_until, reading and writing the same per-orbit state files as
    `advance_orbit` (the numbers are those of one orbit at a time, bit for bit)."""
    spec = StudySpec.from_json(spec_json)
    work = Path(work_dir)
    seeds = list(seeds)
    saved = [_load(_orbit_path(work, N, s), spec_json) for s in seeds]
    key = {(int(d["steps"]) if d is not None else 0) for d in saved}
    # one orbit alone gains nothing from the lanes (benchmarks/README.md, "Batched chaos": the
    # kernel with one lane costs 0.9-1.2x the single-orbit path), so it takes that path
    if len(seeds) == 1 or len(key) != 1 or any(
            d is not None and (bool(d["acc"][10]) or bool(d.get("failed", False))) for d in saved):
        return [advance_orbit(spec_json, N, s, t_until, work_dir, save_every) for s in seeds]
    R, S, k = len(seeds), spec.n_samples, 2
    lats = [Lattice(N, spec.alpha, spec.model, tau=spec.tau, seed=s if spec.tau else None)
            for s in seeds]
    io = ll.integrator_options(spec.dt)
    bo = ll.chaos_batch_options(spec.t_end, renorm_interval=spec.renorm_interval, n_samples=S,
                                sali_threshold=spec.sali_threshold,
                                stop_when_chaotic=spec.stop_when_chaotic)
    y0 = np.ascontiguousarray(np.stack([lat.mode_state() for lat in lats]))
    b = ll.ChaosBatchHandle([lat._h for lat in lats], spec.method, io, 0.0, y0, None, bo)
    arrays = [np.full((R, S), np.nan) for _ in range(5)]
    lane_len = 2 * N * (k + 1)
    walls = [0.0] * R
    if saved[0] is not None:          # into the lanes: the orbits' own accumulators and states
        buf = b.save()                                    # the header of this batch
        steps = int(saved[0]["steps"])
        buf[4], buf[5], buf[6] = steps, saved[0]["acc"][0], R
        for r, d in enumerate(saved):
            p = _BATCH_HEADER + r * (_LANE_ACC + lane_len)
            buf[p:p + _LANE_ACC] = _lane_from_orbit(d["acc"], steps)
            buf[p + _LANE_ACC:p + _LANE_ACC + lane_len] = d["state"]
            for a, name in zip(arrays, ("t", "mle", "sali", "gali", "megno")):
                a[r] = d["s_" + name]
            walls[r] = float(d["wall"])
        b.restore(buf)

    def save(cpu):
        buf = b.save()
        t_batch = b.time()
        for r, s in enumerate(seeds):
            p = _BATCH_HEADER + r * (_LANE_ACC + lane_len)
            lane = buf[p:p + _LANE_ACC]
            acc = _orbit_from_lane(lane, spec.renorm_interval)
            if not lane[15]:                  # running: the lanes' common step and time
                acc[0] = buf[5]
            t_file = t_batch if not lane[15] else float(lane[4])
            tmp_state = buf[p + _LANE_ACC:p + _LANE_ACC + lane_len]
            path = _orbit_path(work, N, s)
            tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
            msg = b.message(r)
            with open(tmp, "wb") as f:
                np.savez(f, spec=np.array(spec_json), steps=np.int64(lane[14]),
                         t=np.float64(t_file), state=tmp_state, acc=acc,
                         s_t=arrays[0][r], s_mle=arrays[1][r], s_sali=arrays[2][r],
                         s_gali=arrays[3][r], s_megno=arrays[4][r], message=np.array(msg),
                         wall=np.float64(walls[r] + cpu / R), failed=np.bool_(False))
                f.flush()
                os.fsync(f.fileno())
            os.replace(tmp, path)

    seg = spec.renorm_interval * max(1, round(2e4 / spec.renorm_interval))
    cpu0 = time.process_time()
    last_save = time.monotonic()
    t_now = b.time()
    while not b.done() and t_now < t_until:
        b.advance(min(t_now + seg, t_until), *arrays)
        t_now = b.time()
        if time.monotonic() - last_save > save_every:
            save(time.process_time() - cpu0)
            last_save = time.monotonic()
    save(time.process_time() - cpu0)
    res = None
    summary = []
    for r, s in enumerate(seeds):
        res = b.get_result(r, res)
        summary.append({"N": N, "seed": s, "t": float(res.t_blowup if res.blew_up else
                                                      (t_now if not res.done else res.t_final)),
                        "done": bool(res.done)})
    del lats
    return summary


def _run_pieces(fn, calls, workers, scheduler):
    """Yield (call, result, error) for fn(*call) over a local process pool or a Dask cluster
    (fputlab.ensemble's engines)."""
    yield from run_calls(fn, calls, workers=workers, scheduler=scheduler)


class ChaosStudy:
    """A resumable chaos study in `work_dir` (see the module docstring).

    Parameters
    ----------
    work_dir : path
        Directory of the study: study.json (the parameters) and one state file per orbit.
        An existing directory is continued; its parameters must match the ones given (only
        the ones given are compared; the rest are taken from it).
    batched : bool, optional
        Advance the orbits of one N together in the vector lanes of the batched kernel
        (fputlab.chaos.batch; default) when the method allows it. The numbers are the same
        either way, and a study can switch between the two at any piece.
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
        desc = self.work / "study.json"
        if desc.exists():
            try:
                old = StudySpec.from_json(desc.read_text())
            except (ValueError, KeyError, TypeError, json.JSONDecodeError) as err:
                raise ValueError(f"{desc}: not a readable study description ({err})") from None
            given = StudySpec(**{**asdict(old), **params}).validate()
            if given != old:
                diff = [k for k in params if getattr(given, k) != getattr(old, k)]
                raise ValueError(f"{self.work} holds a study with other parameters "
                                 f"({', '.join(f'{k}={getattr(old, k)!r}' for k in diff)}); "
                                 f"use another work directory")
            self.spec = old
        else:
            if self.work.exists() and not self.work.is_dir():
                raise ValueError(f"work_dir {self.work} exists and is not a directory")
            self.spec = StudySpec(**params).validate()
            self.work.mkdir(parents=True, exist_ok=True)
            tmp = desc.with_name(".study.json.tmp")
            tmp.write_text(self.spec.to_json())
            os.replace(tmp, desc)
        self._json = self.spec.to_json()

    # -- running ---------------------------------------------------------------------------
    def orbits(self) -> list[tuple[int, int]]:
        s = self.spec
        return [(N, s.first_seed + r) for N in s.Ns for r in range(s.realisations)]

    def run(self, t_until: float | None = None, *, workers: int | None = None, scheduler=None,
            progress: bool = True, save_every: float = 120.0) -> dict:
        """Advance every orbit to t_until (default t_end), horizon by horizon, on a local
        process pool (`workers`, default all cores) or a Dask cluster (`scheduler`). Safe to
        interrupt at any moment: rerun to continue. Returns `status()`."""
        t_until = self.spec.t_end if t_until is None else float(t_until)
        if not (math.isfinite(t_until) and t_until > 0):
            raise ValueError(f"t_until must be finite and > 0 (got {t_until})")
        t_until = min(t_until, self.spec.t_end)
        horizons = [h for h in HORIZONS if h < t_until] + [t_until]
        from tqdm.auto import tqdm
        state = {o.N * 10**9 + o.seed: o for o in self._states()}
        total = sum(t_until if not o.done else o.t for o in state.values())
        bar = tqdm(total=total, desc="chaos study", unit="t", disable=None if progress else True,
                   bar_format="{l_bar}{bar}| {n:.3g}/{total:.3g} [{elapsed}<{remaining}]")
        bar.update(sum(min(o.t, t_until) for o in state.values()))
        try:
            for h in horizons:
                todo = [(o.N, o.seed, o.t) for o in state.values() if not o.done and o.t < h]
                todo.sort(key=lambda ns: -ns[0])     # the costly large-N orbits first
                fn, calls = self._calls(todo, h, workers, save_every)
                for call, outs, err in _run_pieces(fn, calls, workers, scheduler):
                    if err is not None:
                        raise err
                    for out in (outs if isinstance(outs, list) else [outs]):
                        o = state[out["N"] * 10**9 + out["seed"]]
                        before = o.t
                        o.t, o.done = out["t"], out["done"]
                        bar.update(min(o.t, t_until) - min(before, t_until))
                        if o.done:        # decided early: its remaining time is not work
                            bar.total -= t_until - min(o.t, t_until)
                            bar.refresh()
        finally:
            bar.close()
        return self.status()

    def _calls(self, todo, h, workers, save_every):
        """(function, calls) advancing the orbits `todo` to h: with a batchable method the
        orbits of one N go together in the vector lanes, in groups of >= 4 (one per core),
        else one orbit per call."""
        if not self.batched or self.spec.method not in BATCH_METHODS:
            return advance_orbit, [(self._json, N, seed, h, str(self.work), save_every)
                                   for N, seed, _ in todo]
        cores = workers or os.cpu_count() or 1
        calls = []
        # lanes must start at one step: orbits of one N at the same time (an interrupted piece
        # leaves a few in between; they form their own groups)
        for N, t in sorted({(N, t) for N, _, t in todo}, key=lambda nt: (-nt[0], nt[1])):
            seeds = [s for n, s, tt in todo if (n, tt) == (N, t)]
            per = max(4, -(-len(seeds) // cores))
            calls += [(self._json, N, seeds[i:i + per], h, str(self.work), save_every)
                      for i in range(0, len(seeds), per)]
        return advance_group, calls

    # -- reading ---------------------------------------------------------------------------
    def _states(self) -> list[OrbitState]:
        out = []
        for N, seed in self.orbits():
            d = _load(_orbit_path(self.work, N, seed), self._json)
            if d is None:
                out.append(OrbitState(N, seed))
                continue
            acc = d["acc"]
            # accumulators: m, logsum, next, n_samples, chaotic, t_chaotic, mle, sali, gali,
            # t_final, done, blew_up, t_blowup, completed, t_pending, MEGNO's 4 (fpl_chaos_save)
            k = int(acc[3])
            t, mle, sali, gali, megno = (np.asarray(d["s_" + n], float)[:k]
                                         for n in ("t", "mle", "sali", "gali", "megno"))
            blew_up = bool(acc[11])
            res = ChaosResult(t=t, mle=mle, sali=sali, gali=gali, chaotic=bool(acc[4]),
                              t_chaotic=float(acc[5]), t_final=float(acc[9]),
                              steps=int(d["steps"]), method=self.spec.method,
                              completed=bool(acc[13]), message=str(d["message"]),
                              params={"N": N, "model": self.spec.model, "tau": self.spec.tau,
                                      "seed": seed, "t_end": self.spec.t_end, "dt": self.spec.dt},
                              blew_up=blew_up, t_blowup=float(acc[12]), megno=megno)
            t_reached = float(acc[12]) if blew_up else float(d["t"])
            done = bool(acc[10]) or bool(d.get("failed", False))
            out.append(OrbitState(N, seed, t_reached, done, res, float(d["wall"])))
        return out

    def results(self) -> dict[int, list[ChaosResult]]:
        """{N: [ChaosResult per realisation]} as far as computed (None where not started)."""
        out: dict[int, list] = {N: [] for N in self.spec.Ns}
        for o in self._states():
            out[o.N].append(o.result)
        return out

    def reached(self) -> float:
        """The time every orbit has reached or been decided by: the study's honest horizon
        (t_end once every orbit is done)."""
        return min([o.t for o in self._states() if not o.done], default=self.spec.t_end)

    def classes(self, t_eval: float) -> dict[int, dict[str, int]]:
        """{N: {class: count}} at time t_eval; orbits that have not reached t_eval (and were not
        decided before it) are counted as 'not reached'."""
        out = {}
        for N, res in self.results().items():
            counts = {"chaotic": 0, "regular": 0, "blow-up": 0, "undecided": 0, "not reached": 0}
            for r in res:
                if r is None:
                    counts["not reached"] += 1
                    continue
                cls = r.classify(t_eval=t_eval)
                decided_before = cls in ("chaotic", "blow-up")
                t_reached = r.t_blowup if r.blew_up else r.t_final
                if not decided_before and t_reached < t_eval * (1 - 1e-12) and not (
                        r.completed and r.t_final >= self.spec.t_end):
                    counts["not reached"] += 1
                else:
                    counts[cls] += 1
            out[N] = counts
        return out

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
        st = self._states()
        return {"work_dir": str(self.work), "orbits": len(st),
                "done": sum(o.done for o in st), "reached": self.reached(),
                "cpu_seconds": sum(o.wall for o in st),
                "t_min": min(o.t for o in st), "t_max": max(o.t for o in st)}
