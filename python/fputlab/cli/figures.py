"""`fputlab figures`: the paper's figures."""
from __future__ import annotations

import os
import sys

from .parsers import _alias, _sub

def cmd_figures(a):
    from ..figures import all_figures
    only = set(a.only) if a.only else None
    unknown = sorted(k for k in (only or ()) if not 1 <= k <= 14)
    if unknown:
        raise ValueError(f"--only: there is no figure {', '.join(map(str, unknown))} (the paper's "
                         "figures are 1-14)")
    if a.t_end is not None:     # checked now, not after minutes of Figs. 1-11
        from .._validate import _positive_real
        _positive_real(a.t_end, "--t-end")
    if a.work_dir and os.path.exists(os.path.join(a.work_dir, "study.json")) and \
            (only is None or only & {12, 13, 14}):
        # a study with other parameters is refused now, not after Figs. 1-11
        from dataclasses import asdict

        from ..chaos.study import ChaosStudy, StudySpec
        ChaosStudy(a.work_dir, **asdict(StudySpec()))
    study = {"work_dir": a.work_dir, "t_until": a.t_end, "workers": a.workers,
             "scheduler": a.scheduler}
    total = len(only) if only else 14
    done = []

    def report(k, path):
        # what is being made now (stderr; some figures take minutes), each file when written
        if path is None:
            print(f"fputlab: figure {k} ({len(done) + 1}/{total}) ...", file=sys.stderr,
                  flush=True)
        else:
            done.append(path)
            print(path, flush=True)

    all_figures(a.out_dir, full=a.full, only=only, report=report, **study)
    return 0


def _parser_figures(sub, parents):
    s = _sub(sub, "figures", "regenerate the paper's figures as PNGs")
    s.add_argument("--out-dir", default="figures", metavar="DIR",
                   help="output directory (default figures/)")
    _alias(s, "--out", "--out-dir", "out_dir", metavar="DIR")
    s.add_argument("--full", action="store_true",
                   help="the paper's settings, t = 1e8: very long (default: quick settings)")
    s.add_argument("--only", type=int, nargs="+", help="figure numbers to make (default: all)")
    s.add_argument("--work-dir", help="chaos study of Figs. 12-14: one state file per orbit, "
                   "resumed by the next call (default OUT_DIR/chaos_study)")
    s.add_argument("--t-end", type=float, metavar="T", help="how far the chaos study goes in this call "
                   "(default 1e5, with --full 1e8); rerun with a larger value to continue")
    s.add_argument("--workers", type=int, help="local processes for the chaos study "
                   "(default: all cores)")
    s.add_argument("--scheduler", help="Dask scheduler address tcp://host:port for the chaos "
                   "study, the work directory must be shared (default: local processes)")
    s.set_defaults(func=cmd_figures)
