"""Figures of the paper's Sec. 4 (Figs. 4-10). Like every figure function of fputlab,
``figN(out_dir=".", *, full=False, **options)`` writes one PNG into `out_dir` (or to `out_dir`
itself if that ends in .png) and returns a `Figure`: its path, carrying the numbers shown
(``fig.numbers``, ``fig["key"]``). Quick by default (seconds); `full=True` uses the paper's
dt = 0.01 / longer runs / finer grids where that matters. Nothing here opens a window (Agg).

Disorder realisation: Figs. 4 and 6 use seed PAPER_LIKE_SEED (= 578), the realisation among seeds
1..1000 whose (A~, B~) at tau = 10 % is closest to the values the paper quotes for its tau = 10 %
phase portrait (4.97, 0.05); v = 1 + (tau/300) z with the same z for every tau. (Seed 1, say,
has its own tau_c = 9.25 % and blows up at tau = 10 % in the two-mode system.)"""
from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from . import reduction as red
from ._figure import Figure, add_output_options, figure_output, save, target
from .plotting import mode_color, plot_bifurcation, plot_bifurcation_curves, plot_two_mode
from .lattice import Lattice

__all__ = ["fig4", "fig5", "fig6", "fig7", "fig8", "fig9", "fig10", "FIGURES", "PAPER_LIKE_SEED",
           "PAPER_POINTS", "paper_like_seed", "example_main"]

PAPER_LIKE_SEED = 578
#: (A~, B~) the paper quotes for Figs. 9(a), 9(b) and 10
PAPER_POINTS = {"tau0": (3.63, 0.91), "tau10": (4.97, 0.05), "blowup": (5.3932, -0.0015)}
_POINT_NAMES = {"tau0": "τ = 0", "tau10": "τ = 10%", "blowup": "blow-up (Fig. 10)"}


def _pyplot():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def _figure(numbers: dict):
    """The figure's result: its path (numbers["path"]) as a Figure carrying the other numbers."""
    result = Figure(numbers["path"])
    result.numbers = {k: v for k, v in numbers.items() if k != "path"}
    return result


def _save(fig, out) -> str:
    """Write and close `fig` (the house style, format and dpi of `fputlab._figure.save`)."""
    out = os.fspath(out)
    d = os.path.dirname(out)
    if d:
        os.makedirs(d, exist_ok=True)
    return os.fspath(save(fig, out))


def paper_like_seed(tau: float = 10.0, target=(4.97, 0.05), n_seeds: int = 1000) -> int:
    """The seed in 1..n_seeds whose (A~, B~) at tau is closest to target (B~ weighted x10)."""
    rq = red.realisation_quadratics(64, 0.25, n_seeds, seed0=1)
    A = rq.evaluate(rq.A_tilde, tau)[:, 0]
    B = rq.evaluate(rq.B_tilde, tau)[:, 0]
    return int(rq.seeds[np.argmin(np.hypot(A - target[0], 10 * (B - target[1])))])


def _lattice(N, tau, seed, alpha=0.25):
    if tau == 0:
        return Lattice(N, alpha, "nonlinear")
    return Lattice(N, alpha, "nonlinear", tau=tau, seed=seed)


# ---- Fig. 4 ------------------------------------------------------------------------------------

def fig4(out_dir=".", *, full: bool = False, N: int = 64, taus=(0.0, 5.0, 10.0),
         Ms=(2, 4, 8), t_end: float = 1.5e5, dt: float | None = None,
         seed: int = PAPER_LIKE_SEED) -> Figure:
    """E_1..E_4 of the Galerkin truncation to M = 2, 4, 8 modes (rows: tau; columns: M), model 3.
    dt = 0.1 when quick (Yoshida 4; the truncated systems have omega_M <= 0.4, and E_k agree with
    dt = 0.05 to 1e-4 relative), else the paper's 0.01."""
    quick = not full
    out = target(out_dir, "fig04_galerkin.png")
    plt = _pyplot()
    dt = (0.1 if quick else 0.01) if dt is None else dt
    every = max(20.0, t_end / 5000)
    jobs = [(r, c, tau, M) for r, tau in enumerate(taus) for c, M in enumerate(Ms)]

    def work(job):
        _, _, tau, M = job
        g = red.Galerkin(_lattice(N, tau, seed), M)
        return g.run(t_end, dt=dt, sample_every=every, on_failure="return")

    with ThreadPoolExecutor(max_workers=min(len(jobs), os.cpu_count() or 1)) as pool:
        runs = list(pool.map(work, jobs))   # the C runs release the GIL
    fig, axes = plt.subplots(len(taus), len(Ms), figsize=(4.2 * len(Ms), 2.9 * len(taus)),
                             sharex=True, constrained_layout=True, squeeze=False)
    summary = {}
    for i, ((r, c, tau, M), run) in enumerate(zip(jobs, runs)):
        ax = axes[r, c]
        E = run.mode_energies
        for k in range(min(M, 4)):
            ax.plot(run.t, E[:, k], lw=0.8, color=mode_color(k + 1), label=f"$E_{k + 1}$")
        ax.set_title(f"({chr(97 + i)}) M = {M}, τ = {tau:g}%" + ("" if run.completed else
                                                                 " (blew up)"), fontsize=10)
        ax.set_ylim(bottom=0)
        summary[f"tau={tau:g},M={M}"] = {"E_max": E[:, :4].max(axis=0).round(5).tolist(),
                                         "completed": run.completed}
    for ax in axes[-1]:
        ax.set_xlabel("$t$")
    for ax in axes[:, 0]:
        ax.set_ylabel("$E_k$")
    axes[0, -1].legend(loc="upper right", fontsize=8, frameon=False)
    fig.suptitle(f"Disordered chain (nonlinear couplings) kept to its first M normal modes: "
                 f"N = {N}, α = 0.25, disorder seed {seed}, dt = {dt:g}")
    summary["path"] = _save(fig, out)
    return _figure(summary)


# ---- Fig. 5 ------------------------------------------------------------------------------------

def fig5(out_dir=".", *, full: bool = False, N: int = 64, R: int = 100,
         seed0: int = 1, tau_max: float = 20.0) -> Figure:
    """A~(tau), B~(tau): mean over R realisations (dash-dotted) with +-1 sd bands, the quadratic
    fit of the mean (as the paper), the exact expectation and +-1 sd (closed form, black) and
    tau_c. Quick or not, this is cheap (R projections per tau)."""
    quick = not full
    out = target(out_dir, "fig05_coefficients.png")
    plt = _pyplot()
    taus = np.linspace(0.0, tau_max, 41 if quick else 201)
    ens = red.ensemble_statistics(taus, N, 0.25, R, seed0=seed0)
    mom = red.coefficient_moments(taus, N, 0.25)
    tc = red.critical_tolerance(N, 0.25, R, seed0=seed0, tau=taus)
    fig, (ax_a, ax_b) = plt.subplots(1, 2, figsize=(12, 4.4), constrained_layout=True)
    panels = ((ax_a, "A", ens.A_mean, ens.A_std, mom.A_tilde_mean, mom.A_tilde_std, tc.fit_A),
              (ax_b, "B", ens.B_mean, ens.B_std, mom.B_tilde_mean, mom.B_tilde_std, tc.fit_B))
    for ax, name, mean, sd, emean, esd, p in panels:
        ax.fill_between(taus, mean - sd, mean + sd, color="C0", alpha=0.25,
                        label=f"mean ± 1 sd, R = {R}")
        ax.plot(taus, mean, "-.", color="C0", lw=2.0, zorder=4, label="mean of realisations")
        ax.plot(taus, np.polyval(p, taus), color="C1", lw=0.9,
                label=f"fit {p[0]:.5f}τ² {p[1]:+.6f}τ {p[2]:+.5f}")
        ax.plot(taus, emean, "k-", lw=0.9, label="exact expectation")
        ax.plot(taus, emean - esd, "k:", lw=0.8)
        ax.plot(taus, emean + esd, "k:", lw=0.8, label="exact ± 1 sd")
        ax.set_xlabel("τ (%)")
        ax.set_ylabel(rf"$\tilde{{{name}}}$")
        ax.legend(fontsize=8, loc="upper left" if name == "A" else "lower left", frameon=False)
    ax_b.axhline(0.0, color="k", ls="--", lw=0.8)
    ax_b.axvline(tc.exact, color="k", lw=0.6, ls=(0, (2, 2)))
    ax_b.annotate(r"$\tau_c$" + f": exact {tc.exact:.4f}%, fit {tc.fit:.4f}%", (tc.exact, 0.0),
                  xytext=(0.45, 0.9), textcoords="axes fraction", fontsize=9,
                  arrowprops=dict(arrowstyle="->", lw=0.6))
    ax_a.set_title(r"(a) $\tilde A$ vs tolerance, N = %d" % N)
    ax_b.set_title(r"(b) $\tilde B$ vs tolerance (paper: $\tau_c \approx 10.0749\%$)")
    s = tc.summary()
    s["path"] = _save(fig, out)
    return _figure(s)


# ---- Fig. 6 ------------------------------------------------------------------------------------

def fig6(out_dir=".", *, full: bool = False, N: int = 64, taus=(0.0, 10.0),
         t_end: float = 1e5, seed: int = PAPER_LIKE_SEED) -> Figure:
    """Q_1 (blue), Q_2 (orange) of the two-mode ODE (msvar) and their envelopes +-2|q_j| (black) from
    the envelope equations (msfinal2), q_1(0) = Q_1(0)/2, q_2(0) = 0, T = eps t."""
    quick = not full
    out = target(out_dir, "fig06_envelopes.png")
    plt = _pyplot()
    dt = 0.05 if quick else 0.01
    fig, axes = plt.subplots(1, len(taus), figsize=(6.5 * len(taus), 4.2), constrained_layout=True,
                             squeeze=False)
    summary = {}
    for i, (ax, tau) in enumerate(zip(axes[0], taus)):
        c = red.two_mode_coefficients(_lattice(N, tau, seed))
        run = red.two_mode_run(c, t_end, dt=dt, sample_every=2.0)
        env = red.envelope_run(c.A_tilde, c.B_tilde, c.eps * t_end, N=N, dT=1e-3)
        plot_two_mode(run, env, c.eps, ax=ax)
        err = red.envelope_error(run, env, c.eps)
        ax.set_title(f"({chr(97 + i)}) τ = {tau:g}%: " + r"$\tilde A$" + f" = {c.A_tilde:.3f}, "
                     + r"$\tilde B$" + f" = {c.B_tilde:.3f}", fontsize=10)
        summary[f"tau={tau:g}"] = {"A_tilde": c.A_tilde, "B_tilde": c.B_tilde,
                                   "max_error_Q1": float(err[0]), "max_error_Q2": float(err[1])}
    fig.suptitle(f"Two-mode system and its slow envelope equations, N = {N}, "
                 f"disorder seed {seed}; leading order " + r"$Q_j \approx 2\,\mathrm{Re}\,(q_j\, "
                 r"e^{i(\omega_j t + T)})$, $T = \varepsilon t$")
    summary["path"] = _save(fig, out)
    return _figure(summary)


# ---- Figs. 7-8 ---------------------------------------------------------------------------------

def fig7(out_dir=".", *, full: bool = False, N: int = 64,
         extent=(-1.0, 1.0, -1.0, 1.0), wide=(-1.0, 7.0, -1.5, 1.5)) -> Figure:
    """Bifurcation diagram in the (A~, B~) plane for the paper's initial state (r_1^2 = (N+1)/8):
    regions by the equilibria present in the well-defined region and their type; blue
    1 + 12 A~B~r_1^2 = 0 (solid above A~ + B~ = 0, dashed below), red 1 - 4 A~B~r_1^2 = 0, black
    dashed A~ + B~ = 0. Right: wider view with E[A~], E[B~] along tau = 0..20 % and the paper's
    points."""
    quick = not full
    out = target(out_dir, "fig07_bifurcation.png")
    plt = _pyplot()
    r1sq = red.r1_squared(N)
    n = 401 if quick else 1201
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.4), constrained_layout=True)
    plot_bifurcation(axes[0], r1sq=r1sq, extent=extent, n=n, legend="lower left")
    plot_bifurcation(axes[1], r1sq=r1sq, extent=wide, n=n, legend=None)
    taus = np.linspace(0, 20, 81)
    mom = red.coefficient_moments(taus, N)
    axes[1].plot(mom.A_tilde_mean, mom.B_tilde_mean, color="m", lw=1.5,
                 label=r"E[$\tilde A$], E[$\tilde B$], τ = 0..20%")
    for name, (a, b) in PAPER_POINTS.items():
        axes[1].plot(a, b, "o", ms=5, label=f"paper, {_POINT_NAMES[name]}: ({a:g}, {b:g})")
    axes[1].legend(fontsize=8, loc="lower left")
    for ax in axes:
        ax.text(0.98, 0.03, r"$\tilde A\tilde B<0$: well-defined region unbounded", ha="right",
                transform=ax.transAxes, fontsize=8, color="0.3")
    axes[0].set_title(f"(a) equilibria of the reduced two-mode system, r₁² = {r1sq:g}")
    axes[1].set_title("(b) wider view: the tolerance path and the paper's points")
    return _figure({"path": _save(fig, out), "r1sq": r1sq})


def fig8(out_dir=".", *, full: bool = False, N: int = 64,
         extent=(-1.0, 1.0, -1.0, 1.0)) -> Figure:
    """(a) Delta_1 and (b) tanh(Delta_2/100) over the (A~, B~) plane (white: no equilibria), with
    the curves of Fig. 7."""
    quick = not full
    out = target(out_dir, "fig08_equilibria.png")
    plt = _pyplot()
    r1sq = red.r1_squared(N)
    n = 401 if quick else 1201
    A, B = np.meshgrid(np.linspace(extent[0], extent[1], n), np.linspace(extent[2], extent[3], n))
    m = red.equilibrium_map(A, B, r1sq)
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.2), constrained_layout=True)
    d1 = m["delta1"]
    lo, hi = np.nanpercentile(d1, [1, 99])
    for ax, data, label, kw in (
            (axes[0], d1, r"$\Delta_1$", dict(cmap="viridis", vmin=lo, vmax=hi)),
            (axes[1], np.tanh(m["delta2"] / 100.0), r"$\tanh(\Delta_2/100)$",
             dict(cmap="RdBu_r", vmin=-1, vmax=1))):
        im = ax.imshow(data, origin="lower", extent=extent, aspect="auto",
                       interpolation="nearest", **kw)
        fig.colorbar(im, ax=ax, label=label)
        plot_bifurcation_curves(ax, extent[:2], r1sq)
        ax.set_xlim(extent[:2])
        ax.set_ylim(extent[2:])
        ax.set_xlabel(r"$\tilde A$")
        ax.set_ylabel(r"$\tilde B$")
    axes[0].set_title(r"(a) equilibrium $\Delta_1$ of the reduced system, $r_1^2$ = %g" % r1sq)
    axes[1].set_title(r"(b) equilibrium $\Delta_2$, shown as $\tanh(\Delta_2/100)$")
    return _figure({"path": _save(fig, out)})


# ---- Figs. 9-10: phase portraits ----------------------------------------------------------------

def _phase_portrait(ax, A, B, *, N=64, delta_range=None, T_end=3.0, P_max=None, n=301,
                    label=""):
    rs = red.ReducedSystem(A, B, N=N)
    lo, hi = rs.region()
    if delta_range is None:
        delta_range = (lo - 0.05 * (hi - lo), hi + 0.05 * (hi - lo))
    dlo, dhi = delta_range
    th = np.linspace(0, np.pi, n)
    D = np.linspace(dlo, dhi, n)
    TH, DD = np.meshgrid(th, D)
    ok = rs.well_defined(DD)
    ax.imshow(np.where(ok, np.nan, 1.0), origin="lower", extent=(0, np.pi, dlo, dhi),
              aspect="auto", cmap="Greys", vmin=0, vmax=4, interpolation="nearest")
    inv = np.where(ok, rs.invariant(DD, TH), np.nan)
    eqs = rs.equilibria()
    # level sets of I are the orbits: quantile levels plus nested ones around each centre, out to
    # the separatrix of a saddle or to the orbit of the initial state (I = r_1^2(0))
    levels = list(np.nanquantile(inv, np.linspace(0.03, 0.97, 18)))
    saddles = [rs.invariant(e.delta, e.theta) for e in eqs if e.kind == "saddle" and e.well_defined]
    for e in eqs:
        if e.kind == "centre" and e.well_defined:
            ref = saddles[0] if saddles else rs.r1sq
            ic = float(rs.invariant(e.delta, e.theta))
            levels += [ic + f * (ref - ic) for f in (0.1, 0.3, 0.5, 0.7, 0.9)]
    ax.contour(TH, DD, inv, levels=np.unique(levels), colors="0.5", linewidths=0.6,
               linestyles="solid")
    if saddles:
        ax.contour(TH, DD, inv, levels=sorted(saddles), colors="darkorange", linewidths=1.4,
                   linestyles="solid")
    # direction of the flow in T: arrows of fixed length (2.5 % of the axes) on a coarse grid
    tq, dq = np.meshgrid(np.linspace(0, np.pi, 17)[1:-1], np.linspace(dlo, dhi, 15)[1:-1])
    with np.errstate(invalid="ignore", divide="ignore"):
        dD, dth = rs.field(dq, tq)
        u, w = dth / np.pi, dD / (dhi - dlo)
        norm = np.hypot(u, w)
        good = rs.well_defined(dq) & np.isfinite(norm) & (norm > 0)
        u, w = np.where(good, u / norm, np.nan), np.where(good, w / norm, np.nan)
    ax.quiver(tq, dq, 0.025 * u * np.pi, 0.025 * w * (dhi - dlo), angles="xy",
              scale_units="xy", scale=1, color="0.35", width=0.0035, headwidth=4)
    T, Dt, tht, _ = rs.trajectory(T_end, dT=1e-3, P_max=P_max)
    keep = (Dt >= dlo) & (Dt <= dhi)
    # break the line where theta wraps from pi to 0
    jumps = np.flatnonzero(np.abs(np.diff(tht)) > np.pi / 2)
    tht_plot = tht.copy()
    tht_plot[jumps] = np.nan
    tht_plot[0] = np.nan          # theta is undefined at q_2 = 0 itself
    ax.plot(np.where(keep, tht_plot, np.nan), np.where(keep, Dt, np.nan), color="b", lw=1.6,
            label="orbit of q(0) = (Q₁(0)/2, 0)")
    ax.plot(tht[1], Dt[1], "bs", ms=6)   # theta is undefined at q_2 = 0 itself
    for e in eqs:
        if e.well_defined:
            # the marker tells Delta_1 from Delta_2 (both can be centres), the colour the type
            style = dict(marker={1: "o", 2: "D"}.get(e.j, "s"),
                         color="tab:green" if e.kind == "centre" else "tab:red")
            ax.plot(e.theta, e.delta, ls="none", ms=9, mec="k",
                    label=f"Δ{e.j} = {e.delta:.4f}, θ = {e.theta:.3g} ({e.kind})", **style)
            if e.theta == 0.0:   # theta is periodic with period pi
                ax.plot(np.pi, e.delta, ls="none", ms=9, mec="k", clip_on=False, **style)
    ax.set_xlim(0, np.pi)
    ax.set_ylim(dlo, dhi)
    ax.set_xticks([0, np.pi / 4, np.pi / 2, 3 * np.pi / 4, np.pi])
    ax.set_xticklabels(["0", "π/4", "π/2", "3π/4", "π"])
    ax.set_xlabel(r"$\theta$")
    ax.set_ylabel(r"$\Delta$")
    ax.set_title(label + r" $\tilde A$ = %g, $\tilde B$ = %g, C = %.4g" % (A, B, rs.C),
                 fontsize=10)
    ax.legend(fontsize=7.5, loc="lower right", framealpha=0.9)
    return {"A_tilde": A, "B_tilde": B, "C": rs.C, "region": rs.region(),
            "equilibria": [(e.j, e.theta, e.delta, e.kind, e.well_defined) for e in eqs],
            "orbit_delta_range": (float(Dt.min()), float(Dt.max())),
            "orbit_completed_T": float(T[-1])}


def fig9(out_dir=".", *, full: bool = False, N: int = 64,
         points=(PAPER_POINTS["tau0"], PAPER_POINTS["tau10"])) -> Figure:
    """Phase portraits of Eqs. (delta3, theta3) in the slow time T (grey arrows, level sets of the
    invariant I = r_1^2 (1 + 2 A~ r_2 cos 2 theta)) for the paper's tau = 0 % and 10 % values, the
    well-defined region (white; grey outside), the equilibria and the orbit of the initial state."""
    out = target(out_dir, "fig09_phase_portraits.png")   # full: the quick settings are already the paper's
    plt = _pyplot()
    fig, axes = plt.subplots(1, len(points), figsize=(6.5 * len(points), 5.0),
                             constrained_layout=True, squeeze=False)
    res = {}
    for i, (ax, (A, B)) in enumerate(zip(axes[0], points)):
        res[f"({chr(97 + i)})"] = _phase_portrait(ax, A, B, N=N, T_end=3.0,
                                                  label=f"({chr(97 + i)})")
    res["path"] = _save(fig, out)
    return _figure(res)


def fig10(out_dir=".", *, full: bool = False, N: int = 64,
          point=PAPER_POINTS["blowup"], delta_max: float = 40.0) -> Figure:
    """As Fig. 9 for (A~, B~) = (5.3932, -0.0015) (tau ~ 10.0833 % > tau_c): the region Delta > r_1^2
    is unbounded; Delta_1 is a centre, Delta_2 a saddle (orange: its separatrix), and the orbit of the
    initial state (blue) starts at the bottom and escapes to Delta -> infinity."""
    out = target(out_dir, "fig10_phase_portrait_blowup.png")   # full: the quick settings are already the paper's
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7, 5.4), constrained_layout=True)
    r1sq = red.r1_squared(N)
    res = _phase_portrait(ax, *point, N=N, delta_range=(r1sq - 1.0, delta_max), T_end=200.0,
                          P_max=1.5 * delta_max, label=r"τ ≈ 10.0833 % > $\tau_c$:")
    res["path"] = _save(fig, out)
    return _figure(res)


FIGURES = {4: fig4, 5: fig5, 6: fig6, 7: fig7, 8: fig8, 9: fig9, 10: fig10}


def example_main(number: int, doc: str, argv=None) -> int:
    """Command line shared by examples/figXX_*.py: --out DIR [--full] [--format F] [--dpi D]."""
    import argparse
    import json
    import time
    parser = argparse.ArgumentParser(description=doc,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default="figures", help="directory for the figure (default: figures)")
    parser.add_argument("--full", action="store_true",
                        help="paper-quality settings (smaller dt, finer grids; slower)")
    add_output_options(parser)
    args = parser.parse_args(argv)
    start = time.perf_counter()
    with figure_output(args.format, args.dpi):
        fig = FIGURES[number](args.out, full=args.full)
    res = {"path": str(fig), **fig.numbers, "seconds": round(time.perf_counter() - start, 2)}
    print(json.dumps(res, indent=1, default=lambda o: o.tolist() if hasattr(o, "tolist") else
                     str(o)))
    return 0
