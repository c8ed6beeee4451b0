"""The study engine: every ensemble of fputlab is a study, and a study is data.

A study is a declarative `StudySpec`: the *kind* of task (what one grid point computes: chaos
indicators, a blow-up time, ...), the parameter *grid* (e.g. N x tau x seed), the *settings*
every task shares (model, method, dt, ...) and *t_end*. `run_study` turns it into tasks, runs
them on the one ensemble engine (`fputlab._engine.run_calls`: a local process pool or a Dask
cluster) and returns a `StudyResult`, a labelled `xarray.Dataset` underneath.

With ``work_dir`` the study lives on disk (`fputlab.io.store`): the spec with its key (a hash
of kind, grid and settings, t_end excluded), one file per task replaced atomically each time
the task reports, the merged result as netCDF. A rerun continues; a larger t_end continues every
unfinished task from its saved state (bit for bit, for the kinds that keep one); a changed spec
is refused (``overwrite=True`` or a new directory); a second runner is refused (fcntl lock).
Every task reports at the horizons (`HORIZONS`) and, for the kinds that continue from a saved
state, at least every ``max_call_seconds`` of CPU in between.
Without ``work_dir`` everything stays in memory, for small jobs.

Kinds are registered in one table, `KINDS`: name -> "module:attribute" of a `StudyKind`,
imported when first used (the kinds live with their physics, above this module). See
docs/architecture.md, "Studies", for the interface. The checks the kinds over disorder
realisations share (the N x tau x seed grid, unknown settings, defaults, the model) are one
helper, `normalise_disorder`, so every kind names a bad value the same way.
"""
from __future__ import annotations

import hashlib
import importlib
import json
import math
import time
from dataclasses import dataclass, field

import numpy as np

from ._engine import chunks, process_pool, run_calls, total_threads
from ._validate import C_U64, _int

__all__ = ["StudySpec", "StudyKind", "StudyResult", "KINDS", "get_kind", "run_study",
           "load_study", "wilson_interval", "HORIZONS", "MAX_CALL_SECONDS", "grid_values",
           "complete_settings", "normalise_disorder", "DISORDER_COORD_ATTRS", "fraction_rows"]

#: the study kinds: name -> "module:attribute" of its StudyKind. One line per kind.
KINDS = {
    "blowup": "fputlab.blowup:BLOWUP_KIND",
    "chaos": "fputlab.chaos.ensemble:CHAOS_KIND",
    "recurrence": "fputlab.recurrence:RECURRENCE_KIND",
    "run": "fputlab.sampled:RUN_KIND",
    "spectrum": "fputlab.chaos.spectrum:SPECTRUM_KIND",
    "thermalization": "fputlab.thermalization_study:THERMALIZATION_KIND",
}

#: the default bound of one call's CPU seconds (`run_study`'s max_call_seconds): a slow orbit's
#: way to the next horizon is cut into pieces of about this much, so a kill loses at most that
MAX_CALL_SECONDS = 300.0


def get_kind(name: str) -> "StudyKind":
    """The registered StudyKind called `name` (ValueError naming the known ones)."""
    if not isinstance(name, str) or name not in KINDS:
        raise ValueError(f"kind {name!r} is unknown (known: {', '.join(sorted(KINDS))})")
    module, attr = KINDS[name].split(":")
    return getattr(importlib.import_module(module), attr)


class StudyKind:
    """What one kind of task is. Subclass it, give it an instance in its module and a line in
    `KINDS`.

    Attributes
    ----------
    name : str
        As in `KINDS`.
    version : int
        Part of the spec's key: bump it when a task's numbers change.
    dims : tuple of str
        The grid dimensions, in order (e.g. ("N", "tau", "seed")).
    batch : int
        Tasks of one `group` are given to one call in chunks of at least this many (1: no
        batching; the chaos kind: its vector lanes).
    resumable : bool
        A task continues from its saved state (bit for bit): its calls may be cut short.
    variables : dict
        name -> (extra dims, dtype, units, long_name) of each value a task reports; extra dims
        (e.g. ("sample",)) follow the grid dims. dtype str: a string variable.
    """
    name = ""
    version = 1
    dims: tuple = ()
    batch = 1
    variables: dict = {}
    #: the kind continues a task from its saved state, bit for bit, so `run_study` may cut a
    #: call short (max_call_seconds); False: every call runs its tasks from the start
    resumable = False

    def normalise(self, grid: dict, settings: dict) -> tuple[dict, dict]:
        """The grid ({dim: list of values}) and settings, checked (ValueError naming the
        parameter) and completed with the defaults (which come from C)."""
        raise NotImplementedError

    def group(self, coords: dict, settings: dict, previous) -> object:
        """A key: tasks with equal keys may share one call (e.g. one N and one step count for
        the chaos lanes); None: each task alone."""
        return None

    def cost(self, coords: dict, settings: dict) -> float:
        """Relative cost of one unit of t of this task (the ETA and the order of submission)."""
        return 1.0

    def quantum(self, settings: dict) -> float:
        """A call that `run_study` cuts short (``max_call_seconds``) ends on a multiple of this
        time, one where the task's numbers do not depend on the cut (a renormalisation, a
        step): 1 unless the kind says otherwise."""
        return 1.0

    def run(self, settings: dict, coords: list, previous: list, t_end: float) -> list:
        """Worker side (looked up by name in the worker): advance each task (`coords[i]`, from
        its previous report `previous[i]`, or from the start if None) to t_end. Returns one
        report per task: {t (= t_end: the time it was advanced to), done, message, cpu,
        values: {name: array}, state: {name: array} or None}. `done`: a larger t_end changes
        nothing (a decided orbit, a blow-up, a failure). A task that failed and is to be tried
        again by the next run reports {"error": "<type>: <message>"} only: that call stores
        nothing (the task keeps its last good report) and is listed in
        `StudyResult.failed`."""
        raise NotImplementedError

    #: attributes (units, long_name) of the grid coordinates
    coord_attrs: dict = {}

    def extra_sizes(self, settings: dict, t_end: float) -> dict:
        """{extra dim: length} of the merged arrays at this t_end."""
        return {}

    def extra_coords(self, settings: dict, arrays: dict) -> dict:
        """Coordinates of the extra dims (e.g. the sample times), from the merged arrays."""
        return {}

    def summary(self, ds) -> list:
        """Rows of the summary table: dicts of grid coords, counts and fractions."""
        return []


# ---- the checks the kinds share ---------------------------------------------------------------

def grid_values(values, name: str, kind, minimum) -> list:
    """One dimension of a study's grid, checked: a number or a sequence of them.

    Parameters
    ----------
    values : number or array_like
        The values of the dimension.
    name : str
        The parameter the messages name (e.g. "Ns" for the dimension N).
    kind : type
        `int` or `float`: the type of every value (an int dimension refuses 2.5).
    minimum : number
        The smallest value allowed.

    Returns
    -------
    list
        The values as Python ints or floats, in the order given.

    Raises
    ------
    ValueError
        Not numbers, none, not integers (`kind` int), not finite, below `minimum`, or a value
        given twice (each names `name`).
    """
    try:
        # a list as given: numpy would make [2**64 - 1, 4.0] two floats
        raw = list(values) if isinstance(values, (list, tuple)) else np.atleast_1d(np.asarray(values)).tolist()
        vals = [kind(v) for v in raw]
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be numbers (got {values!r})") from None
    if not vals:
        raise ValueError(f"{name} must not be empty")
    # an int as it is (float(2**64 - 1) would round it to 2**64); anything else must be integral
    if kind is int and any(not isinstance(v, int) and not float(v).is_integer() for v in raw):
        raise ValueError(f"{name} must be integers (got {values!r})")
    if any(not math.isfinite(v) or v < minimum for v in vals):
        raise ValueError(f"{name} must be finite and >= {minimum} (got {vals})")
    if len(set(vals)) != len(vals):
        raise ValueError(f"{name} must not repeat values (got {vals})")
    return vals


def complete_settings(settings: dict, defaults: dict, what: str) -> dict:
    """A kind's settings completed with its defaults: a name not in `defaults` is refused
    (ValueError naming it and the known ones, "not a setting of <what> studies"); a setting
    given as None takes its default."""
    unknown = set(settings) - set(defaults)
    if unknown:
        raise ValueError(f"{', '.join(sorted(unknown))}: not a setting of {what} studies "
                         f"(known: {', '.join(sorted(defaults))})")
    return {**defaults, **{k: v for k, v in settings.items() if v is not None}}


#: the attributes of the grid coordinates N, tau, seed of a kind over disorder realisations (a
#: kind adds its extra dims': ``coord_attrs = {**DISORDER_COORD_ATTRS, "t": {...}}``)
DISORDER_COORD_ATTRS = {"N": {"long_name": "number of particles", "units": "1"},
                        "tau": {"long_name": "variability of the disorder", "units": "percent"},
                        "seed": {"long_name": "disorder seed (realisation)", "units": "1"}}


def normalise_disorder(grid: dict, settings: dict, defaults: dict, what: str
                       ) -> tuple[dict, dict]:
    """The checks every kind over disorder realisations shares (dims N, tau, seed): the grid
    and the settings common to them, before the kind checks its own.

    Parameters
    ----------
    grid : dict
        ``{"N": sizes, "tau": tolerances (percent), "seed": disorder seeds}``.
    settings : dict
        The settings as given (None: the default).
    defaults : dict
        The kind's settings and their defaults; it holds "model".
    what : str
        The kind as its messages name it ("blow-up", "chaos", ...).

    Returns
    -------
    grid : dict
        N as ints >= 2, tau as floats >= 0, seed as ints in [0, 2**64), none repeated.
    settings : dict
        `defaults` updated with the settings given; the model checked.

    Raises
    ------
    ValueError
        A bad grid value (naming "Ns", "tau" or "seeds"), an unknown setting (naming it) or
        an unknown model.
    """
    from ._lowlevel import MODEL_CODES     # the names of fputlab.lattice.MODELS, in its order
    grid = {"N": grid_values(grid["N"], "Ns", int, 2),
            "tau": grid_values(grid["tau"], "tau", float, 0.0),
            "seed": grid_values(grid["seed"], "seeds", int, 0)}
    for seed in grid["seed"]:       # the C seeds are unsigned 64-bit
        _int(seed, "seeds", C_U64)
    s = complete_settings(settings, defaults, what)
    if s["model"] not in MODEL_CODES:
        raise ValueError(f"model {s['model']!r} is unknown (known: {', '.join(MODEL_CODES)})")
    return grid, s


@dataclass(frozen=True)
class StudySpec:
    """kind, grid ({dim: tuple of values}), settings (JSON-able), t_end."""
    kind: str
    grid: dict
    settings: dict
    t_end: float

    def doc(self) -> dict:
        k = get_kind(self.kind)
        return {"kind": self.kind, "kind_version": k.version,
                "grid": {d: list(self.grid[d]) for d in k.dims}, "settings": self.settings}

    def key(self) -> str:
        """Hash of everything but t_end: a study with a larger t_end is the same study, run
        further."""
        text = json.dumps(self.doc(), sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(text.encode()).hexdigest()[:16]

    def tasks(self) -> list[dict]:
        dims = get_kind(self.kind).dims
        out = [{}]
        for d in dims:
            out = [{**c, d: v} for c in out for v in self.grid[d]]
        return out


def task_id(coords: dict) -> str:
    return "_".join(f"{k}{v!r}" if isinstance(v, float) else f"{k}{v}" for k, v in coords.items())


def wilson_interval(k: int, n: int, z: float = 1.959963984540054) -> tuple[float, float]:
    """Wilson score interval of a binomial proportion k/n (95 % by default); (nan, nan) if n = 0."""
    if n <= 0:
        return (math.nan, math.nan)
    p = k / n
    d = 1 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    # at k = 0 and k = n one end is exactly 0 or 1 (c - h rounds to ~1e-17 there)
    return (0.0 if k == 0 else max(0.0, c - h), 1.0 if k == n else min(1.0, c + h))


def fraction_rows(ds, hit, count: str, fraction: str) -> list[dict]:
    """The summary rows of a kind over disorder realisations: per (N, tau), of the tasks that
    started (finite ``t_reached``), how many are `hit`, and that fraction with its Wilson 95 %
    interval.

    Parameters
    ----------
    ds : xarray.Dataset
        The merged result (dims N, tau, seed first).
    hit : numpy.ndarray of bool
        Per task (N x tau x seed): the event counted (e.g. the blow-ups).
    count, fraction : str
        The keys of the count and of the fraction (with ``_low``, ``_high`` its interval).

    Returns
    -------
    list of dict
        ``{"N", "tau", "n", count, fraction, fraction_low, fraction_high}`` in the order N, tau
        (fraction NaN where no task started).
    """
    rows = []
    started = np.isfinite(ds["t_reached"].values)
    for i, N in enumerate(ds["N"].values):
        for j, tau in enumerate(ds["tau"].values):
            n = int(np.sum(started[i, j]))
            k = int(np.sum(hit[i, j] & started[i, j]))
            lo, hi = wilson_interval(k, n)
            rows.append({"N": int(N), "tau": float(tau), "n": n, count: k,
                         fraction: k / n if n else math.nan,
                         f"{fraction}_low": lo, f"{fraction}_high": hi})
    return rows


@dataclass(repr=False)
class StudyResult:
    """A finished (or partly finished) study: `to_xarray()` is the labelled result,
    `summary()` the table of counts and fractions with Wilson 95 % intervals."""
    kind: str
    dataset: object
    work_dir: str | None = None
    computed: int = 0
    resumed: int = 0
    reused: int = 0
    extras: dict = field(default_factory=dict)
    #: tasks that failed in this run (the failing call stores nothing: the next run tries
    #: again from the last good report), as (coords, "<type>: <message>") in grid order
    failed: list = field(default_factory=list)
    #: calls made (a task advanced in several pieces counts once per piece)
    calls: int = 0

    def to_xarray(self):
        """The result as an xarray.Dataset (dims: the grid, then e.g. sample)."""
        return self.dataset

    def summary(self) -> list[dict]:
        """Rows ``{grid coords..., n, <class or outcome> counts, fraction_*, *_low, *_high}``."""
        return get_kind(self.kind).summary(self.dataset)

    def __repr__(self) -> str:
        ds = self.dataset
        shape = " x ".join(f"{d}={ds.sizes[d]}" for d in get_kind(self.kind).dims)
        where = f", work_dir={self.work_dir!r}" if self.work_dir else ""
        bad = f", failed={len(self.failed)}" if self.failed else ""
        return (f"StudyResult(kind={self.kind!r}, {shape}, t_end={ds.attrs.get('t_end'):g}, "
                f"computed={self.computed}, reused={self.reused}{bad}{where})")

    def _repr_html_(self):
        rows = self.summary()
        if not rows:
            return f"<pre>{self!r}</pre>"
        head = "".join(f"<th>{k}</th>" for k in rows[0])
        body = "".join("<tr>" + "".join(f"<td>{v:.3g}</td>" if isinstance(v, float) else
                                        f"<td>{v}</td>" for v in r.values()) + "</tr>"
                       for r in rows)
        return f"<p>{self!r}</p><table><tr>{head}</tr>{body}</table>"


def _call(kind_name: str, settings: dict, coords: list, previous: list, t_end: float) -> list:
    """The worker's entry point: the kind's run (the kind is looked up by name in the worker)."""
    return get_kind(kind_name).run(settings, coords, previous, t_end)


class _Progress:
    """One progress display for every study: orbit-time done over orbit-time to do, with an ETA
    from the measured cost per unit of t of each task (cost-weighted: the long N = 64 orbits
    count as what they cost, whether they have started or not)."""

    def __init__(self, kind, settings, todo, t_end, enabled):
        from tqdm.auto import tqdm
        self.kind, self.settings, self.t_end = kind, settings, t_end
        self.left = {task_id(c): (kind.cost(c, settings), t_end - t0) for c, t0 in todo}
        self.total = sum(w * dt for w, dt in self.left.values()) or 1.0
        self.done_work, self.cpu, self.t0 = 0.0, 0.0, time.monotonic()
        self.bar = tqdm(total=len(todo), desc=f"{kind.name} study", unit="task",
                        disable=None if enabled else True)

    def update(self, tid: str, report: dict, cpu: float) -> None:
        w, dt = self.left.pop(tid, (0.0, 0.0))
        self.done_work += w * dt
        self.cpu += cpu
        self.bar.update(1)
        if self.done_work > 0 and self.left:
            rate = (time.monotonic() - self.t0) / self.done_work
            eta = rate * sum(w * d for w, d in self.left.values())
            self.bar.set_postfix_str(f"ETA {eta:.0f} s (cost-weighted)")

    def close(self):
        self.bar.close()


def run_study(kind: str, grid: dict, settings: dict, t_end: float, *, work_dir=None,
              overwrite: bool = False, workers: int | None = None, scheduler=None,
              progress: bool = False, max_call_seconds: float | None = MAX_CALL_SECONDS
              ) -> StudyResult:
    """Run a study (see the module docstring) and return its `StudyResult`.

    Parameters
    ----------
    kind : str
        A kind of `KINDS` ("chaos", "blowup", ...).
    grid : dict
        {dim: values} over the kind's dims.
    settings : dict
        What every task shares (the kind's options; defaults from C).
    t_end : float
        How far every task runs.
    work_dir : path, optional
        The study's directory (created; continued on a rerun). Default: in memory.
    overwrite : bool, optional
        Discard the results of another study in `work_dir` instead of refusing.
    workers : int, optional
        Local processes (default: all cores).
    scheduler : str, dask.distributed.Client or cluster, optional
        Run on Dask: tasks are sized by the cluster's total threads.
    progress : bool, optional
        A progress bar with a cost-weighted ETA.
    max_call_seconds : float or None, optional
        Most CPU seconds of one call of a resumable kind (default `MAX_CALL_SECONDS`): a
        task's first call goes 1/16 of the way to its horizon (a probe of its cost), then its
        way is cut into calls of at most this long by the measured CPU per unit of t (ending
        on multiples of the kind's `StudyKind.quantum`, where the numbers do not depend on the
        cut), so every task reports, and a kill loses, at most about this much. None: one call
        per horizon.

    Raises
    ------
    ValueError
        Invalid grid, settings or t_end (named), another study in `work_dir`, or a t_end below
        the one the study already reached.
    fputlab.io.atomic.DirectoryBusy
        Another process is running this study.
    fputlab._engine.SchedulerLost
        The Dask scheduler went away; the finished tasks are in `work_dir`: rerun to continue.
    """
    k = get_kind(kind)
    if not isinstance(grid, dict) or set(grid) != set(k.dims):
        raise ValueError(f"grid must have exactly the dims {list(k.dims)} (got "
                         f"{sorted(grid) if isinstance(grid, dict) else type(grid).__name__})")
    grid, settings = k.normalise(dict(grid), dict(settings))
    try:
        t_end = float(t_end)
    except (TypeError, ValueError):
        raise ValueError(f"t_end must be a number (got {t_end!r})") from None
    if not (math.isfinite(t_end) and t_end > 0):
        raise ValueError(f"t_end must be finite and > 0 (got {t_end:g})")
    if max_call_seconds is not None:
        try:
            max_call_seconds = float(max_call_seconds)
        except (TypeError, ValueError):
            raise ValueError(f"max_call_seconds must be a number or None (got "
                             f"{max_call_seconds!r})") from None
        if not max_call_seconds > 0:
            raise ValueError(f"max_call_seconds must be > 0 (got {max_call_seconds:g})")
    spec = StudySpec(kind, grid, settings, t_end)
    store = None
    if work_dir is not None:
        from .io.store import StudyStore
        store = StudyStore(work_dir, {**spec.doc(), "key": spec.key()}, overwrite=overwrite)
    try:
        return _run(k, spec, store, workers, scheduler, progress, max_call_seconds)
    finally:
        if store is not None:
            store.close()


#: the horizons of a long study (1, 2, 5 per decade from 1e4): every task reaches one before any
#: goes further, so the classes are known for every task at the same time, and a kill loses at
#: most the piece since the last one (at most 60 % of the time reached)
HORIZONS = tuple(m * 10.0 ** e for e in range(4, 13) for m in (1, 2, 5))


def load_study(work_dir) -> StudyResult:
    """The study in `work_dir` as far as it has been computed, merged from its task files
    without computing anything and without the lock (a runner may be at work)."""
    from .io.store import StudyStore
    store = StudyStore.reader(work_dir)
    d = store.doc
    k = get_kind(d["kind"])
    t_end = store.t_end()
    spec = StudySpec(d["kind"], {dim: list(v) for dim, v in d["grid"].items()}, d["settings"],
                     t_end if t_end is not None else math.nan)
    if spec.key() != d.get("key"):
        raise ValueError(f"{store.path}: the study's key does not match its description "
                         "(written by another version of the kind?)")
    ds = _merge(k, spec, spec.tasks(), store, {})
    return StudyResult(k.name, ds, str(store.path))


def _run(k, spec, store, workers, scheduler, progress, max_call_seconds=None) -> StudyResult:
    t_end = spec.t_end
    if store is not None:
        reached = store.t_end()
        if reached is not None and t_end < reached:
            raise ValueError(f"t_end = {t_end:g} is below the {reached:g} this study was already "
                             "run to: use a new work_dir for a shorter study")
    tasks = spec.tasks()
    memory: dict[str, dict] = {}        # in-memory reports (no work_dir)
    # the last report of every unfinished task this run has written: the next call's
    # `previous` without reading it back (each call carries it to a worker anyway, so this
    # holds no more than a round's calls do)
    latest: dict[str, dict] = {}

    def previous(c):
        tid = task_id(c)
        if store is None:
            return memory.get(tid)
        return latest[tid] if tid in latest else store.read_task(tid, c)
    todo, reused, resumed = [], 0, 0
    for c in tasks:
        rep = previous(c)
        if rep is not None and (rep["done"] or rep["t"] >= t_end):
            reused += 1
        else:
            resumed += rep is not None
            todo.append((c, rep["t"] if rep is not None else 0.0))
    computed, n_calls = 0, 0
    failed: dict[str, tuple] = {}
    if todo:
        if store is not None:
            store.set_t_end(t_end)
        threads = total_threads(workers, scheduler)
        bar = _Progress(k, spec.settings, todo, t_end, progress)
        t_min = min(t0 for _, t0 in todo)
        rounds = [h for h in HORIZONS if t_min < h < t_end] + [t_end]
        reached = {task_id(c): t0 for c, t0 in todo}      # where each task is
        rate: dict[str, float] = {}                       # measured cpu per unit of t
        # one local pool for every round (starting processes is most of a small task's cost)
        pool = process_pool(workers) if scheduler is None else None
        try:
            for h in rounds:
                while True:        # a horizon in pieces of at most max_call_seconds per call
                    live = [c for c, _ in todo if task_id(c) not in failed]
                    calls = _plan(k, spec, live, previous, h, threads, rate, reached,
                                  max_call_seconds)
                    if not calls:
                        break
                    for call, reports, err in run_calls(_call, calls, workers=workers,
                                                        scheduler=scheduler, pool=pool):
                        if err is not None:
                            raise err
                        n_calls += 1
                        for c, rep in zip(call[2], reports):
                            tid = task_id(c)
                            if rep.get("error") is not None:     # not stored: tried again
                                failed[tid] = (c, str(rep["error"]))
                                bar.update(tid, rep, 0.0)
                                continue
                            advanced = float(rep["t"]) - reached[tid]
                            if not rep["done"] and advanced <= 0:
                                raise RuntimeError(f"{k.name} task {tid} did not advance from "
                                                   f"t = {reached[tid]:g} (a bug of the kind)")
                            if advanced > 0 and rep.get("cpu", 0.0) > 0:
                                rate[tid] = float(rep["cpu"]) / advanced
                                per = rate[tid] / max(k.cost(c, spec.settings), 1e-300)
                                rate[_PER_COST] = max(rate.get(_PER_COST, 0.0), per)
                            reached[tid] = float(rep["t"])
                            if store is not None:
                                store.write_task(tid, c, rep)
                                if rep["done"]:
                                    latest.pop(tid, None)
                                else:
                                    latest[tid] = rep
                            else:
                                memory[tid] = rep
                            if rep["done"] or rep["t"] >= t_end:
                                computed += 1
                                bar.update(tid, rep, rep.get("cpu", 0.0))
        finally:
            bar.close()
            if pool is not None:
                pool.shutdown(wait=True, cancel_futures=True)
    elif store is not None and store.t_end() is None:
        store.set_t_end(t_end)
    ds = _merge(k, spec, tasks, store, memory)
    if store is not None:
        store.write_result(ds)
    order = {task_id(c): i for i, c in enumerate(tasks)}
    return StudyResult(k.name, ds, str(store.path) if store is not None else None,
                       computed=computed, resumed=resumed, reused=reused,
                       failed=[failed[t] for t in sorted(failed, key=order.get)],
                       calls=n_calls)


def _plan(k, spec, todo, previous, h, threads, rate=None, reached=None,
          max_call_seconds=None) -> list:
    """The calls that advance the unfinished tasks of `todo` towards h: tasks of one `group`
    key together in chunks (one per thread, at least `k.batch`), the costly ones first. A call
    whose cost per unit of t is measured (`rate`, cpu / t of each task's last call) ends early
    enough to take at most `max_call_seconds`, on a multiple of the kind's quantum (the caller
    plans again until every task is at h)."""
    groups: dict = {}
    for c in todo:
        rep = previous(c)
        if rep is not None and (rep["done"] or rep["t"] >= h):
            continue
        key = k.group(c, spec.settings, rep)
        groups.setdefault(key, []).append((c, rep))
    calls = []
    for key, members in groups.items():
        pieces = chunks(members, threads, k.batch) if key is not None else [[m] for m in members]
        for p in pieces:
            coords = [m[0] for m in p]
            target = h
            if max_call_seconds and k.resumable:
                ids = [task_id(c) for c in coords]
                t0 = max(reached[i] for i in ids)
                per_t = _call_rate(k, spec.settings, coords, ids, rate)
                q = float(k.quantum(spec.settings))
                if per_t is None:       # nothing measured yet: a probe, 1/16 of the way
                    end = t0 + (h - t0) / 16
                else:
                    end = t0 + max_call_seconds / per_t
                n = max(math.floor(end / q + 1e-9), math.floor(t0 / q + 1e-9) + 1)   # >= one q on
                target = min(h, n * q)
            calls.append((k.name, spec.settings, coords, [m[1] for m in p], target))
    calls.sort(key=lambda call: -sum(k.cost(c, spec.settings) for c in call[2]))
    return calls


def _call_rate(k, settings, coords, ids, rate) -> float | None:
    """CPU seconds per unit of t of a call of these tasks: the sum of each task's own measured
    rate, else the largest rate per unit of `cost` measured on any task times their cost (None:
    nothing measured yet)."""
    if all(i in rate for i in ids):
        return sum(rate[i] for i in ids)
    per_cost = rate.get(_PER_COST)
    if per_cost is None:
        return None
    return per_cost * sum(k.cost(c, settings) for c in coords)


#: the key of `rate` holding the largest measured cpu per unit of t and of cost
_PER_COST = "(per unit of cost)"


def _merge(k, spec, tasks, store, memory):
    """The labelled result: one variable per reported value over the grid dims (+ extra dims),
    filled task by task from the store (or memory) in one pass: the client holds the arrays,
    never all the reports."""
    import xarray as xr
    from ._lowlevel import VERSION
    shape = tuple(len(spec.grid[d]) for d in k.dims)
    index = {d: {v: i for i, v in enumerate(spec.grid[d])} for d in k.dims}
    sizes = k.extra_sizes(spec.settings, spec.t_end)
    arrays = {}
    for name, (edims, dtype, _, _) in k.variables.items():
        full = shape + tuple(sizes[d] for d in edims)
        if dtype is str:
            arrays[name] = np.full(full, "", dtype=object)
        elif np.dtype(dtype).kind == "f":
            arrays[name] = np.full(full, np.nan)
        else:
            arrays[name] = np.zeros(full, dtype=dtype)
    t_reached = np.full(shape, np.nan)
    finished = np.zeros(shape, dtype=bool)
    for c in tasks:
        rep = (store.read_task(task_id(c), c, state=False) if store is not None
               else memory.get(task_id(c)))
        if rep is None:
            continue
        at = tuple(index[d][c[d]] for d in k.dims)
        t_reached[at], finished[at] = rep["t"], rep["done"]
        for name, (edims, dtype, _, _) in k.variables.items():
            v = rep["values"].get(name)
            if v is None:
                continue
            if edims:
                v = np.asarray(v)[tuple(slice(0, sizes[d]) for d in edims)]
                arrays[name][at + tuple(slice(0, n) for n in v.shape)] = v
            else:
                arrays[name][at] = str(v) if dtype is str else v
    # an extra dim ends where the last value of any task does (the sample grid runs past t_end)
    for d in sizes:
        used = 0
        for name, (edims, dtype, _, _) in k.variables.items():
            if d in edims and dtype is float:
                axis = len(k.dims) + edims.index(d)
                other = tuple(i for i in range(arrays[name].ndim) if i != axis)
                filled = np.flatnonzero(np.any(np.isfinite(arrays[name]), axis=other))
                used = max(used, int(filled[-1]) + 1 if filled.size else 0)
        for name, (edims, _, _, _) in k.variables.items():
            if d in edims:
                axis = len(k.dims) + edims.index(d)
                arrays[name] = np.take(arrays[name], np.arange(used), axis=axis)
    coords = {d: list(spec.grid[d]) for d in k.dims}
    coords.update(k.extra_coords(spec.settings, arrays))
    data = {}
    for name, (edims, dtype, units, long_name) in k.variables.items():
        arr = arrays[name].astype(str) if dtype is str else arrays[name]
        attrs = {"long_name": long_name}
        if units and units != "1":     # dimensionless: no units (labels "time", not "time [1]")
            attrs["units"] = units
        data[name] = (k.dims + tuple(edims), arr, attrs)
    if "t_reached" not in data:     # a kind's own (the blow-up time of a run stopped there)
        data["t_reached"] = (k.dims, t_reached, {"long_name": "time reached"})
    data["finished"] = (k.dims, finished,
                        {"long_name": "task finished: a larger t_end adds nothing"})
    ds = xr.Dataset(data, coords=coords)
    for d, attrs in k.coord_attrs.items():
        if d in ds.coords:
            ds[d].attrs.update({a: v for a, v in attrs.items() if (a, v) != ("units", "1")})
    ds.attrs.update({"kind": spec.kind, "t_end": spec.t_end, "study_key": spec.key(),
                     "settings": json.dumps(spec.settings, sort_keys=True),
                     "fputlab_version": VERSION})
    return ds
