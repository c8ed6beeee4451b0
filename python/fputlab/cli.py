"""The `fputlab` command: the paper's workflows with defaults that reproduce it."""
from __future__ import annotations

import argparse
import json
import sys

import numpy as np


def _lattice_args(p, model="nonlinear", tau=10.0, N=64):
    p.add_argument("--N", type=int, default=N, help=f"particles (default {N})")
    p.add_argument("--alpha", type=float, default=0.25, help="quadratic coupling (default 0.25)")
    p.add_argument("--beta", type=float, default=0.0, help="quartic coupling (default 0)")
    p.add_argument("--model", default=model, choices=["homogeneous", "hamiltonian", "nonlinear"],
                   help=f"lattice model (default {model})")
    p.add_argument("--tau", type=float, default=tau, help=f"variability in percent (default {tau:g})")
    p.add_argument("--seed", type=int, default=1, help="disorder seed (default 1)")
    p.add_argument("--disorder", default="gaussian", choices=["gaussian", "truncated", "uniform"])


def _method_args(p, dt=0.01):
    p.add_argument("--method", default="yoshida4", help="integrator (see `fputlab methods`)")
    p.add_argument("--dt", type=float, default=None, help=f"fixed step (default {dt:g})")
    p.add_argument("--rtol", type=float, default=1e-10)
    p.add_argument("--atol", type=float, default=1e-12)


def _lattice(a):
    from .lattice import Lattice
    if a.model == "homogeneous":
        return Lattice(a.N, a.alpha, a.model, beta=a.beta)
    return Lattice(a.N, a.alpha, a.model, beta=a.beta, tau=a.tau, seed=a.seed, disorder=a.disorder)


def _emit(summary: dict, as_json: bool):
    if as_json:
        print(json.dumps(summary, indent=2, default=float))
    else:
        for k, v in summary.items():
            print(f"{k:>24}: {v}")


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


def cmd_simulate(a):
    lat = _lattice(a)
    run = lat.integrate(a.t_end, method=a.method, dt=a.dt, rtol=a.rtol, atol=a.atol,
                        sample_every=a.sample_every, store_states=a.states, on_failure="return")
    summary = {"lattice": repr(lat), "method": a.method, "t_reached": float(run.t[-1]) if run.t.size else 0.0,
               "samples": int(run.t.size), "completed": run.completed, "message": run.message,
               "max_relative_energy_error": float(run.relative_energy_error.max()) if run.t.size else None}
    if a.out:
        _write_h5(a.out, {"N": lat.N, "alpha": lat.alpha, "beta": lat.beta, "model": lat.model,
                          "tau": lat.tau, "seed": lat.seed if lat.seed is not None else -1,
                          "method": a.method, "dt": run.dt},
                  {"v": lat.v, "t": run.t, "mode_energies": run.mode_energies, "energy": run.energy,
                   "states": run.states})
        summary["out"] = a.out
    _emit(summary, a.json)
    return 0 if run.completed else 1


def cmd_blowup(a):
    from .blowup import blowup_sweep, blowup_time
    if a.realisations > 1 or len(a.taus) > 1:
        out = blowup_sweep(a.taus, Ns=[a.N], realisations=a.realisations, t_max=a.t_max,
                           model=a.model, alpha=a.alpha, method=a.method, first_seed=a.seed,
                           workers=a.workers, progress=True)
        summary = {"tau": out["tau"].tolist(), "probability": out["probability"][:, 0].tolist(),
                   "realisations": a.realisations, "t_max": a.t_max,
                   "two_mode_prediction_accuracy": out["prediction_accuracy"]}
        if a.out:
            rec = np.array([r[:6] for r in out["records"]], dtype=float)
            _write_h5(a.out, {"t_max": a.t_max, "model": a.model, "N": a.N},
                      {"tau": out["tau"], "probability": out["probability"], "records": rec})
        if a.plot:
            from .blowup import plot_sweep
            plot_sweep(out, a.plot)
            summary["plot"] = a.plot
        _emit(summary, a.json)
        return 0
    res = blowup_time(_lattice(a), a.t_max, method=a.method, dt=a.dt, rtol=a.rtol, atol=a.atol)
    _emit({"blew_up": res.blew_up, "time": res.time, "criterion": res.criterion,
           "t_reached": res.t_reached, "tau": a.tau, "seed": a.seed, "N": a.N}, a.json)
    return 0


def cmd_chaos(a):
    from .chaos import chaotic_fraction, lyapunov
    if a.realisations > 1:
        out = chaotic_fraction(Ns=a.Ns, realisations=a.realisations, tau=a.tau, t_end=a.t_end,
                               model=a.model, alpha=a.alpha, method=a.method, first_seed=a.seed,
                               workers=a.workers, progress=True, n_samples=a.samples)
        _emit({"N": out["N"], "percent_chaotic": out["percent"], "tau": a.tau, "t_end": a.t_end}, a.json)
        return 0
    res = lyapunov(_lattice(a), a.t_end, method=a.method, dt=a.dt, rtol=a.rtol, atol=a.atol,
                   n_samples=a.samples, stop_when_chaotic=a.stop_when_chaotic)
    if a.out:
        _write_h5(a.out, {"N": a.N, "model": a.model, "tau": a.tau, "seed": a.seed, "method": a.method},
                  {"t": res.t, "mle": res.mle, "sali": res.sali, "gali": res.gali})
    _emit({"mle": res.mle_final, "sali": float(res.sali[-1]) if res.sali.size else None,
           "class": res.classify(), "t_final": res.t_final, "steps": res.steps}, a.json)
    return 0


def cmd_figures(a):
    from .figures import all_figures
    only = set(a.only) if a.only else None
    for p in all_figures(a.out, full=a.full, only=only):
        print(p)
    return 0


def cmd_methods(a):
    from .integrate import method_info, methods
    for m in methods():
        info = method_info(m)
        print(f"{m:12s} order {info['order']}  {'adaptive' if info['adaptive'] else 'fixed step'}")
    return 0


def build_parser():
    p = argparse.ArgumentParser(prog="fputlab", description="Ordered and disordered FPUT lattices "
                                "(paper: Energy-recurrence breakdown and chaos in disordered FPUT lattices).")
    p.add_argument("--version", action="store_true", help="print the version and exit")
    sub = p.add_subparsers(dest="command")

    s = sub.add_parser("demo", help="reproduce Fig. 1 (FPUT recurrence, N = 64) as a PNG", add_help=False)
    s = sub.add_parser("simulate", help="integrate one lattice, sample mode energies")
    _lattice_args(s)
    _method_args(s)
    s.add_argument("--t-end", type=float, default=1e4)
    s.add_argument("--sample-every", type=float, default=None)
    s.add_argument("--states", action="store_true", help="also store the states")
    s.add_argument("--out", help="HDF5 file to write")
    s.add_argument("--json", action="store_true")
    s.set_defaults(func=cmd_simulate)

    s = sub.add_parser("blowup", help="blow-up time of one realisation, or the probability over many")
    _lattice_args(s, tau=20.0)
    _method_args(s)
    s.add_argument("--t-max", type=float, default=1e4)
    s.add_argument("--taus", type=float, nargs="+", default=None, help="sweep these tau values")
    s.add_argument("--realisations", type=int, default=1)
    s.add_argument("--workers", type=int, default=None)
    s.add_argument("--out")
    s.add_argument("--plot", help="PNG of the sweep: probability vs tau, blow-up times")
    s.add_argument("--json", action="store_true")
    s.set_defaults(func=cmd_blowup)

    s = sub.add_parser("chaos", help="mLE and SALI of one orbit, or the chaotic fraction (Fig. 14)")
    _lattice_args(s)
    _method_args(s)
    s.add_argument("--t-end", type=float, default=1e4)
    s.add_argument("--samples", type=int, default=200)
    s.add_argument("--stop-when-chaotic", action="store_true")
    s.add_argument("--realisations", type=int, default=1)
    s.add_argument("--Ns", type=int, nargs="+", default=[4, 8, 16, 32, 64])
    s.add_argument("--workers", type=int, default=None)
    s.add_argument("--out")
    s.add_argument("--json", action="store_true")
    s.set_defaults(func=cmd_chaos)

    s = sub.add_parser("figures", help="regenerate the paper's figures as PNGs")
    s.add_argument("--out", default="figures", help="output directory (default figures/)")
    s.add_argument("--full", action="store_true", help="the paper's settings (t = 1e8: very long)")
    s.add_argument("--only", type=int, nargs="+", help="figure numbers to make")
    s.set_defaults(func=cmd_figures)

    s = sub.add_parser("methods", help="list the integrators")
    s.set_defaults(func=cmd_methods)
    return p


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
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
    if getattr(a, "taus", "absent") is None:
        a.taus = [a.tau]
    try:
        return a.func(a)
    except (ValueError, TypeError) as err:
        print(f"fputlab: error: {err}", file=sys.stderr)
        return 2
