"""The two-mode reduction: `fputlab coefficients`, `fputlab tauc`, `fputlab bifurcation`."""
from __future__ import annotations

import numpy as np

from ..io.summary import write_h5, write_summary_h5
from ._common import _emit, _new_file, _output_paths, _positive
from .parsers import DISORDERS, MODELS, _alias, _output_options, _sub

def _coefficient_row(lat) -> dict:
    from ..reduction import two_mode_coefficients
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
    from ..lattice import Lattice
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
        write_h5(a.out, {k: v for k, v in head.items()},
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
    from ..reduction import critical_tolerance
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
        write_summary_h5(a.out, summary)
        summary["out"] = a.out
    _emit(summary, a.json)
    return 0


def cmd_bifurcation(a):
    from ..reduction import REGIONS, ReducedSystem, classify, r1_squared
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
        from ..figures_reduction import fig7
        summary["plot"] = fig7(a.plot, N=a.N)["path"]
    if a.out:
        write_summary_h5(a.out, summary)
        summary["out"] = a.out
    _emit(summary, a.json)
    return 0


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
