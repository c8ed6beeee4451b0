"""The Lyapunov spectrum (Benettin et al. 1980, Shimada & Nagashima 1979) and covariant Lyapunov
vectors (Ginelli et al., PRL 99, 130601 (2007)) of an orbit, on the C handle `fpl_spectrum`
(fputlab/spectrum.h): k deviation vectors carried by the integrator (the symplectic tangent map
of the splitting schemes, the variational equations of the adaptive methods), Householder QR
every `renormalize_every`, exponents lambda_i = (1/t) sum ln R_ii."""
from __future__ import annotations

import math
import os
import tempfile
import time
from dataclasses import dataclass, field

import numpy as np

from .. import _lowlevel as ll
from .._arrays import as_float_array, check_memory
from .._display import ResultMixin, dataclass_repr, fmt, require_xarray, scalar_attrs, variable
from .._errors import IntegrationError, Interrupted, check, last_error
from .._pacing import Pacer, first_span
from .._validate import C_U64, _int, _real
from ..engine import DISORDER_COORD_ATTRS, StudyKind, StudyResult, run_study
from ..integrate import method_info
from ..lattice import Lattice
from .ensemble import orbit_method

__all__ = ["lyapunov_spectrum", "lyapunov_spectra", "SpectrumResult", "covariant_lyapunov_vectors",
           "CLVResult", "covariant_vectors_from_qr", "inverse_participation_ratio",
           "kaplan_yorke_dimension", "ks_entropy"]

#: the C defaults of the spectrum options (fpl_spectrum_options_init)
_S = ll.SPECTRUM_DEFAULTS


def kaplan_yorke_dimension(exponents) -> float:
    """Kaplan-Yorke (Lyapunov) dimension of a spectrum: j + (lambda_1 + ... + lambda_j) /
    abs(lambda_(j+1)) with j the largest index whose partial sum (exponents sorted descending) is
    >= 0; 0 if lambda_1 < 0, and the number of exponents if every partial sum is >= 0."""
    lam = np.sort(np.asarray(exponents, dtype=float))[::-1]
    if lam.size == 0 or not np.all(np.isfinite(lam)):
        return math.nan
    sums = np.cumsum(lam)
    if sums[0] < 0:
        return 0.0
    j = int(np.nonzero(sums >= 0)[0][-1]) + 1      # exponents in the non-negative partial sum
    if j == lam.size:
        return float(j)
    return j + float(sums[j - 1]) / abs(float(lam[j]))


def ks_entropy(exponents) -> float:
    """Kolmogorov-Sinai entropy estimate (Pesin's identity): the sum of the positive exponents."""
    lam = np.asarray(exponents, dtype=float)
    return float(lam[lam > 0].sum())


@dataclass(repr=False)
class SpectrumResult(ResultMixin):
    """The Lyapunov spectrum of one orbit: ``exponents`` (k, at ``t_final``, in the order of the
    QR columns: descending once converged) and their convergence, ``history`` (k, len(t)) at
    the log-spaced times ``t``."""
    exponents: np.ndarray
    t: np.ndarray
    history: np.ndarray
    t_final: float
    steps: int
    method: str
    completed: bool = True      # t_end reached
    message: str = ""           # why the run ended early
    params: dict = field(default_factory=dict)

    @property
    def k(self) -> int:
        """Number of exponents."""
        return int(self.exponents.size)

    @property
    def ks_entropy(self) -> float:
        """Kolmogorov-Sinai entropy estimate: the sum of the positive exponents (Pesin)."""
        return ks_entropy(self.exponents)

    @property
    def kaplan_yorke_dimension(self) -> float:
        """Kaplan-Yorke dimension of the exponents (`kaplan_yorke_dimension`)."""
        return kaplan_yorke_dimension(self.exponents)

    @property
    def mle(self) -> float:
        """lambda_1, the maximum Lyapunov exponent."""
        return float(self.exponents[0]) if self.exponents.size else math.nan

    def __repr__(self) -> str:
        p = self.params
        lead = [f"{k}={fmt(p[k])}" for k in ("N", "model") if p.get(k) is not None]
        lead.append(f"k={self.k}, t_final={fmt(self.t_final)}")
        if self.exponents.size:
            lead.append(f"lambda_1={fmt(self.exponents[0])}, "
                        f"lambda_k={fmt(self.exponents[-1])}, sum={fmt(self.exponents.sum())}, "
                        f"h_KS={fmt(self.ks_entropy)}, D_KY={fmt(self.kaplan_yorke_dimension)}")
        return dataclass_repr(self, lead, skip={"exponents", "t", "history", "t_final", "params",
                                                "steps"})

    def to_xarray(self):
        """The result as an ``xarray.Dataset``: ``exponents`` (exponent), ``history``
        (exponent, t), with units and long names; scalars and ``params`` as attributes.

        Returns
        -------
        xarray.Dataset

        Raises
        ------
        ImportError
            If xarray is not installed.
        """
        xr = require_xarray()
        i = np.arange(1, self.k + 1)
        return xr.Dataset(
            {"exponents": variable("exponent", self.exponents, "exponents"),
             "history": variable(("exponent", "t"), self.history, "history")},
            coords={"exponent": variable("exponent", i, "exponent"),
                    "t": variable("t", self.t, "t")},
            attrs={**scalar_attrs(self), "ks_entropy": self.ks_entropy,
                   "kaplan_yorke_dimension": self.kaplan_yorke_dimension})


def _setup(lattice, method, dt, rtol, atol, y0, w0, k, t0, t_transient):
    """(N, k, integrator options, t0, y0, w0) checked, with the orbit carried through the
    transient t_transient (no deviation vectors)."""
    if not isinstance(lattice, Lattice):
        raise TypeError(f"lattice must be a fputlab.Lattice, got {type(lattice).__name__}")
    adaptive = method_info(method)["adaptive"]
    N = lattice.N
    k = 2 * N if k is None else _int(k, "k")
    if not 1 <= k <= 2 * N:
        raise ValueError(f"k must be 1..2N = {2 * N} (got {k})")
    y = lattice.mode_state() if y0 is None else as_float_array(y0, "y0", (2 * N,))
    w = None if w0 is None else as_float_array(w0, "w0", (k, 2 * N))
    io = ll.integrator_options((0.0 if adaptive else ll.DT) if dt is None else _real(dt, "dt"),
                               _real(rtol, "rtol"), _real(atol, "atol"))
    t0 = _real(t0, "t0")
    t_transient = _real(t_transient, "t_transient")
    if t_transient < 0:
        raise ValueError(f"t_transient must be >= 0 (got {t_transient})")
    if t_transient > 0:                # ChaosTools' Ttr: the orbit alone, then the measurement
        with ll.IntegratorHandle(lattice._h, method, 0, io, t0, np.ascontiguousarray(y)) as ih:
            y = np.empty(2 * N)
            ih.advance(t0 + t_transient, y)
        t0 += t_transient
    return N, k, io, t0, np.ascontiguousarray(y), w


def _spectrum_options(t_end, t0, k, renormalize_every, n_samples, t_first_sample, seed):
    t_end = _real(t_end, "t_end")
    so = ll.spectrum_options(t0 + t_end)
    so.renorm_interval = _real(renormalize_every, "renormalize_every")
    so.n_exponents = k
    so.n_samples = _int(n_samples, "n_samples")
    so.t_first_sample = _real(t_first_sample, "t_first_sample")
    seed = _int(seed, "seed", C_U64)
    if seed < 0:
        raise ValueError(f"seed must be >= 0 (got {seed})")
    so.seed = seed
    return so


def lyapunov_spectrum(lattice: Lattice, t_end: float, *, k: int | None = None, y0=None, w0=None,
                      method: str = "yoshida4", dt: float | None = None, rtol: float = ll.RTOL,
                      atol: float = ll.ATOL, renormalize_every: float = _S["renorm_interval"],
                      n_samples: int = _S["n_samples"],
                      t_first_sample: float = _S["t_first_sample"], t_transient: float = 0.0,
                      seed: int = _S["seed"], t0: float = 0.0,
                      progress: bool = False) -> SpectrumResult:
    """The k largest Lyapunov exponents of an orbit (all 2N by default), by the Benettin /
    Shimada-Nagashima method: k deviation vectors evolved with the integrator's tangent map,
    re-orthonormalised by a Householder QR every `renormalize_every`, λ_i = (1/t) Σ ln R_ii.

    For the Hamiltonian models ("homogeneous", "hamiltonian") a symplectic scheme's tangent map
    has determinant 1: the 2N exponents sum to zero to round-off and pair as
    λ_i + λ_{2N+1-i} -> 0; model 3 ("nonlinear") preserves phase-space volume, so its sum
    vanishes too. λ_1 is `lyapunov`'s maximum exponent on the same orbit.

    Parameters
    ----------
    lattice : Lattice
        The lattice.
    t_end : float
        Length of the measurement (after `t_transient`).
    k : int, optional
        Number of exponents, 1..2N (default: all 2N).
    y0 : array_like, optional
        Initial orbit state, length 2N (default: the paper's mode-1 state).
    w0 : array_like, optional
        Initial deviation vectors, shape (k, 2N), linearly independent (default: Gaussian
        random from `seed`); orthonormalised first.
    method : str, optional
        Integrator name (`fputlab.methods()`); default "yoshida4".
    dt : float, optional
        Step of the fixed-step methods (default 0.01).
    rtol, atol : float, optional
        Tolerances of the adaptive methods.
    renormalize_every : float, optional
        Time between QR re-orthonormalisations (ChaosTools' Δt; default 1). Keep
        λ_1 · renormalize_every well below ~30 so the vectors do not become numerically
        dependent.
    n_samples : int, optional
        Log-spaced samples of the exponents' convergence (``history``).
    t_first_sample : float, optional
        First sample time after the start (0: one renormalisation interval).
    t_transient : float, optional
        The orbit alone is integrated this long first (ChaosTools' Ttr).
    seed : int, optional
        Seed of the random initial deviation vectors.
    t0 : float, optional
        Initial time.
    progress : bool, optional
        A progress bar with ETA (tqdm.auto; the same numbers, computed in segments).

    Returns
    -------
    SpectrumResult
        ``exponents`` (k, in the QR order: descending once converged), ``t``, ``history``
        (k, len(t)), ``ks_entropy`` (sum of the positive exponents), ``kaplan_yorke_dimension``.
        A numerical failure returns what was computed with ``completed`` False and the reason
        in ``message``.

    Raises
    ------
    TypeError
        `lattice` is not a `fputlab.Lattice`.
    ValueError
        An invalid option (unknown method, k out of range, wrong shape of `y0` or `w0`, ...);
        the message names it.
    Interrupted
        Ctrl-C; its ``result`` holds the SpectrumResult computed so far.

    Examples
    --------
    >>> import fputlab
    >>> from fputlab.chaos import lyapunov_spectrum
    >>> lat = fputlab.Lattice(8, alpha=0.0, beta=1.0)
    >>> res = lyapunov_spectrum(lat, 1e3, y0=lat.mode_state(1, 3.0))   # doctest: +SKIP
    >>> res.exponents[:2], res.ks_entropy                                # doctest: +SKIP
    """
    N, k, io, t0, y, w = _setup(lattice, method, dt, rtol, atol, y0, w0, k, t0, t_transient)
    so = _spectrum_options(t_end, t0, k, renormalize_every, n_samples, t_first_sample, seed)
    S = max(so.n_samples, 1)
    check_memory(8.0 * (S * (k + 1) + 2 * N * (k + 1) * 4 + 2 * k * k),
                 f"a spectrum of {k} exponents (N = {N}, {S} samples)")
    t_out, hist = np.full(S, np.nan), np.full((S, k), np.nan)
    status, message, interrupted = 0, "", False
    from tqdm.auto import tqdm
    try:
        s = ll.SpectrumHandle(lattice._h, method, io, t0, y, w, so)
        res = s.get_result()
        pacer = Pacer(max(first_span(io.dt or None, N, k), so.renorm_interval))
        span = so.t_end - t0
        with tqdm(total=span, desc=f"spectrum N={N} k={k}", unit="t",
                  disable=None if progress else True,
                  bar_format="{l_bar}{bar}| {n:.4g}/{total:.4g} [{elapsed}<{remaining}]") as bar:
            target = t0
            try:
                while not s.done():
                    target = min(so.t_end, target + pacer.span)
                    before, clock = res.t_final, time.perf_counter()
                    status = s.advance(target, t_out, hist)
                    s.get_result(res)
                    pacer.record(res.t_final - before, time.perf_counter() - clock)
                    bar.update(res.t_final - t0 - bar.n)
                    if status:
                        message = last_error()
                        break
            except IntegrationError as err:    # NaN/Inf or dependent vectors: keep the samples
                status, message = err.status, str(err)
            except KeyboardInterrupt:
                interrupted = True
        s.get_result(res)
        exps = s.exponents()
    except IntegrationError as err:
        raise ValueError(str(err)) from None
    n = res.n_samples
    out = SpectrumResult(exponents=exps, t=t_out[:n], history=hist[:n].T.copy(),
                         t_final=res.t_final, steps=res.steps, method=method,
                         completed=bool(res.completed), message=message,
                         params={"N": N, "model": lattice.model, "tau": lattice.tau,
                                 "seed": lattice.seed, "t_end": float(t_end), "dt": io.dt,
                                 "renormalize_every": so.renorm_interval, "k": k,
                                 "t_transient": float(t_transient)})
    if interrupted:
        out.completed, out.message = False, f"interrupted (Ctrl-C) at t = {res.t_final:.10g}"
        raise Interrupted(out.message, out)
    return out


# ---- covariant Lyapunov vectors -------------------------------------------------------------

def inverse_participation_ratio(vectors) -> np.ndarray:
    """Inverse participation ratio over sites of deviation vectors (..., 2N) = [δx, δp]: with
    site weights e_j = (δx_j² + δp_j²) / ‖v‖², IPR = Σ_j e_j² (1/N: spread evenly over the
    N sites, 1: on one site); 1/IPR is the number of sites a vector occupies."""
    v = np.asarray(vectors, dtype=float)
    if v.shape[-1] % 2:
        raise ValueError(f"vectors must have an even last axis 2N (got {v.shape[-1]})")
    N = v.shape[-1] // 2
    e = v[..., :N] ** 2 + v[..., N:] ** 2
    e = e / e.sum(axis=-1, keepdims=True)
    return (e * e).sum(axis=-1)


def covariant_vectors_from_qr(Q, R, out=None) -> np.ndarray:
    """Ginelli's backward iteration: covariant Lyapunov vectors from a forward QR run.

    Q[i] (k, L) holds the orthonormal vectors (rows) at the window times i = 0..n-1, and R[j]
    (k, k) the upper-triangular factor of the step j -> j+1 (Φ_j Q_j = Q_{j+1} R[j], Q as
    columns), for j = 0..n-2 inside the window and beyond it (the backward transient:
    len(R) = n - 1 + n_backward). Starting from C = I at the last R, C_j = R[j]^-1 C_{j+1}
    (columns normalised) and the CLVs at window time i are the columns of Q_i C_i.

    Returns
    -------
    ndarray (n, k, L)
        Unit CLVs as rows, in `out` if given (may be Q itself: overwritten in place).
    """
    Q, R = np.asarray(Q), np.asarray(R)
    n, k, L = Q.shape
    if R.ndim != 3 or R.shape[1:] != (k, k) or R.shape[0] < n - 1:
        raise ValueError(f"R must have shape (>= {n - 1}, {k}, {k}) (got {R.shape})")
    out = np.empty((n, k, L)) if out is None else out
    C = np.eye(k)
    for j in range(R.shape[0] - 1, -1, -1):
        if j + 1 <= n - 1:
            v = C.T @ Q[j + 1]
            out[j + 1] = v / np.linalg.norm(v, axis=1, keepdims=True)
        C = _solve_upper(R[j], C)
        C /= np.linalg.norm(C, axis=0, keepdims=True)
    v = C.T @ Q[0]
    out[0] = v / np.linalg.norm(v, axis=1, keepdims=True)
    return out


def _solve_upper(r: np.ndarray, b: np.ndarray) -> np.ndarray:
    """r^-1 b for upper-triangular r, by back substitution (the C of Ginelli stays upper
    triangular, so the result is exact in structure)."""
    k = r.shape[0]
    x = np.zeros_like(b)
    for i in range(k - 1, -1, -1):
        x[i] = (b[i] - r[i, i + 1:] @ x[i + 1:]) / r[i, i]
    return x


@dataclass(repr=False)
class CLVResult(ResultMixin):
    """Covariant Lyapunov vectors along an orbit: ``vectors`` (len(t), k, 2N) unit CLVs (rows;
    vector i grows at rate λ_i), their localisation ``ipr`` (len(t), k) (inverse participation
    ratio over sites), the orbit ``states`` (len(t), 2N) at the window times ``t``, and the
    ``exponents`` of the forward run."""
    t: np.ndarray
    vectors: np.ndarray
    ipr: np.ndarray
    states: np.ndarray
    exponents: np.ndarray
    method: str
    params: dict = field(default_factory=dict)

    @property
    def participation(self) -> np.ndarray:
        """1 / IPR: the number of sites each vector occupies, (len(t), k)."""
        return 1.0 / self.ipr

    def __repr__(self) -> str:
        p = self.params
        lead = [f"{k}={fmt(p[k])}" for k in ("N", "model") if p.get(k) is not None]
        lead.append(f"k={self.vectors.shape[1]}, t={fmt(self.t[0])}..{fmt(self.t[-1])}, "
                    f"{self.t.size} times" if self.t.size else "no times")
        if self.ipr.size:
            lead.append(f"mean IPR {fmt(self.ipr[:, 0].mean())} (v_1).."
                        f"{fmt(self.ipr[:, -1].mean())} (v_k)")
        return dataclass_repr(self, lead, skip={"t", "vectors", "ipr", "states", "exponents",
                                                "params"})

    def to_xarray(self):
        """``ipr`` (t, vector) and ``exponents`` (vector) as an ``xarray.Dataset`` (the vectors
        themselves stay in ``.vectors``)."""
        xr = require_xarray()
        i = np.arange(1, self.ipr.shape[1] + 1)
        return xr.Dataset(
            {"ipr": (("t", "vector"), np.asarray(self.ipr),
                     {"long_name": "inverse participation ratio over sites", "units": "1"}),
             "exponents": variable("vector", self.exponents, "exponents")},
            coords={"t": variable("t", self.t, "t"), "vector": ("vector", i)},
            attrs=scalar_attrs(self))


def covariant_lyapunov_vectors(lattice: Lattice, t_window: float, *, k: int | None = None,
                               t_forward: float | None = None, t_backward: float | None = None,
                               y0=None, method: str = "yoshida4", dt: float | None = None,
                               rtol: float = ll.RTOL, atol: float = ll.ATOL,
                               renormalize_every: float = _S["renorm_interval"],
                               seed: int = _S["seed"], t0: float = 0.0,
                               scratch_dir=None) -> CLVResult:
    """Covariant Lyapunov vectors (Ginelli et al. 2007) at the renormalisation times of a
    window, and their localisation over sites.

    A forward QR run (`lyapunov_spectrum`'s) over t_forward (the vectors converge to the
    backward Lyapunov vectors), t_window (Q and R stored) and t_backward (R stored); then the
    backward iteration of the upper-triangular coefficients (`covariant_vectors_from_qr`).

    Memory: 8 (n_w k 2N + (n_w + n_b) k²) bytes, with n_w = t_window / renormalize_every and
    n_b = t_backward / renormalize_every (N = 64, all 128 vectors: 131 kB per window time).
    With `scratch_dir` the stored factors are memory-mapped files there (the result's
    ``vectors`` stay one, deleted when the result is), so long windows are bounded by disk.

    Parameters
    ----------
    lattice : Lattice
        The lattice (meant for N <= 64: the cost is O(k² 2N) per renormalisation).
    t_window : float
        Length of the window whose CLVs are returned (>= renormalize_every).
    k : int, optional
        Number of vectors, 1..2N (default all 2N).
    t_forward, t_backward : float, optional
        Forward and backward transients (default: t_window each).
    y0 : array_like, optional
        Initial orbit state (default: the paper's mode-1 state).
    method, dt, rtol, atol : optional
        The integrator (as `lyapunov_spectrum`).
    renormalize_every : float, optional
        Time between QR steps: the spacing of the returned vectors.
    seed : int, optional
        Seed of the random initial vectors.
    t0 : float, optional
        Initial time.
    scratch_dir : str or path, optional
        Keep Q and R in memory-mapped files in this folder.

    Returns
    -------
    CLVResult
        ``t`` (the window's renormalisation times), ``vectors`` (len(t), k, 2N), ``ipr``,
        ``states`` (the orbit), ``exponents`` (of the whole forward run).
    """
    N, k, io, t0, y, _ = _setup(lattice, method, dt, rtol, atol, y0, None, k, t0, 0.0)
    tau = _real(renormalize_every, "renormalize_every")
    t_window = _real(t_window, "t_window")
    t_fw = t_window if t_forward is None else _real(t_forward, "t_forward")
    t_bw = t_window if t_backward is None else _real(t_backward, "t_backward")
    if not tau > 0:
        raise ValueError(f"renormalize_every must be > 0 (got {tau})")
    if t_window < tau or t_fw < 0 or t_bw < 0:
        raise ValueError(f"t_window must be >= renormalize_every = {tau} and t_forward, "
                         f"t_backward >= 0 (got {t_window}, {t_fw}, {t_bw})")
    m_a, n_w, n_b = (int(round(x / tau)) for x in (t_fw, t_window, t_bw))
    n_w = max(n_w, 1)
    M = m_a + n_w + n_b
    L = 2 * N
    nbytes = 8.0 * (n_w * k * L + (n_w + n_b) * k * k + n_w * (L + k))
    so = _spectrum_options(M * tau, t0, k, tau, 1, 0.0, seed)
    if scratch_dir is None:
        check_memory(nbytes, f"covariant vectors of {n_w} times (k = {k}, N = {N})")
        Q, R = np.empty((n_w, k, L)), np.empty((max(n_w - 1 + n_b, 0), k, k))
        tmp = None
    else:
        tmp = tempfile.TemporaryDirectory(dir=os.fspath(scratch_dir), prefix="fputlab-clv-")
        Q = np.lib.format.open_memmap(os.path.join(tmp.name, "q.npy"), "w+", float, (n_w, k, L))
        R = np.lib.format.open_memmap(os.path.join(tmp.name, "r.npy"), "w+", float,
                                      (max(n_w - 1 + n_b, 1), k, k))[:max(n_w - 1 + n_b, 0)]
    t = t0 + tau * np.arange(m_a, m_a + n_w, dtype=float)
    states = np.empty((n_w, L))
    try:
        s = ll.SpectrumHandle(lattice._h, method, io, t0, y, None, so)
    except IntegrationError as err:
        raise ValueError(str(err)) from None
    # time m tau after t0: renormalisation m (m = 0: the start, Q = the orthonormalised w0)
    for m in range(0, M + 1):
        if m > 0:
            check(s.advance(t0 + m * tau if m < M else so.t_end, None, None))
            if m - 1 >= m_a and m - 1 - m_a < n_w - 1 + n_b:
                R[m - 1 - m_a] = s.last_r()
        if m_a <= m < m_a + n_w:
            st = s.state()
            Q[m - m_a], states[m - m_a] = st[1:], st[0]
    exps = s.exponents()
    s.close()
    V = covariant_vectors_from_qr(Q, R, out=Q)
    ipr = inverse_participation_ratio(V)
    res = CLVResult(t=t, vectors=V, ipr=ipr, states=states, exponents=exps, method=method,
                    params={"N": N, "model": lattice.model, "tau": lattice.tau,
                            "seed": lattice.seed, "k": k, "renormalize_every": tau,
                            "t_forward": m_a * tau, "t_backward": n_b * tau, "dt": io.dt})
    res._scratch = tmp                      # the memory-mapped files live as long as the result
    return res


# ---- the spectrum study kind: spectra of many realisations -------------------------------------
# As the chaos kind: the C run's sample grid ends beyond t_end (log-spaced at samples_per_decade
# from renormalize_every, the same times whatever t_end), each task keeps the integrator and the
# fpl_spectrum accumulators, so a larger t_end continues every spectrum bit for bit.

#: the settings of spectrum studies and their defaults (C's; method None: the chaos ensembles'
#: srkn14a6 at dt = 0.5)
_SPECTRUM_SETTINGS = {
    "model": "nonlinear", "alpha": 0.25, "beta": 0.0, "method": None, "dt": ll.DT,
    "rtol": ll.RTOL, "atol": ll.ATOL, "renormalize_every": _S["renorm_interval"], "k": None,
    "amplitude": 1.0, "samples_per_decade": 10, "deviation_seed": _S["seed"],
}


def _spectrum_grid(settings: dict, t_end: float) -> tuple[float, int]:
    """(C t_end, C n_samples) of the log grid from renormalize_every that holds t_end."""
    t_first = settings["renormalize_every"]
    K = max(1, math.floor(math.log10(max(t_end / t_first, 1.0))) + 1)
    return t_first * 10.0 ** K, K * settings["samples_per_decade"] + 1


def _study_lattice(settings: dict, N: int, tau: float, seed: int) -> Lattice:
    if settings["model"] == "homogeneous":
        return Lattice(N, settings["alpha"], "homogeneous", beta=settings["beta"])
    return Lattice(N, settings["alpha"], settings["model"], beta=settings["beta"], tau=tau,
                   seed=seed)


def _spectrum_task(settings, N, tau, seed, prev, t_end) -> dict:
    """One spectrum through fpl_spectrum, from its saved state if any, to t_end."""
    cpu0 = time.process_time()
    lat = _study_lattice(settings, N, tau, seed)
    k = settings["k"] or 2 * N
    T, n = _spectrum_grid(settings, t_end)
    adaptive = method_info(settings["method"])["adaptive"]
    io = ll.integrator_options(0.0 if adaptive else settings["dt"], settings["rtol"],
                               settings["atol"])
    so = ll.spectrum_options(T, renorm_interval=settings["renormalize_every"], n_exponents=k,
                             n_samples=n, seed=settings["deviation_seed"])
    s = ll.SpectrumHandle(lat._h, settings["method"], io, 0.0,
                          lat.mode_state(1, settings["amplitude"]), None, so)
    t_s, hist = np.full(n, np.nan), np.full((n, k), np.nan)
    message, done = "", False
    if prev is not None:
        st, v = prev["state"], prev["values"]
        s.integrator().restore(int(st["steps"]), float(st["t"]),
                               np.ascontiguousarray(st["y"], float))
        s.restore(np.ascontiguousarray(st["acc"], float))
        old_t, old_h = np.asarray(v["t_sample"], float), np.asarray(v["history"], float)
        t_s[:old_t.size] = old_t
        hist[:old_h.shape[1], :old_h.shape[0]] = old_h.T
    try:
        if s.advance(t_end, t_s, hist) > 0:
            message, done = last_error(), True      # a stopping criterion: nothing further
    except (IntegrationError, ValueError) as err:  # a numerical failure: the task ends here
        message, done = str(err), True
    res = s.get_result()
    lam = s.exponents()
    ih = s.integrator()
    state = {"steps": np.int64(ih.steps()), "t": np.float64(ih.time()),
             "y": ih.get_state().ravel(), "acc": s.save()}
    values = {"exponents": lam, "ks_entropy": ks_entropy(lam),
              "kaplan_yorke_dimension": kaplan_yorke_dimension(lam),
              "t_final": float(res.t_final), "steps": int(res.steps), "message": message,
              "t_sample": t_s, "history": hist.T}
    return {"t": t_end, "done": done, "message": message, "cpu": time.process_time() - cpu0,
            "values": values, "state": None if done else state}


class SpectrumKind(StudyKind):
    """The Lyapunov spectrum of one orbit per (N, tau, seed) (`lyapunov_spectrum`'s method):
    the exponents at t_end, the KS entropy and Kaplan-Yorke dimension, the convergence on a
    log grid; the state kept, so a larger t_end continues every spectrum bit for bit."""
    name = "spectrum"
    version = 1
    dims = ("N", "tau", "seed")
    batch = 1
    variables = {
        "exponents": (("exponent",), float, "1/time",
                      "Lyapunov exponents at the end (QR order; NaN beyond 2N or k)"),
        "ks_entropy": ((), float, "1/time", "Kolmogorov-Sinai entropy (sum of the positive "
                                            "exponents)"),
        "kaplan_yorke_dimension": ((), float, "1", "Kaplan-Yorke dimension"),
        "t_final": ((), float, "1", "time of the last renormalisation"),
        "steps": ((), np.int64, "1", "integrator steps"),
        "message": ((), str, "", "how the run ended (empty: it can go on)"),
        "t_sample": (("sample",), float, "1", "sample time of the spectrum"),
        "history": (("exponent", "sample"), float, "1/time",
                    "finite-time Lyapunov exponents lambda_i(t)"),
    }
    coord_attrs = {**DISORDER_COORD_ATTRS,
                   "exponent": {"long_name": "exponent index i", "units": "1"},
                   "t": {"long_name": "sample time", "units": "1"}}

    def normalise(self, grid, settings):
        def ints(values, name, low):
            vals = [_int(v, name) for v in np.atleast_1d(values).tolist()]
            if not vals or any(v < low for v in vals) or len(set(vals)) != len(vals):
                raise ValueError(f"{name} must be distinct integers >= {low} (got {vals})")
            return vals
        taus = [_real(v, "tau") for v in np.atleast_1d(grid["tau"]).tolist()]
        if not taus or any(t < 0 for t in taus) or len(set(taus)) != len(taus):
            raise ValueError(f"tau must be distinct values >= 0 (got {taus})")
        grid = {"N": ints(grid["N"], "Ns", 2), "tau": taus, "seed": ints(grid["seed"], "seeds", 0)}
        unknown = set(settings) - set(_SPECTRUM_SETTINGS)
        if unknown:
            raise ValueError(f"{', '.join(sorted(unknown))}: not a setting of spectrum studies "
                             f"(known: {', '.join(sorted(_SPECTRUM_SETTINGS))})")
        s = {**_SPECTRUM_SETTINGS, **{k: v for k, v in settings.items() if v is not None}}
        if s["model"] not in ("homogeneous", "hamiltonian", "nonlinear"):
            raise ValueError(f"model {s['model']!r} is unknown")
        adaptive = orbit_method(s, settings, taus)
        for name in ("alpha", "beta", "dt", "rtol", "atol", "renormalize_every", "amplitude"):
            s[name] = _real(s[name], name)
        for name in ("dt", "rtol", "atol", "renormalize_every"):
            if not s[name] > 0 and not (name == "dt" and adaptive):
                raise ValueError(f"{name} must be > 0 (got {s[name]:g})")
        s["samples_per_decade"] = _int(s["samples_per_decade"], "samples_per_decade")
        if s["samples_per_decade"] < 1:
            raise ValueError(f"samples_per_decade must be >= 1 (got {s['samples_per_decade']})")
        s["deviation_seed"] = _int(s["deviation_seed"], "deviation_seed", C_U64)
        if s["k"] is not None:
            s["k"] = _int(s["k"], "k")
            if not 1 <= s["k"] <= 2 * min(grid["N"]):
                raise ValueError(f"k must be 1..2N = {2 * min(grid['N'])} (got {s['k']})")
        # the length of the exponent axis (2N of the largest N, or k)
        s["n_exponents"] = s["k"] or 2 * max(grid["N"])
        return grid, s

    def cost(self, coords, settings):
        k = settings["k"] or 2 * coords["N"]
        return float(coords["N"] * k)

    def run(self, settings, coords, previous, t_end):
        return [_spectrum_task(settings, c["N"], c["tau"], c["seed"], p, t_end)
                for c, p in zip(coords, previous)]

    def extra_sizes(self, settings, t_end):
        return {"exponent": settings["n_exponents"],
                "sample": _spectrum_grid(settings, t_end)[1]}

    def extra_coords(self, settings, arrays):
        ts = arrays["t_sample"].reshape(-1, arrays["t_sample"].shape[-1])
        counts = np.sum(np.isfinite(ts), axis=1)
        t = ts[int(np.argmax(counts))] if ts.shape[0] else ts[0:0]
        n = arrays["exponents"].shape[-1]
        return {"t": ("sample", t), "exponent": ("exponent", np.arange(1, n + 1))}

    def summary(self, ds):
        rows = []
        for N in ds["N"].values:
            for tau in ds["tau"].values:
                o = ds.sel(N=N, tau=tau)
                lam1 = o["exponents"].isel(exponent=0).values
                rows.append({"N": int(N), "tau": float(tau), "n": int(lam1.size),
                             "lambda_1_mean": float(np.nanmean(lam1)),
                             "lambda_1_std": float(np.nanstd(lam1)),
                             "ks_entropy_mean": float(np.nanmean(o["ks_entropy"].values)),
                             "kaplan_yorke_mean":
                                 float(np.nanmean(o["kaplan_yorke_dimension"].values))})
        return rows


SPECTRUM_KIND = SpectrumKind()


def lyapunov_spectra(Ns=(4, 8, 16), realisations: int = 10, tau=10.0, *, t_end: float = 1e4,
                     model: str = "nonlinear", alpha: float = 0.25, method: str | None = None,
                     first_seed: int = 1, work_dir=None, overwrite: bool = False,
                     workers: int | None = None, scheduler=None, progress: bool = False,
                     **settings) -> StudyResult:
    """Lyapunov spectra of many disorder realisations: a study of the engine (kind
    "spectrum"), resumable with `work_dir` (a larger t_end continues every spectrum bit for
    bit).

    Parameters
    ----------
    Ns : sequence of int, optional
        Lattice sizes (each >= 2).
    realisations : int, optional
        Disorder realisations per N and tau, seeds ``first_seed, first_seed + 1, ...``.
    tau : float or sequence of float, optional
        Variability in percent.
    t_end : float, optional
        Final time of every spectrum.
    model : str, optional
        Lattice model (default "nonlinear", the paper's model 3).
    alpha : float, optional
        Cubic coupling.
    method : str, optional
        Integrator (default: the chaos ensembles' srkn14a6 at dt = 0.5).
    first_seed : int, optional
        Disorder seed of the first realisation.
    work_dir : path, optional
        The study's directory (created; continued on a rerun).
    overwrite : bool, optional
        Discard another study in `work_dir`.
    workers : int, optional
        Local processes (default: all cores).
    scheduler : str or dask.distributed.Client, optional
        Run on a Dask cluster.
    progress : bool, optional
        A progress bar.
    **settings
        beta, dt, rtol, atol, renormalize_every, k, amplitude (of the mode-1 initial state),
        samples_per_decade, deviation_seed.

    Returns
    -------
    StudyResult
        ``to_xarray()``: ``exponents`` (N, tau, seed, exponent), ``history`` (..., exponent,
        sample), ``ks_entropy``, ``kaplan_yorke_dimension``; ``summary()``: mean λ_1, h_KS and
        D_KY per (N, tau).

    Raises
    ------
    ValueError
        An invalid size, realisation count or setting (named).
    """
    realisations = _int(realisations, "realisations")
    if realisations < 1:
        raise ValueError(f"realisations must be >= 1 (got {realisations})")
    taus = [float(t) for t in np.atleast_1d(tau)]
    if model == "homogeneous":
        taus = [0.0]
    grid = {"N": list(np.atleast_1d(Ns)), "tau": taus,
            "seed": [first_seed + r for r in range(realisations)]}
    return run_study("spectrum", grid, {"model": model, "alpha": alpha, "method": method,
                                        **settings},
                     t_end, work_dir=work_dir, overwrite=overwrite, workers=workers,
                     scheduler=scheduler, progress=progress)
