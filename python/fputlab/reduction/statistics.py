"""The coefficients A~, B~ over the disorder v = 1 + (tau/300) z (paper Fig. 5): exact moments in
closed form (the coefficients are quadratic forms in v), each realisation's exact quadratic in
tau, sample statistics over R realisations, and the critical tolerance tau_c (B~ = 0) three
ways."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _lowlevel as ll
from .._display import ResultMixin
from .._arrays import as_float_array, check_memory
from .._validate import C_U64, _int, _real, _size
from ..lattice import DISORDERS, _model_code
from .coefficients import _tilde_scales, quadratic_forms

__all__ = ["CoefficientMoments", "coefficient_moments", "RealisationQuadratics",
           "realisation_quadratics", "EnsembleStatistics", "ensemble_statistics", "quadratic_fit",
           "CriticalTolerance", "critical_tolerance"]



def _draws(N: int, seeds, kind: str) -> np.ndarray:
    """Standardised draws z (R, N) from GSL mt19937, one seed per realisation (as draw_disorder)."""
    if kind not in DISORDERS:
        raise ValueError(f"disorder {kind!r} is unknown (known: {', '.join(DISORDERS)})")
    seeds = [_int(s, "seed", C_U64) for s in seeds]
    z = np.empty((len(seeds), N))
    for r, s in enumerate(seeds):
        if s < 0 or s >= 2**64:
            raise ValueError(f"seed must be in [0, 2**64), got {s}")
        ll.disorder_standard(DISORDERS[kind], s, N, z[r])
    return z


def _disorder_scale(tau, kind: str):
    """s in v = 1 + s z, as fpl_disorder_draw: tau/300 (Gaussian kinds), tau/100 (uniform)."""
    return np.asarray(tau, dtype=float) / (100.0 if kind == "uniform" else 300.0)


@dataclass(repr=False)
class CoefficientMoments(ResultMixin):
    """Exact moments over the disorder at each tau: raw `mean` (T, 6), `cov` (T, 6, 6), and those
    of A~, B~ (linear in a_3, b_1)."""
    _time_field = "tau"   # the sampled axis (short repr, to_xarray)
    tau: np.ndarray
    kind: str
    N: int
    mean: np.ndarray
    cov: np.ndarray

    @property
    def A_tilde_mean(self) -> np.ndarray:
        return self.mean[:, 2] * _tilde_scales(self.N)[0]

    @property
    def B_tilde_mean(self) -> np.ndarray:
        return self.mean[:, 3] * _tilde_scales(self.N)[1]

    @property
    def A_tilde_std(self) -> np.ndarray:
        return np.sqrt(self.cov[:, 2, 2]) * abs(_tilde_scales(self.N)[0])

    @property
    def B_tilde_std(self) -> np.ndarray:
        return np.sqrt(self.cov[:, 3, 3]) * abs(_tilde_scales(self.N)[1])

    @property
    def tilde_correlation(self) -> np.ndarray:
        """Correlation of A~ and B~ (NaN at tau = 0)."""
        with np.errstate(invalid="ignore", divide="ignore"):
            return self.cov[:, 2, 3] / np.sqrt(self.cov[:, 2, 2] * self.cov[:, 3, 3])


def coefficient_moments(tau, N: int = 64, alpha: float = 0.25, *, kind: str = "gaussian",
                        model="nonlinear") -> CoefficientMoments:
    """Exact expectation and covariance of the raw coefficients over the disorder
    v = 1 + s z (z i.i.d. of the given kind, as `fputlab.draw_disorder`): no sampling.

    The Gaussian case needs E z^2 = 1 and E z^4 = 3 only (see reduction.h for the formulas).

    Parameters
    ----------
    tau : float or array_like
        Tolerances (percent).
    N : int, optional
        Lattice size.
    alpha : float, optional
        Cubic coupling.
    kind : {"gaussian", "truncated", "uniform"}, optional
        Distribution of z.
    model : str or int, optional
        Lattice model (default "nonlinear").

    Returns
    -------
    CoefficientMoments
        ``mean`` (T, 6), ``cov`` (T, 6, 6) and those of A~, B~.

    Raises
    ------
    ValueError
        An unknown disorder kind or model, or tau not a scalar or 1-D.
    """
    N = _int(N, "N")
    if kind not in DISORDERS:
        raise ValueError(f"disorder {kind!r} is unknown (known: {', '.join(DISORDERS)})")
    taus = np.atleast_1d(as_float_array(tau, "tau"))
    if taus.ndim != 1:
        raise ValueError(f"tau has shape {taus.shape}, expected a scalar or 1-D")
    mean, cov = np.empty((taus.size, 6)), np.empty((taus.size, 6, 6))
    code, a = _model_code(model), _real(alpha, "alpha")
    for i, t in enumerate(taus):
        ll.reduction_moments(N, a, code, DISORDERS[kind], float(t), mean[i], cov[i])
    return CoefficientMoments(taus, kind, N, mean, cov)


@dataclass(repr=False)
class RealisationQuadratics(ResultMixin):
    """Each realisation's coefficients as exact quadratics in tau, value = c0 + c1 tau + c2 tau^2.

    `raw` has shape (R, 6, 3) ([c0, c1, c2] per coefficient); A_tilde and B_tilde (R, 3)."""
    N: int
    kind: str
    seeds: np.ndarray
    z: np.ndarray
    raw: np.ndarray

    @property
    def A_tilde(self) -> np.ndarray:
        return self.raw[:, 2, :] * _tilde_scales(self.N)[0]

    @property
    def B_tilde(self) -> np.ndarray:
        return self.raw[:, 3, :] * _tilde_scales(self.N)[1]

    @staticmethod
    def evaluate(poly: np.ndarray, tau) -> np.ndarray:
        """poly (..., 3) at tau (T,): shape (..., T)."""
        t = np.atleast_1d(np.asarray(tau, dtype=float))
        return poly[..., :1] + poly[..., 1:2] * t + poly[..., 2:3] * t**2

    def critical_tolerances(self) -> np.ndarray:
        """Smallest tau > 0 with B~(tau) = 0 for each realisation (NaN if B~ never vanishes)."""
        c0, c1, c2 = self.B_tilde.T
        out = np.full(c0.shape, np.nan)
        with np.errstate(invalid="ignore", divide="ignore"):
            disc = c1 * c1 - 4.0 * c0 * c2
            sq = np.sqrt(np.where(disc >= 0, disc, np.nan))
            # both roots in cancellation-free form: q = -(c1 + sign(c1) sq)/2, roots q/c2, c0/q
            q = -0.5 * (c1 + np.copysign(sq, c1))
            r1, r2 = q / c2, c0 / q
        roots = np.stack([r1, r2])
        roots = np.where(np.isfinite(roots) & (roots > 0), roots, np.inf)
        best = roots.min(axis=0)
        out[np.isfinite(best)] = best[np.isfinite(best)]
        return out


def realisation_quadratics(N: int = 64, alpha: float = 0.25, R: int = 100, *, seed0: int = 1,
                           kind: str = "gaussian") -> RealisationQuadratics:
    """Each realisation's coefficients as exact quadratics in tau.

    Realisations r = 0..R-1 have seeds seed0 + r and draws z from fpl_disorder_standard;
    v = 1 + s(tau) z for every tau (the same z). From the tridiagonal forms, c(v) = v^T M v with
    v = 1 + s z gives c0 = 1^T M 1, c1 = 2 (M 1).z s/tau, c2 = z^T M z (s/tau)^2.

    Parameters
    ----------
    N : int, optional
        Lattice size.
    alpha : float, optional
        Cubic coupling.
    R : int, optional
        Number of realisations (>= 1).
    seed0 : int, optional
        Seed of the first realisation.
    kind : {"gaussian", "truncated", "uniform"}, optional
        Distribution of z.

    Returns
    -------
    RealisationQuadratics
        ``raw`` (R, 6, 3) and A~, B~ (R, 3) as [c0, c1, c2]; `critical_tolerances()` gives each
        realisation's tau_c.

    Raises
    ------
    ValueError
        R < 1, a seed out of range or an unknown disorder kind.
    """
    N, R = _size(N), _int(R, "R")
    if R < 1:
        raise ValueError(f"R must be >= 1 (got {R})")
    # z, z^2 and the products (R x N each) and the forms (R x 6 x 3): before any allocation
    check_memory(8.0 * R * (4 * N + 40), f"{R} realisations of N = {N}")
    seeds = np.arange(_int(seed0, "seed0", C_U64), _int(seed0, "seed0", C_U64) + R)
    z = _draws(N, seeds, kind)
    diag, off = quadratic_forms(N, alpha)
    g = diag.copy()                     # M 1
    g[:, 1:] += off
    g[:, :-1] += off
    unit = float(_disorder_scale(1.0, kind))          # s per percent of tau
    c0 = g.sum(axis=1)                                # (6,)
    c1 = 2.0 * unit * (z @ g.T)                       # (R, 6)
    c2 = unit**2 * ((z**2) @ diag.T + 2.0 * (z[:, 1:] * z[:, :-1]) @ off.T)
    raw = np.stack([np.broadcast_to(c0, c1.shape), c1, c2], axis=-1)
    return RealisationQuadratics(N, kind, seeds, z, raw)


@dataclass(repr=False)
class EnsembleStatistics(ResultMixin):
    """A~, B~ over R realisations at each tau: sample mean and standard deviation (ddof = 1),
    computed directly (one C projection per realisation and tau), as the paper did."""
    _time_field = "tau"   # the sampled axis (short repr, to_xarray)
    tau: np.ndarray
    A_tilde: np.ndarray   # (R, T)
    B_tilde: np.ndarray   # (R, T)

    @property
    def R(self) -> int:
        return self.A_tilde.shape[0]

    @property
    def A_mean(self):
        return self.A_tilde.mean(axis=0)

    @property
    def B_mean(self):
        return self.B_tilde.mean(axis=0)

    @property
    def A_std(self):
        return self.A_tilde.std(axis=0, ddof=1) if self.R > 1 else np.zeros(self.tau.size)

    @property
    def B_std(self):
        return self.B_tilde.std(axis=0, ddof=1) if self.R > 1 else np.zeros(self.tau.size)


def ensemble_statistics(tau, N: int = 64, alpha: float = 0.25, R: int = 100, *, seed0: int = 1,
                        kind: str = "gaussian", model="nonlinear") -> EnsembleStatistics:
    """A~(tau), B~(tau) of R realisations, one C projection per realisation and tau (as
    the paper computed them).

    Parameters
    ----------
    tau : array_like
        Tolerances (percent), 1-D, finite, >= 0.
    N : int, optional
        Lattice size.
    alpha : float, optional
        Cubic coupling.
    R : int, optional
        Number of realisations (seeds seed0 .. seed0 + R - 1, the same z for every tau).
    seed0 : int, optional
        Seed of the first realisation.
    kind : {"gaussian", "truncated", "uniform"}, optional
        Distribution of z.
    model : str or int, optional
        Lattice model (default "nonlinear").

    Returns
    -------
    EnsembleStatistics
        A~, B~ of shape (R, T) with their sample means and standard deviations.

    Raises
    ------
    ValueError
        R < 1, tau not 1-D finite and >= 0, or an unknown disorder kind or model.
    """
    N, R = _size(N), _int(R, "R")
    if R < 1:
        raise ValueError(f"R must be >= 1 (got {R})")
    taus = as_float_array(tau, "tau")
    if taus.ndim != 1 or not np.all(np.isfinite(taus)) or np.any(taus < 0):
        raise ValueError("tau must be a 1-D array of finite values >= 0")
    check_memory(8.0 * R * (N + 2 * taus.size), f"{R} realisations of N = {N} at {taus.size} "
                 "tolerances")
    z = _draws(N, range(_int(seed0, "seed0", C_U64), _int(seed0, "seed0", C_U64) + R), kind)
    code, alpha = _model_code(model), _real(alpha, "alpha")
    sA, sB = _tilde_scales(N)
    At, Bt = np.empty((R, taus.size)), np.empty((R, taus.size))
    a, b = np.empty(3), np.empty(3)
    for r in range(R):
        for i, s in enumerate(_disorder_scale(taus, kind)):
            v = 1.0 + s * z[r]
            ll.reduction_coefficients(N, alpha, code, v, a, b)
            At[r, i], Bt[r, i] = a[2] * sA, b[0] * sB
    return EnsembleStatistics(taus, At, Bt)


def quadratic_fit(tau, values) -> tuple[np.ndarray, float]:
    """Least-squares quadratic through (tau, values): the paper's 'polynomial regression'
    of the ensemble mean.

    Parameters
    ----------
    tau : array_like
        Abscissae.
    values : array_like
        Ordinates, the length of `tau`.

    Returns
    -------
    coefficients : numpy.ndarray
        Highest power first (as numpy.polyfit).
    sse : float
        Sum of squared errors of the fit.
    """
    p = np.polyfit(np.asarray(tau, float), np.asarray(values, float), 2)
    sse = float(np.sum((np.polyval(p, tau) - values) ** 2))
    return p, sse


def _smallest_positive_root(p) -> float:
    roots = np.roots(p)
    real = roots[(np.abs(roots.imag) < 1e-12 * np.abs(roots).max()) & (roots.real > 0)].real
    return float(real.min()) if real.size else float("nan")


@dataclass(repr=False)
class CriticalTolerance(ResultMixin):
    """tau_c (B~ = 0) three ways: `exact` from the closed-form expectation E[B~](tau) (exactly
    quadratic, no sampling), `fit` from a quadratic fit of the R-realisation mean (the paper:
    10.0749), and `per_realisation` (each realisation's own root; NaN where B~ has none)."""
    exact: float
    fit: float
    fit_A: np.ndarray
    fit_B: np.ndarray
    sse_A: float
    sse_B: float
    per_realisation: np.ndarray
    exact_B_coefficients: tuple[float, float]   # E[B~] = c0 + c2 tau^2

    def summary(self) -> dict:
        tc = self.per_realisation
        ok = tc[np.isfinite(tc)]
        q = np.quantile(ok, [0.05, 0.25, 0.5, 0.75, 0.95]) if ok.size else [np.nan] * 5
        return {"exact": self.exact, "fit": self.fit, "fit_B": self.fit_B.tolist(),
                "fit_A": self.fit_A.tolist(), "sse_A": self.sse_A, "sse_B": self.sse_B,
                "R": int(tc.size), "without_root": int(tc.size - ok.size),
                "mean": float(ok.mean()) if ok.size else float("nan"),
                "std": float(ok.std(ddof=1)) if ok.size > 1 else float("nan"),
                "q05": float(q[0]), "q25": float(q[1]), "median": float(q[2]),
                "q75": float(q[3]), "q95": float(q[4])}


def critical_tolerance(N: int = 64, alpha: float = 0.25, R: int = 100, *, seed0: int = 1,
                       kind: str = "gaussian", tau=None) -> CriticalTolerance:
    """The critical tolerance tau_c (where B~ changes sign) three ways.

    Parameters
    ----------
    N : int, optional
        Lattice size.
    alpha : float, optional
        Cubic coupling.
    R : int, optional
        Number of realisations for the fit and the per-realisation roots.
    seed0 : int, optional
        Seed of the first realisation (seeds seed0 .. seed0 + R - 1).
    kind : {"gaussian", "truncated", "uniform"}, optional
        Distribution of the disorder draws.
    tau : array_like, optional
        Grid of the quadratic fit, percent (default 0..20 in steps of 0.5).

    Returns
    -------
    CriticalTolerance
        ``exact`` (root of the exact Gaussian expectation of B~, no sampling), ``fit`` (root of a
        quadratic fit of the R-realisation mean, the paper's method; paper: 10.0749 %) and
        ``per_realisation`` (each realisation's own root).
    """
    taus = np.linspace(0.0, 20.0, 41) if tau is None else as_float_array(tau, "tau")
    # a quadratic through fewer than three distinct tolerances is not determined (numpy's
    # fit then fails with an SVD error or silently picks one of infinitely many)
    if taus.ndim != 1 or np.unique(taus).size < 3:
        raise ValueError(f"tau: the quadratic fit needs at least 3 distinct tolerances "
                         f"(got {np.unique(taus).size})")
    if not np.all(np.isfinite(taus)) or np.any(taus < 0):
        raise ValueError("tau: tolerances must be finite and >= 0 (percent)")
    ens = ensemble_statistics(taus, N, alpha, R, seed0=seed0, kind=kind)
    fit_A, sse_A = quadratic_fit(taus, ens.A_mean)
    fit_B, sse_B = quadratic_fit(taus, ens.B_mean)
    # E[B~](tau) = c0 + c2 tau^2 exactly (the term linear in z has mean 0)
    ref = 10.0
    m = coefficient_moments([0.0, ref], N, alpha, kind=kind).B_tilde_mean
    c0, c2 = float(m[0]), float((m[1] - m[0]) / ref**2)
    exact = math.sqrt(-c0 / c2) if c0 * c2 < 0 else float("nan")
    per = realisation_quadratics(N, alpha, R, seed0=seed0, kind=kind).critical_tolerances()
    return CriticalTolerance(exact, _smallest_positive_root(fit_B), fit_A, fit_B, sse_A, sse_B,
                             per, (c0, c2))
