"""The reduced (P, Delta, theta) system (paper Eq. reduced): its constant C, well-defined region,
equilibria (Eqs. theta_1_2, deltaequi), their eigenvalues (eigequi) and type, and the maps over
the (A~, B~) plane of Figs. 7-8 (`equilibrium_map`, `bifurcation_curves`, `classify`)."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._validate import _finite_real


def _r1sq(value) -> float:
    """r_1^2 = |q_1(0)|^2 of the initial state: finite and > 0 (it is (N+1)/8 for the paper's)."""
    r = _finite_real(value, "r1sq")
    if r <= 0:
        raise ValueError(f"r1sq must be > 0 (got {r:g})")
    return r
from .coefficients import r1_squared
from .envelope import envelope_run

__all__ = ["to_reduced", "Equilibrium", "ReducedSystem", "equilibrium_map", "bifurcation_curves",
           "REGIONS", "classify"]



def to_reduced(q) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The reduced variables of envelopes q: q_1 = r_1 e^{i phi_1}, q_2 = r_2 e^{2 i phi_2},
    P = r_1^2 + r_2^2, Delta = r_1^2 - r_2^2, theta = phi_2 - phi_1.

    Parameters
    ----------
    q : array_like
        Complex (q_1, q_2) in the last axis, shape (..., 2).

    Returns
    -------
    P, Delta, theta : numpy.ndarray
        Each of shape (...); theta in [0, pi) (phi_2 is defined modulo pi).
    """
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
        self.r1sq = r1_squared(N) if r1sq is None else _r1sq(r1sq)
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


def equilibrium_map(A_tilde, B_tilde, r1sq: float = r1_squared(64)) -> dict:
    """The equilibria of Eq. (reduced) over arrays of (A~, B~) for the paper's initial
    state, C S = 2 B~ r1sq (so 6 A~ S C = 12 A~ B~ r1sq).

    Delta_1 is written without the cancellation 1 - s at small B~ (s = sqrt(1 + 12 A B r^2)),
    so it tends to r1sq as B~ -> 0 while Delta_2 diverges.

    Parameters
    ----------
    A_tilde, B_tilde : array_like
        The paper-normalised coefficients (broadcast together).
    r1sq : float, optional
        r_1^2 of the initial state (default: N = 64).

    Returns
    -------
    dict
        ``delta1``, ``delta2``, their eigenvalues squared ``lam2_1``, ``lam2_2``, whether each
        is well defined (``well_defined1``, ``well_defined2``) and where they exist
        (``exists``; NaN values where Eq. (equicrit) fails).
    """
    r1sq = _r1sq(r1sq)
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
    """B~ on the curves of Fig. 7 as functions of A~.

    Parameters
    ----------
    A_tilde : array_like
        Values of A~.
    r1sq : float, optional
        r_1^2 of the initial state (default: N = 64).

    Returns
    -------
    dict
        ``blue``: existence, 1 + 12 A~B~r1^2 = 0; ``red``: centre/saddle of Delta_2,
        1 - 4 A~B~r1^2 = 0; ``black``: A~ + B~ = 0.
    """
    r1sq = _r1sq(r1sq)
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
    """The region of each (A~, B~) by its equilibria, for the paper's initial state (Figs. 7-8).

    Parameters
    ----------
    A_tilde, B_tilde : array_like
        The paper-normalised coefficients (broadcast together).
    r1sq : float, optional
        r_1^2 of the initial state (default: N = 64).

    Returns
    -------
    numpy.ndarray
        Integer region codes (see `REGIONS`).
    """
    m = equilibrium_map(A_tilde, B_tilde, r1sq)
    w1, w2 = m["well_defined1"], m["well_defined2"]
    code = np.full(np.shape(w1), 4, dtype=int)
    code[w1 & ~w2] = 3
    both = w1 & w2
    code[both & (m["lam2_2"] < 0)] = 1
    code[both & (m["lam2_2"] >= 0)] = 2
    code[~m["exists"]] = 0
    return code
