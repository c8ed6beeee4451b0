"""`fputlab chaos`: mLE and SALI of one orbit, or the chaotic fraction (Fig. 14)."""
from __future__ import annotations

import json

from ._common import (_checkpoint_kwargs, _emit, _ensemble_lattice_check, _g, _homogeneous_check,
                      _integrator_kwargs, _lattice, _new_file, _output_paths, _positive,
                      _run_summary)
from .parsers import (_alias, _checkpoint_options, _ensemble_options, _fill, _finite_positive,
                      _integrator_options, _lattice_options, _one, _output_options,
                      _resolve_single_lattice, _sub, _time_options, python_defaults)

def cmd_chaos(a):
    from ..chaos import CLASSES, chaotic_fraction, lyapunov
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
        if a.model == "toda" or a.boundary != "fixed":
            raise ValueError("--model toda / --boundary periodic: one orbit only; the chaotic "
                             "fraction runs the paper's fixed chains of models 1-3")
        out = chaotic_fraction(Ns=a.N, realisations=a.realisations, tau=a.tau, t_end=a.t_end,
                               model=a.model, alpha=a.alpha, method=a.method, first_seed=a.seed,
                               workers=a.workers, scheduler=a.scheduler, progress=not a.json,
                               **opts)
        ds = out.to_xarray()
        rows = out.summary()
        summary = {"N": [r["N"] for r in rows],
                   "fraction_chaotic": [r["fraction_chaotic"] for r in rows],
                   "fraction_chaotic_95": [[r["fraction_chaotic_low"],
                                            r["fraction_chaotic_high"]] for r in rows],
                   "blew_up": [r["blow-up"] for r in rows],
                   "classes": {r["N"]: {c: r[c] for c in CLASSES} for r in rows},
                   "tau": a.tau, "t_end": a.t_end,
                   "method": json.loads(ds.attrs["settings"])["method"]}
        if a.out:
            # the labelled result (netCDF-4/HDF5: N x tau x seed x sample, classes as strings)
            from ..io.atomic import write_atomic
            write_atomic(a.out, lambda tmp: ds.to_netcdf(tmp, engine="h5netcdf"))
            summary["out"] = a.out
        _emit(summary, a.json)
        return 0
    if a.out:
        # written as it goes, with checkpoints: runs to t = 1e8 survive interruptions
        from ..io import chaos_to_file
        s = chaos_to_file(_lattice(a), a.t_end, a.out, method=a.method, **opts,
                          overwrite=a.overwrite, **_checkpoint_kwargs(a))
        _emit(_run_summary(s), a.json)
        return {"completed": 0, "interrupted": 130}.get(s.status, 1)
    from .._errors import Interrupted
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
                 seed="disorder seed; the fraction uses SEED, SEED + 1, ... (default 1)",
                 single=True),
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
