"""Recurrence and localisation measures computed from a run's mode energies."""
from __future__ import annotations

import numpy as np

from ._arrays import as_float_array


def _energies(run_or_energies):
    ek = getattr(run_or_energies, "mode_energies", run_or_energies)
    ek = as_float_array(ek, "mode_energies")
    if ek.ndim != 2:
        raise ValueError(f"mode_energies has shape {ek.shape}, expected (samples, N)")
    return ek


def recurrences(run, mode: int = 1, min_fraction: float = 0.1, min_separation: float | None = None):
    """Recurrence times: local maxima of E_mode(t) (after the initial decay) whose height is at
    least `min_fraction` of the total, separated by at least `min_separation` (default: a tenth of
    the run). Returns (times, fractions of the total harmonic energy returned to the mode)."""
    ek = _energies(run)
    t = np.asarray(run.t)
    total = ek.sum(axis=1)
    frac = ek[:, mode - 1] / total
    sep = (t[-1] - t[0]) / 10 if min_separation is None else float(min_separation)
    # the initial state is a maximum of E_1 by construction: start after the first minimum
    start = int(np.argmax(np.diff(frac) > 0)) if np.any(np.diff(frac) > 0) else len(frac)
    peaks = [i for i in range(max(start, 1), len(frac) - 1)
             if frac[i] >= frac[i - 1] and frac[i] > frac[i + 1] and frac[i] >= min_fraction]
    chosen: list[int] = []
    for i in sorted(peaks, key=lambda i: -frac[i]):         # highest first, enforce separation
        if all(abs(t[i] - t[j]) >= sep for j in chosen):
            chosen.append(i)
    chosen.sort()
    return t[chosen], frac[chosen]


def energy_share(run, m: int) -> np.ndarray:
    """Share of the harmonic energy in the first m modes, per sample."""
    ek = _energies(run)
    if not 1 <= m <= ek.shape[1]:
        raise ValueError(f"m must be in 1..N = {ek.shape[1]} (got {m})")
    return ek[:, :m].sum(axis=1) / ek.sum(axis=1)


def spectral_entropy(run) -> np.ndarray:
    """eta = -sum_k e_k ln e_k with e_k = E_k / sum E_k (0: one mode; ln N: equipartition)."""
    ek = _energies(run)
    e = ek / ek.sum(axis=1, keepdims=True)
    with np.errstate(divide="ignore", invalid="ignore"):
        terms = np.where(e > 0, e * np.log(e), 0.0)
    return -terms.sum(axis=1)


def effective_modes(run) -> np.ndarray:
    """exp(spectral entropy): the effective number of modes sharing the energy (1..N)."""
    return np.exp(spectral_entropy(run))


def normalised_entropy(run) -> np.ndarray:
    """eta / ln N in [0, 1]: 0 when one mode holds all the energy, 1 at equipartition."""
    ek = _energies(run)
    return spectral_entropy(run) / np.log(ek.shape[1])
