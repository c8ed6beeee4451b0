"""The `fputlab` command: the paper's workflows with defaults that reproduce it."""
from __future__ import annotations

import argparse
import functools
import inspect
import json
import math
import os
import sys
from typing import NamedTuple

import numpy as np

from ._display import dumps_strict
from ._figure import add_output_options


def _lattice(a):
    from .lattice import Lattice
    if a.model == "homogeneous":
        _homogeneous_check(a)
        return Lattice(a.N, a.alpha, a.model, beta=a.beta)
    return Lattice(a.N, a.alpha, a.model, beta=a.beta, tau=a.tau, seed=a.seed, disorder=a.disorder)


def _homogeneous_check(a):
    """The homogeneous model has no disorder: a --tau given with it is refused, not ignored."""
    taus = np.atleast_1d(np.asarray(a.tau if a.tau is not None else 0.0, dtype=float))
    if a.model == "homogeneous" and getattr(a, "tau_given", False) and np.any(taus != 0):
        raise ValueError(f"--tau {_g(taus.tolist())}: the homogeneous model has no disorder "
                         "(use --model hamiltonian or nonlinear, or drop --tau)")


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


def _new_file(a, name: str):
    """An output file that is written from scratch: refuse to replace an existing one unless
    --overwrite."""
    path = getattr(a, name, None)
    if not path:
        return
    if os.path.isdir(path):
        raise ValueError(f"--{name}: {path!r} is a directory")
    if os.path.exists(path) and not getattr(a, "overwrite", False):
        raise FileExistsError(f"--{name}: {path!r} exists; not overwritten (pass --overwrite to "
                              "replace it)")


def _write_h5(path, attrs: dict, datasets: dict):
    import h5py
    from . import __version__
    with h5py.File(path, "w") as f:
        f.attrs["fputlab_version"] = __version__
        for k, v in attrs.items():
            if v is not None:
                f.attrs[k] = v
        for k, v in datasets.items():
            if v is not None:
                f.create_dataset(k, data=np.asarray(v), compression="gzip")


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


def _summary_h5(path, summary: dict):
    """A command's summary as HDF5: numbers and strings as attributes, numeric lists as datasets,
    dicts as groups, anything else as a JSON string attribute."""
    import h5py
    from . import __version__

    def put(g, d):
        for k, v in d.items():
            if isinstance(v, dict):
                put(g.create_group(k), v)
            elif isinstance(v, (list, tuple, np.ndarray)):
                try:
                    g.create_dataset(k, data=np.asarray(v, dtype=float))
                except (TypeError, ValueError):
                    g.attrs[k] = json.dumps(v, default=float)
            elif v is not None:
                g.attrs[k] = v
    with h5py.File(path, "w") as f:
        f.attrs["fputlab_version"] = __version__
        put(f, summary)


def cmd_simulate(a):
    if a.checkpoint and not a.out:
        raise ValueError("--checkpoint needs --out (the results file it belongs to)")
    _output_paths(a, "out", "checkpoint")
    lat = _lattice(a)
    if a.out:
        # long runs: the C core writes the samples as it goes, with checkpoints and restart
        from .io import simulate_to_file
        s = simulate_to_file(lat, a.t_end, a.out, method=a.method, sample_every=a.sample_every,
                             store_states=a.states, overwrite=a.overwrite,
                             **_integrator_kwargs(a), **_checkpoint_kwargs(a))
        _emit({"lattice": repr(lat), "method": a.method, **_run_summary(s)}, a.json)
        return {"completed": 0, "event": 0, "interrupted": 130}.get(s.status, 1)
    from ._errors import Interrupted
    try:
        run = lat.integrate(a.t_end, method=a.method, sample_every=a.sample_every,
                            store_states=a.states, on_failure="return", progress=not a.json,
                            **_integrator_kwargs(a))
    except Interrupted as err:          # Ctrl-C: the summary of what was computed, exit 130
        run = err.result
    summary = {"lattice": repr(lat), "method": a.method, "t_reached": float(run.t[-1]) if run.t.size else 0.0,
               "samples": int(run.t.size), "completed": run.completed, "message": run.message}
    if lat.model != "nonlinear":        # model 3 (Eq. varnonlin) conserves no energy
        summary["max_relative_energy_error"] = (float(run.relative_energy_error.max())
                                                if run.t.size else None)
    _emit(summary, a.json)
    if run.message.startswith("interrupted"):
        return 130
    return 0 if run.completed else 1


def cmd_blowup(a):
    from .blowup import blowup_sweep, blowup_time
    _positive(a, "realisations")
    _positive(a, "workers")
    _homogeneous_check(a)
    _output_paths(a, "out", "plot")
    _new_file(a, "out")
    if a.sweep:
        _ensemble_lattice_check(a)
        out = blowup_sweep(a.tau, Ns=a.N, realisations=a.realisations, t_max=a.t_end,
                           model=a.model, alpha=a.alpha, method=a.method, first_seed=a.seed,
                           workers=a.workers, scheduler=a.scheduler, progress=not a.json,
                           **_integrator_kwargs(a))
        summary = {"tau": out["tau"].tolist(), "N": out["N"].tolist(),
                   "probability": out["probability"].tolist() if len(a.N) > 1
                   else out["probability"][:, 0].tolist(),
                   "realisations": a.realisations, "t_max": a.t_end,
                   "two_mode_prediction_accuracy": out["prediction_accuracy"],
                   "records": [r._asdict() for r in out["records"]]}
        if a.out:
            # the file keeps its layout: records as rows of floats (tau, N, seed, blew_up,
            # time, tau_c), the BlowupRecord fields in order
            rec = np.array([tuple(r) for r in out["records"]], dtype=float)
            _write_h5(a.out, {"t_max": a.t_end, "model": a.model,
                              "N": a.N[0] if len(a.N) == 1 else np.asarray(a.N)},
                      {"tau": out["tau"], "probability": out["probability"], "records": rec})
        if a.plot:
            from .plotting import plot_blowup_sweep_figure
            plot_blowup_sweep_figure(out, a.plot)
            summary["plot"] = a.plot
        _emit(summary, a.json)
        return 0
    if a.scheduler:
        raise ValueError("--scheduler: only for a sweep (several --tau or --N values, or "
                         "--realisations > 1)")
    res = blowup_time(_lattice(a), a.t_end, method=a.method, progress=not a.json,
                      **_integrator_kwargs(a))
    _emit({"blew_up": res.blew_up, "time": res.time, "criterion": res.criterion,
           "t_reached": res.t_reached, "tau": a.tau, "seed": a.seed, "N": a.N}, a.json)
    return 0


class ChaosRow(NamedTuple):
    """One orbit of `fputlab chaos --realisations R`, a row of its HDF5 file's "records"."""
    N: int
    realisation: int
    mle: float
    sali: float
    t_final: float


def cmd_chaos(a):
    from .chaos import chaotic_fraction, lyapunov
    if a.scheduler and not a.fraction:
        raise ValueError("--scheduler: only for the chaotic fraction (--realisations > 1 or "
                         "several --N)")
    if a.checkpoint and (not a.out or a.fraction):
        raise ValueError("--checkpoint needs --out and one orbit (use `fputlab sweep` for ensembles)")
    _positive(a, "realisations")
    _positive(a, "workers")
    _positive(a, "samples")
    _homogeneous_check(a)
    _output_paths(a, "out", "checkpoint")
    if a.fraction:
        _new_file(a, "out")
    opts = dict(_integrator_kwargs(a), n_samples=a.samples)
    if a.stop_when_chaotic:         # ensembles stop chaotic orbits anyway (chaos.ensemble_defaults)
        opts["stop_when_chaotic"] = True
    if a.fraction:
        _ensemble_lattice_check(a)
        out = chaotic_fraction(Ns=a.N, realisations=a.realisations, tau=a.tau, t_end=a.t_end,
                               model=a.model, alpha=a.alpha, method=a.method, first_seed=a.seed,
                               workers=a.workers, scheduler=a.scheduler, progress=not a.json,
                               **opts)
        summary = {"N": out["N"], "percent_chaotic": out["percent"],
                   "blew_up": out["blowups"], "classes": out["classes"], "tau": a.tau,
                   "t_end": a.t_end, "method": out["results"][out["N"][0]][0].method}
        if a.out:
            rows = [ChaosRow(N, i, r.mle_final, float(r.sali[-1]) if r.sali.size else np.nan,
                             r.t_final)
                    for N in out["N"] for i, r in enumerate(out["results"][N])]
            _write_h5(a.out, {"model": a.model, "tau": a.tau, "t_end": a.t_end,
                              "method": a.method,
                              "columns": ", ".join(ChaosRow._fields)},
                      {"N": out["N"], "percent_chaotic": out["percent"],
                       "records": np.array([tuple(r) for r in rows], dtype=float)})
            summary["out"] = a.out
        _emit(summary, a.json)
        return 0
    if a.out:
        # written as it goes, with checkpoints: runs to t = 1e8 survive interruptions
        from .io import chaos_to_file
        s = chaos_to_file(_lattice(a), a.t_end, a.out, method=a.method, **opts,
                          overwrite=a.overwrite, **_checkpoint_kwargs(a))
        _emit(_run_summary(s), a.json)
        return {"completed": 0, "interrupted": 130}.get(s.status, 1)
    from ._errors import Interrupted
    try:
        res = lyapunov(_lattice(a), a.t_end, method=a.method,
                       progress=not a.json, **opts)
    except Interrupted as err:          # Ctrl-C: the summary of what was computed, exit 130
        res = err.result
    summary = {"mle": res.mle_final, "sali": float(res.sali[-1]) if res.sali.size else None,
               "class": res.classify(), "t_final": res.t_final, "steps": res.steps}
    if res.blew_up:
        summary["t_blowup"] = res.t_blowup
    if res.message:
        summary["message"] = res.message
    _emit(summary, a.json)
    return 130 if res.message.startswith("interrupted") else 0


def cmd_figures(a):
    from .figures import all_figures, figure_output
    only = set(a.only) if a.only else None
    unknown = sorted(k for k in (only or ()) if not 1 <= k <= 14)
    if unknown:
        raise ValueError(f"--only: there is no figure {', '.join(map(str, unknown))} (the paper's "
                         "figures are 1-14)")
    study = {"work_dir": a.work_dir, "t_until": a.t_end, "workers": a.workers,
             "scheduler": a.scheduler}
    with figure_output(a.format, a.dpi):
        for p in all_figures(a.out_dir, full=a.full, only=only, **study):
            print(p)
    return 0


def cmd_methods(a):
    from .integrate import method_info, methods
    names = methods()
    width = max(len(m) for m in names)
    print(f"{'method':{width}s}  order  kind")
    for m in names:
        info = method_info(m)
        print(f"{m:{width}s}  {info['order']:>5d}  {'adaptive' if info['adaptive'] else 'fixed step'}")
    return 0


# ---- ensembles and the two-mode reduction ---------------------------------------------------

def cmd_sweep(a):
    from .ensemble import run_sweep
    _ensemble_lattice_check(a)
    opts = _integrator_kwargs(a)
    if a.kind == "chaos" and a.samples is not None:
        opts["n_samples"] = a.samples
    elif a.samples is not None:
        raise ValueError("--samples: only for --kind chaos")
    work_dir = a.work_dir if a.work_dir else f"{a.out}.tasks"
    a.work_dir = work_dir
    _output_paths(a, "out", "work_dir")
    if os.path.exists(work_dir) and not os.path.isdir(work_dir):
        raise ValueError(f"--work-dir: {work_dir!r} exists and is not a directory")
    if os.path.isdir(a.out):
        raise ValueError(f"--out: {a.out!r} is a directory")
    if os.path.realpath(a.out).startswith(os.path.realpath(work_dir) + os.sep):
        raise ValueError(f"--out {a.out!r} is inside --work-dir {work_dir!r}: keep the merged "
                         "file out of the task folder")
    out = run_sweep(a.kind, a.tau, a.N, a.realisations, t_max=a.t_end, work_dir=work_dir,
                    out=a.out, model=a.model, alpha=a.alpha, first_seed=a.seed,
                    method=a.method, workers=a.workers, scheduler=a.scheduler,
                    progress=not a.json, **opts)
    what = "blew_up" if a.kind == "blowup" else "chaotic"
    summary = {"kind": a.kind, "out": out["out"], "work_dir": out["work_dir"],
               "tasks": out["n_tasks"], "computed": out["computed"], "skipped": out["skipped"],
               "failed": len(out["failed"]), "t_max": a.t_end,
               f"fraction_{what}": [{"tau": r["tau"], "N": r["N"], "n": r["n"],
                                     "fraction": r["fraction"]} for r in out["summary"]]}
    if out["failed"]:
        summary["failures"] = [f"N={f.task.N} tau={f.task.tau:g} seed={f.task.seed}: "
                               f"{f.message}" for f in out["failed"]]
    _emit(summary, a.json)
    return 1 if out["failed"] else 0


def _coefficient_row(lat) -> dict:
    from .reduction import two_mode_coefficients
    c = two_mode_coefficients(lat)
    w1, w2 = c.omega
    row = {"tau": lat.tau, "A_tilde": c.A_tilde, "B_tilde": c.B_tilde}
    row.update({f"A{i + 1}": float(x) for i, x in enumerate(c.A)})
    row.update({f"B{i + 1}": float(x) for i, x in enumerate(c.B)})
    row.update({f"a{i + 1}": float(x) for i, x in enumerate(c.a)})
    row.update({f"b{i + 1}": float(x) for i, x in enumerate(c.b)})
    row.update({"eps": c.eps, "omega1": w1, "omega2": w2})
    return row


def cmd_coefficients(a):
    from .lattice import Lattice
    _new_file(a, "out")
    rows = []
    for tau in a.tau:
        if a.model == "homogeneous":
            if tau != 0:
                raise ValueError("tau: the homogeneous model has no disorder")
            lat = Lattice(a.N, a.alpha, a.model)
        else:
            lat = Lattice(a.N, a.alpha, a.model, tau=tau, seed=a.seed, disorder=a.disorder)
        rows.append(_coefficient_row(lat))
    head = {"N": a.N, "alpha": a.alpha, "model": a.model, "seed": a.seed, "disorder": a.disorder,
            "note": "raw a_i, b_i: quadratic coefficients of Eq. (msvar), alpha included; "
                    "paper-normalised A_i = a_i/eps, B_i = b_i/eps (eps = omega2 - 2 omega1), "
                    "A_tilde = A3/(2 omega1), B_tilde = B1/(2 omega2)"}
    if a.out:
        names = ("a1", "a2", "a3", "b1", "b2", "b3")
        _write_h5(a.out, {k: v for k, v in head.items()},
                  {"tau": [r["tau"] for r in rows],
                   "raw": [[r[n] for n in names] for r in rows],
                   "A": [[r[f"A{i}"] for i in (1, 2, 3)] for r in rows],
                   "B": [[r[f"B{i}"] for i in (1, 2, 3)] for r in rows],
                   "A_tilde": [r["A_tilde"] for r in rows],
                   "B_tilde": [r["B_tilde"] for r in rows]})
        head["out"] = a.out
    if len(rows) == 1:
        _emit({**head, **rows[0]}, a.json)
    else:
        _emit({**head, "rows": rows}, a.json)
    return 0


def cmd_tauc(a):
    from .reduction import critical_tolerance
    _new_file(a, "out")
    tau = None
    if a.fit_taus is not None:
        tau = np.asarray(a.fit_taus, dtype=float)
    _positive(a, "realisations")
    tc = critical_tolerance(a.N, a.alpha, a.realisations, seed0=a.seed, kind=a.disorder, tau=tau)
    s = tc.summary()
    summary = {"N": a.N, "alpha": a.alpha, "disorder": a.disorder, "R": a.realisations,
               "tau_c_exact": s["exact"], "tau_c_fit": s["fit"],
               "tau_c_per_realisation": {k: s[k] for k in ("mean", "std", "q05", "median", "q95",
                                                           "without_root")},
               "fit_B_tilde": s["fit_B"], "fit_A_tilde": s["fit_A"],
               "note": "exact: root of the closed-form E[B~](tau); fit: root of a quadratic fit "
                       "to the R-realisation mean (the paper's method, 10.0749 %); "
                       "per_realisation: each realisation's own B~(tau) = 0"}
    if a.out:
        _summary_h5(a.out, summary)
        summary["out"] = a.out
    _emit(summary, a.json)
    return 0


def cmd_bifurcation(a):
    from .reduction import REGIONS, ReducedSystem, classify, r1_squared
    _positive(a, "N", 2)
    _output_paths(a, "out", "plot")
    _new_file(a, "out")
    r1sq = r1_squared(a.N)
    rs = ReducedSystem(a.A_tilde, a.B_tilde, N=a.N)
    lo, hi = rs.region()
    eqs = []
    for e in rs.equilibria():
        lam = e.eigenvalues[0]
        eqs.append({"j": e.j, "theta": e.theta, "delta": e.delta,
                    "eigenvalues": [[lam.real + 0.0, lam.imag + 0.0], [-lam.real + 0.0, -lam.imag + 0.0]],
                    "lambda_squared": (lam * lam).real, "type": e.kind,
                    "well_defined": e.well_defined})
    code = int(classify(a.A_tilde, a.B_tilde, r1sq))
    summary = {"A_tilde": rs.A, "B_tilde": rs.B, "N": a.N, "r1_squared": r1sq, "k": rs.k,
               "C": rs.C, "existence": rs.existence,
               "well_defined_region": [lo if np.isfinite(lo) else str(lo),
                                       hi if np.isfinite(hi) else str(hi)],
               "region": code, "region_description": REGIONS[code], "equilibria": eqs}
    if a.plot:
        from .figures_reduction import fig7
        summary["plot"] = fig7(a.plot, N=a.N)["path"]
    if a.out:
        _summary_h5(a.out, summary)
        summary["out"] = a.out
    _emit(summary, a.json)
    return 0


# ---- the parsers: one function per subcommand, shared option groups as parent parsers ----------
#
# Defaults. A single-lattice form (simulate, chaos of one orbit) is exactly fputlab.Lattice():
# the homogeneous chain, no disorder. The ensemble forms take the defaults of the Python
# function they call: blowup sweeps blowup.blowup_sweep's, chaos ensembles
# chaos.chaotic_fraction's, `sweep` ensemble.run_sweep's (and per kind blowup_sweep's or
# chaotic_fraction's sizes, realisations and final time). One blow-up realisation needs
# disorder: blowup_sweep's model, with --tau given. The values are read from the signatures
# (python_defaults), so the two cannot drift apart; tests/python/test_cli_options.py checks it.

MODELS = ["homogeneous", "hamiltonian", "nonlinear"]
DISORDERS = ["gaussian", "truncated", "uniform"]
#: the taus of `fputlab sweep --kind blowup` (blowup_sweep has no default taus)
SWEEP_BLOWUP_TAUS = [0.0, 5.0, 10.0, 15.0, 20.0]


def _signature_defaults(fn) -> dict:
    return {n: p.default for n, p in inspect.signature(fn).parameters.items()
            if p.default is not inspect.Parameter.empty}


@functools.lru_cache(maxsize=None)
def python_defaults() -> dict:
    """{Python function name: {parameter: default}} of the functions the subcommands call."""
    from .blowup import blowup_sweep, blowup_time
    from .chaos import chaotic_fraction, lyapunov
    from .ensemble import run_sweep
    from .lattice import Lattice
    return {"Lattice": _signature_defaults(Lattice.__init__),
            "integrate": _signature_defaults(Lattice.integrate),
            "lyapunov": _signature_defaults(lyapunov),
            "blowup_time": _signature_defaults(blowup_time),
            "blowup_sweep": _signature_defaults(blowup_sweep),
            "chaotic_fraction": _signature_defaults(chaotic_fraction),
            "run_sweep": _signature_defaults(run_sweep)}


def _g(v) -> str:
    """A default as --help shows it."""
    if isinstance(v, (list, tuple)):
        return " ".join(_g(x) for x in v)
    if isinstance(v, float):
        return f"{v:.0e}".replace("e+0", "e").replace("e+", "e") if abs(v) >= 1e4 and \
            float(f"{v:.0e}") == v else f"{v:g}"
    return str(v)


class _Deprecated(argparse._StoreAction):
    """An old spelling of an option: hidden from --help, still works, says what replaced it."""

    def __init__(self, option_strings, dest, replacement="", **kw):
        super().__init__(option_strings, dest, **kw)
        self.replacement = replacement

    def __call__(self, parser, namespace, values, option_string=None):
        print(f"fputlab: warning: {option_string} is deprecated; use {self.replacement}",
              file=sys.stderr)
        super().__call__(parser, namespace, values, option_string)


def _alias(p, old: str, new: str, dest: str, **kw):
    """`old` as a hidden deprecated spelling of `new` (same dest, type and nargs)."""
    p.add_argument(old, dest=dest, action=_Deprecated, replacement=new, help=argparse.SUPPRESS,
                   default=argparse.SUPPRESS, **kw)


def _lattice_options(*, N: str, model: str, tau: str, several: tuple = (),
                     seed: str = "disorder seed (default 1)") -> argparse.ArgumentParser:
    """Parent parser: the lattice. N, model and tau are described by the subcommand (their
    defaults depend on its form); several: those of "N", "tau" that take several values
    (ensembles)."""
    L = python_defaults()["Lattice"]
    p = argparse.ArgumentParser(add_help=False)
    g = p.add_argument_group("lattice")
    g.add_argument("--N", type=int, nargs="+" if "N" in several else None, default=None, help=N)
    g.add_argument("--alpha", type=float, default=L["alpha"], help="quadratic (cubic-potential) "
                   f"coupling (default {_g(L['alpha'])})")
    g.add_argument("--beta", type=float, default=L["beta"],
                   help=f"quartic coupling (default {_g(L['beta'])})")
    g.add_argument("--model", default=None, choices=MODELS, help=model)
    # default None: whether --tau was given matters (the homogeneous model refuses it)
    g.add_argument("--tau", type=float, nargs="+" if "tau" in several else None, default=None,
                   help=tau)
    g.add_argument("--seed", type=int, default=1, help=seed)
    g.add_argument("--disorder", default=L["disorder"], choices=DISORDERS,
                   help=f"distribution of the disorder draws (default {L['disorder']})")
    return p


def _integrator_options(*, method: str, dt: str) -> argparse.ArgumentParser:
    """Parent parser: the integrator. rtol/atol default to None = the Python default (not
    passed), so a sweep's task options, hence its work-directory key, stay as they were."""
    I = python_defaults()["integrate"]
    p = argparse.ArgumentParser(add_help=False)
    g = p.add_argument_group("integrator")
    g.add_argument("--method", default=None, help=method + "; see `fputlab methods`")
    g.add_argument("--dt", type=float, default=None, help=dt)
    g.add_argument("--rtol", type=float, default=None,
                   help=f"relative tolerance of the adaptive methods (default {_g(I['rtol'])})")
    g.add_argument("--atol", type=float, default=None,
                   help=f"absolute tolerance of the adaptive methods (default {_g(I['atol'])})")
    return p


def _time_options(default: float, what: str = "final time") -> argparse.ArgumentParser:
    """Parent parser: --t-end (the old spelling --t-max still works)."""
    p = argparse.ArgumentParser(add_help=False)
    p.add_argument("--t-end", dest="t_end", type=float, default=default, metavar="T",
                   help=f"{what} (default {_g(default)})")
    _alias(p, "--t-max", "--t-end", "t_end", type=float)
    return p


def _output_options(out: str, *, out_default=None, overwrite: bool = True):
    """Parent parser: the output file, --overwrite and --json."""
    p = argparse.ArgumentParser(add_help=False)
    g = p.add_argument_group("output")
    g.add_argument("--out", metavar="FILE", default=out_default, help=out)
    if overwrite:
        g.add_argument("--overwrite", action="store_true",
                       help="replace an existing --out file (default: refuse)")
    g.add_argument("--json", action="store_true",
                   help="print the summary as JSON, strict: NaN/Inf as null (default: text)")
    return p


def _ensemble_options(realisations: str) -> argparse.ArgumentParser:
    """Parent parser: realisations and where they run."""
    p = argparse.ArgumentParser(add_help=False)
    g = p.add_argument_group("ensemble")
    g.add_argument("--realisations", type=int, default=None, help=realisations)
    g.add_argument("--workers", type=int, default=None,
                   help="local worker processes (default: all cores)")
    g.add_argument("--scheduler", default=None, help="Dask scheduler address tcp://host:port "
                   "(default: local processes)")
    return p


def _checkpoint_options() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(add_help=False)
    g = p.add_argument_group("checkpoints (with --out)")
    g.add_argument("--checkpoint", metavar="FILE", help="checkpoint file: resume from it if it "
                   "exists (default: none, no restart possible)")
    g.add_argument("--checkpoint-every", type=float, default=600.0, metavar="SECONDS",
                   help="write a checkpoint every SECONDS of wall time (default 600)")
    g.add_argument("--checkpoint-steps", type=int, default=None, metavar="K",
                   help="also write one every K integrator steps (default: only by time)")
    g.add_argument("--restart", action="store_true",
                   help="ignore an existing checkpoint and start from t = 0 (default: resume)")
    return p


def _sub(sub, name, help, parents=(), **kw):
    return sub.add_parser(name, help=help, parents=list(parents),
                          formatter_class=_DefaultsFormatter, **kw)


def _parser_demo(sub, parents):
    # its options are demo.main's own (`fputlab demo --help`)
    sub.add_parser("demo", help="reproduce Fig. 1 (FPUT recurrence, N = 64) as a PNG",
                   add_help=False)


def _parser_simulate(sub, parents):
    L, I = python_defaults()["Lattice"], python_defaults()["integrate"]
    s = _sub(sub, "simulate", "integrate one lattice, sample mode energies",
             description="Integrate one lattice. Without options it is fputlab.Lattice(): the "
             "homogeneous chain, N = 64, alpha = 0.25, no disorder.",
             parents=[_lattice_options(
                 N=f"particles (default {L['N']})",
                 model=f"lattice model (default {L['model']}, as fputlab.Lattice())",
                 tau=f"variability in percent (default {_g(L['tau'])}: no disorder; give it with "
                     "--model hamiltonian or nonlinear)"),
                 _integrator_options(method=f"integrator (default {I['method']})",
                                     dt="fixed step (default 0.01)"),
                 _time_options(1e4),
                 _output_options("HDF5 results file, written as the run goes (default: none, "
                                 "in memory; see docs/hdf5.md)"),
                 _checkpoint_options()])
    s.add_argument("--sample-every", type=float, default=None,
                   help="sample spacing (default t_end/1000, at least dt; on resume: the "
                        "checkpoint's)")
    s.add_argument("--states", action="store_true", help="also store the states (default: no)")
    s.set_defaults(func=cmd_simulate, resolve=_resolve_simulate)


def _parser_blowup(sub, parents):
    B, L = python_defaults()["blowup_sweep"], python_defaults()["Lattice"]
    s = _sub(sub, "blowup", "blow-up time of one realisation, or the probability over many",
             description="One realisation (one --tau, one --N, --realisations 1) or a sweep "
             "(several --tau or --N values, or --realisations > 1: fputlab.blowup.blowup_sweep "
             "and its defaults). --tau is required: a blow-up needs disorder.",
             parents=[_lattice_options(
                 N=f"particles; several for a sweep (default {L['N']})",
                 model=f"lattice model (default {B['model']}, as blowup_sweep)",
                 tau="variability in percent; several for a sweep over tau (required: no "
                     "default, as blowup_sweep's taus)", several=("N", "tau"),
                 seed="disorder seed; a sweep uses SEED, SEED + 1, ... (default 1)"),
                 _integrator_options(method=f"integrator (default {B['method']})",
                                     dt="fixed step (default 0.01)"),
                 _time_options(B["t_max"], "final time: no blow-up before it is blew_up false"),
                 _ensemble_options(f"disorder realisations per tau (default 1; in a sweep "
                                   f"{B['realisations']}, as blowup_sweep)"),
                 _output_options("HDF5 file with the sweep (default: none)")])
    _alias(s, "--taus", "--tau", "tau", type=float, nargs="+")
    s.add_argument("--plot", metavar="FILE", help="PNG of the sweep: probability vs tau, "
                   "blow-up times (default: none)")
    s.set_defaults(func=cmd_blowup, resolve=_resolve_blowup)


def _parser_chaos(sub, parents):
    L, C = python_defaults()["Lattice"], python_defaults()["chaotic_fraction"]
    Y = python_defaults()["lyapunov"]
    s = _sub(sub, "chaos", "mLE and SALI of one orbit, or the chaotic fraction (Fig. 14)",
             description="One orbit (fputlab.chaos.lyapunov; without options the lattice is "
             "fputlab.Lattice(), the homogeneous chain) or, with --realisations > 1 or several "
             "--N, the chaotic fraction (fputlab.chaos.chaotic_fraction and its defaults: "
             f"model {C['model']}, tau {_g(C['tau'])}, N {_g(C['Ns'])}, "
             f"{C['realisations']} realisations).",
             parents=[_lattice_options(
                 N=f"particles (default {L['N']}); several: the chaotic fraction over them "
                   f"(default there {_g(C['Ns'])})", several=("N",),
                 model=f"lattice model (default {L['model']} for one orbit, as "
                       f"fputlab.Lattice(); {C['model']} for the fraction, as chaotic_fraction)",
                 tau=f"variability in percent (default {_g(L['tau'])} for one orbit; "
                     f"{_g(C['tau'])} for the fraction)",
                 seed="disorder seed; the fraction uses SEED, SEED + 1, ... (default 1)"),
                 _integrator_options(method=f"integrator (default {Y['method']} for one orbit; "
                                     "srkn14a6 for the fraction)",
                                     dt="fixed step (default 0.01; the fraction's srkn14a6: 0.5)"),
                 _time_options(C["t_end"]),
                 _ensemble_options(f"disorder realisations per N (default 1; > 1: the chaotic "
                                   f"fraction, default there {C['realisations']})"),
                 _output_options("HDF5 file (default: none; one orbit: written as the run "
                                 "goes, with checkpoints)"),
                 _checkpoint_options()])
    _alias(s, "--Ns", "--N", "N", type=int, nargs="+")
    s.add_argument("--samples", type=int, default=Y["n_samples"],
                   help=f"log-spaced samples of mLE(t), SALI(t), GALI(t) (default "
                        f"{Y['n_samples']})")
    s.add_argument("--stop-when-chaotic", action="store_true",
                   help="stop once SALI falls below its threshold (default: no for one orbit, "
                        "yes for the fraction)")
    s.set_defaults(func=cmd_chaos, resolve=_resolve_chaos)


def _parser_sweep(sub, parents):
    R, B = python_defaults()["run_sweep"], python_defaults()["blowup_sweep"]
    C = python_defaults()["chaotic_fraction"]
    s = _sub(sub, "sweep", "realisation x tau x N ensemble (blow-up or chaos) on a local pool "
             "or a Dask cluster; resumable, merged into one HDF5 file",
             description="Each (tau, N, seed) is an independent task whose result is written to "
             "its own HDF5 file in --work-dir; rerunning skips finished tasks. All results are "
             "merged into --out (one row per task). Defaults: fputlab.ensemble.run_sweep's, and "
             "per kind blowup_sweep's or chaotic_fraction's.",
             parents=[_lattice_options(
                 N=f"lattice sizes (default: {_g(B['Ns'])} for blowup, {_g(C['Ns'])} for chaos)",
                 model=f"lattice model (default {R['model']})",
                 tau=f"variabilities in percent (default: {_g(SWEEP_BLOWUP_TAUS)} for blowup, "
                     f"{_g(C['tau'])} for chaos)", several=("N", "tau"),
                 seed=f"seed of the first realisation: seeds SEED .. SEED + R - 1 (default "
                      f"{R['first_seed']})"),
                 _integrator_options(method="integrator (default yoshida4 for blowup, "
                                     "srkn14a6 for chaos)",
                                     dt="fixed step (default 0.01; chaos's srkn14a6: 0.5)"),
                 _time_options(B["t_max"], "final time of every task"),
                 _ensemble_options(f"disorder realisations per (tau, N) (default "
                                   f"{B['realisations']} for blowup, {C['realisations']} for "
                                   "chaos)"),
                 _output_options("merged HDF5 file (default sweep.h5)", out_default="sweep.h5",
                                 overwrite=False)])
    s.add_argument("--kind", default="blowup", choices=["blowup", "chaos"],
                   help="blowup: blow-up time up to --t-end; chaos: mLE/SALI up to --t-end "
                        "(default blowup)")
    _alias(s, "--taus", "--tau", "tau", type=float, nargs="+")
    _alias(s, "--Ns", "--N", "N", type=int, nargs="+")
    _alias(s, "--first-seed", "--seed", "seed", type=int)
    s.add_argument("--samples", type=int, default=None,
                   help="chaos: log-spaced samples of mLE(t), SALI(t) (default 200)")
    s.add_argument("--work-dir", default=None,
                   help="per-task result files (default OUT.tasks/); reused to resume")
    s.set_defaults(func=cmd_sweep, resolve=_resolve_sweep)


def _parser_coefficients(sub, parents):
    s = _sub(sub, "coefficients", "two-mode coefficients a_i, b_i (raw) and A_i, B_i, A~, B~ "
             "(paper-normalised) of one realisation or over several tau",
             parents=[_output_options("HDF5 file to write (default: none)")])
    s.add_argument("--N", type=int, default=64, help="particles (default 64)")
    s.add_argument("--alpha", type=float, default=0.25, help="quadratic coupling (default 0.25)")
    s.add_argument("--model", default="nonlinear", choices=MODELS,
                   help="lattice model (default nonlinear)")
    s.add_argument("--tau", type=float, nargs="+", default=[0.0],
                   help="variability in percent; several: the same seed, hence the same draws z "
                        "(default 0)")
    _alias(s, "--taus", "--tau", "tau", type=float, nargs="+")
    s.add_argument("--seed", type=int, default=1, help="disorder seed (default 1)")
    s.add_argument("--disorder", default="gaussian", choices=DISORDERS,
                   help="distribution of the disorder draws (default gaussian)")
    s.set_defaults(func=cmd_coefficients)


def _parser_tauc(sub, parents):
    s = _sub(sub, "tauc", "critical variability tau_c (B~ = 0) three ways: exact expectation, "
             "quadratic fit (the paper's), per realisation",
             parents=[_output_options("HDF5 file with the summary (default: none)")])
    s.add_argument("--N", type=int, default=64, help="particles (default 64)")
    s.add_argument("--alpha", type=float, default=0.25, help="quadratic coupling (default 0.25)")
    s.add_argument("--realisations", type=int, default=100,
                   help="realisations (default 100, as the paper)")
    _alias(s, "--R", "--realisations", "realisations", type=int)
    s.add_argument("--seed", type=int, default=1,
                   help="seed of the first realisation: seeds SEED .. SEED + R - 1 (default 1)")
    _alias(s, "--first-seed", "--seed", "seed", type=int)
    s.add_argument("--disorder", default="gaussian", choices=DISORDERS,
                   help="distribution of the disorder draws (default gaussian)")
    s.add_argument("--fit-taus", type=float, nargs="+", default=None,
                   help="tau grid of the fit (default 0, 0.5, ..., 20)")
    s.set_defaults(func=cmd_tauc)


def _parser_bifurcation(sub, parents):
    s = _sub(sub, "bifurcation", "reduced (P, Delta, theta) system at (A~, B~): C, equilibria "
             "Delta_1, Delta_2, theta, eigenvalues and their type",
             parents=[_output_options("HDF5 file with the summary (default: none)")])
    s.add_argument("--A-tilde", dest="A_tilde", type=float, default=3.62805,
                   help="A~ (default 3.62805, tau = 0)")
    s.add_argument("--B-tilde", dest="B_tilde", type=float, default=0.90728,
                   help="B~ (default 0.90728, tau = 0)")
    s.add_argument("--N", type=int, default=64,
                   help="particles: r_1^2 = (N+1)/8 of the paper's initial state (default 64)")
    s.add_argument("--plot", metavar="FILE",
                   help="PNG of the (A~, B~) bifurcation diagram, Fig. 7 (default: none)")
    s.set_defaults(func=cmd_bifurcation)


def _parser_figures(sub, parents):
    s = _sub(sub, "figures", "regenerate the paper's figures (PNG, or PDF/SVG for a paper)")
    s.add_argument("--out-dir", default="figures", metavar="DIR",
                   help="output directory (default figures/)")
    _alias(s, "--out", "--out-dir", "out_dir", metavar="DIR")
    s.add_argument("--full", action="store_true",
                   help="the paper's settings, t = 1e8: very long (default: quick settings)")
    s.add_argument("--only", type=int, nargs="+", help="figure numbers to make (default: all)")
    add_output_options(s)
    s.add_argument("--work-dir", help="chaos study of Figs. 12-14: one state file per orbit, "
                   "resumed by the next call (default OUT_DIR/chaos_study)")
    s.add_argument("--t-end", type=float, metavar="T", help="how far the chaos study goes in this call "
                   "(default 1e5, with --full 1e8); rerun with a larger value to continue")
    s.add_argument("--workers", type=int, help="local processes for the chaos study "
                   "(default: all cores)")
    s.add_argument("--scheduler", help="Dask scheduler address tcp://host:port for the chaos "
                   "study, the work directory must be shared (default: local processes)")
    s.set_defaults(func=cmd_figures)


def _parser_methods(sub, parents):
    s = _sub(sub, "methods", "list the integrators")
    s.set_defaults(func=cmd_methods)


SUBCOMMANDS = (_parser_demo, _parser_simulate, _parser_blowup, _parser_chaos, _parser_sweep,
               _parser_coefficients, _parser_tauc, _parser_bifurcation, _parser_figures,
               _parser_methods)


def build_parser():
    p = argparse.ArgumentParser(prog="fputlab", description="Ordered and disordered FPUT lattices "
                                "(paper: Energy-recurrence breakdown and chaos in disordered FPUT lattices).")
    p.add_argument("--version", action="store_true", help="print the version and exit")
    sub = p.add_subparsers(dest="command")
    for make in SUBCOMMANDS:
        make(sub, None)
    return p


class _DefaultsFormatter(argparse.HelpFormatter):
    """Every option's help ends with its default (unless the help already states it)."""

    def _get_help_string(self, action):
        text = action.help or ""
        default = action.default
        if "default" in text or not action.option_strings or default is argparse.SUPPRESS:
            return text
        if default is None:
            default = "none"
        elif default is False:
            default = "off"
        elif isinstance(default, (list, tuple)):
            default = " ".join(map(str, default))
        elif isinstance(default, float):
            default = f"{default:g}"
        return f"{text} (default {str(default).replace('%', '%%')})".strip()


# ---- resolving the form-dependent defaults -----------------------------------------------------

def _fill(a, **defaults):
    """Set every attribute of a that is None to its default."""
    for k, v in defaults.items():
        if getattr(a, k, None) is None:
            setattr(a, k, v)


def _finite_positive(a, name: str):
    value = getattr(a, name)
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"--{name.replace('_', '-')} must be finite and > 0 (got {value:g})")


def _one(a, name: str, why: str):
    """A list option of a single-lattice form as its one value."""
    values = getattr(a, name)
    if isinstance(values, list):
        if len(values) != 1:
            raise ValueError(f"--{name}: {why}")
        setattr(a, name, values[0])


def _resolve_single_lattice(a):
    L = python_defaults()["Lattice"]
    a.tau_given = a.tau is not None
    _fill(a, N=L["N"], model=L["model"], tau=L["tau"])


def _resolve_simulate(a):
    _resolve_single_lattice(a)
    _fill(a, method=python_defaults()["integrate"]["method"])
    _finite_positive(a, "t_end")


def _resolve_blowup(a):
    B = python_defaults()["blowup_sweep"]
    a.tau_given = a.tau is not None
    if a.tau is None:
        raise ValueError("--tau is required: the variability in percent of the realisation "
                         "(e.g. --tau 20), several for a sweep (e.g. --tau 0 5 10 15 20)")
    _fill(a, N=[python_defaults()["Lattice"]["N"]], model=B["model"], method=B["method"])
    a.sweep = len(a.tau) > 1 or len(a.N) > 1 or (a.realisations or 1) > 1
    _fill(a, realisations=B["realisations"] if a.sweep else 1)
    if not a.sweep:
        _one(a, "tau", "one realisation has one value")
        _one(a, "N", "one realisation has one value")
    _finite_positive(a, "t_end")


def _resolve_chaos(a):
    C = python_defaults()["chaotic_fraction"]
    a.fraction = (a.realisations or 1) > 1 or (a.N is not None and len(a.N) > 1)
    if a.fraction:
        a.tau_given = a.tau is not None
        _fill(a, N=list(C["Ns"]), model=C["model"], realisations=C["realisations"])
        _fill(a, tau=0.0 if a.model == "homogeneous" else C["tau"])
        # method None: chaotic_fraction's ensemble default (srkn14a6 at dt = 0.5)
    else:
        _one(a, "N", "one orbit has one value (several: the chaotic fraction)")
        _resolve_single_lattice(a)
        _fill(a, realisations=1, method=python_defaults()["lyapunov"]["method"])
    _finite_positive(a, "t_end")


def _resolve_sweep(a):
    B, C = python_defaults()["blowup_sweep"], python_defaults()["chaotic_fraction"]
    R = python_defaults()["run_sweep"]
    if a.kind == "blowup":
        _fill(a, tau=list(SWEEP_BLOWUP_TAUS), N=list(B["Ns"]), realisations=B["realisations"])
    else:
        _fill(a, tau=[C["tau"]], N=list(C["Ns"]), realisations=C["realisations"])
    _fill(a, model=R["model"])
    a.tau_given = True
    _finite_positive(a, "t_end")


def parse_args(argv):
    """The arguments of a command line with every default resolved (as the subcommand runs)."""
    a = build_parser().parse_args(argv)
    if getattr(a, "resolve", None):
        a.resolve(a)
    return a


def _run(argv) -> int:
    if argv[:1] == ["demo"]:
        from .demo import main as demo_main
        return demo_main(argv[1:])
    parser = build_parser()
    a = parser.parse_args(argv)
    if a.version:
        from . import __version__
        print(__version__)
        return 0
    if not getattr(a, "func", None):
        parser.print_help()
        return 2
    if getattr(a, "resolve", None):
        a.resolve(a)
    return a.func(a)


def _one_line(err: BaseException) -> str:
    msg = " ".join(str(err).split()) or type(err).__name__
    if isinstance(err, (ValueError, TypeError)):
        return msg
    if isinstance(err, OSError) and err.filename and str(err.filename) not in msg:
        msg = f"{msg}: {err.filename}"
    if isinstance(err, ImportError) and err.name:
        return f"{msg} (the Python package {err.name!r} is needed for this; pip install it)"
    return f"{type(err).__name__}: {msg}" if not isinstance(err, OSError) else msg


def main(argv=None) -> int:
    """The `fputlab` command. Every failure is one line on stderr and exit status 2 (130 on
    Ctrl-C / SIGINT); FPUTLAB_TRACEBACK=1 shows the traceback instead."""
    argv = sys.argv[1:] if argv is None else list(argv)
    try:
        return _run(argv)
    except KeyboardInterrupt:
        print("fputlab: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:                   # `fputlab ... | head`: not an error of ours
        try:
            sys.stdout = open(os.devnull, "w")
        except OSError:
            pass
        return 0
    except SystemExit:
        raise
    except Exception as err:                  # noqa: BLE001 - the CLI never shows a traceback
        if os.environ.get("FPUTLAB_TRACEBACK"):
            raise
        print(f"fputlab: error: {_one_line(err)}", file=sys.stderr)
        return 2
