"""Recurrence and localisation measures computed from a run's mode energies (paper Figs. 1-2).

Every function takes a `fputlab.Run` (or its ``mode_energies``, shape (samples, N)).

    >>> import fputlab
    >>> from fputlab import analysis
    >>> run = fputlab.Lattice(32).integrate(2e4, sample_every=10.0)
    >>> times, heights = analysis.recurrences(run)       # FPUT recurrences of mode 1
    >>> analysis.effective_modes(run)[-1]                 # modes sharing the energy at the end
"""
from __future__ import annotations

import numpy as np

from ._arrays import as_float_array

__all__ = ["recurrences", "energy_share", "spectral_entropy", "effective_modes",
           "normalised_entropy"]


def _energies(run_or_energies):
    ek = getattr(run_or_energies, "mode_energies", run_or_energies)
    ek = as_float_array(ek, "mode_energies")
    if ek.ndim != 2:
        raise ValueError(f"mode_energies has shape {ek.shape}, expected (samples, N)")
    return ek


def recurrences(run, mode: int = 1, min_fraction: float = 0.1, min_separation: float | None = None):
    """Recurrence times of a mode: the returns of its energy towards the initial state.

    A recurrence is a local maximum of E_mode(t) / sum_k E_k(t) after the initial decay, at least
    `min_fraction` high; of maxima closer than `min_separation` only the highest is kept.

    Parameters
    ----------
    run : Run
        A run with sample times ``t`` and ``mode_energies`` (samples, N).
    mode : int, optional
        Mode number k (1-based; the paper's initial state is mode 1).
    min_fraction : float, optional
        Smallest share of the total harmonic energy that counts as a recurrence.
    min_separation : float, optional
        Smallest time between two recurrences (default: a tenth of the run's duration).

    Returns
    -------
    times : numpy.ndarray
        Recurrence times, ascending.
    fractions : numpy.ndarray
        Share of the total harmonic energy back in the mode at each of them.

    Raises
    ------
    ValueError
        The mode energies are not a 2-D array.

    Examples
    --------
    >>> run = fputlab.Lattice(32).integrate(2e4, sample_every=10.0)   # doctest: +SKIP
    >>> times, fractions = recurrences(run)                          # doctest: +SKIP
    """
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
    """Share of the harmonic energy in the first m modes, per sample.

    Parameters
    ----------
    run : Run or array_like
        A run (its ``mode_energies``) or the mode energies themselves, shape (samples, N).
    m : int
        Number of modes counted, 1..N.

    Returns
    -------
    numpy.ndarray
        ``sum_{k<=m} E_k / sum_k E_k`` per sample, in [0, 1].

    Raises
    ------
    ValueError
        `m` outside 1..N, or mode energies that are not a 2-D array.
    """
    ek = _energies(run)
    if not 1 <= m <= ek.shape[1]:
        raise ValueError(f"m must be in 1..N = {ek.shape[1]} (got {m})")
    return ek[:, :m].sum(axis=1) / ek.sum(axis=1)


def spectral_entropy(run) -> np.ndarray:
    """Spectral entropy ``eta = -sum_k e_k ln e_k`` with ``e_k = E_k / sum_k E_k``, per sample.

    Parameters
    ----------
    run : Run or array_like
        A run (its ``mode_energies``) or the mode energies themselves, shape (samples, N).

    Returns
    -------
    numpy.ndarray
        eta per sample: 0 when one mode holds all the energy, ln N at equipartition.

    Raises
    ------
    ValueError
        Mode energies that are not a 2-D array.
    """
    ek = _energies(run)
    e = ek / ek.sum(axis=1, keepdims=True)
    with np.errstate(divide="ignore", invalid="ignore"):
        terms = np.where(e > 0, e * np.log(e), 0.0)
    return -terms.sum(axis=1)


def effective_modes(run) -> np.ndarray:
    """The effective number of modes sharing the energy: ``exp(eta)`` (`spectral_entropy`).

    Parameters
    ----------
    run : Run or array_like
        A run (its ``mode_energies``) or the mode energies themselves, shape (samples, N).

    Returns
    -------
    numpy.ndarray
        Per sample, between 1 (one mode) and N (equipartition).

    Raises
    ------
    ValueError
        Mode energies that are not a 2-D array.
    """
    return np.exp(spectral_entropy(run))


def normalised_entropy(run) -> np.ndarray:
    """The spectral entropy normalised by its largest value: ``eta / ln N``.

    Parameters
    ----------
    run : Run or array_like
        A run (its ``mode_energies``) or the mode energies themselves, shape (samples, N).

    Returns
    -------
    numpy.ndarray
        Per sample, in [0, 1]: 0 when one mode holds all the energy, 1 at equipartition.

    Raises
    ------
    ValueError
        Mode energies that are not a 2-D array.
    """
    ek = _energies(run)
    return spectral_entropy(run) / np.log(ek.shape[1])
