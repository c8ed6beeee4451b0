"""The paper's figures 1-3 and 11-14 (figures 4-10, the two-mode reduction, are in
figures_reduction). Every figure function is ``figN(out_dir=".", *, full=False, **options)``:
it writes one PNG into `out_dir` (or to `out_dir` itself if that ends in .png) and returns its
path as a `Figure` (a pathlib.Path that also carries the figure's numbers). `full=True` uses the
paper's settings (t = 1e8 for the chaos figures: days of CPU); the default is quick."""
from __future__ import annotations

import os

import numpy as np

from ._figure import FORMATS, figure_output, sci

__all__ = ["fig1", "fig2", "fig3", "fig11", "fig12", "fig13", "fig14", "fig12_13", "chaos_study",
           "all_figures", "figure_output", "FORMATS", "QUICK_STUDY_T"]


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def fig1(out_dir=".", *, full: bool = False):
    """Fig. 1: FPUT recurrence of the homogeneous chain, N = 64 (envelope of x_j, E_1..E_4).

    Parameters
    ----------
    out_dir : str or path-like, optional
        Directory for ``fig01_recurrence.png`` (or a file name ending in .png).
    full : bool, optional
        The paper's settings (t = 1e5) instead of the quick ones (t = 8e4).

    Returns
    -------
    Figure
        Path of the PNG (``.numbers``: the energy and the best recurrence).
    """
    from ._figure import save, target
    from .demo import run_fig1
    from .plotting import plot_envelope, plot_mode_energies
    plt = _plt()
    run = run_fig1(t_end=1e5 if full else 8e4)
    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 4.2), constrained_layout=True)
    plot_envelope(run, max(1, int(round(200.0 / (run.t[1] - run.t[0])))), ax=a)
    a.set_title("(a) envelope of $x_j(t)$, N = 64, τ = 0")
    plot_mode_energies(run, ax=b, legend="center right")
    b.set_title(f"(b) $E_1, \\dots, E_4$, E = {run.energy[0]:.5f}")
    late = run.t > 1e4
    best = int(np.argmax(np.where(late, run.mode_energies[:, 0], -np.inf)))
    return save(fig, target(out_dir, "fig01_recurrence.png"),
                {"energy": float(run.energy[0]), "recurrence_time": float(run.t[best]),
                 "recurrence_share": float(run.mode_energies[best, 0] / run.energy[0])})


def fig2(out_dir=".", *, full: bool = False, seed: int = 3):
    """Fig. 2: model 3 (variability in the nonlinear couplings), N = 64, tau = 5 % and 10 %:
    recurrences degrade and the energy localises in mode 1 (a q-breather).

    Parameters
    ----------
    out_dir : str or path-like, optional
        Directory for ``fig02_disorder_recurrence.png`` (or a file name ending in .png).
    full : bool, optional
        The paper's settings (t = 1.5e5) instead of the quick ones (t = 8e4).
    seed : int, optional
        Disorder realisation. Seed 3 does not blow up before t = 1.5e5 (seeds 1, 2, 4 and 7
        do at tau = 10 %).

    Returns
    -------
    Figure
        Path of the PNG (``.numbers``: for each tau, whether the run completed and the time
        reached).
    """
    from ._figure import save, target
    from .lattice import Lattice
    from .plotting import plot_envelope, plot_mode_energies
    plt = _plt()
    fig, axes = plt.subplots(2, 2, figsize=(12, 8), constrained_layout=True)
    numbers = {}
    for row, tau in enumerate((5.0, 10.0)):
        lat = Lattice(64, 0.25, "nonlinear", tau=tau, seed=seed)
        run = lat.integrate(1.5e5 if full else 8e4, sample_every=5.0, store_states=True,
                            on_failure="return")
        plot_envelope(run, 40, ax=axes[row, 0])
        note = "" if run.completed else f", blew up at t ≈ {run.t[-1]:.0f}"
        axes[row, 0].set_title(f"({'ac'[row]}) envelope of $x_j(t)$, τ = {tau:g}%, seed {seed}{note}")
        # E_1 dominates the top of the panel once the energy localises: the legend goes
        # where matplotlib finds no curve
        plot_mode_energies(run, ax=axes[row, 1], legend="best")
        axes[row, 1].set_title(f"({'bd'[row]}) $E_1, \\dots, E_4$, τ = {tau:g}%")
        numbers[f"tau={tau:g}"] = {"completed": run.completed, "t_reached": float(run.t[-1])}
    return save(fig, target(out_dir, "fig02_disorder_recurrence.png"), numbers)


def _criterion_mathtext(text: str) -> str:
    """A stopping criterion as the C library describes it ("max |x_{j+1} - x_j| > 4") in
    mathtext, so a title shows formulas rather than markup."""
    text = text.replace("max_k", r"\max_k").replace("max ", r"\max ").replace("energy", r"\mathrm{energy}")
    return "$" + text + "$"


def fig3(out_dir=".", *, full: bool = False, seed: int = 1):
    """Fig. 3: model 3, N = 64, tau = 20 % > tau_c: finite-time blow-up (abrupt growth of
    E_1..E_4); the run stops when a bond passes the cubic barrier (stretch 1/alpha).

    Parameters
    ----------
    out_dir : str or path-like, optional
        Directory for ``fig03_blowup.png`` (or a file name ending in .png).
    full : bool, optional
        Accepted for the common signature; the quick and full settings are the same here.
    seed : int, optional
        Disorder realisation (seed 1 blows up at t = 2545).

    Returns
    -------
    Figure
        Path of the PNG (``.numbers``: the blow-up time and criterion, if any).
    """
    from ._figure import save, target
    from .lattice import Lattice
    from .plotting import plot_mode_energies
    plt = _plt()
    lat = Lattice(64, 0.25, "nonlinear", tau=20.0, seed=seed)
    run = lat.integrate(1e4, sample_every=1.0, stop_on=[("stretch", 4.0)])
    fig, ax = plt.subplots(figsize=(7, 4.2), constrained_layout=True)
    plot_mode_energies(run, ax=ax, log=True, legend="lower right")
    numbers = {"blowup_time": None, "criterion": None}
    if run.event:
        ax.axvline(run.event["time"], color="k", ls="--", lw=0.8)
        ax.set_title(f"τ = 20%, seed {seed}: blow-up at t = {run.event['time']:.1f} "
                     f"({_criterion_mathtext(run.event['criterion'])})")
        numbers = {"blowup_time": run.event["time"], "criterion": run.event["criterion"]}
    ax.set_ylim(1e-8, None)
    return save(fig, target(out_dir, "fig03_blowup.png"), numbers)


def fig11(out_dir=".", *, full: bool = False, t_end: float | None = None):
    """Fig. 11: the homogeneous chain (Eq. Hamilt), N = 4, 8, 16, 32, 64, the paper's mode-1
    initial state: regular orbits (lambda ~ 1/t, SALI bounded away from 0). Tangent-map method
    with Yoshida 4 at dt = 0.01 (the paper's), to t = 1e5 (full: 1e8, CPU-days).

    Parameters
    ----------
    out_dir : path, optional
        Directory of the PNG (fig11_chaos_homogeneous.png), or a .png file name.
    full : bool, optional
        The paper's length t = 1e8.
    t_end : float, optional
        Another final time.

    Returns
    -------
    Figure
        The PNG's path; ``numbers``: {"N": [...], "mle_final": [...], "sali_final": [...]}.
    """
    from ._figure import save, target
    from .chaos import lyapunov
    from .lattice import Lattice
    from .plotting import plot_mle, plot_sali
    t_end = (1e8 if full else 1e5) if t_end is None else float(t_end)
    Ns = (4, 8, 16, 32, 64)
    res = [lyapunov(Lattice(N, 0.25), t_end, n_samples=100) for N in Ns]
    plt = _plt()
    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 4.2), constrained_layout=True)
    labels = [f"N = {N}" for N in Ns]
    plot_mle(res, a, labels=labels)
    plot_sali(res, b, labels=labels, legend=None)
    a.set_title(f"(a) homogeneous chain, Yoshida 4, dt = 0.01, t = {sci(t_end)}", loc="left",
                fontsize=10)
    b.set_title("(b) SALI", loc="left", fontsize=10)
    return save(fig, target(out_dir, "fig11_chaos_homogeneous.png"),
                {"N": list(Ns), "mle_final": [r.mle_final for r in res],
                 "sali_final": [float(r.sali[-1]) for r in res]})


#: how far the chaos study goes for the quick figures 12-14 (--full: the paper's t = 1e8)
QUICK_STUDY_T = 1e5


def chaos_study(work_dir=None, *, full=False, t_until=None, workers=None, scheduler=None,
                progress=True, out_dir="figures", **params):
    """The chaos study behind Figs. 12-14 (fputlab.chaos.study.ChaosStudy: model 3, tau = 10 %,
    30 realisations, N = 4..64, t_end = 1e8), continued in `work_dir` (default
    out_dir/chaos_study) up to t_until (default 1e8 with full, else 1e5). Orbits that already
    reached t_until are not recomputed, so a second call redraws in seconds."""
    from dataclasses import asdict

    from .chaos.study import ChaosStudy, StudySpec
    # every parameter of the paper's study, not only the ones given: a work directory holding
    # a study with other parameters is refused instead of being drawn as Figs. 12-14
    study = ChaosStudy(work_dir if work_dir is not None else os.path.join(out_dir, "chaos_study"),
                       **{**asdict(StudySpec()), **params})
    t_until = (study.spec.t_end if full else min(QUICK_STUDY_T, study.spec.t_end)) \
        if t_until is None else float(t_until)
    if study.reached() < min(t_until, study.spec.t_end):
        study.run(t_until, workers=workers, scheduler=scheduler, progress=progress)
    return study


def _reached_label(study):
    return f"t = {sci(study.reached())}"


#: the sequential palette of the realisations in Figs. 12-13 (dark to light by disorder seed;
#: its light end is cut off, where thin lines would vanish on white)
REALISATION_CMAP = "viridis"


def _study_panels(study, Ns, name, letters, out_dir):
    """Rows of (lambda(t) with the 1/t guide, SALI(t)) for each N: one colour per realisation
    (a sequential palette by disorder seed, with a colour bar), every orbit drawn up to the time
    all of them have reached; an orbit that blew up ends in a marker, one that turned chaotic
    stops at the SALI threshold."""
    import matplotlib as mpl
    from matplotlib.lines import Line2D
    from ._figure import save, target
    from .plotting import plot_mle, plot_sali
    plt = _plt()
    res = study.results()
    fig, axes = plt.subplots(len(Ns), 2, figsize=(11, 3.3 * len(Ns) + 0.6),
                             constrained_layout=True, squeeze=False)
    t_top = study.reached()
    R = study.spec.realisations
    threshold = study.spec.sali_threshold
    seeds = sorted({int((r.params or {}).get("seed", i + 1)) for N in Ns
                    for i, r in enumerate(res[N]) if r is not None} or {1})
    norm = mpl.colors.Normalize(vmin=min(seeds), vmax=max(max(seeds), min(seeds) + 1))
    cmap = plt.get_cmap(REALISATION_CMAP)

    def color(seed):
        return cmap(0.9 * norm(seed))

    numbers = {"t": t_top}
    sali_lo = threshold
    for row, N in enumerate(Ns):
        a, b = axes[row]
        shown, colors, ends = [], [], []
        for i, r in enumerate(res[N]):
            if r is None or not r.t.size:
                continue
            k = r.t <= t_top * (1 + 1e-12)      # orbits ahead of the others: up to the same t
            if not k.any():
                continue
            c = color(int((r.params or {}).get("seed", i + 1)))
            shown.append({"t": r.t[k], "mle": r.mle[k], "sali": np.maximum(r.sali[k], 1e-17)})
            colors.append(c)
            if r.blew_up and r.t[k][-1] >= r.t[-1]:
                ends.append((r.t[k][-1], abs(r.mle[k][-1]), r.sali[k][-1], c))
            sali_lo = min(sali_lo, float(np.min(shown[-1]["sali"])))
        plot_mle(shown, a, colors=colors, lw=0.7, legend=None)
        plot_sali(shown, b, colors=colors, lw=0.7, threshold=threshold, legend=None)
        for t_end, mle, sali, c in ends:
            a.plot(t_end, mle, "X", ms=7, mfc=c, mec="k", mew=0.6, zorder=5)
            b.plot(t_end, sali, "X", ms=7, mfc=c, mec="k", mew=0.6, zorder=5)
        counts = study.classes(t_top)[N]
        numbers[f"N{N}"] = counts
        summary = ", ".join(f"{v} {k}" for k, v in counts.items() if v)
        a.set_title(f"({letters[2 * row]}) N = {N}: at t = {sci(t_top)}, {summary}",
                    fontsize=10, loc="left")
        b.set_title(f"({letters[2 * row + 1]}) N = {N}", fontsize=10, loc="left")
        handles = [Line2D([], [], color="k", ls="--", lw=1.0, label="$1/t$ (regular orbits)")]
        if ends:
            handles.append(Line2D([], [], ls="none", marker="X", ms=7, mfc="0.6", mec="k",
                                  label=f"blow-up: the orbit ends ({len(ends)})"))
        a.legend(handles=handles, loc="lower left", frameon=False, fontsize=8)
        b.legend(handles=[Line2D([], [], color="gray", ls=":", lw=0.8,
                                 label=f"chaos threshold SALI = {sci(threshold)}")]
                 + handles[1:], loc="lower left", frameon=False, fontsize=8)
    for a, b in axes:
        # the SALI axis fits the data: chaotic orbits stop just below the threshold
        b.set_ylim(sali_lo / 5.0, 3.0)
    fig.colorbar(mpl.cm.ScalarMappable(norm=norm, cmap=mpl.colors.ListedColormap(
                     cmap(np.linspace(0, 0.9, 256)))), ax=axes, location="right", shrink=0.8,
                 label="disorder seed (realisation)")
    s = study.spec
    fig.suptitle(f"Disordered chain (nonlinear couplings), τ = {s.tau:g} %, {R} realisations, "
                 f"{s.method} at dt = {s.dt:g}, {_reached_label(study)}")
    return save(fig, target(out_dir, name), numbers)


def fig12(out_dir=".", *, full: bool = False, study=None, **study_options):
    """Fig. 12: model 3 (Eq. varnonlin), tau = 10 %, 30 realisations: lambda(t) with the 1/t
    guide and SALI(t) for N = 4 (a, b), 8 (c, d), 16 (e, f), drawn from the resumable chaos
    study (`chaos_study`; `study_options` go to it, `study` reuses one).

    Returns
    -------
    Figure
        The PNG's path; ``numbers``: the time reached and the class counts per N.
    """
    study = study or chaos_study(full=full, out_dir=out_dir, **study_options)
    return _study_panels(study, [N for N in (4, 8, 16) if N in study.spec.Ns],
                         "fig12_chaos_N4_8_16.png", "abcdef", out_dir)


def fig13(out_dir=".", *, full: bool = False, study=None, **study_options):
    """Fig. 13: as Fig. 12 for N = 32 (a, b) and 64 (c, d)."""
    study = study or chaos_study(full=full, out_dir=out_dir, **study_options)
    return _study_panels(study, [N for N in (32, 64) if N in study.spec.Ns],
                         "fig13_chaos_N32_64.png", "abcd", out_dir)


def fig14(out_dir=".", *, full: bool = False, study=None, **study_options):
    """Fig. 14: percentage of chaotic orbits (SALI < 1e-8 on a finite orbit) among the
    realisations versus N, with the percentage that blew up (never counted as chaotic), at the
    time every orbit has reached, with Wilson 95 % intervals (the paper draws none).

    Returns
    -------
    Figure
        The PNG's path; ``numbers``: {"t", "N", "percent_chaotic", "percent_blowup",
        their Wilson 95 % intervals "percent_chaotic_interval", "percent_blowup_interval"
        ([low, high] per N), "classes"}.
    """
    from ._figure import save, target
    study = study or chaos_study(full=full, out_dir=out_dir, **study_options)
    plt = _plt()
    t = study.reached()
    counts = study.classes(t)
    Ns = sorted(counts)
    R = study.spec.realisations
    from .engine import wilson_interval
    fig, ax = plt.subplots(figsize=(6.4, 4.2), constrained_layout=True)
    pct = lambda k: [100.0 * counts[N][k] / R for N in Ns]
    # the paper's figure has no error bars: Wilson 95 % intervals of each binomial proportion
    # (R realisations per N), as the open-questions figures draw them
    wilson = lambda k: np.array([wilson_interval(counts[N][k], R) for N in Ns]) * 100.0
    for key, fmt, colour, label in (("chaotic", "o-", "k", "chaotic"),
                                    ("blow-up", "s--", "tab:red", "blew up (not chaos)")):
        lo_hi = wilson(key)
        y = np.array(pct(key))
        ax.errorbar(Ns, y, yerr=np.clip([y - lo_hi[:, 0], lo_hi[:, 1] - y], 0, None), fmt=fmt, color=colour,
                    capsize=3, lw=1.2, label=label)
    if any(counts[N]["not reached"] for N in Ns):
        ax.plot(Ns, pct("not reached"), "x:", color="gray", label="not yet at t")
    ax.set_xscale("log", base=2)
    ax.set_xticks(Ns, [str(N) for N in Ns])
    ax.set_ylim(-4, 104)
    ax.set_xlabel("N")
    ax.set_ylabel(f"% of {R} realisations (Wilson 95 % intervals)")
    ax.legend(frameon=False)
    ax.set_title(f"Disordered chain (nonlinear couplings), τ = {study.spec.tau:g} %, "
                 f"{_reached_label(study)}", fontsize=10)
    return save(fig, target(out_dir, "fig14_chaotic_fraction.png"),
                {"t": t, "N": Ns, "percent_chaotic": pct("chaotic"),
                 "percent_chaotic_interval": wilson("chaotic").tolist(),
                 "percent_blowup": pct("blow-up"),
                 "percent_blowup_interval": wilson("blow-up").tolist(), "classes": counts})


def fig12_13(out_dir=".", *, full: bool = False, **study_options):
    """Figs. 12, 13 and 14 from one chaos study (see `chaos_study`)."""
    study = chaos_study(full=full, out_dir=out_dir, **study_options)
    return [fig12(out_dir, study=study), fig13(out_dir, study=study),
            fig14(out_dir, study=study)]


def all_figures(out_dir="figures", full=False, only=None, report=None, **study_kwargs):
    """Regenerate every figure (1-14); `only` is an optional set of figure numbers;
    study_kwargs (work_dir, t_until, workers, scheduler) go to `chaos_study` (Figs. 12-14).
    Figs. 1-11 are called as ``figN(out_dir, full=full)``. `report(k, path)`, if given, is
    called before figure k (path None) and after it (its path): progress, since some figures
    take minutes."""
    paths = []
    want = lambda k: only is None or k in only

    def make(k, fn, *args, **kw):
        if report is not None:
            report(k, None)
        paths.append(fn(*args, **kw))
        if report is not None:
            report(k, paths[-1])

    for k, fn in ((1, fig1), (2, fig2), (3, fig3), (11, fig11)):
        if want(k):
            make(k, fn, out_dir, full=full)
    if want(12) or want(13) or want(14):
        study = chaos_study(full=full, out_dir=out_dir, **study_kwargs)
        for k, fn in ((12, fig12), (13, fig13), (14, fig14)):
            if want(k):
                make(k, fn, out_dir, study=study)
    from .figures_reduction import FIGURES
    for k in range(4, 11):
        if want(k):
            make(k, FIGURES[k], out_dir, full=full)
    return paths
