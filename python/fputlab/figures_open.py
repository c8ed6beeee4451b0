"""Beyond the paper: the figures of its two open questions (issue 25).

1. Is the rise of chaos with N monotone? Model 3 (Eq. varnonlin), alpha = 0.25, tau = 10 %,
   the mode-1 initial state, 100 realisations for each N = 4 ... 128: the fraction chaotic /
   blown up / regular with Wilson 95 % intervals against N at several times, of all orbits and
   of those that did not blow up (blow-ups compete with chaos), and the survival curves.
   The same question at a fixed fraction (0.5 and 0.9) of each size's own threshold tau_c(N).
2. The Hamiltonian disorder (model 2, Eqs. dis1/Hamilt2mod): its chaos study against model 3's,
   and the recurrence quality against tau for both models.
3. An (N, tau) phase diagram of model 3 at t = 1e6 with the two-mode theory's tau_c(N).
"""
from __future__ import annotations

import math
import re
import warnings

import numpy as np

from ._figure import sci
from .chaos.outcomes import (OrbitOutcomes, cumulative_incidence, monotonicity,
                             outcome_table, outcomes_from_dataset)
from .recurrence import recurrence_quality, recurrence_time

__all__ = ["open_questions", "fig_monotone", "fig_threshold", "fig_models", "fig_recurrence",
           "fig_phase", "plot_fraction_vs_N", "plot_survival", "threshold_tau", "chaos_studies",
           "recurrence_table", "monotone_markdown", "reached_markdown", "answer_markdown",
           "generated_tables"]

_CLASS_COLOURS = {"chaotic": "#c0392b", "regular": "#2471a3", "blow-up": "#7f8c8d",
                  "undecided": "#f5b041"}


def _fraction_axes(ax, rows, key, label, colour, marker, offset=0.0):
    rows = [r for r in rows if np.isfinite(r[key])]
    N = np.array([r["N"] for r in rows], float)
    f = np.array([r[key] for r in rows])
    lo = np.array([r[key + "_low"] for r in rows])
    hi = np.array([r[key + "_high"] for r in rows])
    ax.errorbar(N * (1 + offset), f, yerr=[np.maximum(f - lo, 0), np.maximum(hi - f, 0)], color=colour, marker=marker, ms=5,
                capsize=3, lw=1.2, label=label)


def plot_fraction_vs_N(ax, rows_by_t: dict, key: str, title: str):
    """Fraction `key` against N (log axis) at each time of rows_by_t ({t: rows})."""
    colours = ["#fdae6b", "#e6550d", "#a63603", "#54278f", "#2171b5"]
    markers = ["o", "s", "D", "^", "v"]
    for i, (t, rows) in enumerate(sorted(rows_by_t.items())):
        _fraction_axes(ax, rows, key, f"t = {sci(t)}", colours[i % 5], markers[i % 5],
                       offset=0.03 * (i - 1))
    ax.set_xscale("log", base=2)
    Ns = sorted({r["N"] for rows in rows_by_t.values() for r in rows})
    ax.set_xticks(Ns, [str(n) for n in Ns])
    ax.minorticks_off()
    ax.set_ylim(-0.03, 1.03)
    ax.set_xlabel("number of particles N")
    ax.set_title(title)
    ax.grid(alpha=0.3)


def plot_survival(ax, outcomes, t):
    """Fraction of each N's orbits still neither chaotic nor blown up against t (solid), and the
    cumulative incidence of blow-up (dotted), on a log time axis."""
    import matplotlib.pyplot as plt
    Ns = np.unique(outcomes.N)
    cmap = plt.get_cmap("viridis")
    for i, N in enumerate(Ns):
        surv, chaos, blow = cumulative_incidence(outcomes, int(N), t)
        c = cmap(i / max(1, len(Ns) - 1))
        ax.plot(t, surv, color=c, lw=1.5, label=f"N = {N}")
        if np.nanmax(blow) > 0:
            ax.plot(t, blow, color=c, lw=1.0, ls=":")
    ax.set_xscale("log")
    ax.set_ylim(-0.03, 1.03)
    ax.set_xlabel("time t")
    ax.set_ylabel("fraction of orbits")
    ax.set_title("still regular (solid) and blown up (dotted)")
    ax.grid(alpha=0.3)


def fig_monotone(outcomes, t_evals, path, *, reference=None):
    """The monotonicity figure: chaotic fraction of all orbits and of those that did not blow
    up, blow-up fraction against N at the times t_evals, and the survival curves."""
    import matplotlib.pyplot as plt
    rows = outcome_table(outcomes, t_evals)
    by_t = {t: [r for r in rows if r["t"] == t and r["n"] > 0] for t in t_evals}
    fig, axes = plt.subplots(2, 2, figsize=(10, 8), constrained_layout=True)
    plot_fraction_vs_N(axes[0, 0], by_t, "fraction_chaotic", "(a) chaotic, of all orbits")
    plot_fraction_vs_N(axes[0, 1], by_t, "fraction_chaotic_given_no_blowup",
                       "(b) chaotic, of the orbits that did not blow up")
    plot_fraction_vs_N(axes[1, 0], by_t, "fraction_blowup", "(c) blown up")
    axes[0, 0].set_ylabel("fraction (Wilson 95 % interval)")
    axes[1, 0].set_ylabel("fraction (Wilson 95 % interval)")
    if reference is not None:   # the paper's set-up: 30 realisations to 1e8 (studies/fig12_14)
        ref_rows = [r for r in outcome_table(reference, [1e8]) if r["n"] > 0]
        for ax, key in ((axes[0, 0], "fraction_chaotic"),
                        (axes[0, 1], "fraction_chaotic_given_no_blowup"),
                        (axes[1, 0], "fraction_blowup")):
            _fraction_axes(ax, ref_rows, key, "t = 10$^8$ (30 realisations)", "k", "x", 0.06)
    axes[0, 0].legend(loc="upper left", fontsize=8)
    t = np.logspace(3, math.log10(max(t_evals)), 200)
    plot_survival(axes[1, 1], outcomes, t)
    axes[1, 1].legend(loc="lower left", fontsize=7, ncol=2)
    fig.suptitle("Model 3, alpha = 0.25, tau = 10 %: is the rise of chaos with N monotone?")
    return fig, rows


def fig_threshold(outcomes_by_fraction: dict, t_eval: float, path, *, tau_c: dict):
    """The monotonicity question at a fixed fraction of each size's own threshold: fraction
    chaotic and blown up against N at tau = f tau_c(N), one column per f."""
    import matplotlib.pyplot as plt
    fracs = sorted(outcomes_by_fraction)
    fig, axes = plt.subplots(1, len(fracs), figsize=(5 * len(fracs), 4), squeeze=False,
                             constrained_layout=True)
    rows_all = {}
    for ax, f in zip(axes[0], fracs):
        rows = [r for r in outcome_table(outcomes_by_fraction[f], [t_eval]) if r["n"] > 0]
        rows_all[f] = rows
        _fraction_axes(ax, rows, "fraction_chaotic", "chaotic", _CLASS_COLOURS["chaotic"], "o")
        _fraction_axes(ax, rows, "fraction_blowup", "blown up", _CLASS_COLOURS["blow-up"], "s",
                       0.03)
        Ns = [r["N"] for r in rows]
        ax.set_xscale("log", base=2)
        ax.set_xticks(Ns, [f"{n}\n{f * tau_c[n]:.1f} %" for n in Ns])
        ax.minorticks_off()
        ax.set_ylim(-0.03, 1.03)
        ax.set_xlabel("N (and its tau = f tau_c(N))")
        ax.set_title(f"tau = {f:g} tau_c(N), t = {sci(t_eval)}")
        ax.grid(alpha=0.3)
    axes[0, 0].set_ylabel("fraction (Wilson 95 % interval)")
    axes[0, 0].legend(loc="upper left", fontsize=8)
    fig.suptitle("Model 3 below its own blow-up threshold: chaos against N")
    return fig, rows_all


def fig_models(outcomes_m3, outcomes_m2, t_evals, path):
    """Model 2 (Hamiltonian disorder) against model 3 at tau = 10 %: fraction chaotic and blown
    up against N."""
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    rows = {}
    for ax, (name, o) in zip(axes, (("model 3 (nonlinear couplings)", outcomes_m3),
                                    ("model 2 (Hamiltonian)", outcomes_m2))):
        r = outcome_table(o, t_evals)
        rows[name] = r
        by_t = {t: [x for x in r if x["t"] == t and x["n"] > 0] for t in t_evals}
        plot_fraction_vs_N(ax, by_t, "fraction_chaotic", f"{name}: chaotic")
        last = by_t[max(t_evals)]
        _fraction_axes(ax, last, "fraction_blowup", "blown up (last t)",
                       _CLASS_COLOURS["blow-up"], "s", 0.06)
        ax.legend(loc="upper left", fontsize=8)
    axes[0].set_ylabel("fraction (Wilson 95 % interval)")
    fig.suptitle("tau = 10 %: the Hamiltonian disorder against the paper's model 3")
    return fig, rows


def fig_recurrence(table: dict, path):
    """Recurrence quality (peak share of mode 1 at the ordered chain's first recurrence) and
    the depth of the energy sharing before it, against tau, for models 2 and 3: median and
    quartiles over the realisations; blow-ups counted apart."""
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 3, figsize=(14, 4), constrained_layout=True)
    style = {"nonlinear": ("model 3", "#c0392b", "o"), "hamiltonian": ("model 2", "#2471a3", "s")}
    for model, d in table.items():
        label, colour, marker = style[model]
        taus = np.asarray(d["tau"])
        for ax, key in ((axes[0], "peak"), (axes[1], "dip")):
            v = np.asarray(d[key])          # (tau, seed), NaN where the orbit blew up
            with warnings.catch_warnings():     # a tau where every orbit blew up: NaN
                warnings.simplefilter("ignore", RuntimeWarning)
                med = np.nanmedian(v, axis=1)
                q1, q3 = np.nanpercentile(v, 25, axis=1), np.nanpercentile(v, 75, axis=1)
            ax.plot(taus, med, color=colour, marker=marker, label=label)
            ax.fill_between(taus, q1, q3, color=colour, alpha=0.2)
        axes[2].plot(taus, np.asarray(d["blown_up"]).mean(axis=1), color=colour, marker=marker,
                     label=label)
    axes[0].set_title("(a) mode-1 share at the first recurrence")
    axes[1].set_title("(b) smallest mode-1 share before it")
    axes[2].set_title("(c) fraction blown up before 1.5 t_r")
    for ax in axes:
        ax.set_xlabel("disorder tau (%)")
        ax.set_ylim(-0.03, 1.03)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("E_1 / E (median, quartiles)")
    axes[0].legend()
    fig.suptitle("N = 64, mode-1 initial state: recurrence against disorder")
    return fig


def fig_phase(outcomes_by_tau: dict, t_eval: float, path, *, tau_c_curve):
    """(N, tau) phase diagram of model 3 at t_eval: the fractions chaotic, blown up and
    regular on the grid, with the two-mode theory's tau_c(N) (exact expectation) drawn over."""
    import matplotlib.pyplot as plt
    taus = sorted(outcomes_by_tau)
    Ns = sorted({int(n) for o in outcomes_by_tau.values() for n in np.unique(o.N)})
    grids = {k: np.full((len(taus), len(Ns)), np.nan) for k in ("chaotic", "blow-up", "regular")}
    for i, tau in enumerate(taus):
        for r in outcome_table(outcomes_by_tau[tau], [t_eval]):
            if r["n"] == 0:
                continue
            j = Ns.index(r["N"])
            grids["chaotic"][i, j] = r["chaotic"] / r["n"]
            grids["blow-up"][i, j] = r["blow-up"] / r["n"]
            grids["regular"][i, j] = (r["regular"] + r["undecided"]) / r["n"]
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.6), layout="constrained", sharey=True)
    cmaps = {"chaotic": "Reds", "blow-up": "Greys", "regular": "Blues"}
    Nc, tc = tau_c_curve
    for ax, (k, g) in zip(axes, grids.items()):
        im = ax.pcolormesh(np.arange(len(Ns) + 1) - 0.5, np.arange(len(taus) + 1) - 0.5, g,
                           vmin=0, vmax=1, cmap=cmaps[k])
        for i in range(len(taus)):
            for j in range(len(Ns)):
                if np.isfinite(g[i, j]):
                    ax.text(j, i, f"{g[i, j]:.2f}", ha="center", va="center", fontsize=7,
                            color="white" if g[i, j] > 0.6 else "black")
        # tau_c(N) on the index axes: interpolate log2 N -> column, tau -> row
        cols = np.interp(np.log2(Nc), np.log2(Ns), np.arange(len(Ns)))
        rows = np.interp(tc, taus, np.arange(len(taus)), left=np.nan, right=np.nan)
        ax.plot(cols, rows, "k--", lw=1.5, label="tau_c(N), two-mode theory")
        ax.set_xticks(range(len(Ns)), [str(n) for n in Ns])
        ax.set_yticks(range(len(taus)), [f"{t:g}" for t in taus])
        ax.set_xlabel("N")
        ax.set_title(f"{k}")
        fig.colorbar(im, ax=ax, fraction=0.05)
    axes[0].set_ylabel("disorder tau (%)")
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles[:1], labels[:1], loc="outside lower center", fontsize=8)
    fig.suptitle(f"Model 3 at t = {sci(t_eval)}: fraction of the "
                 "realisations in each class")
    return fig, grids



# ---- the studies and the driver ---------------------------------------------------------------

#: the sizes of the monotonicity study
ALL_N = (4, 8, 12, 16, 24, 32, 48, 64, 96, 128)
#: the sizes and fractions of tau_c(N) of the threshold studies
THRESHOLD_N = (8, 16, 32, 64, 128)
THRESHOLD_FRACTIONS = (0.5, 0.9)
#: the (N, tau) grid of the phase diagram
PHASE_N = (8, 16, 32, 64)
PHASE_TAU = (0, 2, 4, 6, 8, 10, 12, 14)
#: the recurrence study: N = 64, tau = 0..20 %, 20 realisations, to 1.5 t_r
RECURRENCE_TAU = (0.0, 2.0, 4.0, 6.0, 8.0, 10.0, 12.0, 14.0, 16.0, 18.0, 20.0)
RECURRENCE_SEEDS = tuple(range(1, 21))
RECURRENCE_T_END = 8.4e4
RECURRENCE_EVERY = 100.0


def threshold_tau(N: int, fraction: float) -> float:
    """fraction x tau_c(N), tau_c from the exact expectation of the two-mode coefficient B~
    (percent, rounded to 1e-4 as the study directories record it)."""
    from .reduction.statistics import critical_tolerance
    return round(fraction * critical_tolerance(N, R=2).exact, 4)


def chaos_studies() -> dict:
    """name -> ChaosStudy parameters of every chaos study of the open questions (the work
    directory of each is WORK_DIR/name)."""
    out = {"monotone": dict(Ns=ALL_N, realisations=100, t_end=1e7),
           "model2": dict(Ns=(4, 8, 16, 24, 32, 48, 64), realisations=50, t_end=1e7,
                          model="hamiltonian")}
    for frac in THRESHOLD_FRACTIONS:
        for N in THRESHOLD_N:
            out[f"tauc/f{frac}_N{N:03d}"] = dict(Ns=(N,), realisations=30,
                                                 tau=threshold_tau(N, frac), t_end=1e7)
    for tau in PHASE_TAU:
        out[f"phase/tau{tau:02d}"] = dict(Ns=PHASE_N, realisations=20, tau=float(tau), t_end=1e6)
    return out


def _recurrence_study(work_dir, model, t_until, workers, progress):
    from .engine import run_study
    grid = {"N": [64], "tau": list(RECURRENCE_TAU), "seed": list(RECURRENCE_SEEDS)}
    return run_study("recurrence", grid, {"model": model, "sample_every": RECURRENCE_EVERY},
                     RECURRENCE_T_END if t_until else
                     _reached(work_dir), work_dir=work_dir, workers=workers, progress=progress)


def _reached(work_dir) -> float:
    from .io.store import StudyStore
    t = StudyStore.reader(work_dir).t_end()
    if t is None:
        raise ValueError(f"{work_dir}: the recurrence study has not been run (give t_until)")
    return t


def recurrence_table(ds) -> dict:
    """{tau, seed, peak, dip, blown_up, t_recurrence} of a recurrence study's labelled result
    (N = 64): t_r is the first recurrence of its tau = 0 run."""
    t = ds["t"].values
    share = ds["share"].values[0]            # (tau, seed, sample, mode) at the one N
    taus = [float(v) for v in ds["tau"].values]
    t_r = recurrence_time(t, share[taus.index(0.0), 0])
    peak = np.full(share.shape[:2], np.nan)
    dip = np.full_like(peak, np.nan)
    blown = ds["blew_up"].values[0].astype(bool)
    for i in range(share.shape[0]):
        for j in range(share.shape[1]):
            if not blown[i, j] or ds["t_stop"].values[0, i, j] >= 1.5 * t_r:
                peak[i, j], dip[i, j] = recurrence_quality(t, share[i, j], t_r)
    return {"tau": taus, "seed": [int(s) for s in ds["seed"].values], "peak": peak, "dip": dip,
            "blown_up": blown, "t_recurrence": t_r}


def open_questions(out_dir=".", *, work_dir="studies/open_questions", t_until=None,
                   workers=None, progress=True, reference_dir="studies/fig12_14",
                   formats=("png",)) -> list:
    """Continue every study of the open questions to `t_until` (None: only draw what is
    stored) and draw their figures into `out_dir`; returns the figures (their numbers: the
    tables, the monotonicity tests). Resumable: rerun to continue."""
    import json
    import os

    import matplotlib.pyplot as plt

    from ._figure import save, target
    from .chaos.study import ChaosStudy
    from .reduction.statistics import critical_tolerance

    work = os.fspath(work_dir)
    loaded = {}
    for name, params in chaos_studies().items():
        if t_until is None and not os.path.isdir(os.path.join(work, name)):
            continue                    # not run yet: its figure is left out
        study = ChaosStudy(os.path.join(work, name), **params)
        if t_until is not None:
            study.run(t_until=min(float(t_until), params["t_end"]), workers=workers,
                      progress=progress)
        loaded[name] = outcomes_from_dataset(study.result().to_xarray())
    rec = {}
    for model in ("nonlinear", "hamiltonian"):
        d = os.path.join(work, f"recurrence_{model}")
        rec[model] = recurrence_table(
            _recurrence_study(d, model, t_until, workers, progress).to_xarray())
    reached = {name: float(np.nanmin(np.where(np.isnan(o.t_chaotic) & np.isnan(o.t_blowup),
                                              o.t_reached, np.inf)))
               for name, o in loaded.items()}
    figs, numbers = [], {"reached": reached}

    mono = loaded["monotone"]
    t_mono = _times((1e4, 1e5, 1e6, 1e7), reached["monotone"])
    ref = None
    if reference_dir and os.path.isdir(reference_dir):
        ref = outcomes_from_dataset(ChaosStudy(reference_dir).result().to_xarray())
    fig, rows = fig_monotone(mono, t_mono, None, reference=ref)
    tests = {f"{t:g}": {k: monotonicity([r for r in rows if r["t"] == t and r["n"] > 0], k)
                        for k in ("fraction_chaotic", "fraction_chaotic_given_no_blowup")}
             for t in t_mono}
    numbers["monotone"] = {"rows": rows, "tests": tests}
    figs.append(save(fig, target(out_dir, "open_monotone.png"), numbers["monotone"]))

    t_m = _times((1e5, 1e6, 1e7), min(reached["model2"], reached["monotone"]))
    fig, rows = fig_models(mono, loaded["model2"], t_m, None)
    numbers["models"] = rows
    figs.append(save(fig, target(out_dir, "open_models.png"), {"models": rows}))

    have = lambda prefix, n: sum(name.startswith(prefix) for name in loaded) == n
    if not have("tauc/", len(THRESHOLD_N) * len(THRESHOLD_FRACTIONS)):
        return _finish(figs, numbers, out_dir, rec)
    t_thr = min(reached[n] for n in loaded if n.startswith("tauc/"))
    t_thr = max([t for t in (1e4, 1e5, 1e6, 1e7) if t <= t_thr * (1 + 1e-12)], default=1e4)
    by_f = {}
    for frac in THRESHOLD_FRACTIONS:
        parts = [loaded[f"tauc/f{frac}_N{N:03d}"] for N in THRESHOLD_N]
        by_f[frac] = OrbitOutcomes(*(np.concatenate([getattr(p, a) for p in parts])
                                     for a in ("N", "seed", "t_chaotic", "t_blowup",
                                               "t_reached")))
    tau_c = {N: critical_tolerance(N, R=2).exact for N in THRESHOLD_N}
    fig, rows = fig_threshold(by_f, t_thr, None, tau_c=tau_c)
    numbers["threshold"] = {"t": t_thr, "rows": {str(f): r for f, r in rows.items()},
                            "tests": {str(f): monotonicity(r) for f, r in rows.items()}}
    figs.append(save(fig, target(out_dir, "open_threshold.png"), numbers["threshold"]))

    return _finish(figs, numbers, out_dir, rec, loaded, reached)


def _times(decades, reached: float) -> list:
    """The decades up to the time every orbit has reached, and that time itself (a study
    continued in pieces stops between decades: its latest numbers are shown too)."""
    out = [t for t in decades if t <= reached * (1 + 1e-12)]
    if math.isfinite(reached) and (not out or reached > out[-1] * (1 + 1e-9)):
        out.append(float(reached))
    return out


def _numbers_path(out_dir) -> str:
    """open_questions.json beside the figures (out_dir, or the folder of a figure file name)."""
    import os
    out = os.fspath(out_dir)
    folder = os.path.dirname(out) if os.path.splitext(out)[1] else out
    if folder:
        os.makedirs(folder, exist_ok=True)
    return os.path.join(folder, "open_questions.json")


def _finish(figs, numbers, out_dir, rec, loaded=None, reached=None):
    """The figures that need only the recurrence and the phase-diagram studies, and the
    numbers file."""
    import json

    import matplotlib.pyplot as plt

    from ._figure import save, target
    from .reduction.statistics import critical_tolerance
    fig = fig_recurrence(rec, None)
    with warnings.catch_warnings():     # tau where every orbit blew up: NaN, said so
        warnings.simplefilter("ignore", RuntimeWarning)
        numbers["recurrence"] = {m: {"tau": d["tau"], "t_recurrence": d["t_recurrence"],
                                 "peak_median": np.nanmedian(d["peak"], axis=1).tolist(),
                                     "dip_median": np.nanmedian(d["dip"], axis=1).tolist(),
                                     "blown_up": d["blown_up"].mean(axis=1).tolist()}
                                 for m, d in rec.items()}
    figs.append(save(fig, target(out_dir, "open_recurrence.png"), numbers["recurrence"]))

    if loaded is None or sum(n.startswith("phase/") for n in loaded) != len(PHASE_TAU):
        plt.close("all")
        with open(_numbers_path(out_dir), "w") as fh:
            json.dump(numbers, fh, indent=1, default=float)
        return figs
    t_ph = min(reached[n] for n in loaded if n.startswith("phase/"))
    t_ph = max([t for t in (1e4, 1e5, 1e6) if t <= t_ph * (1 + 1e-12)], default=1e4)
    Nc = np.arange(PHASE_N[0], PHASE_N[-1] + 1)
    curve = (Nc, np.array([critical_tolerance(int(n), R=2).exact for n in Nc]))
    fig, grids = fig_phase({float(t): loaded[f"phase/tau{t:02d}"] for t in PHASE_TAU}, t_ph,
                           None, tau_c_curve=curve)
    numbers["phase"] = {"t": t_ph, **{k: g.tolist() for k, g in grids.items()}}
    figs.append(save(fig, target(out_dir, "open_phase.png"), numbers["phase"]))
    plt.close("all")
    with open(_numbers_path(out_dir), "w") as fh:
        json.dump(numbers, fh, indent=1, default=float)
    return figs


def _pct(f, lo, hi) -> str:
    if not np.isfinite(f):
        return "–"
    return f"{100 * f:.0f} % ({100 * lo:.0f}–{100 * hi:.0f})"


def monotone_markdown(rows: list[dict], t: float) -> str:
    """The README / docs table of the monotonicity study at time t: per N the counts chaotic /
    regular (+ undecided) / blow-up and the fractions chaotic of all orbits and of those that did
    not blow up, with Wilson 95 % intervals. Generated from the stored study (a test compares
    the README with it)."""
    lines = [f"| N | chaotic / regular / undecided / blow-up at t = {t:.0e} | chaotic, of all "
             "| chaotic, of those not blown up |",
             "|---|---|---|---|"]
    for r in sorted((r for r in rows if r["t"] == t and r["n"] > 0), key=lambda r: r["N"]):
        lines.append(
            f"| {r['N']} | {r['chaotic']} / {r['regular']} / {r['undecided']} / {r['blow-up']} | "
            f"{_pct(r['fraction_chaotic'], r['fraction_chaotic_low'], r['fraction_chaotic_high'])}"
            f" | {_pct(r['fraction_chaotic_given_no_blowup'], r['fraction_chaotic_given_no_blowup_low'], r['fraction_chaotic_given_no_blowup_high'])} |")
    return "\n".join(lines)


def _power(t: float) -> str:
    """t as text: 10⁶, 2×10⁶, 2.5×10⁶."""
    e = math.floor(math.log10(t))
    m = round(t / 10.0 ** e, 2)
    sup = str(e).translate(str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹"))
    return f"10{sup}" if m == 1 else f"{m:g}×10{sup}"


def reached_markdown(loaded: dict, per_N: bool = True) -> str:
    """The README / docs table of how far each chaos study of the open questions has followed
    its orbits, per study and N (per study only if not `per_N`): the orbits neither chaotic nor
    blown up (regular or undecided: followed on) and the time every one of them has reached;
    "all decided" where none is left. Generated from the stored studies (`loaded`: name ->
    OrbitOutcomes)."""
    lines = ["| study | N | orbits | neither chaotic nor blown up | followed to |",
             "|---|---|---|---|---|"]
    for name in sorted(loaded, key=lambda n: (n != "monotone", n)):
        o = loaded[name]
        sizes = np.unique(o.N)
        for N in (sizes if per_N else [None]):
            sel = o.N == N if per_N else np.ones(o.N.size, bool)
            label = N if per_N else ", ".join(str(n) for n in sizes)
            open_ = sel & np.isnan(o.t_chaotic) & np.isnan(o.t_blowup)
            t = float(np.min(o.t_reached[open_])) if open_.any() else math.nan
            lines.append(f"| `{name}` | {label} | {int(sel.sum())} | {int(open_.sum())} | "
                         + (f"t = {_power(t)}" if open_.any() else "all decided") + " |")
    return "\n".join(lines)


def _p(p: float) -> str:
    e = math.floor(math.log10(p)) if p > 0 else 0
    m = round(p / 10.0 ** e)
    if m == 10:
        m, e = 1, e + 1
    sup = str(e).translate(str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹"))
    return f"{p:.2g}" if p >= 0.01 else f"{m}×10{sup}"


def answer_markdown(outcomes: OrbitOutcomes, t: float) -> str:
    """The monotonicity answer of one chaos study at time t, as Markdown bullets: where the
    chaotic fraction peaks and every significant decrease after it (Fisher's exact test,
    Bonferroni over all pairs of sizes), of all orbits and of those that did not blow up.
    Generated from the stored study, so the README states no number by hand."""
    rows = [r for r in outcome_table(outcomes, [t]) if r["n"] > 0]
    out = []
    for key, what in (("fraction_chaotic", "of all orbits"),
                      ("fraction_chaotic_given_no_blowup", "of the orbits that did not blow up")):
        if key != "fraction_chaotic" and not any(r["blow-up"] for r in rows):
            continue                            # no blow-up: the same numbers again
        ok = [r for r in rows if np.isfinite(r[key])]
        top = max(ok, key=lambda r: r[key])
        test = monotonicity(ok, key)
        drops = [d for d in test["significant_decreases"] if d["from_N"] == top["N"]]
        head = (f"- chaotic fraction {what}: largest at N = {top['N']}, "
                f"{_pct(top[key], top[key + '_low'], top[key + '_high'])}; ")
        if test["monotone"]:
            out.append(head + f"no significant decrease between any two sizes "
                       f"(Fisher, Bonferroni over {test['pairs']} pairs): **monotone within "
                       "the errors**")
            continue
        fall = drops or test["significant_decreases"]
        by_n = {r["N"]: r for r in ok}
        parts = [f"N = {d['from_N']} → {d['to_N']}: {_pct(d['from'], *_ci(by_n[d['from_N']], key))}"
                 f" → {_pct(d['to'], *_ci(by_n[d['to_N']], key))}, p = {_p(d['p'])}"
                 for d in fall]
        out.append(head + "significant decreases (Fisher, Bonferroni over "
                   f"{test['pairs']} pairs): " + "; ".join(parts) + ": **not monotone**")
    return "\n".join(out)


def _ci(row, key):
    return row[key + "_low"], row[key + "_high"]


#: the generated blocks of README.md and docs/open_questions.md:
#: <!-- open-questions[:STUDY] [t=T] --> ... <!-- end -->; STUDY monotone (default), model2
#: (the monotonicity table of that study at t), answer / answer_model2 (`answer_markdown`),
#: reached (`reached_markdown` of monotone and model2) or reached_other (the other studies)
GENERATED = re.compile(r"<!-- open-questions(?::(\w+))?(?: t=(\S+))? -->\n"
                       r"((?:(?!<!--).)*?)<!-- end -->", re.S)


def generated_tables(text: str, work_dir="studies/open_questions") -> str:
    """`text` (a page) with every generated block (`GENERATED`) rewritten from the stored
    studies in `work_dir` (nothing is computed). tools/update-open-tables.py applies it to the
    README and docs/open_questions.md; a test checks they are up to date."""
    import os

    from .chaos.study import ChaosStudy
    cache: dict = {}

    def outcomes(name):
        if name not in cache:
            cache[name] = outcomes_from_dataset(
                ChaosStudy(os.path.join(os.fspath(work_dir), name)).result().to_xarray())
        return cache[name]

    def block(m):
        study, t = m.group(1) or "monotone", m.group(2)
        if study.startswith("answer"):           # answer (monotone) or answer_model2
            name = study.partition("_")[2] or "monotone"
            if t is None:
                raise ValueError(f"generated block {m.group(0).splitlines()[0]} needs t=")
            body = answer_markdown(outcomes(name), float(t))
        elif study in ("reached", "reached_other"):
            names = [n for n in chaos_studies() if os.path.isdir(os.path.join(work_dir, n))
                     and (n in ("monotone", "model2")) == (study == "reached")]
            body = reached_markdown({n: outcomes(n) for n in names},
                                    per_N=study == "reached")
        else:
            if t is None:
                raise ValueError(f"generated block {m.group(0).splitlines()[0]} needs t=")
            body = monotone_markdown(outcome_table(outcomes(study), [float(t)]), float(t))
        head = m.group(0).splitlines()[0]
        return f"{head}\n{body}\n<!-- end -->"  # noqa: E501
    return GENERATED.sub(block, text)
