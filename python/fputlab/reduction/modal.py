"""Truncated modal systems integrated in C with the splitting schemes: the two-mode ODE (paper
Eq. msvar) and the Galerkin truncation of the lattice to its first M normal modes (Eq.
eqnmfsvarnonlin, Fig. 4)."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _lowlevel as ll
from .._display import ResultMixin
from .._arrays import as_float_array
from .._errors import IntegrationError, check
from .._validate import _finite_real, _positive_real, _real
from ..integrate import _sample_times
from ..lattice import Lattice
from .coefficients import TwoModeCoefficients

__all__ = ["ModalRun", "two_mode_run", "Galerkin"]


def _scheme(method: str):
    if not isinstance(method, str):
        raise TypeError(f"method must be a string, got {type(method).__name__}")
    return ll.splitting_lookup(method)


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
    dt = _positive_real(dt, "dt")
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

    def run(self, t_end: float, *, dt: float = ll.DT, sample_every: float | None = None,
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
