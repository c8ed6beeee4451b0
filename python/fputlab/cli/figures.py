"""`fputlab figures`: the paper's figures."""
from __future__ import annotations

import os
import sys

from .._figure import add_output_options
from .parsers import _alias, _sub

#: the figure sets beyond the paper's numbered figures
OPEN_QUESTIONS = "open-questions"


def _figure_key(text: str):
    """--only values: a figure number 1-14 or the name of a set of figures."""
    if text == OPEN_QUESTIONS:
        return text
    try:
        k = int(text)
    except ValueError:
        raise ValueError(f"--only: {text!r} is neither a figure number (1-14) nor "
                         f"{OPEN_QUESTIONS!r}") from None
    if not 1 <= k <= 14:
        raise ValueError(f"--only: there is no figure {k} (the paper's figures are 1-14)")
    return k


def cmd_figures(a):
    from ..figures import figure_output
    with figure_output(a.format, a.dpi):
        return _figures(a)


def _figures(a):
    from ..figures import all_figures
    keys = [_figure_key(k) for k in a.only] if a.only else None
    only = {k for k in keys if isinstance(k, int)} if keys else None
    if a.t_end is not None:     # checked now, not after minutes of Figs. 1-11
        from .._validate import _positive_real
        _positive_real(a.t_end, "--t-end")
    if keys is None or only:
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
    if keys is not None and OPEN_QUESTIONS in keys:
        # the studies of the paper's open questions (docs/open_questions.md): drawn from the
        # stored studies, continued to --t-end when given; --work-dir is theirs unless
        # numbered figures (whose chaos study it then is) are made in the same call
        from ..figures_open import open_questions
        work = a.work_dir if a.work_dir and not only else "studies/open_questions"
        for p in open_questions(a.out_dir, work_dir=work, t_until=a.t_end, workers=a.workers):
            print(p, flush=True)
    return 0


def _parser_figures(sub, parents):
    s = _sub(sub, "figures", "regenerate the paper's figures (PNG, or PDF/SVG for a paper)")
    s.add_argument("--out-dir", default="figures", metavar="DIR",
                   help="output directory (default figures/)")
    _alias(s, "--out", "--out-dir", "out_dir", metavar="DIR")
    s.add_argument("--full", action="store_true",
                   help="the paper's settings, t = 1e8: very long (default: quick settings)")
    s.add_argument("--only", nargs="+", metavar="FIG",
                   help="figure numbers (1-14) to make, or open-questions: the figures of the "
                   "paper's open questions from the studies in --work-dir (default "
                   "studies/open_questions; docs/open_questions.md) (default: figures 1-14)")
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
