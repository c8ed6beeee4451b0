"""What the commands share: the lattice of a command line, checks of its options, the
summary printed (text or JSON) and the HDF5 files of a summary."""
from __future__ import annotations

import os

import numpy as np

from .._display import dumps_strict

def _lattice(a):
    from ..lattice import Lattice
    boundary = getattr(a, "boundary", "fixed")
    if a.model in ("homogeneous", "toda"):
        _homogeneous_check(a)
        return Lattice(a.N, a.alpha, a.model, beta=a.beta, boundary=boundary)
    return Lattice(a.N, a.alpha, a.model, beta=a.beta, tau=a.tau, seed=a.seed, disorder=a.disorder,
                   boundary=boundary)


#: the models without disorder
_ORDERED = ("homogeneous", "toda")


def _homogeneous_check(a):
    """The homogeneous and Toda chains have no disorder: a --tau given with them is refused,
    not ignored; the Toda chain's potential is fixed by alpha: a --beta is refused."""
    taus = np.atleast_1d(np.asarray(a.tau if a.tau is not None else 0.0, dtype=float))
    if a.model in _ORDERED and getattr(a, "tau_given", False) and np.any(taus != 0):
        raise ValueError(f"--tau {_g(taus.tolist())}: the {a.model} model has no disorder "
                         "(use --model hamiltonian or nonlinear, or drop --tau)")
    if a.model == "toda" and getattr(a, "beta", 0.0) != 0.0:
        raise ValueError(f"--beta {_g(a.beta)}: the Toda chain has no quartic coupling of its "
                         "own (its potential is fixed by --alpha); drop --beta")


#: the most tasks one sweep may have (every task is a record in memory and a file on disk)
MAX_SWEEP_TASKS = 10**7


def _check_args(a):
    """The checks every command shares, before anything runs: file names (not empty, no NUL),
    seeds in [0, 2**64) and only with disorder, sizes and counts in range, steps and tolerances
    finite and > 0, and sweeps of a size that fits in memory."""
    from .._arrays import check_memory
    from .._validate import C_INT, _int, _path, _positive_real, _seed
    for name in ("out", "checkpoint", "plot", "work_dir", "out_dir"):
        if getattr(a, name, None) is not None:
            setattr(a, name, _path(getattr(a, name), "--" + name.replace("_", "-")))
    boundary = getattr(a, "boundary", None)
    if boundary is not None:
        from ..lattice import BOUNDARIES
        if boundary not in BOUNDARIES:
            raise ValueError(f"--boundary {boundary!r} is unknown (known: "
                             f"{', '.join(BOUNDARIES)})")
    if getattr(a, "seed", None) is not None:
        _seed(a.seed, "--seed")
        if getattr(a, "model", None) in _ORDERED and getattr(a, "seed_given", False):
            raise ValueError(f"--seed {a.seed}: the {a.model} model has no disorder (use "
                             "--model hamiltonian or nonlinear, or drop --seed)")
    for name in ("dt", "rtol", "atol", "sample_every"):
        if getattr(a, name, None) is not None:
            _positive_real(getattr(a, name), "--" + name.replace("_", "-"))
    sizes = getattr(a, "N", None)
    for n in (sizes if isinstance(sizes, list) else [sizes] if sizes is not None else []):
        n = _int(n, "--N", C_INT)
        if n < 2:
            raise ValueError(f"--N must be >= 2 (got {n})")
        from ..lattice import _BYTES_PER_SITE
        check_memory(_BYTES_PER_SITE * n, f"a lattice of N = {n}")
    for name in ("realisations", "workers", "samples"):
        value = getattr(a, name, None)
        if value is not None:
            value = _int(value, "--" + name, C_INT)
            if value < 1:
                raise ValueError(f"--{name} must be >= 1 (got {value})")
    reps = getattr(a, "realisations", None)
    if reps is not None and isinstance(sizes, list):
        taus = getattr(a, "tau", None)
        tasks = reps * len(sizes) * (len(taus) if isinstance(taus, list) else 1)
        if tasks > MAX_SWEEP_TASKS:
            raise ValueError(f"--realisations {reps}: {tasks:.3g} tasks, more than "
                             f"{MAX_SWEEP_TASKS:.0e} in one sweep; split it")
        if reps * 1.0 >= 2**64 or (getattr(a, "seed", None) or 0) + reps > 2**64:
            raise ValueError("--seed + --realisations: the seeds pass 2**64 - 1")


def _g(v) -> str:
    """A default as --help shows it."""
    if isinstance(v, (list, tuple)):
        return " ".join(_g(x) for x in v)
    if isinstance(v, float):
        return f"{v:.0e}".replace("e+0", "e").replace("e+", "e") if abs(v) >= 1e4 and \
            float(f"{v:.0e}") == v else f"{v:g}"
    return str(v)


def _positive(a, name: str, minimum: int = 1):
    value = getattr(a, name, None)
    if value is not None and value < minimum:
        raise ValueError(f"--{name.replace('_', '-')} must be >= {minimum} (got {value})")


def _human(v) -> str:
    """A value as a person reads it: numbers to 6 significant digits, mappings as 'key value'
    pairs, sequences comma-separated, no Python reprs."""
    if isinstance(v, bool) or v is None:
        return {True: "yes", False: "no", None: "-"}[v]
    if isinstance(v, (float, np.floating)):
        return f"{float(v):.6g}"
    if isinstance(v, dict):
        if v and all(isinstance(x, dict) for x in v.values()):       # e.g. classes per N
            return " | ".join(f"{k}: {_human(x)}" for k, x in v.items())
        return ", ".join(f"{k} {_human(x)}" for k, x in v.items())
    if isinstance(v, (list, tuple, np.ndarray)):
        return ", ".join(_human(x) for x in v)
    return str(v)


def _emit(summary: dict, as_json: bool):
    if as_json:
        print(dumps_strict(summary, indent=2))
    else:
        width = max((len(str(k)) for k in summary), default=0)
        for k, v in summary.items():
            if isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
                print(f"{k:>{width}}:")                 # a table: one row per record
                for row in v:
                    print(f"{'':>{width}}  {_human(row)}")
            else:
                print(f"{k:>{width}}: {_human(v)}")


def _output_paths(a, *names):
    """Refuse, before anything is written, output paths that collide with each other or an
    existing file that --overwrite does not allow to replace. names: attribute names of a
    (out, checkpoint, plot, work_dir); files a run resumes (checkpoint, a resumed --out) are
    left to the run's own checks."""
    given = [(n, getattr(a, n, None)) for n in names]
    given = [(n, os.fspath(p)) for n, p in given if p]
    for i, (n1, p1) in enumerate(given):
        for n2, p2 in given[i + 1:]:
            same = os.path.realpath(p1) == os.path.realpath(p2)
            if not same and os.path.exists(p1) and os.path.exists(p2):
                same = os.path.samefile(p1, p2)
            if same:
                raise ValueError(f"--{n2.replace('_', '-')} {p2!r} is the same file as "
                                 f"--{n1.replace('_', '-')}: every output needs its own path")


def _new_file(a, name: str, extra: str = ""):
    """An output file that is written from scratch: refuse to replace an existing one unless
    --overwrite (`extra`: what else the message should say)."""
    path = getattr(a, name, None)
    if not path:
        return
    if os.path.isdir(path):
        raise ValueError(f"--{name}: {path!r} is a directory")
    if os.path.exists(path) and not os.path.isfile(path):
        raise ValueError(f"--{name}: {path!r} is not a regular file (a device, FIFO or socket "
                         "cannot hold an HDF5 file)")
    if os.path.exists(path) and not getattr(a, "overwrite", False):
        raise FileExistsError(f"--{name}: {path!r} exists; not overwritten (pass --overwrite to "
                              f"replace it{extra})")


def _integrator_kwargs(a) -> dict:
    return {k: v for k, v in (("dt", a.dt), ("rtol", a.rtol), ("atol", a.atol)) if v is not None}


def _ensemble_lattice_check(a):
    """Ensembles draw their own lattices: options they cannot honour are refused, not ignored."""
    if a.beta != 0.0:
        raise ValueError("--beta: ensembles use the paper's FPUT-alpha chain (beta = 0)")
    if a.disorder != "gaussian":
        raise ValueError("--disorder: ensembles use the paper's Gaussian disorder")


def _checkpoint_kwargs(a) -> dict:
    return {"checkpoint": a.checkpoint, "checkpoint_every_steps": a.checkpoint_steps,
            "checkpoint_every_seconds": a.checkpoint_every, "resume": not a.restart,
            "progress": not a.json}


def _run_summary(s) -> dict:
    out = {"status": s.status, "t_reached": s.t_reached, "samples": s.samples,
           "resumed_from": s.resumed_from, "checkpoints_written": s.checkpoints,
           "message": s.message, "out": s.path}
    if s.event:
        out["event"] = s.event
    out.update(s.extra)
    return out
