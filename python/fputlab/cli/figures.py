"""`fputlab figures`: the paper's figures."""
from __future__ import annotations

from .._figure import add_output_options
from .parsers import _alias, _sub


def cmd_figures(a):
    from ..figures import all_figures, figure_output
    only = set(a.only) if a.only else None
    unknown = sorted(k for k in (only or ()) if not 1 <= k <= 14)
    if unknown:
        raise ValueError(f"--only: there is no figure {', '.join(map(str, unknown))} (the paper's "
                         "figures are 1-14)")
    study = {"work_dir": a.work_dir, "t_until": a.t_end, "workers": a.workers,
             "scheduler": a.scheduler}
    with figure_output(a.format, a.dpi):
        for p in all_figures(a.out_dir, full=a.full, only=only, **study):
            print(p)
    return 0


def _parser_figures(sub, parents):
    s = _sub(sub, "figures", "regenerate the paper's figures (PNG, or PDF/SVG for a paper)")
    s.add_argument("--out-dir", default="figures", metavar="DIR",
                   help="output directory (default figures/)")
    _alias(s, "--out", "--out-dir", "out_dir", metavar="DIR")
    s.add_argument("--full", action="store_true",
                   help="the paper's settings, t = 1e8: very long (default: quick settings)")
    s.add_argument("--only", type=int, nargs="+", help="figure numbers to make (default: all)")
    add_output_options(s)
    s.add_argument("--work-dir", help="chaos study of Figs. 12-14: one state file per orbit, "
                   "resumed by the next call (default OUT_DIR/chaos_study)")
    s.add_argument("--t-end", type=float, metavar="T", help="how far the chaos study goes in this call "
                   "(default 1e5, with --full 1e8); rerun with a larger value to continue")
    s.add_argument("--workers", type=int, help="local processes for the chaos study "
                   "(default: all cores)")
    s.add_argument("--scheduler", help="Dask scheduler address tcp://host:port for the chaos "
                   "study, the work directory must be shared (default: local processes)")
    s.set_defaults(func=cmd_figures)
