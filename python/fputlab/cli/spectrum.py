"""`fputlab spectrum`: the Lyapunov spectrum of one orbit (fputlab.chaos.lyapunov_spectrum)."""
from __future__ import annotations

from ..io.summary import write_h5
from ._common import (_emit, _g, _homogeneous_check, _integrator_kwargs, _lattice, _new_file,
                      _output_paths, _positive)
from .parsers import (_finite_positive, _integrator_options, _lattice_options, _output_options,
                      _resolve_single_lattice, _sub, _time_options, python_defaults)


def cmd_spectrum(a):
    from ..chaos import lyapunov_spectrum
    from .._errors import Interrupted
    _homogeneous_check(a)
    _positive(a, "samples")
    _output_paths(a, "out", "plot")
    _new_file(a, "out")
    _new_file(a, "plot")
    lat = _lattice(a)
    y0 = None if a.initial_amplitude is None else lat.mode_state(1, a.initial_amplitude)
    try:
        res = lyapunov_spectrum(lat, a.t_end, k=a.k, y0=y0, method=a.method,
                                renormalize_every=a.renormalize_every,
                                t_transient=a.t_transient, n_samples=a.samples, seed=a.w_seed,
                                progress=not a.json, **_integrator_kwargs(a))
    except Interrupted as err:           # Ctrl-C: the summary of what was computed, exit 130
        res = err.result
    lam = res.exponents
    summary = {"N": lat.N, "k": res.k, "t_final": res.t_final, "lambda_1": res.mle,
               "lambda_k": float(lam[-1]), "sum": float(lam.sum()), "ks_entropy": res.ks_entropy,
               "kaplan_yorke_dimension": res.kaplan_yorke_dimension, "steps": res.steps,
               "exponents": lam.tolist()}
    if res.message:
        summary["message"] = res.message
    if a.out:
        write_h5(a.out, {"kind": "spectrum", "model": lat.model, "N": lat.N, "k": res.k,
                          "method": res.method, "t_end": a.t_end, "t_final": res.t_final,
                          "renormalize_every": a.renormalize_every,
                          "t_transient": a.t_transient, "ks_entropy": res.ks_entropy,
                          "kaplan_yorke_dimension": res.kaplan_yorke_dimension},
                  {"exponents": lam, "t": res.t, "history": res.history,
                   "v": lat.v})
        summary["out"] = a.out
    if a.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from ..plotting import plot_spectrum, plot_spectrum_convergence
        fig, ax = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
        plot_spectrum(res, ax=ax[0])
        plot_spectrum_convergence(res, ax=ax[1], every=max(1, res.k // 32))
        fig.savefig(a.plot, dpi=120)
        plt.close(fig)
        summary["plot"] = a.plot
    _emit(summary, a.json)
    return 130 if res.message.startswith("interrupted") else 0


def _parser_spectrum(sub, parents):
    L, S = python_defaults()["Lattice"], python_defaults()["lyapunov_spectrum"]
    s = _sub(sub, "spectrum", "the Lyapunov spectrum of one orbit (all 2N exponents)",
             description="The k largest Lyapunov exponents of one orbit by the Benettin / QR "
             "method (fputlab.chaos.lyapunov_spectrum; without options the lattice is "
             "fputlab.Lattice(), the homogeneous chain, from the paper's mode-1 state), with "
             "the Kolmogorov-Sinai entropy and the Kaplan-Yorke dimension.",
             parents=[_lattice_options(N=f"particles (default {L['N']})",
                                       model=f"lattice model (default {L['model']})",
                                       tau=f"variability in percent (default {_g(L['tau'])})"),
                      _integrator_options(method=f"integrator (default {S['method']})",
                                          dt="fixed step (default 0.01)"),
                      _time_options(1e4, "length of the measurement after --t-transient"),
                      _output_options("HDF5 file with exponents, t, history (default: none)")])
    s.add_argument("--k", type=int, default=None,
                   help="number of exponents, 1..2N (default: all 2N)")
    s.add_argument("--renormalize-every", type=float, default=S["renormalize_every"],
                   metavar="TAU", help="time between QR re-orthonormalisations (default "
                   f"{_g(S['renormalize_every'])})")
    s.add_argument("--t-transient", type=float, default=S["t_transient"], metavar="T",
                   help=f"integrate the orbit alone this long first (default "
                        f"{_g(S['t_transient'])})")
    s.add_argument("--samples", type=int, default=S["n_samples"],
                   help=f"log-spaced samples of the exponents' convergence (default "
                        f"{S['n_samples']})")
    s.add_argument("--initial-amplitude", type=float, default=None, metavar="A",
                   help="start from mode 1 at amplitude A (default: the paper's, A = 1)")
    s.add_argument("--w-seed", type=int, default=S["seed"],
                   help=f"seed of the random initial deviation vectors (default {S['seed']})")
    s.add_argument("--plot", metavar="FILE", default=None,
                   help="also draw the spectrum against i/(2N) and its convergence (default: no)")
    s.set_defaults(func=cmd_spectrum, resolve=_resolve_spectrum)


def _resolve_spectrum(a):
    _resolve_single_lattice(a)
    if a.method is None:
        a.method = python_defaults()["lyapunov_spectrum"]["method"]
    _finite_positive(a, "t_end")
