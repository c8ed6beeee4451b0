"""The envelope equations (paper Eq. msfinal2) in the slow time T = eps t, integrated with
fixed-step RK4 (numpy only), and the leading-order reconstruction of Q_j(t) (Fig. 6)."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._display import ResultMixin
from .._validate import _finite_real, _size
from .coefficients import r1_squared
from .modal import ModalRun

__all__ = ["envelope_rhs", "EnvelopeRun", "ENVELOPE_MAX_STEPS", "envelope_run", "envelope_error"]



def envelope_rhs(q: np.ndarray, A_tilde: float, B_tilde: float) -> np.ndarray:
    """dq/dT of the envelope equations, Eq. (msfinal2): i q1' = q1 + A~ conj(q1) q2,
    i q2' = q2 + B~ q1^2.

    Parameters
    ----------
    q : numpy.ndarray
        Complex (q_1, q_2) in the last axis, shape (..., 2).
    A_tilde, B_tilde : float
        The paper-normalised coefficients.

    Returns
    -------
    numpy.ndarray
        dq/dT, the shape of `q`.
    """
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
    N = _size(N)
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
    """How far the envelope equations are from the two-mode system: the largest
    ``|Q_j - Q_j^env|`` over the samples, j = 1, 2 (Q^env from `EnvelopeRun.reconstruct`).

    Parameters
    ----------
    two_mode : ModalRun
        A run of the two-mode system (`two_mode_run`).
    envelope : EnvelopeRun
        The envelope run (`envelope_run`) covering the slow times eps t of its samples.
    eps : float
        The detuning omega_2 - 2 omega_1 (`detuning`).

    Returns
    -------
    numpy.ndarray
        The two maxima, shape (2,).
    """
    Qe = envelope.reconstruct(two_mode.t, two_mode.omega, eps)
    return np.abs(two_mode.Q - Qe).max(axis=0)
