"""The two-mode system's coefficients (paper Eq. msvar): the raw a_i, b_i of an N-particle
chain by projection (closed sums over the bonds, in C), the chain's frequencies and detuning,
and the paper's normalisation A~, B~ (docs/conventions.md)."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _lowlevel as ll
from .._arrays import as_float_array
from .._validate import _int, _real, _size
from ..lattice import Lattice, _model_code

__all__ = ["COEFFICIENT_NAMES", "frequencies", "detuning", "r1_squared", "TwoModeCoefficients",
           "two_mode_coefficients", "quadratic_forms"]


#: order of the raw coefficients everywhere (mode-1 equation a, mode-2 equation b)
COEFFICIENT_NAMES = ("a1", "a2", "a3", "b1", "b2", "b3")


def frequencies(N: int) -> tuple[float, float]:
    """The two lowest normal-mode frequencies of the fixed-end chain.

    Parameters
    ----------
    N : int
        Lattice size.

    Returns
    -------
    tuple of float
        (omega_1, omega_2), omega_k = 2 sin(k pi/(2(N+1))).

    Raises
    ------
    TypeError
        N is not an integer.
    ValueError
        N < 2.
    """
    N = _size(N)
    return 2.0 * math.sin(math.pi / (2 * (N + 1))), 2.0 * math.sin(math.pi / (N + 1))


def detuning(N: int) -> float:
    """The detuning eps = omega_2 - 2 omega_1 of the two-mode resonance.

    Parameters
    ----------
    N : int
        Lattice size.

    Returns
    -------
    float
        eps (negative, about -(pi/(N+1))^3 / 4 for large N).
    """
    w1, w2 = frequencies(N)
    return w2 - 2.0 * w1


def r1_squared(N: int) -> float:
    """``r_1^2 = |q_1(0)|^2 = (Q_1(0)/2)^2 = (N+1)/8`` for the paper's initial state (Eq. initxi).

    Parameters
    ----------
    N : int
        Lattice size.

    Returns
    -------
    float
        (N + 1)/8.
    """
    return (_size(N) + 1) / 8.0


def _tilde_scales(N: int) -> tuple[float, float]:
    """A~ = sA a_3 and B~ = sB b_1."""
    w1, w2 = frequencies(N)
    eps = w2 - 2.0 * w1
    return 1.0 / (eps * 2.0 * w1), 1.0 / (eps * 2.0 * w2)


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
        if lat.boundary != "fixed":
            raise ValueError("N: the two-mode reduction uses the fixed-end chain's sine modes; "
                             f"this lattice is {lat.boundary}")
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
    """The tridiagonal matrix M of each raw coefficient, c = v^T M v (models 2 and 3).

    Parameters
    ----------
    N : int
        Lattice size (>= 2).
    alpha : float, optional
        Cubic coupling.

    Returns
    -------
    diag : numpy.ndarray
        Diagonals, shape (6, N), one row per coefficient (order `COEFFICIENT_NAMES`).
    off : numpy.ndarray
        Off-diagonals, shape (6, N - 1).

    Raises
    ------
    ValueError
        N < 2.
    """
    N = _int(N, "N")
    if N < 2:
        raise ValueError(f"N must be >= 2 (got {N})")
    return ll.reduction_quadratic_forms(N, _real(alpha, "alpha"))
