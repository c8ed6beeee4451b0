"""Reduction of the FPUT lattice to a few normal modes (paper Sec. 4).

Pieces, in the order of the paper:

* `Galerkin`: the lattice truncated to its first M normal modes (Eq. eqnmfsvarnonlin with
  Q_k = 0 for k > M), integrated in C with the splitting schemes (paper Fig. 4).
* `two_mode_coefficients`: the raw coefficients a_i, b_i of the two-mode system (Eq. msvar),
  alpha included, as closed sums; the paper's A_i = a_i/eps, B_i = b_i/eps with
  eps = omega_2 - 2 omega_1 < 0, and A~ = A_3/(2 omega_1), B~ = B_1/(2 omega_2).
* `coefficient_moments`, `realisation_quadratics`, `ensemble_statistics`, `critical_tolerance`:
  A~, B~ over the disorder v = 1 + (tau/300) z (Fig. 5): the exact expectation and variance in
  closed form (the coefficients are quadratic forms in v), sample statistics over R realisations,
  and tau_c (B~ = 0) three ways.
* `two_mode_run` (Eq. msvar, in C) and `envelope_run` (Eq. msfinal2) with q_1(0) = Q_1(0)/2,
  q_2(0) = 0; Q_j(t) ~ 2 Re(q_j(T) exp(i(omega_j t + T))), T = eps t (Fig. 6).
* `ReducedSystem`: the (P, Delta, theta) system (Eq. reduced), its constant C, well-defined
  region, equilibria (Eqs. theta_1_2, deltaequi), eigenvalues (eigequi) and their type;
  `equilibrium_map`, `bifurcation_curves`, `classify` for Figs. 7-8; phase portraits (Figs. 9-10)
  in `fputlab.figures_reduction`.

Only numpy is needed here (no scipy): the slow envelope equations are integrated with a fixed-step
RK4 in the slow time."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ._display import ResultMixin
from . import _lowlevel as ll
from ._arrays import as_float_array
from ._errors import IntegrationError, check
from ._validate import C_U64, _finite_real, _int, _real
from .lattice import DISORDERS, Lattice, _model_code

#: order of the raw coefficients everywhere (mode-1 equation a, mode-2 equation b)
COEFFICIENT_NAMES = ("a1", "a2", "a3", "b1", "b2", "b3")


# ---- small helpers ---------------------------------------------------------------------------

def frequencies(N: int) -> tuple[float, float]:
    """(omega_1, omega_2) of the fixed-end chain, omega_k = 2 sin(k pi/(2(N+1)))."""
    N = _int(N, "N")
    return 2.0 * math.sin(math.pi / (2 * (N + 1))), 2.0 * math.sin(math.pi / (N + 1))


def detuning(N: int) -> float:
    """eps = omega_2 - 2 omega_1 (negative, about -(pi/(N+1))^3 / 4 for large N)."""
    w1, w2 = frequencies(N)
    return w2 - 2.0 * w1


def r1_squared(N: int) -> float:
    """``r_1^2 = |q_1(0)|^2 = (Q_1(0)/2)^2 = (N+1)/8`` for the paper's initial state (Eq. initxi)."""
    return (_int(N, "N") + 1) / 8.0


def _tilde_scales(N: int) -> tuple[float, float]:
    """A~ = sA a_3 and B~ = sB b_1."""
    w1, w2 = frequencies(N)
    eps = w2 - 2.0 * w1
    return 1.0 / (eps * 2.0 * w1), 1.0 / (eps * 2.0 * w2)


def _scheme(method: str):
    if not isinstance(method, str):
        raise TypeError(f"method must be a string, got {type(method).__name__}")
    return ll.splitting_lookup(method)


def _sample_times(t0: float, t_end: float, sample_every, times) -> np.ndarray:
    if times is not None:
        if sample_every is not None:
            raise ValueError("give either times or sample_every, not both")
        ts = as_float_array(times, "times")
        if ts.ndim != 1:
            raise ValueError(f"times has shape {ts.shape}, expected 1-D")
        return ts
    if not (math.isfinite(t_end) and t_end >= t0):
        raise ValueError(f"t_end must be finite and >= t0 = {t0:g} (got {t_end:g})")
    if t_end == t0:
        return np.array([t0])
    every = (t_end - t0) / 1000 if sample_every is None else _real(sample_every, "sample_every")
    if not (math.isfinite(every) and every > 0):
        raise ValueError(f"sample_every must be finite and > 0 (got {every:g})")
    n = int(math.floor((t_end - t0) / every * (1 + 1e-12)))
    return t0 + every * np.arange(n + 1)


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


# ---- two-mode coefficients -------------------------------------------------------------------

@dataclass(frozen=True)
class TwoModeCoefficients:
    """Coefficients of the two-mode system (Eq. msvar) of an N-particle chain.

    Raw (alpha included): Q_1'' = -omega_1^2 Q_1 + a1 Q_1^2 + a2 Q_2^2 + a3 Q_1 Q_2 and
    Q_2'' = -omega_2^2 Q_2 + b1 Q_1^2 + b2 Q_2^2 + b3 Q_1 Q_2. Paper-normalised: A = a/eps,
    B = b/eps (eps = omega_2 - 2 omega_1), A_tilde = A_3/(2 omega_1), B_tilde = B_1/(2 omega_2)."""
    N: int
    a: np.ndarray
    b: np.ndarray

    @property
    def omega(self) -> tuple[float, float]:
        return frequencies(self.N)

    @property
    def eps(self) -> float:
        return detuning(self.N)

    @property
    def A(self) -> np.ndarray:
        return self.a / self.eps

    @property
    def B(self) -> np.ndarray:
        return self.b / self.eps

    @property
    def A_tilde(self) -> float:
        return float(self.a[2] * _tilde_scales(self.N)[0])

    @property
    def B_tilde(self) -> float:
        return float(self.b[0] * _tilde_scales(self.N)[1])

    @property
    def raw(self) -> np.ndarray:
        """(a1, a2, a3, b1, b2, b3)."""
        return np.concatenate([self.a, self.b])

    def __repr__(self) -> str:
        return (f"TwoModeCoefficients(N={self.N}, A_tilde={self.A_tilde:.6f}, "
                f"B_tilde={self.B_tilde:.6f}, a={np.array2string(self.a, precision=4)}, "
                f"b={np.array2string(self.b, precision=4)})")


def two_mode_coefficients(N=64, alpha: float = 0.25, v=None, *,
                          model="nonlinear") -> TwoModeCoefficients:
    """Two-mode coefficients of a chain, by projection (closed sums over the bonds, in C).

    Models 2 and 3 share the quadratic part; beta does not enter (Eq. msvar has no cubic terms).
    Eq. (msvar) assumes a diagonal linear part, which holds for models 1 and 3 only: for model 2
    these are the quadratic coefficients of the projected acceleration (see reduction.h).

    Parameters
    ----------
    N : int or Lattice, optional
        Lattice size, or a `Lattice` whose N, alpha, model and v are used.
    alpha : float, optional
        Cubic coupling.
    v : array_like, optional
        Variability v_j, length N (None: v_j = 1).
    model : str or int, optional
        Lattice model (default "nonlinear").

    Returns
    -------
    TwoModeCoefficients
        Raw coefficients ``a``, ``b`` (alpha included) and the paper-normalised ``A``, ``B``,
        ``A_tilde``, ``B_tilde`` (see docs/conventions.md). At N = 64, alpha = 0.25, v = 1:
        A~ = 3.62805, B~ = 0.90728.
    """
    if isinstance(N, Lattice):
        lat = N
        N, alpha, code, v = lat.N, lat.alpha, lat.model_code, lat.v
    else:
        N = _int(N, "N")
        code = _model_code(model)
        alpha = _real(alpha, "alpha")
    if N < 2:
        raise ValueError(f"N must be >= 2 (got {N})")
    v_arr = None if v is None else as_float_array(v, "v", (N,))
    a, b = np.empty(3), np.empty(3)
    ll.reduction_coefficients(N, alpha, code, v_arr, a, b)
    return TwoModeCoefficients(N, a, b)


def quadratic_forms(N: int, alpha: float = 0.25) -> tuple[np.ndarray, np.ndarray]:
    """Tridiagonal M of each raw coefficient, c = v^T M v (models 2, 3): (diag (6, N), off (6, N-1))."""
    N = _int(N, "N")
    if N < 2:
        raise ValueError(f"N must be >= 2 (got {N})")
    return ll.reduction_quadratic_forms(N, _real(alpha, "alpha"))


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
    """Exact expectation and covariance of the raw coefficients over v = 1 + s z (z i.i.d. of the
    given kind, as fputlab.draw_disorder) for each tau (percent): no sampling. The Gaussian case
    needs E z^2 = 1 and E z^4 = 3 only (see reduction.h for the formulas)."""
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


# ---- realisations ----------------------------------------------------------------------------

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
    """Realisations r = 0..R-1 with seeds seed0 + r: z from fpl_disorder_standard, v = 1 + s(tau) z
    for every tau (same z). Exact quadratics from the tridiagonal forms: c(v) = v^T M v with
    v = 1 + s z gives c0 = 1^T M 1, c1 = 2 (M 1).z s/tau, c2 = z^T M z (s/tau)^2."""
    N, R = _int(N, "N"), _int(R, "R")
    if R < 1:
        raise ValueError(f"R must be >= 1 (got {R})")
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
    """A~(tau), B~(tau) for R realisations (seeds seed0..seed0+R-1, the same z for every tau)."""
    N, R = _int(N, "N"), _int(R, "R")
    if R < 1:
        raise ValueError(f"R must be >= 1 (got {R})")
    taus = as_float_array(tau, "tau")
    if taus.ndim != 1 or not np.all(np.isfinite(taus)) or np.any(taus < 0):
        raise ValueError("tau must be a 1-D array of finite values >= 0")
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
    """Least-squares quadratic (highest power first, as numpy.polyfit) and its sum of squared
    errors: the paper's 'polynomial regression' of the ensemble mean."""
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


# ---- the two-mode ODE (Eq. msvar) and the Galerkin truncation --------------------------------

@dataclass(repr=False)
class ModalRun(ResultMixin):
    """Samples of a truncated system: Q, P = Q' (S, M) at t (S,), E_k = (P_k^2 + omega_k^2 Q_k^2)/2."""
    t: np.ndarray
    Q: np.ndarray
    P: np.ndarray
    omega: np.ndarray
    dt: float
    method: str
    completed: bool = True
    message: str = ""

    @property
    def mode_energies(self) -> np.ndarray:
        return 0.5 * (self.P**2 + (self.omega * self.Q) ** 2)


def _initial_modal_state(M: int, N: int, Q0, P0) -> np.ndarray:
    Q = np.zeros(M)
    if Q0 is None:
        Q[0] = math.sqrt((N + 1) / 2.0)     # Eq. (initxi): x_j = sin(pi j/(N+1))
    else:
        Q = as_float_array(Q0, "Q0", (M,)).copy()
    P = np.zeros(M) if P0 is None else as_float_array(P0, "P0", (M,))
    for name, arr in (("Q0", Q), ("P0", P)):
        bad = np.flatnonzero(~np.isfinite(arr))
        if bad.size:
            raise ValueError(f"{name}[{bad[0]}] is not finite ({arr[bad[0]]})")
    return np.ascontiguousarray(np.concatenate([Q, P]))


def _finish(run: ModalRun, status: int, on_failure: str) -> ModalRun:
    if status >= 0:
        return run
    try:
        check(status)
    except IntegrationError as err:
        run.completed, run.message = False, str(err)
        if on_failure == "raise":
            err.result = run
            raise
    return run


def _run_args(t_end, dt, t0, sample_every, times, on_failure):
    if on_failure not in ("raise", "return"):
        raise ValueError(f"on_failure must be 'raise' or 'return', got {on_failure!r}")
    t0 = _finite_real(t0, "t0")
    dt = _real(dt, "dt")
    if not (math.isfinite(dt) and dt > 0):
        raise ValueError(f"dt must be finite and > 0 (got {dt:g})")
    t_end = _real(t_end, "t_end")
    if not math.isfinite(t_end):
        raise ValueError(f"t_end must be finite (got {t_end})")
    return t0, dt, _sample_times(t0, t_end, sample_every, times)


def two_mode_run(coefficients: TwoModeCoefficients, t_end: float, *, dt: float = 0.05,
                 sample_every: float | None = None, times=None, Q0=None, P0=None, omega=None,
                 method: str = "yoshida4", t0: float = 0.0,
                 on_failure: str = "raise") -> ModalRun:
    """Integrate the two-mode system, Eq. (msvar), with the raw coefficients (in C).

    Parameters
    ----------
    coefficients : TwoModeCoefficients
        From `two_mode_coefficients`.
    t_end : float
        Final time.
    dt : float, optional
        Fixed step of `method`.
    sample_every : float, optional
        Sampling interval (exclusive with `times`).
    times : array_like, optional
        Explicit increasing sample times.
    Q0, P0 : array_like, optional
        Initial (Q_1, Q_2) and (P_1, P_2); default Q_1(0) = sqrt((N+1)/2), Q_2 = P = 0
        (Eq. initxi).
    omega : array_like, optional
        (omega_1, omega_2) instead of the chain's, e.g. to vary the detuning.
    method : str, optional
        Splitting scheme.
    t0 : float, optional
        Initial time.
    on_failure : {"raise", "return"}, optional
        A blow-up raises `IntegrationError` (its ``.result`` holds the finite samples) or
        returns them with ``completed=False``.

    Returns
    -------
    ModalRun
        ``t``, ``Q``, ``P`` (and ``mode_energies``).
    """
    if not isinstance(coefficients, TwoModeCoefficients):
        raise TypeError("coefficients must be a TwoModeCoefficients")
    t0, dt, ts = _run_args(t_end, dt, t0, sample_every, times, on_failure)
    w = np.array(coefficients.omega if omega is None else as_float_array(omega, "omega", (2,)),
                 dtype=float)
    z0 = _initial_modal_state(2, coefficients.N, Q0, P0)
    a = np.ascontiguousarray(coefficients.a, dtype=float)
    b = np.ascontiguousarray(coefficients.b, dtype=float)
    states = np.empty((max(ts.size, 1), 4))
    status, k = ll.reduction_two_mode_run(_scheme(method), w, a, b, z0, t0, dt, ts, states)
    run = ModalRun(ts[:k].copy(), states[:k, :2].copy(), states[:k, 2:].copy(), w, dt, method)
    return _finish(run, status, on_failure)


def _modes_arg(M) -> int:
    if isinstance(M, bool) or not isinstance(M, (int, np.integer, float, np.floating)):
        raise TypeError(f"M must be an integer, got {type(M).__name__}")
    if isinstance(M, (float, np.floating)):
        if not (math.isfinite(M) and float(M).is_integer()):
            raise ValueError(f"M (number of modes) must be a whole number (got {M})")
    return int(M)


class Galerkin:
    """The lattice truncated to its first M normal modes (Eq. eqnmfsvarnonlin, Q_k = 0 for k > M):
    Q_k'' = [A x''(A Q)]_k, k <= M, with x'' the model's full acceleration. Models 1, 3: exactly
    -omega_k^2 Q_k + [A F^(A Q)]_k. Model 2: the projection of Eq. (dis1), whose linear part
    couples the kept modes (not the Hamiltonian Galerkin system). M = N is the full lattice."""

    def __init__(self, lattice: Lattice, M: int):
        if not isinstance(lattice, Lattice):
            raise TypeError(f"lattice must be a fputlab.Lattice, got {type(lattice).__name__}")
        M = _modes_arg(M)
        self._h = ll.GalerkinHandle(lattice._h, M)
        self.lattice, self.M, self.N = lattice, M, lattice.N
        self.omega = lattice.omega[:M].copy()

    def __repr__(self) -> str:
        return f"Galerkin({self.lattice!r}, M={self.M})"

    def acceleration(self, Q) -> np.ndarray:
        """Q'' of the truncated system at Q (length M)."""
        q = as_float_array(Q, "Q", (self.M,))
        bad = np.flatnonzero(~np.isfinite(q))
        if bad.size:
            raise ValueError(f"Q[{bad[0]}] is not finite ({q[bad[0]]})")
        return self._h.acceleration(q)

    def run(self, t_end: float, *, dt: float = 0.01, sample_every: float | None = None,
            times=None, Q0=None, P0=None, method: str = "yoshida4", t0: float = 0.0,
            on_failure: str = "raise") -> ModalRun:
        """Integrate from (Q0, P0) (default: the paper's mode-1 state) with a fixed-step splitting
        scheme (drift Q += h P, kick P += h Q''), sampling at `times` or every `sample_every`."""
        t0, dt, ts = _run_args(t_end, dt, t0, sample_every, times, on_failure)
        z0 = _initial_modal_state(self.M, self.N, Q0, P0)
        M = self.M
        states = np.empty((max(ts.size, 1), 2 * M))
        status, k = self._h.run(_scheme(method), z0, t0, dt, ts, states)
        run = ModalRun(ts[:k].copy(), states[:k, :M].copy(), states[:k, M:].copy(), self.omega,
                       dt, method)
        return _finish(run, status, on_failure)


# ---- envelope equations (Eq. msfinal2) -------------------------------------------------------

def envelope_rhs(q: np.ndarray, A_tilde: float, B_tilde: float) -> np.ndarray:
    """dq/dT of Eq. (msfinal2): i q1' = q1 + A~ conj(q1) q2, i q2' = q2 + B~ q1^2."""
    q1, q2 = q[..., 0], q[..., 1]
    return np.stack([-1j * (q1 + A_tilde * np.conj(q1) * q2), -1j * (q2 + B_tilde * q1 * q1)],
                    axis=-1)


@dataclass(repr=False)
class EnvelopeRun(ResultMixin):
    """q_1, q_2 (complex, (K, 2)) of Eq. (msfinal2) on a uniform slow-time grid T (K,)."""
    _time_field = "T"   # the sampled axis (short repr, to_xarray)
    T: np.ndarray
    q: np.ndarray
    A_tilde: float
    B_tilde: float
    completed: bool = True

    def at(self, T) -> np.ndarray:
        """q at slow times T (cubic Hermite interpolation with the exact derivative; O(dT^4))."""
        Ts = np.asarray(T, dtype=float)
        h = self.T[1] - self.T[0] if self.T.size > 1 else 1.0
        u = (Ts - self.T[0]) / h
        if np.any((u < -1e-9) | (u > self.T.size - 1 + 1e-9)):
            raise ValueError("T outside the integrated range")
        i = np.clip(np.floor(u).astype(int), 0, max(self.T.size - 2, 0))
        s = (u - i)[..., None]
        f = envelope_rhs(self.q, self.A_tilde, self.B_tilde) * h
        if self.T.size == 1:
            return np.broadcast_to(self.q[0], Ts.shape + (2,)).copy()
        y0, y1, d0, d1 = self.q[i], self.q[i + 1], f[i], f[i + 1]
        h00, h10 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s
        h01, h11 = -2 * s**3 + 3 * s**2, s**3 - s**2
        return h00 * y0 + h10 * d0 + h01 * y1 + h11 * d1

    def reconstruct(self, t, omega, eps: float) -> np.ndarray:
        """Leading-order Q_j(t) = 2 Re(q_j(T) exp(i(omega_j t + T))), T = eps t: shape (S, 2).
        (The paper's q_j carry the gauge exp(-iT) that turns the resonance exp(iT) into the
        linear terms of Eq. msfinal2.)"""
        t = np.asarray(t, dtype=float)
        T = eps * t
        q = self.at(T)
        phase = np.exp(1j * (np.outer(t, np.asarray(omega, float)) + T[:, None]))
        return 2.0 * np.real(q * phase)


#: envelope_run's limit on RK4 steps (each kept: about 50 bytes and a few microseconds)
ENVELOPE_MAX_STEPS = 2e7


def envelope_run(A_tilde: float, B_tilde: float, T_end: float, *, q0=None, N: int = 64,
                 dT: float = 1e-3, P_max: float | None = None) -> EnvelopeRun:
    """Integrate the envelope equations, Eq. (msfinal2), in the slow time T = eps t with
    fixed-step RK4.

    Parameters
    ----------
    A_tilde, B_tilde : float
        The paper-normalised coefficients.
    T_end : float
        Final slow time, either sign (eps < 0, so forward physical time is negative T).
    q0 : array_like, optional
        Initial complex (q_1, q_2); default (Q_1(0)/2, 0) = (sqrt((N+1)/8), 0)
        (Eqs. ic-q1, ic-q2).
    N : int, optional
        Lattice size (for the default q0).
    dT : float, optional
        Step size ``|dT|`` (> 0).
    P_max : float, optional
        Stop (``completed=False``) once ``|q_1|^2 + |q_2|^2`` exceeds it (the unbounded case
        B~ < 0).

    Returns
    -------
    EnvelopeRun
        ``T``, ``q`` (complex, shape (S, 2)); ``at(T)`` interpolates.
    """
    A, B = _finite_real(A_tilde, "A_tilde"), _finite_real(B_tilde, "B_tilde")
    T_end, dT = _finite_real(T_end, "T_end"), _finite_real(dT, "dT")
    if dT <= 0:
        raise ValueError(f"dT must be > 0 (got {dT})")
    if q0 is None:
        q1, q2 = complex(math.sqrt(r1_squared(N))), 0j
    else:
        q = np.asarray(q0, dtype=complex)
        if q.shape != (2,) or not np.all(np.isfinite(q)):
            raise ValueError(f"q0 must be 2 finite (complex) numbers, got {q0!r}")
        q1, q2 = complex(q[0]), complex(q[1])
    steps = abs(T_end) / dT
    if steps > ENVELOPE_MAX_STEPS:      # a Python loop keeping every step: refuse, do not hang
        raise ValueError(f"dT = {dT:g} up to |T_end| = {abs(T_end):g} means {steps:.3g} RK4 steps, "
                         f"more than {ENVELOPE_MAX_STEPS:.0e}: use a larger dT")
    n = max(1, int(math.ceil(steps - 1e-9)))
    h = T_end / n if T_end != 0 else 0.0
    P_lim = math.inf if P_max is None else _finite_real(P_max, "P_max")

    def f(a, b):
        return -1j * (a + A * a.conjugate() * b), -1j * (b + B * a * a)

    out = [(q1, q2)]
    completed = True
    for _ in range(n if T_end != 0 else 0):
        k1 = f(q1, q2)
        k2 = f(q1 + 0.5 * h * k1[0], q2 + 0.5 * h * k1[1])
        k3 = f(q1 + 0.5 * h * k2[0], q2 + 0.5 * h * k2[1])
        k4 = f(q1 + h * k3[0], q2 + h * k3[1])
        q1 = q1 + h / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
        q2 = q2 + h / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
        out.append((q1, q2))
        if not (abs(q1) ** 2 + abs(q2) ** 2 <= P_lim):
            completed = False
            break
    qs = np.array(out, dtype=complex)
    return EnvelopeRun(h * np.arange(qs.shape[0]), qs, A, B, completed)


def envelope_error(two_mode: ModalRun, envelope: EnvelopeRun, eps: float) -> np.ndarray:
    """max over the samples of ``|Q_j - Q_j^env|`` for j = 1, 2 (Q^env from `reconstruct`)."""
    Qe = envelope.reconstruct(two_mode.t, two_mode.omega, eps)
    return np.abs(two_mode.Q - Qe).max(axis=0)


# ---- the reduced (P, Delta, theta) system (Eq. reduced) --------------------------------------

def to_reduced(q) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(P, Delta, theta) from q (..., 2): q_1 = r_1 e^{i phi_1}, q_2 = r_2 e^{2 i phi_2},
    theta = phi_2 - phi_1 in [0, pi) (phi_2 is defined modulo pi)."""
    q = np.asarray(q, dtype=complex)
    r1s, r2s = np.abs(q[..., 0]) ** 2, np.abs(q[..., 1]) ** 2
    theta = np.mod(0.5 * np.angle(q[..., 1]) - np.angle(q[..., 0]), np.pi)
    return r1s + r2s, r1s - r2s, theta


@dataclass(frozen=True)
class Equilibrium:
    """One equilibrium (theta_j, Delta_j) of Eqs. (delta3, theta3) with eigenvalues +-lambda."""
    j: int
    theta: float
    delta: float
    eigenvalues: tuple[complex, complex]
    kind: str             # "centre", "saddle" or "degenerate"
    well_defined: bool    # P - Delta > 0 and P + Delta >= 0 there (an equilibrium of Eq. msfinal2)


class ReducedSystem:
    """Eqs. (P2, delta3, theta3) in the slow time T for given (A~, B~) and constant
    C = P - k Delta, k = (A~ - B~)/(A~ + B~). By default C is that of the paper's initial state
    (q_1(0) = sqrt(r1sq), q_2(0) = 0, so P = Delta = r1sq and C = 2 B~ r1sq/(A~ + B~))."""

    def __init__(self, A_tilde: float, B_tilde: float, *, N: int = 64, r1sq: float | None = None,
                 C: float | None = None):
        self.A, self.B = _finite_real(A_tilde, "A_tilde"), _finite_real(B_tilde, "B_tilde")
        self.S = self.A + self.B
        if self.S == 0:
            raise ValueError("A_tilde + B_tilde must not vanish (k = (A~-B~)/(A~+B~))")
        if self.A == 0 or self.B == 0:
            raise ValueError("A_tilde and B_tilde must be non-zero (Eq. deltaequi divides by both)")
        self.k = (self.A - self.B) / self.S
        self.r1sq = r1_squared(N) if r1sq is None else _finite_real(r1sq, "r1sq")
        self.C = self.r1sq * (1.0 - self.k) if C is None else _finite_real(C, "C")

    def __repr__(self) -> str:
        return f"ReducedSystem(A_tilde={self.A:g}, B_tilde={self.B:g}, C={self.C:.6g})"

    # -- the vector field --------------------------------------------------------------------
    def P_of(self, delta):
        return self.C + self.k * np.asarray(delta, dtype=float)

    def rhs(self, P, delta, theta):
        """(P', Delta', theta') of Eq. (reduced), as printed in the paper."""
        P, D, th = (np.asarray(x, dtype=float) for x in (P, delta, theta))
        root = np.sqrt(2.0 * (P - D))
        dD = root * np.sin(2 * th) * (P + D) * self.S / 2.0
        dth = -(2 * self.A * np.cos(2 * th) * (D - P) + self.B * np.cos(2 * th) * (D + P) - root) \
            / (2.0 * root)
        return self.k * dD, dD, dth

    def field(self, delta, theta):
        """(Delta', theta') with P = C + k Delta (Eqs. delta3, theta3)."""
        _, dD, dth = self.rhs(self.P_of(delta), delta, theta)
        return dD, dth

    def invariant(self, delta, theta):
        """I = r_1^2 (1 + 2 A~ r_2 cos 2 theta), conserved along Eq. (reduced) (with C it makes the
        system integrable; level sets of I are the orbits in the phase portraits)."""
        P = self.P_of(delta)
        D = np.asarray(delta, dtype=float)
        r1s, r2 = (P + D) / 2.0, np.sqrt(np.maximum((P - D) / 2.0, 0.0))
        return r1s * (1.0 + 2.0 * self.A * r2 * np.cos(2 * np.asarray(theta, float)))

    # -- the well-defined region -------------------------------------------------------------
    @property
    def delta_crit(self) -> tuple[float, float]:
        """(Delta_crit^1, Delta_crit^2) = (C S/(2 B~), -C S/(2 A~)): r_2 = 0 and r_1 = 0."""
        return self.C * self.S / (2 * self.B), -self.C * self.S / (2 * self.A)

    def well_defined(self, delta) -> np.ndarray:
        """P - Delta > 0 and P + Delta >= 0 (r_2^2 > 0, r_1^2 >= 0)."""
        P, D = self.P_of(delta), np.asarray(delta, dtype=float)
        return (P - D > 0) & (P + D >= 0)

    def region(self) -> tuple[float, float]:
        """The Delta-interval of the well-defined region (either end may be infinite), from the
        paper's three cases in k."""
        d1, d2 = self.delta_crit
        if self.k >= 1:
            return max(d1, d2), math.inf
        if self.k >= -1:
            return d2, d1
        return -math.inf, min(d1, d2)

    # -- equilibria --------------------------------------------------------------------------
    @property
    def existence(self) -> float:
        """1 + 6 A~ (A~ + B~) C (Eq. equicrit): equilibria exist where it is >= 0."""
        return 1.0 + 6.0 * self.A * self.S * self.C

    def equilibria(self) -> list[Equilibrium]:
        """Both equilibria from Eqs. (theta_1_2, deltaequi, eigequi); [] where Eq. (equicrit)
        fails. theta_j is 0 or pi/2, whichever makes r_2 = -cos(2 theta)(2A~r_2^2 - B~r_1^2) >= 0."""
        disc = self.existence
        if disc < 0:
            return []
        s = math.sqrt(disc)
        A, B, C, S = self.A, self.B, self.C, self.S
        out = []
        for j in (1, 2):
            delta = (6 * A * A * C - 3 * A * B * C - (-1) ** j * s - 1) * S / (18 * A * A * B)
            lam2 = (-3 - 18 * A * A * C - 18 * A * B * C + 6 * (-1) ** j * s) / 9.0
            lam = complex(math.sqrt(lam2)) if lam2 >= 0 else 1j * math.sqrt(-lam2)
            P = C + self.k * delta
            r1s, r2s = (P + delta) / 2, (P - delta) / 2
            # theta from the sign of 2 A~ r_2^2 - B~ r_1^2 = (1 -+ s)/(6 A~)
            w = 2 * A * r2s - B * r1s
            theta = 0.0 if w < 0 else math.pi / 2
            kind = "centre" if lam2 < 0 else ("saddle" if lam2 > 0 else "degenerate")
            out.append(Equilibrium(j, theta, float(delta), (lam, -lam), kind,
                                   bool(r2s > 0 and r1s >= 0)))
        return out

    def jacobian(self, delta: float, theta: float, h: float = 1e-6) -> np.ndarray:
        """Central finite-difference Jacobian of (Delta', theta') in (Delta, theta)."""
        J = np.empty((2, 2))
        for c, e in enumerate(np.eye(2) * h):
            fp = self.field(delta + e[0], theta + e[1])
            fm = self.field(delta - e[0], theta - e[1])
            J[:, c] = (np.array(fp) - np.array(fm)) / (2 * h)
        return J

    def trajectory(self, T_end: float, *, dT: float = 1e-3, P_max: float | None = None):
        """The orbit of the paper's initial state q = (sqrt(r1sq), 0), from Eq. (msfinal2) (regular
        at r_2 = 0, where theta is undefined): (T, Delta, theta, P)."""
        run = envelope_run(self.A, self.B, T_end, q0=(math.sqrt(self.r1sq), 0.0), dT=dT,
                           P_max=P_max)
        P, D, th = to_reduced(run.q)
        return run.T, D, th, P


# ---- Figs. 7-8: maps over the (A~, B~) plane (paper's initial state) --------------------------

def equilibrium_map(A_tilde, B_tilde, r1sq: float = r1_squared(64)) -> dict:
    """Delta_1, Delta_2, lambda^2 of each and well-definedness over arrays of (A~, B~) for the
    paper's initial state, C S = 2 B~ r1sq (so 6 A~ S C = 12 A~ B~ r1sq). NaN where Eq. (equicrit)
    fails. Delta_1 is written without the cancellation 1 - s at small B~ (s = sqrt(1 + 12 A B r^2)),
    so it tends to r1sq as B~ -> 0 while Delta_2 diverges."""
    A, B = np.broadcast_arrays(np.asarray(A_tilde, float), np.asarray(B_tilde, float))
    S = A + B
    with np.errstate(invalid="ignore", divide="ignore"):
        disc = 1.0 + 12.0 * A * B * r1sq
        s = np.sqrt(np.where(disc >= 0, disc, np.nan))
        d1 = r1sq * (2 * A - B + 2 * S / (1 + s)) / (3 * A)
        d2 = (12 * A * A * B * r1sq - 6 * A * B * B * r1sq - S * (1 + s)) / (18 * A * A * B)
        lam2_1 = -s * (2 + s) / 3.0       # (eigequi) with 18 A S C = 3 (s^2 - 1)
        lam2_2 = s * (2 - s) / 3.0
        CS = 2 * B * r1sq

        def ok(d):  # r_1^2 = (C S + 2 A d)/(2 S) >= 0 and r_2^2 = (C S - 2 B d)/(2 S) > 0
            return ((CS + 2 * A * d) / (2 * S) >= 0) & ((CS - 2 * B * d) / (2 * S) > 0)

        return {"delta1": d1, "delta2": d2, "lam2_1": lam2_1, "lam2_2": lam2_2,
                "well_defined1": ok(d1) & np.isfinite(d1), "well_defined2": ok(d2) & np.isfinite(d2),
                "exists": disc >= 0}


def bifurcation_curves(A_tilde, r1sq: float = r1_squared(64)) -> dict:
    """B~ on the curves of Fig. 7 as functions of A~: existence 1 + 12 A~B~r1^2 = 0 ("blue"),
    centre/saddle of Delta_2 1 - 4 A~B~r1^2 = 0 ("red") and A~ + B~ = 0 ("black")."""
    A = np.asarray(A_tilde, dtype=float)
    with np.errstate(divide="ignore"):
        return {"blue": -1.0 / (12.0 * A * r1sq), "red": 1.0 / (4.0 * A * r1sq), "black": -A}


#: region codes of `classify`
REGIONS = {
    0: "no equilibria (1 + 12 A~B~r1^2 < 0)",
    1: "Delta_1, Delta_2 well defined, both centres",
    2: "Delta_1 centre, Delta_2 saddle, both well defined",
    3: "only Delta_1 well defined",
    4: "neither well defined",
}


def classify(A_tilde, B_tilde, r1sq: float = r1_squared(64)) -> np.ndarray:
    """Region code (see REGIONS) over arrays of (A~, B~) for the paper's initial state."""
    m = equilibrium_map(A_tilde, B_tilde, r1sq)
    w1, w2 = m["well_defined1"], m["well_defined2"]
    code = np.full(np.shape(w1), 4, dtype=int)
    code[w1 & ~w2] = 3
    both = w1 & w2
    code[both & (m["lam2_2"] < 0)] = 1
    code[both & (m["lam2_2"] >= 0)] = 2
    code[~m["exists"]] = 0
    return code
