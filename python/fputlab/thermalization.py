"""Observables of the approach to equipartition: spectral entropies, the normalised entropy
eta(t), the effective number of modes n_eff, the equipartition time T_eq with a bootstrap
interval over the ensemble, and power-law fits T_eq ~ eps^-a.

Definitions (docs/thermalization.md). For harmonic mode energies e_k, k = 1..M (M = N on a
fixed chain, M = N - 1 travelling waves on a periodic one; `initial_states.wave_energies`):

* f_k = M e_k / sum_j e_j, so f_k = 1 for every k at equipartition;
* the information entropy S = sum_k f_k ln f_k (>= 0, 0 only at equipartition; M ln M for a
  single mode) -- the entropy of Onorato, Vozella, Proment & Lvov (PNAS 2015) and of nlchains
  ("information entropy"); S/M = ln M - S_Shannon with S_Shannon = -sum_k (f_k/M) ln(f_k/M);
* the wave-turbulence entropy S_WT = -sum_k ln f_k (>= 0, 0 only at equipartition; Pistone et
  al. 2019, nlchains' "Wave Turbulence entropy");
* eta(t) = S(t)/S(0): 1 at the start, 0 at equipartition (equivalently
  (S_max - S_Shannon(t))/(S_max - S_Shannon(0)) with S_max = ln M: Livi et al. 1985);
* n_eff = exp(S_Shannon)/M = exp(-S/M) in (0, 1]: 1/M for one mode, 1 at equipartition
  (Goedde, Lichtenberg & Lieberman 1992).

Per-orbit quantities take the energies of one orbit; the ensemble quantities (the papers')
take the ensemble average <e_k>(t) first and the entropy of that spectrum after.
"""
from __future__ import annotations

import math

import numpy as np

from ._validate import C_U64, _int, _real

__all__ = ["normalized_spectrum", "information_entropy", "wave_turbulence_entropy", "eta",
           "effective_modes", "ensemble_spectrum", "first_crossing", "equipartition_time",
           "fit_power_law", "ENTROPIES"]


def _energies(e, name="energies") -> np.ndarray:
    arr = np.asarray(e, dtype=float)
    if arr.ndim < 1 or arr.shape[-1] < 2:
        raise ValueError(f"{name} must have at least 2 modes on its last axis, "
                         f"got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} has non-finite entries")
    if np.any(arr < 0):
        raise ValueError(f"{name} has negative entries (mode energies are >= 0)")
    if np.any(arr.sum(axis=-1) <= 0):
        raise ValueError(f"{name}: a spectrum with zero total energy has no entropy")
    return arr


def normalized_spectrum(energies) -> np.ndarray:
    """f_k = M e_k / sum_j e_j over the last axis (M modes): 1 everywhere at equipartition."""
    e = _energies(energies)
    return e.shape[-1] * e / e.sum(axis=-1, keepdims=True)


def information_entropy(energies) -> np.ndarray:
    """S = sum_k f_k ln f_k over the last axis (0 at equipartition, M ln M for one mode)."""
    f = normalized_spectrum(energies)
    with np.errstate(divide="ignore", invalid="ignore"):
        terms = np.where(f > 0, f * np.log(np.where(f > 0, f, 1.0)), 0.0)
    return terms.sum(axis=-1)


def wave_turbulence_entropy(energies) -> np.ndarray:
    """S_WT = -sum_k ln f_k over the last axis (0 at equipartition, +inf if a mode is empty)."""
    f = normalized_spectrum(energies)
    with np.errstate(divide="ignore"):
        return -np.log(f).sum(axis=-1)


#: entropy name -> function
ENTROPIES = {"information": information_entropy, "wave_turbulence": wave_turbulence_entropy}


def _entropy_fn(entropy):
    if entropy not in ENTROPIES:
        raise ValueError(f"entropy {entropy!r} is unknown (known: {', '.join(ENTROPIES)})")
    return ENTROPIES[entropy]


def eta(energies, *, entropy: str = "information", reference=None) -> np.ndarray:
    """eta = S / S_ref for spectra e of shape (T, M) (a time series, the first row the start):
    S_ref = S of the first spectrum unless `reference` (a spectrum or a number) is given."""
    fn = _entropy_fn(entropy)
    s = fn(energies)
    if reference is None:
        if np.ndim(s) < 1:
            raise ValueError("energies: eta of a single spectrum needs a reference")
        s_ref = s[..., :1]
    elif np.ndim(reference) == 0:
        s_ref = _real(reference, "reference")
    else:
        s_ref = fn(reference)
    s_ref = np.asarray(s_ref, dtype=float)
    if np.any(s_ref <= 0) or not np.all(np.isfinite(s_ref)):
        raise ValueError("reference: the reference entropy must be finite and > 0 "
                         "(an equipartitioned start has none)")
    return s / s_ref


def effective_modes(energies) -> np.ndarray:
    """n_eff = exp(-S/M) = exp(S_Shannon)/M: 1/M for a single mode, 1 at equipartition."""
    e = _energies(energies)
    return np.exp(-information_entropy(e) / e.shape[-1])


def ensemble_spectrum(energies) -> np.ndarray:
    """<e_k>(t): the ensemble average of per-orbit spectra of shape (R, T, M) -> (T, M)."""
    e = np.asarray(energies, dtype=float)
    if e.ndim != 3:
        raise ValueError(f"energies must have shape (orbits, times, modes), got {e.shape}")
    return e.mean(axis=0)


def first_crossing(t, y, threshold: float) -> float:
    """The first time y(t) falls to `threshold` or below, linearly interpolated between the
    samples in log t (t > 0) or t; nan if it never does (and 0 if it starts there)."""
    t = np.asarray(t, dtype=float)
    y = np.asarray(y, dtype=float)
    if t.shape != y.shape or t.ndim != 1:
        raise ValueError(f"t and y must be 1-D of the same length, got {t.shape}, {y.shape}")
    below = np.flatnonzero(y <= threshold)
    if below.size == 0:
        return math.nan
    i = int(below[0])
    if i == 0:
        return float(t[0])
    t0, t1, y0, y1 = t[i - 1], t[i], y[i - 1], y[i]
    w = (y0 - threshold) / (y0 - y1)
    if t0 > 0:
        return float(math.exp(math.log(t0) + w * (math.log(t1) - math.log(t0))))
    return float(t0 + w * (t1 - t0))


def equipartition_time(t, energies, *, threshold: float = 0.1, entropy: str = "information",
                       n_boot: int = 200, level: float = 0.9, seed: int = 0) -> dict:
    """T_eq: the first time the ensemble eta(t) falls to `threshold`, with a bootstrap interval.

    Parameters
    ----------
    t : array_like, shape (T,)
        Sample times (t[0] the start: eta is normalised by the entropy there).
    energies : array_like, shape (R, T, M)
        Per-orbit mode energies of R orbits.
    threshold : float, optional
        The eta level that counts as equipartition (0 < threshold < 1).
    entropy : {"information", "wave_turbulence"}, optional
    n_boot : int, optional
        Bootstrap resamples of the orbits (with replacement); 0 for none.
    level : float, optional
        Coverage of the percentile interval.
    seed : int, optional
        Seed of the resampling (``Generator(PCG64(seed))``).

    Returns
    -------
    dict
        ``t_eq`` (nan if eta never reaches the threshold), ``interval`` (lo, hi) (nan where too
        few resamples cross), ``boot`` (the resampled T_eq, nan for those that never cross),
        ``eta`` (the ensemble eta(t)), ``threshold``, ``orbits``.
    """
    t = np.asarray(t, dtype=float)
    e = np.asarray(energies, dtype=float)
    if e.ndim != 3 or e.shape[1] != t.size:
        raise ValueError(f"energies must have shape (orbits, {t.size}, modes), got {e.shape}")
    threshold = _real(threshold, "threshold")
    if not 0 < threshold < 1:
        raise ValueError(f"threshold must lie in (0, 1), got {threshold:g}")
    level = _real(level, "level")
    if not 0 < level < 1:
        raise ValueError(f"level must lie in (0, 1), got {level:g}")
    n_boot = _int(n_boot, "n_boot")
    if n_boot < 0:
        raise ValueError(f"n_boot must be >= 0, got {n_boot}")
    fn = _entropy_fn(entropy)
    R = e.shape[0]

    def t_of(spec):
        s = fn(spec)
        return first_crossing(t, s / s[0], threshold), s / s[0]

    t_eq, eta_t = t_of(e.mean(axis=0))
    rng = np.random.Generator(np.random.PCG64(_int(seed, "seed", C_U64)))
    boot = np.array([t_of(e[rng.integers(0, R, R)].mean(axis=0))[0] for _ in range(n_boot)])
    lo = hi = math.nan
    if n_boot and np.isfinite(boot).mean() >= level:
        # resamples that never cross count as +inf: an upper bound then stays honest
        b = np.where(np.isfinite(boot), boot, np.inf)
        # an observed value as each quantile (no interpolation towards +inf)
        lo, hi = np.quantile(b, [(1 - level) / 2, (1 + level) / 2], method="inverted_cdf")
        lo, hi = float(lo), float(hi)
    return {"t_eq": t_eq, "interval": (lo, hi), "boot": boot, "eta": eta_t,
            "threshold": threshold, "orbits": R}


def fit_power_law(eps, t_eq, boot=None, *, level: float = 0.9, seed: int = 0) -> dict:
    """Least-squares fit log T_eq = c - a log eps (T_eq ~ eps^-a) with a bootstrap interval.

    Parameters
    ----------
    eps, t_eq : array_like, shape (P,)
        Nonlinearities and equipartition times (P >= 2 finite points are used).
    boot : array_like, shape (P, B), optional
        Bootstrap replicates of each T_eq (e.g. ``equipartition_time(...)["boot"]``): the fit
        is repeated on replicate b of every point; the interval is the percentile interval of
        those exponents. Without it, the interval is the t-based one of the regression (needs
        P >= 3).
    level : float, optional
        Coverage of the interval.

    Returns
    -------
    dict
        ``exponent`` a, ``prefactor`` e^c, ``interval`` (lo, hi) of a, ``points`` used.
    """
    x = np.asarray(eps, dtype=float)
    y = np.asarray(t_eq, dtype=float)
    if x.shape != y.shape or x.ndim != 1:
        raise ValueError("eps and t_eq must be 1-D of the same length")
    ok = np.isfinite(x) & np.isfinite(y) & (x > 0) & (y > 0)
    if ok.sum() < 2:
        raise ValueError("t_eq: a power-law fit needs at least 2 finite positive points")
    lx, ly = np.log(x[ok]), np.log(y[ok])
    slope, icpt = np.polyfit(lx, ly, 1)
    a = -float(slope)
    lo = hi = math.nan
    if boot is not None:
        b = np.asarray(boot, dtype=float)
        if b.ndim != 2 or b.shape[0] != x.size:
            raise ValueError(f"boot must have shape ({x.size}, B), got {b.shape}")
        bb = b[ok]
        good = np.all(np.isfinite(bb) & (bb > 0), axis=0)
        if good.sum() >= 10:
            slopes = [-np.polyfit(lx, np.log(bb[:, j]), 1)[0] for j in np.flatnonzero(good)]
            lo, hi = (float(q) for q in np.quantile(slopes, [(1 - level) / 2, (1 + level) / 2]))
    elif ok.sum() >= 3:
        from scipy import stats
        res = stats.linregress(lx, ly)
        tq = stats.t.ppf((1 + level) / 2, ok.sum() - 2)
        lo, hi = a - tq * res.stderr, a + tq * res.stderr
    return {"exponent": a, "prefactor": float(math.exp(icpt)), "interval": (lo, hi),
            "points": int(ok.sum())}
