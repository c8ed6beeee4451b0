"""The `fputlab` command: the paper's workflows with defaults that reproduce it."""
from __future__ import annotations

import argparse
import json
import os
import sys

import numpy as np

from ._display import dumps_strict


def _lattice_args(p, model="nonlinear", tau=10.0, N=64):
    p.add_argument("--N", type=int, default=N, help=f"particles (default {N})")
    p.add_argument("--alpha", type=float, default=0.25, help="quadratic coupling (default 0.25)")
    p.add_argument("--beta", type=float, default=0.0, help="quartic coupling (default 0)")
    p.add_argument("--model", default=model, choices=["homogeneous", "hamiltonian", "nonlinear"],
                   help=f"lattice model (default {model})")
    # default None: whether --tau was given matters (the homogeneous model refuses it)
    p.add_argument("--tau", type=float, default=None, help=f"variability in percent (default {tau:g})")
    p.set_defaults(tau_default=tau)
    p.add_argument("--seed", type=int, default=1, help="disorder seed (default 1)")
    p.add_argument("--disorder", default="gaussian", choices=["gaussian", "truncated", "uniform"],
                   help="distribution of the disorder draws")


def _method_args(p, dt=0.01, method="yoshida4"):
    p.add_argument("--method", default=method, help=f"integrator (see `fputlab methods`; "
                   f"default {method or 'yoshida4, ensembles srkn14a6 at dt = 0.5'})")
    p.add_argument("--dt", type=float, default=None, help=f"fixed step (default {dt:g})")
    p.add_argument("--rtol", type=float, default=1e-10, help="relative tolerance (adaptive methods)")
    p.add_argument("--atol", type=float, default=1e-12, help="absolute tolerance (adaptive methods)")


def _lattice(a):
    from .lattice import Lattice
    if a.model == "homogeneous":
        _homogeneous_check(a)
        return Lattice(a.N, a.alpha, a.model, beta=a.beta)
    return Lattice(a.N, a.alpha, a.model, beta=a.beta, tau=a.tau, seed=a.seed, disorder=a.disorder)


def _homogeneous_check(a):
    """The homogeneous model has no disorder: a --tau given with it is refused, not ignored."""
    if a.model == "homogeneous" and getattr(a, "tau_given", False) and a.tau != 0:
        raise ValueError(f"--tau {a.tau:g}: the homogeneous model has no disorder (use --model "
                         "hamiltonian or nonlinear, or drop --tau)")


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
    if a.realisations > 1 or len(a.taus) > 1:
        _ensemble_lattice_check(a)
        out = blowup_sweep(a.taus, Ns=[a.N], realisations=a.realisations, t_max=a.t_max,
                           model=a.model, alpha=a.alpha, method=a.method, first_seed=a.seed,
                           workers=a.workers, progress=not a.json, **_integrator_kwargs(a))
        summary = {"tau": out["tau"].tolist(), "probability": out["probability"][:, 0].tolist(),
                   "realisations": a.realisations, "t_max": a.t_max,
                   "two_mode_prediction_accuracy": out["prediction_accuracy"],
                   "records": [dict(zip(("tau", "N", "seed", "blew_up", "time", "tau_c"),
                                        (float(x) for x in r[:6]))) for r in out["records"]]}
        if a.out:
            rec = np.array([r[:6] for r in out["records"]], dtype=float)
            _write_h5(a.out, {"t_max": a.t_max, "model": a.model, "N": a.N},
                      {"tau": out["tau"], "probability": out["probability"], "records": rec})
        if a.plot:
            from .plotting import plot_blowup_sweep_figure
            plot_blowup_sweep_figure(out, a.plot)
            summary["plot"] = a.plot
        _emit(summary, a.json)
        return 0
    res = blowup_time(_lattice(a), a.t_max, method=a.method, progress=not a.json,
                      **_integrator_kwargs(a))
    _emit({"blew_up": res.blew_up, "time": res.time, "criterion": res.criterion,
           "t_reached": res.t_reached, "tau": a.tau, "seed": a.seed, "N": a.N}, a.json)
    return 0


def cmd_chaos(a):
    from .chaos import chaotic_fraction, lyapunov
    if a.checkpoint and (not a.out or a.realisations > 1):
        raise ValueError("--checkpoint needs --out and one orbit (use `fputlab sweep` for ensembles)")
    _positive(a, "realisations")
    _positive(a, "workers")
    _positive(a, "samples")
    _homogeneous_check(a)
    _output_paths(a, "out", "checkpoint")
    if a.realisations > 1:
        _new_file(a, "out")
    opts = dict(_integrator_kwargs(a), n_samples=a.samples)
    if a.stop_when_chaotic:         # ensembles stop chaotic orbits anyway (chaos.ensemble_defaults)
        opts["stop_when_chaotic"] = True
    if a.realisations > 1:
        _ensemble_lattice_check(a)
        out = chaotic_fraction(Ns=a.Ns, realisations=a.realisations, tau=a.tau, t_end=a.t_end,
                               model=a.model, alpha=a.alpha, method=a.method, first_seed=a.seed,
                               workers=a.workers, progress=not a.json, **opts)
        summary = {"N": out["N"], "percent_chaotic": out["percent"],
                   "blew_up": out["blowups"], "classes": out["classes"], "tau": a.tau,
                   "t_end": a.t_end, "method": out["results"][out["N"][0]][0].method}
        if a.out:
            rows = [(N, i, r.mle_final, float(r.sali[-1]) if r.sali.size else np.nan, r.t_final)
                    for N in out["N"] for i, r in enumerate(out["results"][N])]
            _write_h5(a.out, {"model": a.model, "tau": a.tau, "t_end": a.t_end, "method": a.method,
                              "columns": "N, realisation, mle, sali, t_final"},
                      {"N": out["N"], "percent_chaotic": out["percent"], "records": rows})
            summary["out"] = a.out
        _emit(summary, a.json)
        return 0
    if a.out:
        # written as it goes, with checkpoints: runs to t = 1e8 survive interruptions
        from .io import chaos_to_file
        s = chaos_to_file(_lattice(a), a.t_end, a.out, method=a.method or "yoshida4", **opts,
                          overwrite=a.overwrite, **_checkpoint_kwargs(a))
        _emit(_run_summary(s), a.json)
        return {"completed": 0, "interrupted": 130}.get(s.status, 1)
    from ._errors import Interrupted
    try:
        res = lyapunov(_lattice(a), a.t_end, method=a.method or "yoshida4",
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
    from .figures import all_figures
    only = set(a.only) if a.only else None
    unknown = sorted(k for k in (only or ()) if not 1 <= k <= 14)
    if unknown:
        raise ValueError(f"--only: there is no figure {', '.join(map(str, unknown))} (the paper's "
                         "figures are 1-14)")
    study = {"work_dir": a.work_dir, "t_until": a.t_end, "workers": a.workers,
             "scheduler": a.scheduler}
    for p in all_figures(a.out, full=a.full, only=only, **study):
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

_SWEEP_DEFAULTS = {"blowup": {"taus": [0.0, 5.0, 10.0, 15.0, 20.0], "Ns": [64]},
                   "chaos": {"taus": [10.0], "Ns": [4, 8, 16, 32, 64]}}


def cmd_sweep(a):
    from .ensemble import run_sweep
    taus = getattr(a, "taus", None) or _SWEEP_DEFAULTS[a.kind]["taus"]
    Ns = getattr(a, "Ns", None) or _SWEEP_DEFAULTS[a.kind]["Ns"]
    opts = {k: v for k, v in (("dt", a.dt), ("rtol", a.rtol), ("atol", a.atol)) if v is not None}
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
    out = run_sweep(a.kind, taus, Ns, a.realisations, t_max=a.t_max, work_dir=work_dir,
                    out=a.out, model=a.model, alpha=a.alpha, first_seed=a.first_seed,
                    method=a.method, workers=a.workers, scheduler=a.scheduler,
                    progress=not a.json, **opts)
    what = "blew_up" if a.kind == "blowup" else "chaotic"
    summary = {"kind": a.kind, "out": out["out"], "work_dir": out["work_dir"],
               "tasks": out["n_tasks"], "computed": out["computed"], "skipped": out["skipped"],
               "failed": len(out["failed"]), "t_max": a.t_max,
               f"fraction_{what}": [{"tau": r["tau"], "N": r["N"], "n": r["n"],
                                     "fraction": r["fraction"]} for r in out["summary"]]}
    if out["failed"]:
        summary["failures"] = [f"N={t.N} tau={t.tau:g} seed={t.seed}: {msg}"
                               for t, msg in out["failed"]]
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
    for tau in a.taus:
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
    tc = critical_tolerance(a.N, a.alpha, a.R, seed0=a.first_seed, kind=a.disorder, tau=tau)
    s = tc.summary()
    summary = {"N": a.N, "alpha": a.alpha, "disorder": a.disorder, "R": a.R,
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


def _overwrite_arg(p):
    p.add_argument("--overwrite", action="store_true",
                   help="replace an existing --out file (otherwise refused)")


def _checkpoint_args(p):
    p.add_argument("--checkpoint", help="checkpoint file (with --out): resume from it if it exists")
    p.add_argument("--checkpoint-every", type=float, default=600.0, metavar="SECONDS",
                   help="write a checkpoint every SECONDS of wall time (default 600)")
    p.add_argument("--checkpoint-steps", type=int, default=None, metavar="K",
                   help="also write one every K integrator steps")
    p.add_argument("--restart", action="store_true",
                   help="ignore an existing checkpoint and start from t = 0")


def build_parser():
    p = argparse.ArgumentParser(prog="fputlab", description="Ordered and disordered FPUT lattices "
                                "(paper: Energy-recurrence breakdown and chaos in disordered FPUT lattices).")
    p.add_argument("--version", action="store_true", help="print the version and exit")
    sub = p.add_subparsers(dest="command")

    s = sub.add_parser("demo", help="reproduce Fig. 1 (FPUT recurrence, N = 64) as a PNG", add_help=False)
    s = sub.add_parser("simulate", help="integrate one lattice, sample mode energies")
    _lattice_args(s)
    _method_args(s)
    s.add_argument("--t-end", "--t-max", dest="t_end", type=float, default=1e4, help="final time")
    s.add_argument("--sample-every", type=float, default=None,
                   help="sample spacing (default t_end/1000, at least dt; on resume: the "
                        "checkpoint's)")
    s.add_argument("--states", action="store_true", help="also store the states")
    s.add_argument("--out", help="HDF5 results file, written as the run goes (see docs/hdf5.md)")
    _overwrite_arg(s)
    _checkpoint_args(s)
    s.add_argument("--json", action="store_true",
                   help="print the summary as JSON (strict: NaN/Inf as null)")
    s.set_defaults(func=cmd_simulate)

    s = sub.add_parser("blowup", help="blow-up time of one realisation, or the probability over many")
    _lattice_args(s, tau=20.0)
    _method_args(s)
    s.add_argument("--t-max", "--t-end", dest="t_max", type=float, default=1e4,
                   help="final time (no blow-up before it: blew_up false)")
    s.add_argument("--taus", type=float, nargs="+", default=None, help="sweep these tau values")
    s.add_argument("--realisations", type=int, default=1,
                   help="disorder realisations (seeds --seed, --seed + 1, ...)")
    s.add_argument("--workers", type=int, default=None, help="local processes (default all cores)")
    s.add_argument("--out", help="HDF5 file with the sweep (with --taus or --realisations)")
    _overwrite_arg(s)
    s.add_argument("--plot", help="PNG of the sweep: probability vs tau, blow-up times")
    s.add_argument("--json", action="store_true",
                   help="print the summary as JSON (strict: NaN/Inf as null)")
    s.set_defaults(func=cmd_blowup)

    s = sub.add_parser("chaos", help="mLE and SALI of one orbit, or the chaotic fraction (Fig. 14)")
    _lattice_args(s)
    _method_args(s, method=None)
    s.add_argument("--t-end", "--t-max", dest="t_end", type=float, default=1e4, help="final time")
    s.add_argument("--samples", type=int, default=200,
                   help="log-spaced samples of mLE(t), SALI(t), GALI(t)")
    s.add_argument("--stop-when-chaotic", action="store_true",
                   help="stop once SALI falls below its threshold")
    s.add_argument("--realisations", type=int, default=1,
                   help="disorder realisations per N (> 1: the chaotic fraction over --Ns)")
    s.add_argument("--Ns", type=int, nargs="+", default=[4, 8, 16, 32, 64],
                   help="lattice sizes of the chaotic fraction")
    s.add_argument("--workers", type=int, default=None, help="local processes (default all cores)")
    s.add_argument("--out", help="HDF5 file (one orbit: written as the run goes, with checkpoints)")
    _overwrite_arg(s)
    _checkpoint_args(s)
    s.add_argument("--json", action="store_true",
                   help="print the summary as JSON (strict: NaN/Inf as null)")
    s.set_defaults(func=cmd_chaos)

    s = sub.add_parser("sweep", help="realisation x tau x N ensemble (blow-up or chaos) on a local "
                       "pool or a Dask cluster; resumable, merged into one HDF5 file",
                       description="Each (tau, N, seed) is an independent task whose result is "
                       "written to its own HDF5 file in --work-dir; rerunning skips finished "
                       "tasks. All results are merged into --out (one row per task).")
    s.add_argument("--kind", default="blowup", choices=["blowup", "chaos"],
                   help="blowup: blow-up time up to --t-max; chaos: mLE/SALI up to --t-end "
                        "(default blowup)")
    s.add_argument("--taus", type=float, nargs="+", default=argparse.SUPPRESS,
                   help="variabilities in percent (default: 0 5 10 15 20 for blowup, 10 for chaos)")
    s.add_argument("--Ns", type=int, nargs="+", default=argparse.SUPPRESS,
                   help="lattice sizes (default: 64 for blowup, 4 8 16 32 64 for chaos)")
    s.add_argument("--realisations", type=int, default=30,
                   help="disorder realisations per (tau, N) (default 30, as Fig. 14)")
    s.add_argument("--first-seed", type=int, default=1, help="seeds first..first+R-1 (default 1)")
    s.add_argument("--t-max", "--t-end", dest="t_max", type=float, default=1e4,
                   help="final time of every task (default 1e4)")
    s.add_argument("--model", default="nonlinear", choices=["homogeneous", "hamiltonian", "nonlinear"],
                   help="lattice model (default nonlinear)")
    s.add_argument("--alpha", type=float, default=0.25, help="quadratic coupling (default 0.25)")
    s.add_argument("--method", default=None, help="integrator (default yoshida4)")
    s.add_argument("--dt", type=float, default=None, help="fixed step (default 0.01)")
    s.add_argument("--rtol", type=float, default=None,
                   help="relative tolerance, adaptive methods (default 1e-10)")
    s.add_argument("--atol", type=float, default=None,
                   help="absolute tolerance, adaptive methods (default 1e-12)")
    s.add_argument("--samples", type=int, default=None,
                   help="chaos: log-spaced samples of mLE(t), SALI(t) (default 200)")
    s.add_argument("--out", default="sweep.h5", help="merged HDF5 file (default sweep.h5)")
    s.add_argument("--work-dir", default=None,
                   help="per-task result files (default OUT.tasks/); reused to resume")
    s.add_argument("--scheduler", default=None,
                   help="Dask scheduler address tcp://host:port (default: local processes)")
    s.add_argument("--workers", type=int, default=None, help="local processes (default all cores)")
    s.add_argument("--json", action="store_true",
                   help="print the summary as JSON (strict: NaN/Inf as null)")
    s.set_defaults(func=cmd_sweep)

    s = sub.add_parser("coefficients", help="two-mode coefficients a_i, b_i (raw) and A_i, B_i, "
                       "A~, B~ (paper-normalised) of one realisation or over --taus")
    s.add_argument("--N", type=int, default=64, help="particles (default 64)")
    s.add_argument("--alpha", type=float, default=0.25, help="quadratic coupling (default 0.25)")
    s.add_argument("--model", default="nonlinear", choices=["homogeneous", "hamiltonian", "nonlinear"],
                   help="lattice model (default nonlinear)")
    s.add_argument("--tau", type=float, default=0.0, help="variability in percent (default 0)")
    s.add_argument("--taus", type=float, nargs="+", default=None,
                   help="several variabilities (same seed, hence the same draws z)")
    s.add_argument("--seed", type=int, default=1, help="disorder seed (default 1)")
    s.add_argument("--disorder", default="gaussian", choices=["gaussian", "truncated", "uniform"],
                   help="distribution of the disorder draws")
    s.add_argument("--out", help="HDF5 file to write")
    _overwrite_arg(s)
    s.add_argument("--json", action="store_true",
                   help="print the summary as JSON (strict: NaN/Inf as null)")
    s.set_defaults(func=cmd_coefficients)

    s = sub.add_parser("tauc", help="critical variability tau_c (B~ = 0) three ways: exact "
                       "expectation, quadratic fit (the paper's), per realisation")
    s.add_argument("--N", type=int, default=64, help="particles (default 64)")
    s.add_argument("--alpha", type=float, default=0.25, help="quadratic coupling (default 0.25)")
    s.add_argument("--R", "--realisations", dest="R", type=int, default=100,
                   help="realisations (default 100, as the paper)")
    s.add_argument("--first-seed", type=int, default=1, help="seeds first..first+R-1 (default 1)")
    s.add_argument("--disorder", default="gaussian", choices=["gaussian", "truncated", "uniform"],
                   help="distribution of the disorder draws")
    s.add_argument("--fit-taus", type=float, nargs="+", default=None,
                   help="tau grid of the fit (default 0, 0.5, ..., 20)")
    s.add_argument("--json", action="store_true",
                   help="print the summary as JSON (strict: NaN/Inf as null)")
    s.add_argument("--out", help="HDF5 file with the summary")
    _overwrite_arg(s)
    s.set_defaults(func=cmd_tauc)

    s = sub.add_parser("bifurcation", help="reduced (P, Delta, theta) system at (A~, B~): C, "
                       "equilibria Delta_1, Delta_2, theta, eigenvalues and their type")
    s.add_argument("--A-tilde", dest="A_tilde", type=float, default=3.62805,
                   help="A~ (default 3.62805, tau = 0)")
    s.add_argument("--B-tilde", dest="B_tilde", type=float, default=0.90728,
                   help="B~ (default 0.90728, tau = 0)")
    s.add_argument("--N", type=int, default=64,
                   help="particles: r_1^2 = (N+1)/8 of the paper's initial state (default 64)")
    s.add_argument("--plot", help="PNG of the (A~, B~) bifurcation diagram (Fig. 7)")
    s.add_argument("--json", action="store_true",
                   help="print the summary as JSON (strict: NaN/Inf as null)")
    s.add_argument("--out", help="HDF5 file with the summary")
    _overwrite_arg(s)
    s.set_defaults(func=cmd_bifurcation)

    s = sub.add_parser("figures", help="regenerate the paper's figures as PNGs")
    s.add_argument("--out", default="figures", help="output directory (default figures/)")
    s.add_argument("--full", action="store_true", help="the paper's settings (t = 1e8: very long)")
    s.add_argument("--only", type=int, nargs="+", help="figure numbers to make")
    s.add_argument("--work-dir", help="chaos study of Figs. 12-14: one state file per orbit, "
                   "resumed by the next call (default OUT/chaos_study)")
    s.add_argument("--t-end", type=float, help="how far the chaos study goes in this call "
                   "(default 1e5, with --full 1e8); rerun with a larger value to continue")
    s.add_argument("--workers", type=int, help="local processes for the chaos study "
                   "(default: all cores)")
    s.add_argument("--scheduler", help="Dask scheduler address tcp://host:port for the chaos "
                   "study (the work directory must be shared)")
    s.set_defaults(func=cmd_figures)

    s = sub.add_parser("methods", help="list the integrators")
    s.set_defaults(func=cmd_methods)
    for s in sub.choices.values():
        if s.formatter_class is argparse.HelpFormatter:
            s.formatter_class = _DefaultsFormatter
    return p


class _DefaultsFormatter(argparse.HelpFormatter):
    """Every option's help ends with its default (unless the help already states it)."""

    def _get_help_string(self, action):
        text = action.help or ""
        default = action.default
        if ("default" in text or not action.option_strings or default is None
                or default is False or default is argparse.SUPPRESS):
            return text
        if isinstance(default, (list, tuple)):
            default = " ".join(map(str, default))
        elif isinstance(default, float):
            default = f"{default:g}"
        return f"{text} (default {str(default).replace('%', '%%')})".strip()


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
    if hasattr(a, "tau_default"):
        a.tau_given = a.tau is not None
        if a.tau is None:
            a.tau = a.tau_default
    if getattr(a, "taus", "absent") is None:
        a.taus = [a.tau]
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
