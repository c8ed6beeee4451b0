"""`fputlab thermalization`: run a thermalization study (on the study engine) in bounded,
resumable pieces and report T_eq(eps) with its fitted exponent (a module of its own so that the
CLI only registers it)."""
from __future__ import annotations

import math
import os
from dataclasses import replace


def add_parser(sub, formatter_class) -> None:
    from ..thermalization_study import STUDIES
    s = sub.add_parser(
        "thermalization", formatter_class=formatter_class,
        help="equipartition times T_eq(eps) of random-phase ensembles (resumable study)",
        description="Runs a built-in thermalization study in WORK_DIR (one engine study per "
        "eps and block of orbits, t_end doubling until the ensemble eta crosses the threshold; "
        "rerun to continue) and prints T_eq for every eps with its bootstrap interval and the "
        "fitted exponent. See docs/thermalization.md.")
    s.add_argument("study", choices=sorted(STUDIES), help="the built-in study (required, no default)")
    s.add_argument("--work-dir", required=True, metavar="DIR",
                   help="study directory (created; continued when it holds the same study; "
                   "required, no default)")
    s.add_argument("--eps", type=float, nargs="+", help="eps values (default: the study's)")
    s.add_argument("--orbits", type=int, help="orbits in the ensemble, a multiple of the "
                   "study's block of 16 (4 for tiny); a stored study may grow (default: the "
                   "study's)")
    s.add_argument("--only-eps", type=float, nargs="+", metavar="EPS",
                   help="run only these eps of the study (e.g. more orbits where they are "
                   "cheap; default: every eps)")
    s.add_argument("--N", type=int, help="number of particles (default: the study's)")
    s.add_argument("--t-end", type=float, help="longest time t_max of every point (default: the "
                   "study's)")
    s.add_argument("--t-until", type=float, help="stop this piece once every point reached "
                   "this time (default: t_max)")
    s.add_argument("--max-seconds", type=float, help="stop this piece after about this much "
                   "wall time (default: none)")
    s.add_argument("--fit-range", type=float, nargs=2, action="append", metavar=("LO", "HI"),
                   help="also fit T_eq ~ eps^-a over LO <= eps <= HI; repeatable (default: the "
                   "study's ranges, beta: 0-0.07 and 0.1-0.5)")
    s.add_argument("--workers", type=int, default=1, help="local worker processes (default 1)")
    s.add_argument("--figure", metavar="PNG", help="write the T_eq(eps) figure to this file")
    s.add_argument("--overwrite", action="store_true", help="allow --figure to replace a file")
    s.add_argument("--report-only", action="store_true",
                   help="integrate nothing: report what WORK_DIR holds")
    s.set_defaults(func=cmd_thermalization)


def _spec(a):
    from ..thermalization_study import STUDIES, check_spec
    spec = STUDIES[a.study]
    over = {k: getattr(a, k) for k in ("orbits", "N") if getattr(a, k) is not None}
    if a.t_end is not None:
        over["t_max"] = a.t_end
    if a.eps is not None:
        over["eps"] = tuple(a.eps)
    return check_spec(replace(spec, **over))


def _fmt(x):
    return "-" if not math.isfinite(x) else f"{x:.3g}"


def cmd_thermalization(a) -> int:
    from ..thermalization_study import ThermalizationStudy
    if a.figure and os.path.exists(a.figure) and not a.overwrite:
        raise FileExistsError(f"--figure: {a.figure!r} exists; not overwritten (pass "
                              "--overwrite to replace it)")
    if a.work_dir and os.path.exists(a.work_dir) and not os.path.isdir(a.work_dir):
        raise ValueError(f"--work-dir: {a.work_dir!r} exists and is not a directory")
    for name in ("t_until", "max_seconds"):
        v = getattr(a, name)
        if v is not None and not (math.isfinite(v) and v > 0):
            raise ValueError(f"--{name.replace('_', '-')} must be finite and > 0 (got {v:g})")
    spec = _spec(a)
    points = None
    if a.only_eps is not None:
        missing = [e for e in a.only_eps if e not in spec.eps]
        if missing:
            raise ValueError(f"--only-eps: {missing} not among the study's eps "
                             f"{list(spec.eps)}")
        points = [spec.eps.index(e) for e in a.only_eps]
    study = ThermalizationStudy(a.work_dir, spec)
    complete = None
    if not a.report_only:
        complete = study.run(t_until=a.t_until, max_seconds=a.max_seconds, workers=a.workers,
                             points=points)
    res = study.results(fit_ranges=a.fit_range)
    sp = res["spec"]
    print(f"# {sp['label']}: model {sp['model']}, {sp['boundary']} N = {sp['N']}, "
          f"alpha = {sp['alpha']:g}, beta = {sp['beta']:g}, tau = {sp['tau']:g} %, band "
          f"{list(sp['band'])}, up to {sp['orbits']} orbits, {sp['method']} dt = {sp['dt']:g}, "
          f"eta threshold {sp['threshold']:g}")
    print(f"{'eps':>7} {'E':>9} {'orbits':>6} {'T_eq':>9} {'90% interval':>21} "
          f"{'t reached':>10} {'eta(t)':>7} {'|dE/E|':>8} {'CPU s':>8} {'lost':>4} fitted")
    for p in res["points"]:
        lo, hi = p["interval"]
        print(f"{p['eps']:7.4g} {p['E']:9.4g} {p['orbits']:6d} {_fmt(p['t_eq']):>9} "
              f"{'[' + _fmt(lo) + ', ' + _fmt(hi) + ']':>21} {_fmt(p['t_reached']):>10} "
              f"{_fmt(p['eta_last']):>7} {_fmt(p['energy_error']):>8} {p['cpu']:8.1f} "
              f"{p['failed']:>4} {'yes' if p['resolved'] else 'no'}")
    fit = res["fit"]
    print(f"(fitted: T_eq >= {res['min_windows']:g} averaging windows of {res['window']:.3g}, "
          "so eta(t) resolves the crossing)")
    if fit is None:
        print("fit: fewer than 2 points have crossed the threshold late enough to be resolved")
    else:
        lo, hi = fit["interval"]
        print(f"fit: T_eq ~ eps^-a, a = {fit['exponent']:.3f}, 90% interval "
              f"[{_fmt(lo)}, {_fmt(hi)}] over {fit['points']} points")
    print("(orbits: those with samples that did not fail; lost: orbits that crossed the alpha "
          "barrier and left the ensemble; |dE/E|: the largest relative energy error of the "
          "kept orbits; CPU (process) seconds summed over the point's orbits, wall seconds "
          "where migrated files did not record CPU)")
    for f in res["range_fits"]:
        lo, hi = f["interval"]
        print(f"fit over {f['range'][0]:g} <= eps <= {f['range'][1]:g}: a = {f['exponent']:.3f}, "
              f"90% interval [{_fmt(lo)}, {_fmt(hi)}] over {f['points']} points")
    if complete is False:
        print("(stopped early: rerun the same command to continue)")
    if a.figure:
        from ..figures_thermalization import thermalization_figure
        thermalization_figure([res], a.figure)
        print(f"wrote {a.figure}")
    return 0
