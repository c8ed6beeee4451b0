"""The thermalization figure: T_eq against eps on log-log axes with the bootstrap intervals,
the fitted power law and its exponent interval, the published law for comparison, and the
ensemble eta(t) of every point (paper style: Onorato et al. 2015, Fig. 4; Lvov & Onorato
2018, Fig. 2)."""
from __future__ import annotations

import math

import numpy as np

from ._figure import save

__all__ = ["thermalization_figure", "PUBLISHED"]

#: the published exponents a of T_eq ~ eps^-a for the built-in studies: (eps range or None for
#: all points, a, legend)
PUBLISHED = {
    "alpha": [(None, 8.0, "Onorato et al. 2015: $\\varepsilon^{-8}$")],
    "beta": [((0.0, 0.07), 4.0, "Lvov & Onorato 2018: $\\varepsilon^{-4}$ (small $\\varepsilon$)"),
             ((0.1, 0.5), 2.0, "Lvov & Onorato 2018: $\\varepsilon^{-2}$ (past the overlap)")],
    "beta-overlap": [(None, 2.0, "Lvov & Onorato 2018: $\\varepsilon^{-2}$ (past the overlap)")],
}


def thermalization_figure(results: list, path: str, *, title: str | None = None):
    """Write the figure for one or more studies' `ThermalizationStudy.results()` to `path`
    (the merged results of the studies on the study engine).

    Left: T_eq(eps) with 90 % bootstrap intervals; points that never crossed are drawn as
    lower bounds at the time reached (open triangles); each study's fitted line is labelled
    with its exponent and interval, and the published slope is drawn through the fit's middle
    point. Right: the ensemble eta(t) of every point, with the threshold.

    Returns
    -------
    fputlab._figure.Figure
        The path, with ``numbers`` = {label: fit dict}.
    """
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4.4))
    numbers = {}
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for i, res in enumerate(results):
        spec, pts, fit = res["spec"], res["points"], res["fit"]
        label = spec["label"]
        c = colours[i % len(colours)]
        eps = np.array([p["eps"] for p in pts])
        teq = np.array([p["t_eq"] for p in pts])
        ok = np.isfinite(teq)
        lo = np.array([p["interval"][0] for p in pts])
        hi = np.array([p["interval"][1] for p in pts])
        err = np.vstack([np.where(np.isfinite(lo), teq - lo, 0), np.where(np.isfinite(hi),
                                                                           hi - teq, 0)])
        counts = sorted({p.get("orbits", spec["orbits"]) for p in pts})
        orbits = f"{counts[0]}" if len(counts) == 1 else f"{counts[0]}-{counts[-1]}"
        ax.errorbar(eps[ok], teq[ok], yerr=err[:, ok], fmt="o", color=c, capsize=3,
                    label=f"{label} (N = {spec['N']}, {orbits} orbits per ε)")
        reached = np.array([p["t_reached"] for p in pts])
        nb = ~ok & (reached > 0)
        if nb.any():
            ax.plot(eps[nb], reached[nb], "^", mfc="none", color=c,
                    label=f"{label}: no crossing by the time shown")
        range_fits = res.get("range_fits", [])
        if fit is not None:
            xs = np.geomspace(eps[ok].min(), eps[ok].max(), 20)
            a, (alo, ahi) = fit["exponent"], fit["interval"]
            ival = "" if not math.isfinite(alo) else f" [{alo:.1f}, {ahi:.1f}]"
            # with range fits the all-points line is only a guide: drawn thin
            ax.plot(xs, fit["prefactor"] * xs ** -a, "-", color=c,
                    lw=0.8 if range_fits else 1.5, alpha=0.5 if range_fits else 1.0,
                    label=f"fit: $T_{{eq}} \\propto \\varepsilon^{{-{a:.2f}}}$ {ival}")
            numbers[label] = fit
        for k, rf in enumerate(range_fits):
            sel = ok & (eps >= rf["range"][0]) & (eps <= rf["range"][1])
            if sel.sum() < 2:
                continue
            xs = np.geomspace(eps[sel].min(), eps[sel].max(), 10)
            a, (alo, ahi) = rf["exponent"], rf["interval"]
            ival = "" if not math.isfinite(alo) else f" [{alo:.1f}, {ahi:.1f}]"
            ax.plot(xs, rf["prefactor"] * xs ** -a, ":" if k % 2 else "-.", color=c, lw=2,
                    label=f"fit over {rf['range'][0]:g}-{rf['range'][1]:g}: "
                          f"$\\varepsilon^{{-{a:.2f}}}$ {ival}")
            numbers[f"{label} {rf['range'][0]:g}-{rf['range'][1]:g}"] = rf
        for rng, ap, text in PUBLISHED.get(label, []):
            sel = ok if rng is None else ok & (eps >= rng[0]) & (eps <= rng[1])
            if sel.sum() < 2:
                continue
            # the published slope through the geometric mean of the points it applies to
            xs = np.geomspace(eps[sel].min(), eps[sel].max(), 10)
            xm = math.exp(np.log(eps[sel]).mean())
            ym = math.exp(np.log(teq[sel]).mean())
            ax.plot(xs, ym * (xs / xm) ** -ap, "--", color="0.4", label=text)
        shades = plt.get_cmap("viridis")(np.linspace(0, 0.85, max(len(pts), 1)))
        for j, p in enumerate(pts):
            if "eta" in p and len(p["eta"]) > 1:
                # one study: a colour per eps, labelled; several: a colour per study
                col = shades[j] if len(results) == 1 else c
                lab = f"$\\varepsilon$ = {p['eps']:g}" if len(results) == 1 else None
                ax2.semilogx(p["t"][1:], p["eta"][1:], color=col, alpha=0.9, lw=1, label=lab)
        if pts:
            ax2.axhline(spec["threshold"], color="k", lw=0.8, ls=":")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("$\\varepsilon$")
    ax.set_ylabel("$T_{eq}$")
    ax.legend(fontsize=7)
    ax2.set_xlabel("t")
    ax2.set_ylabel("ensemble $\\eta(t)$")
    ax2.set_ylim(0, 1.05)
    if len(results) == 1:
        ax2.legend(fontsize=7)
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    return save(fig, path, numbers)


#: the rows of the README table: (study label, what is fitted: None (all points) or an eps
#: range, the chain as written, the published value)
TABLE_ROWS = [
    ("alpha", None, "α-FPUT, ε = α√(E/N)", "8 (Onorato et al., PNAS 2015)"),
    ("beta", (0.0, 0.07), "β-FPUT, ε = βE/N", "4 (Lvov & Onorato, PRL 2018)"),
    ("beta-overlap", None, "β-FPUT, past the overlap (window 16)", "2 (ibid.)"),
    ("toda", None, "Toda (control), ε as α-FPUT", "no equipartition"),
    ("disorder-nonlinear-5", None, "model 3, τ = 5 %", "—"),
    ("disorder-nonlinear-10", None, "model 3, τ = 10 %", "—"),
    ("disorder-hamiltonian-5", None, "model 2, τ = 5 %", "—"),
    ("disorder-hamiltonian-10", None, "model 2, τ = 10 %", "—"),
]


def _sci(x: float) -> str:
    """1.0×10⁶ style."""
    e = int(math.floor(math.log10(x)))
    sup = str(e).translate(str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹"))
    return f"{x / 10 ** e:.1f}×10{sup}"


def markdown_table(results: dict) -> str:
    """The README / docs table of the measured exponents, from `ThermalizationStudy.results()`
    of the built-in studies ({label: results}); tests/python/test_thermalization_study.py checks
    that the committed pages hold exactly this."""
    lines = ["| chain | ε fitted | orbits per ε | measured T_eq ∝ ε⁻ᵃ, a [90 % bootstrap] | "
             "published |", "|---|---|---|---|---|"]
    for label, rng, chain, published in TABLE_ROWS:
        res = results[label]
        pts = [p for p in res["points"]
               if rng is None or rng[0] <= p["eps"] <= rng[1]]
        # the points a fit uses: crossed, T_eq resolved by the averaging window (MIN_WINDOWS)
        crossed = [p for p in pts if p.get("resolved", math.isfinite(p["t_eq"]))]
        orbits = sorted({p["orbits"] for p in pts})
        n = f"{orbits[0]}" if len(orbits) == 1 else f"{orbits[0]}–{orbits[-1]}"
        if rng is None:
            fit = res["fit"]
        else:
            fit = next((f for f in res["range_fits"] if tuple(f["range"]) == tuple(rng)), None)
        if crossed and fit is not None:
            e = [p["eps"] for p in crossed]
            lo, hi = fit["interval"]
            measured = f"{fit['exponent']:.2f} [{lo:.2f}, {hi:.2f}]"
            span = f"{min(e):g}–{max(e):g}"
        else:
            e = [p["eps"] for p in pts]
            span = ", ".join(f"{x:g}" for x in e)
            etas = ", ".join(f"{p['eta_last']:.2f}" for p in pts)
            t = min(p["t_reached"] for p in pts)
            measured = f"no crossing of η = {res['spec']['threshold']:g}: η = {etas} at t = " \
                       f"{_sci(t)}"
        lines.append(f"| {chain} | {span} | {n} | {measured} | {published} |")
    return "\n".join(lines)
