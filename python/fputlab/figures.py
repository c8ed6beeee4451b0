"""The paper's figures 1-3 and 11-14 (figures 4-10, the two-mode reduction, are in
figures_reduction). Every figure function is ``figN(out_dir=".", *, full=False, **options)``:
it writes one PNG into `out_dir` (or to `out_dir` itself if that ends in .png) and returns its
path as a `Figure` (a pathlib.Path that also carries the figure's numbers). `full=True` uses the
paper's settings (t = 1e8 for the chaos figures: days of CPU); the default is quick."""
from __future__ import annotations

import os

import numpy as np


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def _save(fig, out_dir, name):
    os.makedirs(out_dir, exist_ok=True)
    path = os.path.join(out_dir, name)
    fig.savefig(path, dpi=110)
    _plt().close(fig)
    return path


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


def _chaos_panels(results, title, out_dir, name, t_end):
    plt = _plt()
    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 4.2), constrained_layout=True)
    for label, res in results:
        a.loglog(res.t, np.abs(res.mle), lw=0.8, label=label)
        b.loglog(res.t, res.sali, lw=0.8, label=label)
    tt = np.logspace(0, np.log10(t_end), 50)
    a.loglog(tt, 1.0 / tt, "k--", lw=1, label="1/t")
    a.set_xlabel("$t$"); a.set_ylabel("mLE $\\lambda(t)$")
    b.set_xlabel("$t$"); b.set_ylabel("SALI")
    b.axhline(1e-8, color="gray", lw=0.6, ls=":")
    if len(results) <= 8:
        a.legend(frameon=False, fontsize=8)
    a.set_title(title)
    return _save(fig, out_dir, name)


def fig11(out_dir=".", full=False):
    """Fig. 11: homogeneous chain, N = 4..64, paper initial state: regular (lambda ~ 1/t, SALI
    bounded away from 0). Tangent-map method with Yoshida 4, dt = 0.01."""
    from .chaos import lyapunov
    from .lattice import Lattice
    t_end = 1e8 if full else 1e5
    res = [(f"N = {N}", lyapunov(Lattice(N, 0.25), t_end, n_samples=100)) for N in (4, 8, 16, 32, 64)]
    return _chaos_panels(res, f"homogeneous, t = {t_end:g}", out_dir, "fig11_chaos_homogeneous.png", t_end)


def _ensemble(Ns, full, realisations, t_end, method):
    from .chaos import chaotic_fraction
    t_end = 1e8 if full else t_end
    return chaotic_fraction(Ns=Ns, realisations=realisations, tau=10.0, t_end=t_end, method=method,
                            n_samples=100, progress=True), t_end


def fig12_13(out_dir=".", full=False, realisations=30, t_end=2e4, method="yoshida4"):
    """Figs. 12-13: model 3, tau = 10 %, 30 realisations for N = 4, 8, 16 (Fig. 12) and 32, 64
    (Fig. 13): lambda(t) and SALI(t). The paper used DOP853 to t = 1e8 (method="dop853", full=True)."""
    out, t_end = _ensemble((4, 8, 16, 32, 64), full, realisations, t_end, method)
    paths = []
    for N in out["N"]:
        res = [(f"seed {r.params['seed']}", r) for r in out["results"][N]]
        name = f"fig{12 if N <= 16 else 13}_chaos_N{N}.png"
        paths.append(_chaos_panels(res, f"model 3, τ = 10%, N = {N}, t = {t_end:g}", out_dir, name, t_end))
    paths.append(_fig14_from(out, out_dir, t_end))
    return paths


def _fig14_from(out, out_dir, t_end):
    plt = _plt()
    fig, ax = plt.subplots(figsize=(6, 4), constrained_layout=True)
    ax.plot(out["N"], out["percent"], "ko--")
    ax.set_xscale("log", base=2)
    ax.set_xlabel("$N$")
    ax.set_ylabel("chaotic orbits (%)")
    R = len(next(iter(out["results"].values())))
    blown = ", ".join(f"N={N}: {b}" for N, b in zip(out["N"], out["blowups"]) if b)
    ax.set_title(f"τ = 10%, {R} realisations, t = {t_end:g}" + (f"\nblew up first: {blown}" if blown else ""))
    return _save(fig, out_dir, "fig14_chaotic_fraction.png")


def fig14(out_dir=".", full=False, realisations=30, t_end=2e4, method="yoshida4"):
    """Fig. 14: percentage of chaotic orbits (SALI < 1e-8) among realisations versus N."""
    out, t_end = _ensemble((4, 8, 16, 32, 64), full, realisations, t_end, method)
    return _fig14_from(out, out_dir, t_end)


def all_figures(out_dir="figures", full=False, only=None):
    """Regenerate every figure (1-14); `only` is an optional set of figure numbers. Every
    figure function is called as ``figN(out_dir, full=full)``."""
    paths = []
    want = lambda k: only is None or k in only
    for k, fn in ((1, fig1), (2, fig2), (3, fig3), (11, fig11)):
        if want(k):
            paths.append(fn(out_dir, full=full))
    if want(12) or want(13) or want(14):
        paths += fig12_13(out_dir, full=full)
    from .figures_reduction import FIGURES
    for k in range(4, 11):
        if want(k):
            paths.append(FIGURES[k](out_dir, full=full))
    return paths
