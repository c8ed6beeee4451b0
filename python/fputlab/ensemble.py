"""Ensembles beyond one machine: realisation x tau x N sweeps of blow-up times or chaos indicators
run as independent tasks, on a local process pool or on a Dask cluster, resumable from a work
directory, merged into one HDF5 file at the end. A sweep is a study of the study engine
(`fputlab.engine.run_study`, kinds "blowup" and "chaos"); `run_sweep` adds the merged file of
one row per task.

    >>> from fputlab.ensemble import run_sweep, load_sweep
    >>> out = run_sweep("blowup", tau=[10, 20], Ns=[64], realisations=50, t_end=1e4,
    ...                 work_dir="sweep.d", out="sweep.h5")                  # all local cores
    >>> out = run_sweep("chaos", [10], [8, 16], 30, t_end=1e6, work_dir="c.d", out="c.h5",
    ...                 scheduler="tcp://10.0.0.1:8786")                      # a Dask cluster
    >>> load_sweep("sweep.h5")["blew_up"]

Each task (kind, N, tau, seed) is one disorder realisation `Lattice(N, alpha, model, tau=tau,
seed=seed)`; seeds are first_seed .. first_seed + realisations - 1, the same for every tau and N.
The task's result travels back to the client, which writes it to the study's directory
(`fputlab.io.store`: tasks/<id>.h5, replaced atomically), so the work directory need not be
shared with remote workers. Running the same sweep again skips every finished task; a task that
raised is reported and not written, so the next run retries it.
"""
from __future__ import annotations

import hashlib
import inspect
import json
import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from ._lowlevel import VERSION
from ._engine import check_ensemble, process_pool, run_calls  # noqa: F401 (public here too)
from ._validate import _finite_real, _path, _renamed, _seed
from .io.atomic import write_h5_atomic

__all__ = ["run_sweep", "load_sweep", "run_task", "run_chaos_group", "run_calls", "check_ensemble",
           "process_pool", "SweepSpec", "Task", "TaskOutcome", "Failure", "TaskFailed", "KINDS",
           "COLUMNS", "SERIES"]

#: kinds of task
KINDS = ("blowup", "chaos")
#: scalar outcome columns of each kind (name -> numpy dtype); "criterion"/"classification" are str
COLUMNS = {
    "blowup": {"blew_up": bool, "time": float, "criterion": str, "t_reached": float,
               "tau_c": float},
    "chaos": {"mle": float, "sali": float, "classification": str, "t_final": float,
              "chaotic": bool, "t_chaotic": float, "steps": np.int64, "completed": bool,
              "blew_up": bool, "t_blowup": float},
}
#: per-task series of the chaos kind (stored as 2-D datasets, NaN-padded, in the merged file)
SERIES = {"chaos": ("t", "mle_t", "sali_t")}

@dataclass(frozen=True)
class Task:
    """One realisation: the unit of work."""
    kind: str
    N: int
    tau: float
    seed: int

    def stem(self, key: str) -> str:
        """File name stem of the task's result file in a sweep with key `key`
        (`SweepSpec.key`)."""
        return f"{self.kind}_N{self.N}_tau{self.tau!r}_seed{self.seed}_{key}"


@dataclass(frozen=True)
class SweepSpec:
    """What every task of a sweep shares."""
    kind: str
    model: str
    alpha: float
    t_max: float
    method: str
    options: tuple          # sorted (name, value) pairs passed to blowup_time / lyapunov

    def key(self) -> str:
        """Short hash of the shared parameters: part of every task file name."""
        text = json.dumps({"kind": self.kind, "model": self.model, "alpha": self.alpha,
                           "t_max": self.t_max, "method": self.method,
                           "options": self.options}, sort_keys=True, default=_jsonable)
        return hashlib.sha256(text.encode()).hexdigest()[:10]


def _jsonable(x):
    if isinstance(x, np.ndarray):
        return x.tolist()
    if isinstance(x, np.generic):
        return x.item()
    return repr(x)


class Failure(NamedTuple):
    """A task that raised (`run_sweep`'s ``failed``): the task and "<exception type>: <message>"."""
    task: Task
    message: str


class TaskOutcome(NamedTuple):
    """What a worker returns for one task of a group (`run_chaos_group`): exactly one of
    `record` and `message` is None."""
    task: Task
    record: dict | None
    message: str | None


# ---- one task (runs in a worker process) ------------------------------------------------------

class TaskFailed(RuntimeError):
    """A task raised: the message is "<exception type>: <message>" (plain, hence picklable, so it
    crosses process and machine boundaries where e.g. IntegrationError(.., result) does not)."""


def run_task(task: Task, spec: SweepSpec) -> dict:
    """Compute one task in the calling process.

    Parameters
    ----------
    task : Task
        The realisation (kind, N, tau, seed).
    spec : SweepSpec
        What every task of the sweep shares (model, alpha, t_max, method, options).

    Returns
    -------
    dict
        The task's record: ``kind``, ``N``, ``tau``, ``seed``, the outcome columns of its kind
        (`COLUMNS`) and, for chaos, the series (`SERIES`).

    Raises
    ------
    TaskFailed
        Whatever the computation raised, as "<exception type>: <message>" (picklable).
    """
    try:
        return _compute(task, spec)
    except Exception as err:
        raise TaskFailed(f"{type(err).__name__}: {err}") from None


def _compute(task: Task, spec: SweepSpec) -> dict:
    """Compute one task; returns its record {kind, N, tau, seed, <outcome columns>, [series]}.

    blowup: fputlab.blowup.blowup_time and the realisation's own two-mode tau_c
    (fputlab.blowup.realisation_tau_c), i.e. what blowup_sweep's per-task function computes, plus
    the criterion and the time reached. chaos: fputlab.chaos's per-task function
    (`_one_realisation`, as chaotic_fraction) and ChaosResult.classify()."""
    from .lattice import Lattice
    opts = dict(spec.options)
    rec: dict[str, Any] = {"kind": task.kind, "N": task.N, "tau": task.tau, "seed": task.seed}
    if task.kind == "blowup":
        from .blowup import blowup_time, realisation_tau_c
        lat = Lattice(task.N, spec.alpha, spec.model, tau=task.tau, seed=task.seed)
        res = blowup_time(lat, spec.t_max, method=spec.method, **opts)
        tau_c = (realisation_tau_c(task.N, task.seed, spec.alpha)
                 if spec.model != "homogeneous" else float("nan"))
        rec.update(blew_up=bool(res.blew_up), time=float(res.time), criterion=res.criterion,
                   t_reached=float(res.t_reached), tau_c=float(tau_c))
    elif task.kind == "chaos":
        from .chaos import _one_realisation
        orbit = _one_realisation((task.N, task.tau, task.seed, spec.model, spec.alpha,
                                  spec.t_max, spec.method, opts))
        rec.update(_chaos_outcome(orbit.result))
    else:
        raise ValueError(f"kind {task.kind!r} is unknown (known: {', '.join(KINDS)})")
    return rec


def _chaos_outcome(res) -> dict:
    """The outcome columns and series of a chaos task from its ChaosResult."""
    return dict(mle=res.mle_final, sali=float(res.sali[-1]) if res.sali.size else float("nan"),
                classification=res.classify(), t_final=float(res.t_final),
                chaotic=bool(res.chaotic), t_chaotic=float(res.t_chaotic),
                steps=int(res.steps), completed=bool(res.completed),
                blew_up=bool(res.blew_up), t_blowup=float(res.t_blowup),
                t=np.asarray(res.t, float), mle_t=np.asarray(res.mle, float),
                sali_t=np.asarray(res.sali, float))


def run_chaos_group(tasks: list, spec: SweepSpec) -> list:
    """Several chaos tasks of one (tau, N) in the batched kernel's vector lanes
    (`fputlab.chaos.batch`): the records `run_task` gives for each, at a fraction of the cost
    for small N.

    Parameters
    ----------
    tasks : list of Task
        Chaos tasks sharing tau and N.
    spec : SweepSpec
        The sweep's shared parameters (a batchable method and options).

    Returns
    -------
    list of TaskOutcome
        One per task, in the order given: the record, or the message of the failure (a
        failure of the batch fails every task in it).
    """
    from .chaos import _batch_of_realisations
    t0 = tasks[0]
    try:
        out = _batch_of_realisations((t0.N, t0.tau, [t.seed for t in tasks], spec.model,
                                      spec.alpha, spec.t_max, spec.method, dict(spec.options)))
    except Exception as err:
        return [TaskOutcome(t, None, f"{type(err).__name__}: {err}") for t in tasks]
    return [TaskOutcome(t, {"kind": t.kind, "N": t.N, "tau": t.tau, "seed": t.seed,
                            **_chaos_outcome(orbit.result)}, None)
            for t, orbit in zip(tasks, out)]


# ---- validation -------------------------------------------------------------------------------

def _validate(kind, taus, Ns, realisations, t_max, model, alpha, first_seed, method, workers,
              task_options) -> tuple[list[float], list[int], int, SweepSpec]:
    from .integrate import method_info
    from .lattice import MODELS
    if kind not in KINDS:
        raise ValueError(f"kind {kind!r} is unknown (known: {', '.join(KINDS)})")
    try:
        taus = [float(t) for t in np.atleast_1d(np.asarray(taus, dtype=float))]
    except (TypeError, ValueError):
        raise ValueError(f"tau must be numbers (got {taus!r})") from None
    if not taus:
        raise ValueError("tau must not be empty")
    if not all(math.isfinite(t) and t >= 0 for t in taus):
        raise ValueError(f"tau must be finite and >= 0 (got {taus})")
    try:
        Ns_arr = np.atleast_1d(np.asarray(Ns))
        if Ns_arr.size and not np.all(np.equal(np.mod(Ns_arr.astype(float), 1), 0)):
            raise ValueError
        Ns = [int(n) for n in Ns_arr]
    except (TypeError, ValueError):
        raise ValueError(f"Ns must be integers (got {Ns!r})") from None
    if not Ns:
        raise ValueError("Ns must not be empty")
    if min(Ns) < 2:
        raise ValueError(f"Ns must all be >= 2 (got {Ns})")
    if isinstance(realisations, bool) or not isinstance(realisations, (int, np.integer)):
        raise ValueError(f"realisations must be an integer (got {realisations!r})")
    if realisations < 1:
        raise ValueError(f"realisations must be >= 1 (got {realisations})")
    try:
        t_max = float(t_max)
    except (TypeError, ValueError):
        raise ValueError(f"t_end must be a number (got {t_max!r})") from None
    if not (math.isfinite(t_max) and t_max > 0):
        raise ValueError(f"t_end must be finite and > 0 (got {t_max:g})")
    if model not in MODELS:
        raise ValueError(f"model {model!r} is unknown (known: {', '.join(MODELS)})")
    if model == "homogeneous" and any(t != 0 for t in taus):
        raise ValueError("taus: the homogeneous model has no disorder (use taus=[0])")
    alpha = _finite_real(alpha, "alpha")          # a TypeError naming alpha, not float()'s
    if isinstance(first_seed, bool) or not isinstance(first_seed, (int, np.integer)) \
            or first_seed < 0:
        raise ValueError(f"first_seed must be an integer >= 0 (got {first_seed!r})")
    # every seed is a C unsigned 64-bit integer (2**64 failed inside HDF5 with a dtype message)
    _seed(int(first_seed) + int(realisations) - 1, "first_seed + realisations - 1")
    if workers is not None and (not isinstance(workers, (int, np.integer)) or workers < 1):
        raise ValueError(f"workers must be an integer >= 1 (got {workers!r})")
    if kind == "chaos":      # the validated fast scheme and early stop, unless given
        from .chaos import ensemble_defaults
        method, task_options = ensemble_defaults(method, task_options)
    method = "yoshida4" if method is None else method
    if not isinstance(method, str):
        raise ValueError(f"method must be a string (got {method!r})")
    method_info(method)                       # raises ValueError naming an unknown method
    from .blowup import blowup_time
    from .chaos import lyapunov
    fn = blowup_time if kind == "blowup" else lyapunov
    allowed = set(inspect.signature(fn).parameters) - {"lattice", "t_max", "t_end", "method"}
    for name in task_options:
        if name not in allowed:
            raise ValueError(f"{name}: not an option of {kind} tasks "
                             f"(known: {', '.join(sorted(allowed))})")
    spec = SweepSpec(kind, model, alpha, t_max, method, tuple(sorted(task_options.items())))
    return taus, Ns, int(realisations), spec


# ---- the sweep --------------------------------------------------------------------------------

def run_sweep(kind: str, tau=None, Ns=None, realisations: int | None = None, *,
              t_end: float | None = None, work_dir=None, out=None, model: str = "nonlinear",
              alpha: float = 0.25, first_seed: int = 1, method: str | None = None,
              workers: int | None = None, scheduler=None, progress: bool = True, taus=None,
              t_max: float | None = None, overwrite: bool = False, **task_options) -> dict:
    """Run a sweep of (tau, N, seed) tasks as a study of the study engine
    (`fputlab.engine.run_study`, kind "blowup" or "chaos") and merge all results into one HDF5
    file (one row per task, in the order tau, N, seed).

    Each task is one disorder realisation ``Lattice(N, alpha, model, tau=tau, seed=seed)``; with
    `work_dir` its result is written to the study's directory as it arrives (`fputlab.io.store`),
    so running the same sweep again computes only what is missing (a task that raised is
    retried) and a larger t_end continues the blow-up runs from their saved states.

    Parameters
    ----------
    kind : {"blowup", "chaos"}
        "blowup": `fputlab.blowup.blowup_time`'s numbers up to `t_end`; "chaos":
        `fputlab.chaos.lyapunov`'s numbers up to `t_end` (on its sample grid: `n_samples`
        log-spaced samples up to t_end).
    tau : sequence of float
        Variabilities in percent. (`taus`: its old spelling, deprecated.)
    Ns : sequence of int
        Lattice sizes.
    realisations : int
        Realisations per (tau, N), seeds ``first_seed .. first_seed + realisations - 1``.
    t_end : float
        Final time of every task. (`t_max`: its old spelling, deprecated.)
    work_dir : str or path, optional
        The study's directory (created; reused to resume; another sweep's is refused). Default:
        in memory. A directory of the per-task files of run_sweep before the study engine is
        refused with a message (finish it with that version, or use a new directory).
    out : str or path, optional
        The merged HDF5 file (layout: docs/hdf5.md); default: none.
    model : str, optional
        Lattice model (default "nonlinear", the paper's model 3).
    alpha : float, optional
        Cubic coupling.
    first_seed : int, optional
        Disorder seed of the first realisation.
    method : str, optional
        Integrator (default "yoshida4" for blowup; for chaos the ensemble default
        `fputlab.chaos.ENSEMBLE_METHOD` at `fputlab.chaos.ENSEMBLE_DT`).
    workers : int, optional
        Local worker processes (default: all cores).
    scheduler : str, dask.distributed.Client or cluster, optional
        Run the tasks on Dask instead of the local pool.
    progress : bool, optional
        The study engine's progress bar (tasks, cost-weighted ETA).
    taus : sequence of float, optional
        Deprecated spelling of `tau` (warns; removed in the next release).
    t_max : float, optional
        Deprecated spelling of `t_end` (warns; removed in the next release).
    overwrite : bool, optional
        Discard another study found in `work_dir` instead of refusing.
    **task_options
        Passed to `blowup_time` / `lyapunov` (e.g. dt, rtol, n_samples).

    Returns
    -------
    dict
        ``out``, ``work_dir``, ``n_tasks``, ``computed``, ``skipped``, ``failed`` (a list of
        `Failure`: task and message), ``records`` (one dict per finished task), ``summary``
        ([{"tau", "N", "n", "fraction"}], fraction: the share that blew up, or was classified
        chaotic) and ``study``: the `fputlab.engine.StudyResult` (``to_xarray()``,
        ``summary()`` with Wilson 95 % intervals).

    Raises
    ------
    ValueError
        An invalid argument (the message names it), a task option the kind does not take,
        another study or old-format task files in `work_dir`.

    Examples
    --------
    >>> out = run_sweep("blowup", [10, 20], [64], 50, t_end=1e4,
    ...                 work_dir="sweep.d", out="sweep.h5")        # doctest: +SKIP
    >>> out["summary"]                                             # doctest: +SKIP
    >>> out["study"].to_xarray()                                   # doctest: +SKIP
    """
    from .engine import run_study
    taus = _renamed(tau, taus, "tau", "taus")
    t_max = _renamed(t_end, t_max, "t_end", "t_max")
    if taus is None or Ns is None or realisations is None or t_max is None:
        raise TypeError("run_sweep() needs tau, Ns, realisations and t_end")
    taus, Ns, realisations, spec = _validate(kind, taus, Ns, realisations, t_max, model, alpha,
                                             first_seed, method, workers, task_options)
    if work_dir is not None:
        work_dir = _path(work_dir, "work_dir")           # bytes, NUL, "" checked
        _refuse_old_task_files(Path(work_dir))
    if out is not None:
        out = _path(out, "out")
    seeds = [int(first_seed) + r for r in range(realisations)]
    grid = {"N": Ns, "tau": taus, "seed": seeds}
    study = run_study(kind, grid, _study_settings(spec), spec.t_max, work_dir=work_dir,
                      overwrite=overwrite, workers=workers, scheduler=scheduler,
                      progress=progress)
    failed = [Failure(Task(kind, int(c["N"]), float(c["tau"]), int(c["seed"])), msg)
              for c, msg in study.failed]
    order = {(t, N, s): i for i, (t, N, s) in
             enumerate((t, N, s) for t in taus for N in Ns for s in seeds)}
    failed.sort(key=lambda f: order[(f.task.tau, f.task.N, f.task.seed)])
    done = _study_records(kind, study.dataset, {(f.task.N, f.task.tau, f.task.seed)
                                                for f in failed})
    n_tasks = len(taus) * len(Ns) * realisations
    # one name per idea: the merged file says tau and t_end, as the arguments do
    params = {"kind": kind, "tau": np.array(taus), "Ns": np.array(Ns),
              "realisations": realisations, "t_end": spec.t_max, "model": model,
              "alpha": spec.alpha, "first_seed": int(first_seed), "method": spec.method,
              "task_options": json.dumps(dict(spec.options), sort_keys=True, default=_jsonable),
              "sweep_key": study.dataset.attrs["study_key"], "n_tasks": n_tasks,
              "n_failed": len(failed)}
    if out is not None:
        _write_merged(Path(out), kind, done, params)
    return {"out": str(out) if out is not None else None,
            "work_dir": str(work_dir) if work_dir is not None else None, "n_tasks": n_tasks,
            "computed": study.computed, "skipped": study.reused,
            "failed": failed, "records": done,
            "summary": _summary(kind, done, taus, Ns), "study": study}


#: a task file of run_sweep before the study engine: <kind>_N<N>_tau<tau>_seed<seed>_<hash>.h5
_OLD_TASK_FILE = re.compile(r"(blowup|chaos)_N\d+_tau[^_]+_seed\d+_[0-9a-f]{10}\.h5")


def _refuse_old_task_files(work: Path) -> None:
    """ValueError if `work` holds task files of run_sweep before the study engine (never
    ignored, never overwritten)."""
    if not work.is_dir():
        return
    old = sorted(p.name for p in work.iterdir() if _OLD_TASK_FILE.fullmatch(p.name))
    if old:
        raise ValueError(
            f"work_dir {str(work)!r} holds {len(old)} task file(s) of an older run_sweep (e.g. "
            f"{old[0]}), which the study engine does not read: finish that sweep with the "
            "fputlab that started it, or give a new work_dir (the old files are left as they are)")


def _study_settings(spec: SweepSpec) -> dict:
    """The study settings of a sweep's shared parameters (a fixed sample grid up to t_end for
    chaos: lyapunov's, so the records are lyapunov's numbers)."""
    opts = dict(spec.options)
    s = {"model": spec.model, "alpha": spec.alpha, "method": spec.method}
    if spec.kind == "blowup":
        if "progress" in opts:
            raise ValueError("progress: not an option of blowup tasks (run_sweep's own "
                             "progress shows the study's)")
        s.update(opts)
        return s
    from .chaos.single import _C
    for name in ("w0", "t0", "progress"):
        if name in opts:
            raise ValueError(f"{name}: not an option of chaos sweeps (chaos studies start "
                             "every orbit at t = 0 with random deviation vectors)")
    if "seed" in opts:
        opts["deviation_seed"] = opts.pop("seed")
    if opts.get("y0") is not None:
        opts["y0"] = [float(v) for v in np.asarray(opts["y0"], float).ravel()]
    opts["sample_grid_end"] = spec.t_max
    opts["n_samples"] = opts.get("n_samples") or _C["n_samples"]
    s.update(opts)
    return s


def _study_records(kind: str, ds, failed: set) -> list[dict]:
    """One record per finished task of a study's dataset, in the order tau, N, seed, as
    `run_task` gives them."""
    reached = ds["t_reached"].values
    t_end = float(ds.attrs["t_end"])
    arrays = {name: ds[name].values for name in ds.data_vars
              if ds[name].dims[:3] == ("N", "tau", "seed")}
    out = []
    for j, tau in enumerate(ds["tau"].values):
        for i, N in enumerate(ds["N"].values):
            for r, seed in enumerate(ds["seed"].values):
                if not np.isfinite(reached[i, j, r]) or (int(N), float(tau), int(seed)) in failed:
                    continue
                o = {name: a[i, j, r] for name, a in arrays.items()}
                rec: dict[str, Any] = {"kind": kind, "N": int(N), "tau": float(tau),
                                       "seed": int(seed)}
                if kind == "blowup":
                    rec.update(blew_up=bool(o["blew_up"]), time=float(o["time"]),
                               criterion=str(o["criterion"]), t_reached=float(o["t_reached"]),
                               tau_c=float(o["tau_c"]))
                else:
                    t = np.asarray(o["t_sample"], float)
                    k = int(np.sum(np.isfinite(t)))
                    blew = bool(o["blew_up"])
                    rec.update(mle=float(o["mle"]), sali=float(o["sali"]),
                               classification=str(o["orbit_class"]),
                               t_final=float(o["t_final"]), chaotic=bool(o["chaotic"]),
                               t_chaotic=float(o["t_chaotic"]), steps=int(o["steps"]),
                               completed=bool(o["finished"]) and not blew and (
                                   bool(o["chaotic"]) or float(o["t_final"]) >= t_end),
                               blew_up=blew, t_blowup=float(o["t_blowup"]),
                               t=t[:k], mle_t=np.asarray(o["mle_t"], float)[:k],
                               sali_t=np.asarray(o["sali_t"], float)[:k])
                out.append(rec)
    return out


def _summary(kind: str, records: list[dict], taus, Ns) -> list[dict]:
    rows = []
    for tau in taus:
        for N in Ns:
            sel = [r for r in records if r["tau"] == tau and r["N"] == N]
            hit = [r["blew_up"] if kind == "blowup" else r["classification"] == "chaotic"
                   for r in sel]
            rows.append({"tau": tau, "N": N, "n": len(sel),
                         "fraction": float(np.mean(hit)) if hit else float("nan")})
    return rows


def _write_merged(path: Path, kind: str, records: list[dict], params: dict) -> None:
    import h5py
    path.parent.mkdir(parents=True, exist_ok=True)

    def fill(f):
        f.attrs["fputlab_version"] = VERSION
        for k, v in params.items():
            f.attrs[k] = v
        strs = h5py.string_dtype()
        f.create_dataset("kind", data=[r["kind"] for r in records], dtype=strs)
        f.create_dataset("N", data=np.array([r["N"] for r in records], dtype=np.int64))
        f.create_dataset("tau", data=np.array([r["tau"] for r in records], dtype=float))
        f.create_dataset("seed", data=np.array([r["seed"] for r in records], dtype=np.int64))
        for name, dt in COLUMNS[kind].items():
            col = [r[name] for r in records]
            if dt is str:
                f.create_dataset(name, data=col, dtype=strs)
            else:
                f.create_dataset(name, data=np.array(col, dtype=dt))
        for name in SERIES.get(kind, ()):
            width = max((r[name].size for r in records), default=0)
            arr = np.full((len(records), width), np.nan)
            for i, r in enumerate(records):
                arr[i, :r[name].size] = r[name]
            f.create_dataset(name, data=arr)
        if kind in SERIES:
            f.create_dataset("n_samples", data=np.array([r["t"].size for r in records],
                                                         dtype=np.int64))
    write_h5_atomic(path, fill)


def load_sweep(path) -> dict:
    """Read a merged sweep file (written by `run_sweep`).

    Parameters
    ----------
    path : str or path
        The merged HDF5 file.

    Returns
    -------
    dict
        {column: array} (string columns as str arrays; the chaos series ``t``, ``mle_t``,
        ``sali_t`` as (n_tasks, n_samples) arrays padded with NaN, row i has ``n_samples[i]``
        values) plus ``attrs``: the sweep parameters and ``fputlab_version``.

    Raises
    ------
    OSError
        The file cannot be opened as HDF5.
    """
    import h5py
    out: dict[str, Any] = {}
    with h5py.File(path, "r") as f:
        attrs = {}
        for k, v in f.attrs.items():
            attrs[k] = v.decode() if isinstance(v, bytes) else v
        out["attrs"] = attrs
        for name, ds in f.items():
            if h5py.check_string_dtype(ds.dtype) is not None:
                out[name] = np.array(ds.asstr()[...], dtype=str)
            else:
                out[name] = ds[...]
    return out
