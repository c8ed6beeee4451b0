"""Outcome statistics of chaos ensembles: class fractions with Wilson intervals, competing
risks (chaos against blow-up), survival curves and a monotonicity check along N.

Each orbit of an ensemble ends in one of two absorbing events, turning chaotic (SALI below its
threshold) or blowing up (escape over the potential barrier), or neither by the time it has
reached. Blow-ups compete with chaos: an orbit that blows up at t = 1e4 can never be called
chaotic later, so the fraction chaotic among *all* orbits and among those that did *not* blow
up answer different questions; both are reported. With every orbit followed to the same
horizon there is no censoring before it, so the cumulative incidence of each event is its
empirical fraction (the Aalen-Johansen estimator reduces to it).
"""
from __future__ import annotations

import math

import numpy as np

from ..engine import wilson_interval

__all__ = ["OrbitOutcomes", "outcome_table", "cumulative_incidence", "monotonicity",
           "outcomes_from_dataset"]

class OrbitOutcomes:
    """Per-orbit outcomes of one ensemble (arrays of equal length): N, seed, when the orbit
    turned chaotic (nan: never), when it blew up (nan: never), and how far it was followed."""

    def __init__(self, N, seed, t_chaotic, t_blowup, t_reached, classify=None):
        self.N = np.asarray(N, int)
        self.seed = np.asarray(seed, int)
        self.t_chaotic = np.asarray(t_chaotic, float)
        self.t_blowup = np.asarray(t_blowup, float)
        self.t_reached = np.asarray(t_reached, float)
        # classify(i, t) -> 'regular' | 'undecided' for an orbit neither chaotic nor blown up
        # by t (the lambda ~ 1/t test on its samples); None: all such orbits count as regular
        self._classify = classify

    def classes(self, t: float) -> np.ndarray:
        """The class of every orbit at time t: chaotic, blow-up, regular, undecided or
        'not reached' (followed to a time before t without being decided)."""
        out = np.empty(self.N.size, dtype=object)
        for i in range(self.N.size):
            if self.t_chaotic[i] <= t:
                out[i] = "chaotic"
            elif self.t_blowup[i] <= t:
                out[i] = "blow-up"
            elif self.t_reached[i] < t * (1 - 1e-12):
                out[i] = "not reached"
            else:
                out[i] = self._classify(i, t) if self._classify else "regular"
        return out


def outcome_table(outcomes: OrbitOutcomes, t_evals) -> list[dict]:
    """Rows {t, N, n, chaotic, regular, undecided, blow-up, not reached, and the fractions
    fraction_chaotic (of all orbits that reached t or were decided by it), fraction_blowup and
    fraction_chaotic_given_no_blowup (of those that did not blow up), each with its Wilson 95 %
    interval (_low, _high)}."""
    rows = []
    for t in t_evals:
        cls = outcomes.classes(float(t))
        for N in np.unique(outcomes.N):
            c = cls[outcomes.N == N]
            row = {"t": float(t), "N": int(N)}
            for name in ("chaotic", "regular", "undecided", "blow-up", "not reached"):
                row[name] = int(np.sum(c == name))
            n = row["chaotic"] + row["regular"] + row["undecided"] + row["blow-up"]
            nb = n - row["blow-up"]
            row["n"] = n
            for key, k, m in (("fraction_chaotic", row["chaotic"], n),
                              ("fraction_blowup", row["blow-up"], n),
                              ("fraction_chaotic_given_no_blowup", row["chaotic"], nb)):
                row[key] = k / m if m else math.nan
                row[key + "_low"], row[key + "_high"] = wilson_interval(k, m)
            rows.append(row)
    return rows


def cumulative_incidence(outcomes: OrbitOutcomes, N: int, t):
    """(still regular, chaotic, blown up) fractions of the N-orbits at the times t: the
    survival curve "neither event yet" and the two cumulative incidences (they add up to 1
    while every orbit is followed; orbits not followed to t leave the denominators)."""
    sel = outcomes.N == N
    tc, tb, tr = outcomes.t_chaotic[sel], outcomes.t_blowup[sel], outcomes.t_reached[sel]
    t = np.asarray(t, float)
    surv, chaos, blow = (np.full(t.shape, np.nan) for _ in range(3))
    for j, tj in enumerate(t):
        ch = tc <= tj
        bl = (tb <= tj) & ~ch
        at = ch | bl | (tr >= tj * (1 - 1e-12))
        n = int(at.sum())
        if n:
            chaos[j] = ch.sum() / n
            blow[j] = bl.sum() / n
            surv[j] = 1.0 - chaos[j] - blow[j]
    return surv, chaos, blow


def _two_proportion_p(k1, n1, k2, n2) -> float:
    """Two-sided p-value of Fisher's exact test for k1/n1 against k2/n2."""
    from scipy.stats import fisher_exact
    return float(fisher_exact([[k1, n1 - k1], [k2, n2 - k2]])[1])


def monotonicity(rows: list[dict], key: str = "fraction_chaotic", *, alpha: float = 0.05) -> dict:
    """Is the fraction `key` non-decreasing along N (rows of one t, as from outcome_table)?
    Every pair N_i < N_j whose fraction falls with Fisher's exact two-sided p below alpha / m
    (Bonferroni over the m pairs compared) is a significant decrease; `monotone` is True if
    there is none."""
    rows = sorted(rows, key=lambda r: r["N"])
    m = max(1, len(rows) * (len(rows) - 1) // 2)
    base = {"fraction_chaotic": "n", "fraction_blowup": "n",
            "fraction_chaotic_given_no_blowup": None}[key]
    falls = []
    for i, a in enumerate(rows):
        for b in rows[i + 1:]:
            na = a["n"] if base else a["n"] - a["blow-up"]
            nb = b["n"] if base else b["n"] - b["blow-up"]
            ka = a["blow-up"] if key == "fraction_blowup" else a["chaotic"]
            kb = b["blow-up"] if key == "fraction_blowup" else b["chaotic"]
            if na == 0 or nb == 0 or kb / nb >= ka / na:
                continue
            p = _two_proportion_p(ka, na, kb, nb)
            if p < alpha / m:
                falls.append({"from_N": a["N"], "to_N": b["N"], "from": ka / na, "to": kb / nb,
                              "p": p})
    return {"key": key, "monotone": not falls, "significant_decreases": falls,
            "pairs": m, "alpha": alpha}


def outcomes_from_dataset(ds, tau=None) -> OrbitOutcomes:
    """The outcomes of the orbits of a chaos study's labelled result (`StudyResult.to_xarray()`
    of kind "chaos"), at one tau (default: the only one); the class between decisions by the
    C rule on each orbit's lambda(t) samples (`classify_orbit`)."""
    from .result import classify_orbit
    taus = [float(t) for t in ds["tau"].values]
    if tau is None:
        if len(taus) != 1:
            raise ValueError(f"tau: the study has {len(taus)} values ({taus}); pick one")
        tau = taus[0]
    j = taus.index(float(tau))
    N, seed, tc, tb, tr, samples = [], [], [], [], [], []
    for i, n in enumerate(ds["N"].values):
        for k, s in enumerate(ds["seed"].values):
            g = lambda name: ds[name].values[i, j, k]
            if not np.isfinite(g("t_final")) and not bool(g("blew_up")):
                continue                     # not started
            N.append(int(n))
            seed.append(int(s))
            tc.append(float(g("t_chaotic")) if bool(g("chaotic")) else math.nan)
            tb.append(float(g("t_blowup")) if bool(g("blew_up")) else math.nan)
            tr.append(float(g("t_blowup")) if bool(g("blew_up")) else float(g("t_final")))
            samples.append((np.asarray(g("t_sample"), float), np.asarray(g("mle_t"), float),
                            bool(g("chaotic")), float(g("t_chaotic")), bool(g("blew_up")),
                            float(g("t_blowup")), float(g("t_final"))))

    def classify(i, t):
        ts, mle, ch, t_ch, bl, t_bl, t_fin = samples[i]
        ok = np.isfinite(ts)
        return classify_orbit(ts[ok], mle[ok], chaotic=ch, t_chaotic=t_ch, blew_up=bl,
                              t_blowup=t_bl, t_final=t_fin, t_eval=t)
    return OrbitOutcomes(N, seed, tc, tb, tr, classify=classify)
