"""Plots of what fputlab computes (matplotlib; nothing here opens a window or picks a backend).

Every function but `plot_blowup_sweep_figure` (a whole figure) draws into `ax` (a new figure's
Axes when None) and returns that Axes, so plots compose:
``ax = plot_mle(results); plot_mle(other, ax=ax, colors="k")``. The paper's figures
(`fputlab.figures`, `fputlab.figures_reduction`) are made with these functions.

=========================  =========================================================================
function                   plots
=========================  =========================================================================
plot_mode_energies         E_k(t) of a run (Figs. 1b, 2b/d, 3)
plot_envelope              top view of the oscillation envelope max|x_j| (Figs. 1a, 2a/c)
plot_mle                   finite-time mLE lambda(t) with the 1/t guide of regular orbits (Figs. 11-13)
plot_sali                  SALI(t) with the chaos threshold (Figs. 11-13)
plot_two_mode              Q_1, Q_2 of the two-mode system with the envelope equations (Fig. 6)
plot_blowup_sweep          probability of blow-up versus tau, or the blow-up times
plot_blowup_sweep_figure   both panels of a blow-up sweep in one figure, optionally a PNG
plot_bifurcation           regions of the (A~, B~) plane by their equilibria, and the curves (Fig. 7)
plot_spectrum              Lyapunov spectrum lambda_i against i/(2N) (the thermodynamic-limit shape)
plot_spectrum_convergence  lambda_i(t) of a spectrum run: convergence of the exponents in time
plot_megno                 MEGNO <Y>(t) with the quasi-periodic limit 2
plot_clv_localisation      localisation of covariant Lyapunov vectors: 1/IPR against i/(2N)
=========================  =========================================================================
"""
from __future__ import annotations

from collections.abc import Sequence

import numpy as np

__all__ = ["mode_color", "LOG_ENERGY_DECADES", "plot_mode_energies", "envelope", "plot_envelope",
           "plot_mle", "plot_sali", "plot_two_mode", "plot_blowup_sweep", "plot_blowup_sweep_figure",
           "plot_bifurcation_curves", "plot_bifurcation", "BIFURCATION_REGIONS", "plot_spectrum",
           "plot_spectrum_convergence", "plot_megno", "plot_clv_localisation"]


def mode_color(k: int) -> str:
    """The colour of normal mode `k` (1-based) in every fputlab plot: E_k, Q_k and P_k of mode
    k are drawn in matplotlib's k-th cycle colour ("C0" for mode 1, "C1" for mode 2, ...), so a
    mode keeps its colour from figure to figure.

    Parameters
    ----------
    k : int
        Mode number, >= 1.

    Returns
    -------
    str
        A matplotlib colour ("C0" ... "C9", repeating after mode 10).
    """
    if isinstance(k, bool) or not isinstance(k, (int, np.integer)):
        raise TypeError(f"k must be an integer mode number, got {type(k).__name__}")
    if k < 1:
        raise ValueError(f"k must be >= 1 (got {k})")
    return f"C{(int(k) - 1) % 10}"


#: the lowest decade a logarithmic energy axis shows, relative to its largest value: below it
#: lies only round-off (mode energies that start at exactly 0 sit near 1e-32)
LOG_ENERGY_DECADES = 12


def _axes(ax, figsize=(6, 4)):
    if ax is not None:
        return ax
    import matplotlib.pyplot as plt
    return plt.subplots(figsize=figsize, constrained_layout=True)[1]


def _as_list(results) -> list:
    """One result (anything with a `t` attribute) or a sequence of them, as a list."""
    if hasattr(results, "t"):
        return [results]
    if isinstance(results, dict) and "t" in results:
        return [results]
    out = list(results)
    if not out:
        raise ValueError("results: nothing to plot (empty sequence)")
    return out


def _get(result, name):
    value = result[name] if isinstance(result, dict) else getattr(result, name)
    return np.asarray(value, dtype=float)


def _per_result(value, n: int, name: str) -> list:
    """A single value (or None) for every result, or one value per result."""
    if value is None or isinstance(value, str) or not isinstance(value, Sequence):
        return [value] * n
    value = list(value)
    if len(value) != n:
        raise ValueError(f"{name}: {len(value)} values for {n} results")
    return value


def _labels_colors(labels, colors, n: int) -> tuple[list, list]:
    """Per-result labels (one string labels the first result only) and colours."""
    labels = [labels] + [None] * (n - 1) if isinstance(labels, str) else \
        _per_result(labels, n, "labels")
    return labels, _per_result(colors, n, "colors")


def plot_mode_energies(run, modes=(1, 2, 3, 4), ax=None, relative: bool = False, *,
                       log: bool = False, legend: str | None = "best"):
    """Normal-mode energies E_k(t) of a run (paper Figs. 1b, 2b/d, 3).

    Parameters
    ----------
    run : Run
        A result of `fputlab.integrate` (needs ``t``, ``mode_energies``, ``energy``).
    modes : sequence of int, optional
        Mode numbers k (1-based) to draw; default the first four.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure when None.
    relative : bool, optional
        Divide by the initial total energy E(0).
    log : bool, optional
        Logarithmic energy axis (useful for blow-ups, Fig. 3).
    legend : str or None, optional
        Legend location (matplotlib ``loc``; "best" avoids the curves), None for no legend.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = _axes(ax)
    N = run.mode_energies.shape[1]
    for k in modes:
        if not 1 <= int(k) <= N:
            raise ValueError(f"modes: mode {k} is outside 1..{N}")
    scale = run.energy[0] if relative else 1.0
    draw = ax.semilogy if log else ax.plot
    shown = []
    for k in modes:
        values = run.mode_energies[:, k - 1] / scale
        shown.append(values)
        draw(run.t, values, lw=0.9, color=mode_color(int(k)), label=f"$E_{{{k}}}$")
    if log:
        # floor the axis LOG_ENERGY_DECADES below the largest value drawn: what lies lower is
        # round-off and would squeeze the dynamics into the top of the panel
        finite = np.concatenate([v[np.isfinite(v) & (v > 0)] for v in shown] or [np.zeros(0)])
        if finite.size:
            top = finite.max()
            ax.set_ylim(max(finite.min(), top * 10.0 ** -LOG_ENERGY_DECADES) / 2, top * 3)
    ax.set_xlabel("$t$")
    ax.set_ylabel("$E_k/E$" if relative else "$E_k$")
    if legend is not None:
        ax.legend(loc=legend, frameon=False)
    return ax


def envelope(run, window: int) -> tuple[np.ndarray, np.ndarray]:
    """Running maximum of ``|x_j|`` over blocks of samples.

    Parameters
    ----------
    run : Run
        A run integrated with ``store_states=True``.
    window : int
        Samples per block.

    Returns
    -------
    t : numpy.ndarray
        Mid-time of each block, shape (B,).
    env : numpy.ndarray
        max ``|x_j|`` over each block, shape (B, N).
    """
    if run.states is None:
        raise ValueError("run has no states: integrate with store_states=True")
    N = run.lattice.N
    x = np.abs(run.states[:, :N] if run.states.ndim == 2 else run.states[:, 0, :N])
    B = x.shape[0] // window
    if B == 0:
        raise ValueError(f"window {window} is longer than the run ({x.shape[0]} samples)")
    env = x[: B * window].reshape(B, window, N).max(axis=1)
    t = run.t[: B * window].reshape(B, window).mean(axis=1)
    return t, env


def plot_envelope(run, window: int, ax=None, *, colorbar: bool = True):
    """Top view of the oscillation envelope max|x_j| over time (paper Figs. 1a, 2a/c).

    Parameters
    ----------
    run : Run
        A run integrated with ``store_states=True``.
    window : int
        Samples per block over which the maximum is taken (see `envelope`).
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure when None.
    colorbar : bool, optional
        Add a colour bar to the figure.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = _axes(ax)
    t, env = envelope(run, window)
    N = run.lattice.N
    im = ax.imshow(env.T, aspect="auto", origin="lower", cmap="viridis",
                   extent=(t[0], t[-1], 1, N), interpolation="nearest")
    ax.set_xlabel("$t$")
    ax.set_ylabel("$j$")
    if colorbar:
        ax.figure.colorbar(im, ax=ax, label=r"max $|x_j|$")
    return ax


def plot_mle(results, ax=None, *, labels=None, colors=None, guide: bool = True,
             lw: float = 0.8, alpha: float = 1.0, legend: str | None = "best"):
    """Finite-time maximum Lyapunov exponent lambda(t) on log-log axes (paper Figs. 11-13).

    Regular orbits follow lambda ~ 1/t (drawn as a dashed guide); chaotic ones level off at a
    positive value. ``|lambda|`` is drawn, since a finite-time estimate can dip below zero.

    Parameters
    ----------
    results : ChaosResult or sequence of ChaosResult
        Anything with array attributes (or keys) ``t`` and ``mle``.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure when None.
    labels : str or sequence of str, optional
        Legend label for each result (one string: the first result only).
    colors : colour or sequence of colours, optional
        One colour for all results, or one per result (default: the colour cycle).
    guide : bool, optional
        Draw the 1/t guide over the time span of the results.
    lw, alpha : float, optional
        Line width and opacity of the curves.
    legend : str or None, optional
        Legend location when anything is labelled, None for no legend.

    Returns
    -------
    matplotlib.axes.Axes
    """
    items = _as_list(results)
    ax = _axes(ax)
    labels, colors = _labels_colors(labels, colors, len(items))
    t_lo, t_hi = np.inf, 0.0
    for res, label, color in zip(items, labels, colors):
        t, mle = _get(res, "t"), _get(res, "mle")
        ax.loglog(t, np.abs(mle), lw=lw, alpha=alpha, color=color, label=label)
        if t.size:
            t_lo, t_hi = min(t_lo, t[t > 0].min(initial=np.inf)), max(t_hi, t.max())
    if guide and np.isfinite(t_lo) and t_hi > t_lo:
        tt = np.logspace(np.log10(t_lo), np.log10(t_hi), 50)
        ax.loglog(tt, 1.0 / tt, "k--", lw=1.0, label="$1/t$")
    ax.set_xlabel("$t$")
    ax.set_ylabel(r"$\lambda(t)$")
    if legend is not None and (guide or any(label for label in labels)):
        ax.legend(loc=legend, frameon=False, fontsize=8)
    return ax


def plot_sali(results, ax=None, *, labels=None, colors=None, threshold: float | None = 1e-8,
              lw: float = 0.8, alpha: float = 1.0, legend: str | None = "best"):
    """SALI(t) on log-log axes (paper Figs. 11-13): bounded away from 0 for regular orbits, falling
    exponentially to 0 for chaotic ones.

    Parameters
    ----------
    results : ChaosResult or sequence of ChaosResult
        Anything with array attributes (or keys) ``t`` and ``sali``.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure when None.
    labels : str or sequence of str, optional
        Legend label for each result.
    colors : colour or sequence of colours, optional
        One colour for all results, or one per result.
    threshold : float or None, optional
        Draw the chaos threshold (SALI below it: chaotic; default 1e-8), None for none.
    lw, alpha : float, optional
        Line width and opacity of the curves.
    legend : str or None, optional
        Legend location when anything is labelled, None for no legend.

    Returns
    -------
    matplotlib.axes.Axes
    """
    items = _as_list(results)
    ax = _axes(ax)
    labels, colors = _labels_colors(labels, colors, len(items))
    for res, label, color in zip(items, labels, colors):
        ax.loglog(_get(res, "t"), _get(res, "sali"), lw=lw, alpha=alpha, color=color, label=label)
    if threshold is not None:
        ax.axhline(threshold, color="gray", lw=0.6, ls=":")
    ax.set_xlabel("$t$")
    ax.set_ylabel("SALI")
    if legend is not None and any(label for label in labels):
        ax.legend(loc=legend, frameon=False, fontsize=8)
    return ax


def plot_two_mode(run, env=None, eps: float | None = None, ax=None, *, legend: str | None = "upper right"):
    """Q_1(t), Q_2(t) of the two-mode system, with the envelopes ±2|q_j| from the envelope
    equations (paper Fig. 6).

    Parameters
    ----------
    run : ModalRun
        A result of `fputlab.reduction.two_mode_run` (``t``, ``Q``).
    env : EnvelopeRun, optional
        A result of `fputlab.reduction.envelope_run`, in the slow time T = eps t.
    eps : float, optional
        The detuning ω₂ − 2ω₁ that maps t to T (required with `env`).
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure when None.
    legend : str or None, optional
        Legend location, None for no legend.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = _axes(ax)
    ax.plot(run.t, run.Q[:, 0], color=mode_color(1), lw=0.3, label="$Q_1$")
    ax.plot(run.t, run.Q[:, 1], color=mode_color(2), lw=0.3, label="$Q_2$")
    if env is not None:
        if eps is None:
            raise ValueError("eps: the detuning is needed to draw the envelopes")
        tt = np.linspace(run.t[0], run.t[-1], 2000)
        amp = 2.0 * np.abs(env.at(eps * tt))
        for j in range(2):
            ax.plot(tt, amp[:, j], "k", lw=1.0, label=r"$\pm 2|q_j|$" if j == 0 else None)
            ax.plot(tt, -amp[:, j], "k", lw=1.0)
    ax.set_xlabel("$t$")
    ax.set_ylabel("$Q_1$, $Q_2$")
    if legend is not None:
        leg = ax.legend(loc=legend, fontsize=8, ncol=3, framealpha=0.9)
        for line in leg.get_lines():
            line.set_linewidth(2.0)
    return ax


def plot_blowup_sweep(sweep: dict, ax=None, *, kind: str = "probability",
                      prediction: bool = True, legend: str | None = "best"):
    """A blow-up sweep (`fputlab.blowup.blowup_sweep`).

    Parameters
    ----------
    sweep : dict
        The sweep: ``tau``, ``N``, ``probability`` (len(tau) x len(N)), ``records``
        (tau, N, seed, blew_up, time, tau_c), ``t_max``.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure when None.
    kind : {"probability", "times"}, optional
        "probability": P(blow-up before t_max) versus tau, one curve per N; "times": histogram
        of the blow-up times.
    prediction : bool, optional
        With kind="probability", also the share of realisations whose own two-mode tau_c is
        below tau (the reduction's prediction).
    legend : str or None, optional
        Legend location, None for no legend.

    Returns
    -------
    matplotlib.axes.Axes
    """
    if kind not in ("probability", "times"):
        raise ValueError(f"kind must be 'probability' or 'times', got {kind!r}")
    ax = _axes(ax)
    recs = sweep["records"]
    if kind == "times":
        times = [r[4] for r in recs if r[3]]
        if times:
            ax.hist(times, bins=min(30, max(5, len(times) // 3)), color="C3", alpha=0.8)
        ax.set_xlabel("blow-up time")
        ax.set_ylabel("realisations")
        ax.set_title(f"{len(times)} of {len(recs)} runs blew up")
        return ax
    prob = np.asarray(sweep["probability"], dtype=float).reshape(len(sweep["tau"]), -1)
    for j, N in enumerate(sweep["N"]):
        line, = ax.plot(sweep["tau"], prob[:, j], "o-", label=f"N = {N}: blew up")
        if prediction:
            pred = [np.mean([r[0] > r[5] for r in recs if r[0] == tau and r[1] == N])
                    for tau in sweep["tau"]]
            ax.plot(sweep["tau"], pred, "s--", alpha=0.7, color=line.get_color(),
                    label=f"N = {N}: τ > own $\\tau_c$ (two-mode)")
    ax.set_xlabel("τ (%)")
    ax.set_ylabel(f"P(blow-up before t = {sweep.get('t_end', sweep.get('t_max')):g})")
    ax.set_ylim(-0.05, 1.05)
    if legend is not None:
        ax.legend(loc=legend, frameon=False, fontsize=8)
    return ax


#: region colours and descriptions of `plot_bifurcation` (codes of fputlab.reduction.classify)
BIFURCATION_REGIONS = {
    0: ("#ffffff", r"no equilibria: $1+12\tilde A\tilde B r_1^2<0$"),
    1: ("#b7d7f0", r"$\Delta_1$, $\Delta_2$ well defined, both centres"),
    2: ("#f5c9a8", r"$\Delta_1$ centre, $\Delta_2$ saddle, both well defined"),
    3: ("#d9ecc4", r"only $\Delta_1$ well defined"),
    4: ("#e0e0e0", "neither well defined"),
}


def plot_blowup_sweep_figure(sweep: dict, path=None):
    """Both panels of a blow-up sweep in one figure: (a) the probability of blow-up before t_max
    versus tau (one curve per N) with the reduction's prediction, (b) the distribution of
    blow-up times (see `plot_blowup_sweep`).

    Parameters
    ----------
    sweep : dict
        The result of `fputlab.blowup.blowup_sweep`.
    path : str or path-like, optional
        Write the figure there as a PNG (110 dpi); then it is drawn without pyplot, so no
        backend is chosen or needed.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if path is None:
        import matplotlib.pyplot as plt
        fig = plt.figure(figsize=(12, 4.2), layout="constrained")
    else:
        from matplotlib.figure import Figure
        fig = Figure(figsize=(12, 4.2), layout="constrained")
    a, b = fig.subplots(1, 2)
    plot_blowup_sweep(sweep, ax=a)
    plot_blowup_sweep(sweep, ax=b, kind="times")
    if path is not None:
        fig.savefig(path, dpi=110)
    return fig


def plot_bifurcation_curves(ax, A_range, r1sq: float):
    """The curves 1 + 12 A~B~r₁² = 0 (blue: solid above A~ + B~ = 0, dashed below),
    1 − 4 A~B~r₁² = 0 (red) and A~ + B~ = 0 (black dashed) over A~ in `A_range`.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    A_range : (float, float)
        Range of A~.
    r1sq : float
        r₁² of the initial state ((N+1)/8 for the paper's).

    Returns
    -------
    matplotlib.axes.Axes
    """
    from .reduction import bifurcation_curves
    A = np.linspace(A_range[0], A_range[1], 4001)
    # a NaN at A~ = 0 keeps the hyperbolas' two branches apart
    A = np.concatenate([A[A < -1e-9], [np.nan], A[A > 1e-9]])
    cv = bifurcation_curves(A, r1sq)
    above = cv["blue"] > -A      # above the line A~ + B~ = 0: solid, below: dashed
    for mask, ls in ((above, "-"), (~above, "--")):
        ax.plot(np.where(mask, A, np.nan), np.where(mask, cv["blue"], np.nan), color="b", ls=ls,
                lw=1.3)
    ax.plot(A, cv["red"], color="r", lw=1.3)
    ax.plot(A, cv["black"], "k--", lw=1.0)
    return ax


def plot_bifurcation(ax=None, *, N: int = 64, r1sq: float | None = None,
                     extent=(-1.0, 1.0, -1.0, 1.0), n: int = 401, legend: str | None = "lower left"):
    """Bifurcation diagram of the reduced two-mode system in the (A~, B~) plane (paper Fig. 7):
    regions by the equilibria present in the well-defined region and their type, and the curves
    where they change (`plot_bifurcation_curves`).

    Parameters
    ----------
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure when None.
    N : int, optional
        Lattice size; sets r₁² = (N+1)/8 of the paper's initial state unless `r1sq` is given.
    r1sq : float, optional
        r₁² of the initial state.
    extent : (float, float, float, float), optional
        (A~ min, A~ max, B~ min, B~ max).
    n : int, optional
        Grid points per axis.
    legend : str or None, optional
        Legend location for the regions and curves, None for no legend.

    Returns
    -------
    matplotlib.axes.Axes
    """
    from matplotlib.colors import ListedColormap
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    from .reduction import classify, r1_squared
    ax = _axes(ax, figsize=(6.5, 5.4))
    r1sq = r1_squared(N) if r1sq is None else float(r1sq)
    A, B = np.meshgrid(np.linspace(extent[0], extent[1], n), np.linspace(extent[2], extent[3], n))
    code = classify(A, B, r1sq)
    colours = [BIFURCATION_REGIONS[k][0] for k in range(5)]
    ax.imshow(code, origin="lower", extent=extent, aspect="auto", cmap=ListedColormap(colours),
              vmin=-0.5, vmax=4.5, interpolation="nearest")
    plot_bifurcation_curves(ax, extent[:2], r1sq)
    ax.axhline(0, color="0.4", lw=0.5)
    ax.axvline(0, color="0.4", lw=0.5)
    ax.set_xlim(extent[:2])
    ax.set_ylim(extent[2:])
    ax.set_xlabel(r"$\tilde A$")
    ax.set_ylabel(r"$\tilde B$")
    if legend is not None:
        handles = [Patch(facecolor=c, edgecolor="0.5", label=text)
                   for c, text in BIFURCATION_REGIONS.values()]
        handles += [Line2D([], [], color="b", label=r"$1+12\tilde A\tilde B r_1^2=0$"),
                    Line2D([], [], color="r", label=r"$1-4\tilde A\tilde B r_1^2=0$"),
                    Line2D([], [], color="k", ls="--", label=r"$\tilde A+\tilde B=0$")]
        ax.legend(handles=handles, fontsize=7.5, loc=legend, framealpha=0.9)
    return ax


def plot_spectrum(results, ax=None, *, labels=None, colors=None, marker: str = ".",
                  legend: str | None = "best"):
    """Lyapunov spectra λ_i against i/(2N): spectra of different N collapse onto one curve in
    the thermodynamic limit (Livi, Politi & Ruffo 1986).

    Parameters
    ----------
    results : SpectrumResult or sequence of SpectrumResult
        Anything with ``exponents`` and ``params["N"]`` (or a dict with ``exponents``, ``N``).
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure when None.
    labels : str or sequence of str, optional
        Legend labels (default: "N = ..." for each).
    colors : colour or sequence of colours, optional
        One colour for all results, or one per result.
    marker : str, optional
        Marker of the points.
    legend : str or None, optional
        Legend location, None for no legend.

    Returns
    -------
    matplotlib.axes.Axes
    """
    items = [results] if hasattr(results, "exponents") or isinstance(results, dict) \
        else list(results)
    if not items:
        raise ValueError("results: nothing to plot (empty sequence)")
    ax = _axes(ax)
    labels, colors = _labels_colors(labels, colors, len(items))
    for res, label, color in zip(items, labels, colors):
        lam = _get(res, "exponents")
        N = int(res["N"] if isinstance(res, dict) else res.params.get("N", lam.size // 2))
        x = np.arange(1, lam.size + 1) / (2 * N)
        ax.plot(x, lam, marker=marker, lw=0.8, color=color,
                label=label if label is not None else f"$N = {N}$")
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.set_xlabel(r"$i / (2N)$")
    ax.set_ylabel(r"$\lambda_i$")
    if legend is not None:
        ax.legend(loc=legend, frameon=False, fontsize=8)
    return ax


def plot_spectrum_convergence(result, ax=None, *, every: int = 1, cmap: str = "viridis"):
    """The exponents λ_i(t) of one spectrum run against t (log time axis): how far they have
    converged. Positive exponents are drawn solid, the others dashed.

    Parameters
    ----------
    result : SpectrumResult
        Anything with ``t`` and ``history`` (k, len(t)).
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure when None.
    every : int, optional
        Draw every `every`-th exponent (for large k).
    cmap : str, optional
        Colour map over the exponent index.

    Returns
    -------
    matplotlib.axes.Axes
    """
    import matplotlib
    ax = _axes(ax)
    t, hist = _get(result, "t"), _get(result, "history")
    k = hist.shape[0]
    colors = matplotlib.colormaps[cmap](np.linspace(0, 1, max(k, 2)))
    for i in range(0, k, max(1, int(every))):
        final = hist[i, -1] if hist.shape[1] else 0.0
        ax.semilogx(t, hist[i], lw=0.8, color=colors[i], ls="-" if final > 0 else "--")
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.set_xlabel("$t$")
    ax.set_ylabel(r"$\lambda_i(t)$")
    return ax


def plot_megno(results, ax=None, *, labels=None, colors=None, legend: str | None = "best"):
    """MEGNO <Y>(t) (Cincotta & Simó 2000): it tends to 2 on quasi-periodic orbits (dashed
    guide) and grows like λt/2 on chaotic ones.

    Parameters
    ----------
    results : ChaosResult or sequence of ChaosResult
        Anything with ``t`` and ``megno``.
    ax, labels, colors, legend : optional
        As `plot_mle`.

    Returns
    -------
    matplotlib.axes.Axes
    """
    items = _as_list(results)
    ax = _axes(ax)
    labels, colors = _labels_colors(labels, colors, len(items))
    for res, label, color in zip(items, labels, colors):
        ax.semilogx(_get(res, "t"), _get(res, "megno"), lw=0.8, color=color, label=label)
    ax.axhline(2.0, color="k", ls="--", lw=1.0, label="2 (quasi-periodic)")
    ax.set_xlabel("$t$")
    ax.set_ylabel(r"$\langle Y \rangle(t)$")
    if legend is not None:
        ax.legend(loc=legend, frameon=False, fontsize=8)
    return ax


def plot_clv_localisation(results, ax=None, *, labels=None, colors=None,
                          legend: str | None = "best"):
    """Localisation of covariant Lyapunov vectors: the participation number 1/IPR (the number
    of sites a vector occupies), averaged over the window, against i/(2N). Extended vectors
    reach ~2N/3 sites; localised ones (Anderson localisation of the disordered chains) a few.

    Parameters
    ----------
    results : CLVResult or sequence of CLVResult
        Anything with ``ipr`` (times, k) and ``params["N"]``.
    ax, labels, colors, legend : optional
        As `plot_spectrum`.

    Returns
    -------
    matplotlib.axes.Axes
    """
    items = [results] if hasattr(results, "ipr") else list(results)
    if not items:
        raise ValueError("results: nothing to plot (empty sequence)")
    ax = _axes(ax)
    labels, colors = _labels_colors(labels, colors, len(items))
    for res, label, color in zip(items, labels, colors):
        ipr = np.asarray(res.ipr, dtype=float)
        N = int(res.params.get("N", ipr.shape[1] // 2))
        x = np.arange(1, ipr.shape[1] + 1) / (2 * N)
        ax.plot(x, (1.0 / ipr).mean(axis=0), marker=".", lw=0.8, color=color,
                label=label if label is not None else f"$N = {N}$")
    ax.set_xlabel(r"$i / (2N)$")
    ax.set_ylabel(r"participation $1/\mathrm{IPR}$ (sites)")
    if legend is not None:
        ax.legend(loc=legend, frameon=False, fontsize=8)
    return ax
