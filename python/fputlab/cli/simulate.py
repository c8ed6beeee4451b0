"""`fputlab simulate`: integrate one lattice."""
from __future__ import annotations

from ._common import (_checkpoint_kwargs, _emit, _g, _integrator_kwargs, _lattice, _output_paths,
                      _run_summary)
from .parsers import (_checkpoint_options, _fill, _finite_positive, _integrator_options,
                      _lattice_options, _output_options, _resolve_single_lattice, _sub,
                      _time_options, python_defaults)

def cmd_simulate(a):
    if a.checkpoint and not a.out:
        raise ValueError("--checkpoint needs --out (the results file it belongs to)")
    _output_paths(a, "out", "checkpoint")
    lat = _lattice(a)
    _warn_undersampled(a, lat)
    if a.out:
        # long runs: the C core writes the samples as it goes, with checkpoints and restart
        from ..io import simulate_to_file
        s = simulate_to_file(lat, a.t_end, a.out, method=a.method, sample_every=a.sample_every,
                             store_states=a.states, overwrite=a.overwrite,
                             **_integrator_kwargs(a), **_checkpoint_kwargs(a))
        summary = {"lattice": repr(lat), "method": a.method, "t_end": a.t_end,
                   **_run_summary(s), "checkpoint": a.checkpoint}
        if lat.model != "nonlinear" and s.samples:     # model 3 conserves no energy
            import h5py
            import numpy as np
            with h5py.File(a.out, "r") as f:
                e = f["energy"][...]
            summary["max_relative_energy_error"] = (float(np.max(np.abs(e - e[0]))) /
                                                    abs(e[0]) if e[0] else None)
        _emit(summary, a.json)
        return {"completed": 0, "event": 0, "interrupted": 130}.get(s.status, 1)
    from .._errors import Interrupted
    try:
        run = lat.integrate(a.t_end, method=a.method, sample_every=a.sample_every,
                            store_states=a.states, on_failure="return", progress=not a.json,
                            **_integrator_kwargs(a))
    except Interrupted as err:          # Ctrl-C: the summary of what was computed, exit 130
        run = err.result
    summary = {"lattice": repr(lat), "method": a.method, "t_end": a.t_end,
               "t_reached": float(run.t[-1]) if run.t.size else 0.0,
               "samples": int(run.t.size),
               "sample_every": float(run.t[1] - run.t[0]) if run.t.size > 1 else None,
               "completed": run.completed, "message": run.message,
               "steps": run.counters.get("steps"), "force_evals": run.counters.get("force_evals")}
    if lat.model != "nonlinear":        # model 3 (Eq. varnonlin) conserves no energy
        summary["max_relative_energy_error"] = (float(run.relative_energy_error.max())
                                                if run.t.size else None)
    _emit(summary, a.json)
    if run.message.startswith("interrupted"):
        return 130
    return 0 if run.completed else 1


def _warn_undersampled(a, lat):
    """The default spacing t_end/1000 passes the slowest oscillation of the chain, the period
    2 pi/omega_1 of mode 1, once t_end is long (N = 64: t_end > 1.3e5): the sampled mode
    energies then alias the energy exchange and the recurrences. Said, not silently done."""
    import math
    import sys
    if a.sample_every is not None:
        return
    k1 = math.pi / lat.N if lat.boundary == "periodic" else math.pi / (2 * (lat.N + 1))
    period = 2 * math.pi / (2 * math.sin(k1))
    every = a.t_end / 1000
    if every > period:
        print(f"fputlab: warning: samples every {every:.4g} (t_end/1000) are longer than the "
              f"period 2 pi/omega_1 = {period:.4g} of mode 1: the mode energies are undersampled "
              "and alias the energy exchange; give --sample-every (e.g. "
              f"{_g(float(f'{period / 10:.1g}'))})", file=sys.stderr)


def _parser_simulate(sub, parents):
    L, I = python_defaults()["Lattice"], python_defaults()["integrate"]
    s = _sub(sub, "simulate", "integrate one lattice, sample mode energies",
             description="Integrate one lattice. Without options it is fputlab.Lattice(): the "
             "homogeneous chain, N = 64, alpha = 0.25, no disorder.",
             parents=[_lattice_options(
                 N=f"particles (default {L['N']})",
                 model=f"lattice model (default {L['model']}, as fputlab.Lattice())",
                 tau=f"variability in percent (default {_g(L['tau'])}: no disorder; give it with "
                     "--model hamiltonian or nonlinear)", single=True),
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


def _resolve_simulate(a):
    _resolve_single_lattice(a)
    _fill(a, method=python_defaults()["integrate"]["method"])
    _finite_positive(a, "t_end")
