"""`fputlab blowup`: the blow-up time of one realisation, or the probability over many."""
from __future__ import annotations

import numpy as np

from ..io.summary import write_h5
from ._common import (_emit, _ensemble_lattice_check, _homogeneous_check, _integrator_kwargs,
                      _lattice, _new_file, _output_paths, _positive)
from .parsers import (_alias, _ensemble_options, _fill, _finite_positive, _integrator_options,
                      _lattice_options, _one, _output_options, _sub, _time_options,
                      python_defaults)

def cmd_blowup(a):
    from ..blowup import blowup_sweep, blowup_time
    _positive(a, "realisations")
    _positive(a, "workers")
    _homogeneous_check(a)
    _output_paths(a, "out", "plot")
    _new_file(a, "out")
    if a.sweep:
        _ensemble_lattice_check(a)
        out = blowup_sweep(a.tau, Ns=a.N, realisations=a.realisations, t_end=a.t_end,
                           model=a.model, alpha=a.alpha, method=a.method, first_seed=a.seed,
                           workers=a.workers, scheduler=a.scheduler, progress=not a.json,
                           **_integrator_kwargs(a))
        summary = {"tau": out["tau"].tolist(), "N": out["N"].tolist(),
                   "probability": out["probability"].tolist() if len(a.N) > 1
                   else out["probability"][:, 0].tolist(),
                   "realisations": a.realisations, "t_end": a.t_end,
                   "two_mode_prediction_accuracy": out["prediction_accuracy"],
                   # JSON keeps one named record per realisation; the text summary is for a
                   # person (five taus of 50 were 250 lines): the count, the records in --out
                   "records": [r._asdict() for r in out["records"]] if a.json else
                   (f"{len(out['records'])} in {a.out}" if a.out else
                    f"{len(out['records'])} (write them with --out FILE)")}
        if a.out:
            # the file keeps its layout: records as rows of floats (tau, N, seed, blew_up,
            # time, tau_c), the BlowupRecord fields in order
            rec = np.array([tuple(r) for r in out["records"]], dtype=float)
            write_h5(a.out, {"t_end": a.t_end, "model": a.model,
                              "N": a.N[0] if len(a.N) == 1 else np.asarray(a.N)},
                      {"tau": out["tau"], "probability": out["probability"], "records": rec})
        if a.plot:
            from ..plotting import plot_blowup_sweep_figure
            plot_blowup_sweep_figure(out, a.plot)
            summary["plot"] = a.plot
        _emit(summary, a.json)
        return 0
    for name in ("scheduler", "plot", "out"):
        if getattr(a, name):     # refused, not ignored
            raise ValueError(f"--{name}: only for a sweep (several --tau or --N values, or "
                             "--realisations > 1); one realisation prints its blow-up time")
    res = blowup_time(_lattice(a), a.t_end, method=a.method, progress=not a.json,
                      **_integrator_kwargs(a))
    _emit({"blew_up": res.blew_up, "time": res.time, "criterion": res.criterion,
           "t_reached": res.t_reached, "tau": a.tau, "seed": a.seed, "N": a.N}, a.json)
    return 0


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
                 _time_options(B["t_end"], "final time: no blow-up before it is blew_up false"),
                 _ensemble_options(f"disorder realisations per tau (default 1; in a sweep "
                                   f"{B['realisations']}, as blowup_sweep)"),
                 _output_options("HDF5 file with the sweep (default: none)")])
    _alias(s, "--taus", "--tau", "tau", type=float, nargs="+")
    s.add_argument("--plot", metavar="FILE", help="PNG of the sweep: probability vs tau, "
                   "blow-up times (default: none)")
    s.set_defaults(func=cmd_blowup, resolve=_resolve_blowup)


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
