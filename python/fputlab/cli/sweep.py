"""`fputlab sweep`: a realisation x tau x N ensemble, resumable from its work directory."""
from __future__ import annotations

import os

from ._common import (_emit, _ensemble_lattice_check, _g, _integrator_kwargs, _new_file,
                      _output_paths)
from .parsers import (SWEEP_BLOWUP_TAUS, _alias, _ensemble_options, _fill, _finite_positive,
                      _integrator_options, _lattice_options, _output_options, _sub,
                      _time_options, python_defaults)

def cmd_sweep(a):
    from ..ensemble import run_sweep
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
    # the merged file is rewritten from the tasks: like every other output, only with
    # --overwrite (the finished tasks in the work directory are kept and skipped either way)
    _new_file(a, "out", "; the finished tasks in the work directory are kept and skipped "
                        "either way")
    out = run_sweep(a.kind, a.tau, a.N, a.realisations, t_end=a.t_end, work_dir=work_dir,
                    out=a.out, model=a.model, alpha=a.alpha, first_seed=a.seed,
                    method=a.method, workers=a.workers, scheduler=a.scheduler,
                    progress=not a.json, **opts)
    what = "blew_up" if a.kind == "blowup" else "chaotic"
    summary = {"kind": a.kind, "out": out["out"], "work_dir": out["work_dir"],
               "tasks": out["n_tasks"], "computed": out["computed"], "skipped": out["skipped"],
               "failed": len(out["failed"]), "t_end": a.t_end,
               f"fraction_{what}": [{"tau": r["tau"], "N": r["N"], "n": r["n"],
                                     "fraction": r["fraction"]} for r in out["summary"]]}
    if out["failed"]:
        summary["failures"] = [f"N={f.task.N} tau={f.task.tau:g} seed={f.task.seed}: "
                               f"{f.message}" for f in out["failed"]]
    _emit(summary, a.json)
    return 1 if out["failed"] else 0


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
                 _time_options(B["t_end"], "final time of every task"),
                 _ensemble_options(f"disorder realisations per (tau, N) (default "
                                   f"{B['realisations']} for blowup, {C['realisations']} for "
                                   "chaos)"),
                 _output_options("merged HDF5 file (default sweep.h5)", out_default="sweep.h5")])
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
