"""The lattice: N particles with fixed ends, one of three models, and its evaluation API."""
from __future__ import annotations

import math
import os

import numpy as np

from ._arrays import as_float_array, ptr
from ._errors import check
from ._native import ffi, lib

#: model names (and the paper's equations) -> C model codes
MODELS = {
    "homogeneous": lib.FPL_MODEL_HOMOGENEOUS,   # Eqs. (Hamilt), (eqnmotions)
    "hamiltonian": lib.FPL_MODEL_HAMILTONIAN,   # Eqs. (dis1), (Hamilt2mod): v in both couplings
    "nonlinear": lib.FPL_MODEL_NONLINEAR,       # Eq. (varnonlin): v in the nonlinear terms only
}
DISORDERS = {
    "gaussian": lib.FPL_DISORDER_GAUSSIAN,
    "truncated": lib.FPL_DISORDER_TRUNCATED_GAUSSIAN,
    "uniform": lib.FPL_DISORDER_UNIFORM,
}


def _model_code(model) -> int:
    if isinstance(model, str):
        if model not in MODELS:
            raise ValueError(f"model {model!r} is unknown (known: {', '.join(MODELS)})")
        return MODELS[model]
    if isinstance(model, (int, np.integer)) and not isinstance(model, bool):
        if int(model) not in MODELS.values():
            raise ValueError(f"model {model} is unknown (1 homogeneous, 2 hamiltonian, 3 nonlinear)")
        return int(model)
    raise TypeError(f"model must be a name or 1, 2, 3, got {type(model).__name__}")


def _real(value, name: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a real number, got {type(value).__name__}")
    return float(value)


#: ranges of C integer parameters
C_INT = (-2**31, 2**31 - 1)
C_LONG = (-2**63, 2**63 - 1)
C_U64 = (-2**63, 2**64 - 1)     # seeds (negative values get their own "must be >= 0" errors)


def _int(value, name: str, bounds: tuple = C_INT) -> int:
    """An integer parameter, checked against the range of the C type it goes to (int by
    default): out of range is a ValueError naming it, not cffi's anonymous OverflowError."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an integer, got {type(value).__name__}")
    value = int(value)
    lo, hi = bounds
    if not lo <= value <= hi:
        raise ValueError(f"{name} = {value} is out of range (it must lie in [{lo}, {hi}])")
    return value


#: parameters a Lattice is built from: fixed once built (the C lattice holds copies)
_PARAMETERS = frozenset({"N", "alpha", "beta", "model", "model_code", "tau", "seed", "disorder"})

#: bytes of memory per site of a lattice (C arrays, modes, Python copies), for the estimate
_BYTES_PER_SITE = 8 * 24


def draw_disorder(N: int, tau: float, seed: int, kind: str = "gaussian") -> np.ndarray:
    """Variability v (length N) for tolerance tau (percent) from GSL's mt19937 seeded with seed.

    gaussian: v = 1 + (tau/300) z (the paper); truncated: the same with ``|z| <= 3``; uniform:
    v = 1 + (tau/100) u, u in (-1, 1)."""
    N = _int(N, "N")
    seed = _int(seed, "seed", C_U64)
    if seed < 0 or seed >= 2**64:
        raise ValueError(f"seed must be in [0, 2**64), got {seed}")
    if kind not in DISORDERS:
        raise ValueError(f"disorder {kind!r} is unknown (known: {', '.join(DISORDERS)})")
    v = np.empty(max(N, 0))
    check(lib.fpl_disorder_draw(DISORDERS[kind], _real(tau, "tau"), seed, N,
                                ptr(v) if N > 0 else ffi.NULL))
    return v


class Lattice:
    """An FPUT lattice x_0 = x_{N+1} = 0 with bond potential s^2/2 + alpha s^3/3 + beta s^4/4.

    States are flat arrays y = [x, p] of length 2N (p = v x' for model 2, x' otherwise); with
    deviation vectors, y = [x, p, dx1, dp1, ...] of length 2N(1+k) or shape (1+k, 2N).
    Conventions (α = 0.25, normal modes, σ = τ/300) are in docs/conventions.md.

    Parameters
    ----------
    N : int, optional
        Number of particles (>= 2).
    alpha : float, optional
        Cubic coupling α (the paper's value is 0.25).
    model : {"homogeneous", "hamiltonian", "nonlinear"} or {1, 2, 3}, optional
        "homogeneous" (1; Eqs. Hamilt/eqnmotions); "hamiltonian" (2; v in the linear and
        nonlinear couplings, masses v; Eqs. dis1/Hamilt2mod); "nonlinear" (3; v in the
        nonlinear terms only, not Hamiltonian; Eq. varnonlin).
    beta : float, optional
        Quartic coupling β (FPUT-αβ; 0 in the paper).
    tau : float, optional
        Tolerance τ in percent: v_j = 1 + (τ/300) z_j (models 2 and 3).
    seed : int, optional
        Seed of the disorder draw (GSL mt19937); with `tau` and no seed a fresh one is drawn
        and kept in ``.seed``, so every lattice can be rebuilt exactly.
    disorder : {"gaussian", "truncated", "uniform"}, optional
        Distribution of z (see `draw_disorder`).
    v : array_like, optional
        The variability v_j itself (length N), instead of `tau` and `seed`.

    Raises
    ------
    ValueError, TypeError
        Invalid arguments; the message names the parameter.
    """

    def __init__(self, N: int = 64, alpha: float = 0.25, model="homogeneous", *,
                 beta: float = 0.0, tau: float = 0.0, seed: int | None = None,
                 disorder: str = "gaussian", v=None):
        self.N = _int(N, "N")
        self.alpha = _real(alpha, "alpha")
        self.beta = _real(beta, "beta")
        self.model_code = _model_code(model)
        self.model = ffi.string(lib.fpl_model_name(self.model_code)).decode()
        self.tau = _real(tau, "tau")
        if not isinstance(disorder, str):
            raise TypeError(f"disorder must be a string, got {type(disorder).__name__}")
        if disorder not in DISORDERS:
            raise ValueError(f"disorder {disorder!r} is unknown (known: {', '.join(DISORDERS)})")
        self.disorder = disorder
        if self.N < 2:
            raise ValueError(f"N must be >= 2 (got {self.N})")
        from ._arrays import check_memory
        check_memory(_BYTES_PER_SITE * self.N, f"a lattice of N = {self.N}")
        if v is not None:
            if self.tau != 0.0 or seed is not None:
                raise ValueError("give either v or (tau, seed), not both")
            self.seed = None
            v_arr = as_float_array(v, "v", (self.N,))
        elif self.tau != 0.0 or seed is not None:
            if self.model_code == lib.FPL_MODEL_HOMOGENEOUS and self.tau != 0.0:
                raise ValueError("tau: the homogeneous model has no disorder; "
                                 "use model='hamiltonian' or 'nonlinear'")
            self.seed = (int.from_bytes(os.urandom(4), "little") if seed is None
                         else _int(seed, "seed", C_U64))
            v_arr = draw_disorder(self.N, self.tau, self.seed, disorder)
        else:
            self.seed = None
            v_arr = np.ones(self.N)
        out = ffi.new("fpl_lattice **")
        check(lib.fpl_lattice_create(self.N, self.alpha, self.beta, self.model_code, ptr(v_arr), out))
        self._h = ffi.gc(out[0], lambda h: lib.fpl_lattice_free(ffi.new("fpl_lattice **", h)))
        self._built = True

    def __setattr__(self, name, value):
        if name in _PARAMETERS and self.__dict__.get("_built"):
            raise AttributeError(f"Lattice.{name} is read-only: the lattice was built from it; "
                                 f"make a new Lattice(...) with {name}={value!r}")
        object.__setattr__(self, name, value)

    def __delattr__(self, name):
        if name in _PARAMETERS or name in ("_h", "_built"):
            raise AttributeError(f"Lattice.{name} cannot be deleted")
        object.__delattr__(self, name)

    # -- parameters ---------------------------------------------------------------------------
    @property
    def v(self) -> np.ndarray:
        """The variability v_j (a copy)."""
        v = np.empty(self.N)
        check(lib.fpl_lattice_get_v(self._h, ptr(v), self.N))
        return v

    @property
    def omega(self) -> np.ndarray:
        """Normal-mode frequencies omega_k = 2 sin(k pi / (2(N+1))), k = 1..N."""
        from .modes import omega
        return omega(self.N)

    def __repr__(self) -> str:
        dis = f", tau={self.tau:g}, seed={self.seed}" if self.seed is not None else ""
        return (f"Lattice(N={self.N}, alpha={self.alpha:g}, model={self.model!r}"
                f"{', beta=%g' % self.beta if self.beta else ''}{dis})")

    # -- helpers ------------------------------------------------------------------------------
    def _check(self, status: int) -> int:
        return check(status, self._h)

    def _state(self, y, name="y"):
        """(array (1+k, 2N), k) from a flat or 2-D state with k deviation vectors."""
        arr = as_float_array(y, name)
        two_n = 2 * self.N
        if arr.ndim == 1 and arr.size % two_n == 0 and arr.size > 0:
            arr = arr.reshape(-1, two_n)
        if arr.ndim != 2 or arr.shape[1] != two_n:
            raise ValueError(f"{name} has shape {np.shape(y)}, expected (2N(1+k),) or (1+k, 2N) "
                             f"with 2N = {two_n}")
        return arr, arr.shape[0] - 1

    # -- evaluation ---------------------------------------------------------------------------
    def force(self, x) -> np.ndarray:
        """F(x) = p' (length N)."""
        x = as_float_array(x, "x", (self.N,))
        f = np.empty(self.N)
        self._check(lib.fpl_lattice_force(self._h, ptr(x), ptr(f)))
        return f

    def force_jacobian(self, x, dense: bool = False):
        """dF/dx at x: (lower, diag, upper) of the tridiagonal, or the dense N x N matrix."""
        x = as_float_array(x, "x", (self.N,))
        lo, di, up = np.zeros(self.N), np.empty(self.N), np.zeros(self.N)
        self._check(lib.fpl_lattice_force_jacobian(self._h, ptr(x), ptr(lo), ptr(di), ptr(up)))
        lo, up = lo[:-1].copy(), up[:-1].copy()
        if not dense:
            return lo, di, up
        return np.diag(di) + np.diag(up, 1) + np.diag(lo, -1)

    def tangent_force(self, x, dx) -> np.ndarray:
        """(dF/dx)(x) . dx for one vector (N,) or k vectors (k, N)."""
        x = as_float_array(x, "x", (self.N,))
        dx = as_float_array(dx, "dx", last=self.N)
        if dx.ndim not in (1, 2):
            raise ValueError(f"dx has shape {dx.shape}, expected (N,) or (k, N)")
        k = 1 if dx.ndim == 1 else dx.shape[0]
        out = np.empty_like(dx)
        if k:
            self._check(lib.fpl_lattice_tangent_force(self._h, ptr(x), k, ptr(dx), ptr(out)))
        return out

    def rhs(self, y) -> np.ndarray:
        """y' of the first-order system (with the variational equations for deviation vectors);
        same shape as y."""
        arr, k = self._state(y)
        out = np.empty_like(arr)
        self._check(lib.fpl_lattice_rhs(self._h, ptr(arr), k, ptr(out)))
        return out.reshape(np.shape(y))

    def jacobian(self, y) -> np.ndarray:
        """Dense Jacobian of the first-order system at y (with deviation vectors if present)."""
        arr, k = self._state(y)
        dim = arr.size
        jac = np.empty((dim, dim))
        self._check(lib.fpl_lattice_jacobian_dense(self._h, ptr(arr), k, ptr(jac)))
        return jac

    def energy(self, y) -> float | np.ndarray:
        """H for models 1-2; for model 3 the energy of Eq. (Hamilt) (not conserved). y of shape
        (2N,) or (S, 2N)."""
        arr = as_float_array(y, "y", last=2 * self.N)
        flat = arr.reshape(-1, 2 * self.N)
        out = np.empty(flat.shape[0])
        e = ffi.new("double *")
        for i, row in enumerate(flat):
            self._check(lib.fpl_lattice_energy(self._h, ptr(row), e))
            out[i] = e[0]
        return float(out[0]) if arr.ndim == 1 else out.reshape(arr.shape[:-1])

    def velocity(self, y) -> np.ndarray:
        """x' = p/m from a state (2N,)."""
        arr = as_float_array(y, "y", (2 * self.N,))
        out = np.empty(self.N)
        self._check(lib.fpl_lattice_velocity(self._h, ptr(arr), ptr(out)))
        return out

    # -- modes --------------------------------------------------------------------------------
    def to_modes(self, x) -> np.ndarray:
        """Q = A x (A^{-1} = A, so this also maps Q back to x). x of shape (N,) or (S, N)."""
        arr = as_float_array(x, "x", last=self.N)
        flat = arr.reshape(-1, self.N)
        out = np.empty_like(flat)
        for i in range(flat.shape[0]):
            self._check(lib.fpl_modes_transform(self._h, ptr(flat[i]), ptr(out[i])))
        return out.reshape(arr.shape)

    from_modes = to_modes

    def mode_energies(self, y) -> np.ndarray:
        """E_k = (P_k^2 + omega_k^2 Q_k^2)/2, k = 1..N, for a state (2N,) or states (S, 2N)."""
        arr = as_float_array(y, "y", last=2 * self.N)
        flat = arr.reshape(-1, 2 * self.N)
        out = np.empty((flat.shape[0], self.N))
        for i in range(flat.shape[0]):
            self._check(lib.fpl_modes_energies(self._h, ptr(flat[i]), ptr(out[i])))
        return out.reshape(arr.shape[:-1] + (self.N,))

    def mode_state(self, k: int = 1, amplitude: float = 1.0, coupled: bool = False) -> np.ndarray:
        """Single-mode state: x_j = amplitude sin(pi k j/(N+1)), p = 0 (paper Eq. initxi for k = 1,
        amplitude 1). coupled=True puts the sine in v_j x_j instead (model 2's smooth mode)."""
        y = np.empty(2 * self.N)
        fn = lib.fpl_modes_initial_state_coupled if coupled else lib.fpl_modes_initial_state
        self._check(fn(self._h, _int(k, "k"), _real(amplitude, "amplitude"), ptr(y)))
        return y

    # -- integration --------------------------------------------------------------------------
    def integrate(self, t_end: float, *, method: str = "yoshida4", dt: float | None = None,
                  rtol: float = 1e-10, atol: float = 1e-12, sample_every: float | None = None,
                  times=None, y0=None, deviations=None, t0: float = 0.0,
                  store_states: bool = False, stop_on=None, chunk: int = 4096,
                  on_failure: str = "raise", progress: bool = False,
                  compensated_sums: bool = False):
        """Integrate this lattice: ``fputlab.integrate(self, t_end, ...)``.

        Parameters
        ----------
        t_end : float
            Final time (finite, >= `t0`).
        method : str, optional
            Integrator name (`fputlab.methods()`); default "yoshida4", the paper's.
        dt : float, optional
            Step of the fixed-step methods (default 0.01); an initial step for adaptive ones.
        rtol, atol : float, optional
            Tolerances of the adaptive methods.
        sample_every : float, optional
            Sampling interval (default: (t_end - t0)/1000). Exclusive with `times`.
        times : array_like, optional
            Explicit increasing sample times.
        y0 : array_like, optional
            Initial state [x, p], length 2N (default: the paper's mode-1 state, Eq. initxi).
        deviations : array_like, optional
            Initial deviation vectors, shape (k, 2N).
        t0 : float, optional
            Initial time.
        store_states : bool, optional
            Keep the full state at every sample.
        stop_on : list of tuple, optional
            Stopping criteria, e.g. ``[("stretch", 4.0)]`` (see `fputlab.blowup`).
        chunk : int, optional
            Samples computed per call into the C library.
        on_failure : {"raise", "return"}, optional
            What a blow-up (NaN/Inf state) does: raise `IntegrationError` or return the finite
            samples with ``completed=False``.
        progress : bool, optional
            A progress bar with ETA (tqdm.auto).
        compensated_sums : bool, optional
            SPRKStep methods ("sprk-*") only: compensated summation (ValueError otherwise).

        Returns
        -------
        Run

        See Also
        --------
        fputlab.integrate : the same, with the details of every parameter.
        """
        from .integrate import integrate
        return integrate(self, t_end, method=method, dt=dt, rtol=rtol, atol=atol,
                         sample_every=sample_every, times=times, y0=y0, deviations=deviations,
                         t0=t0, store_states=store_states, stop_on=stop_on, chunk=chunk,
                         on_failure=on_failure, progress=progress,
                         compensated_sums=compensated_sums)

    def __reduce__(self):
        # Picklable for process pools: rebuilt from its parameters (v passed explicitly).
        return (_rebuild, (self.N, self.alpha, self.model, self.beta, self.v, self.tau, self.seed,
                           self.disorder))


def _rebuild(N, alpha, model, beta, v, tau, seed, disorder):
    lat = Lattice(N, alpha, model, beta=beta, v=v)
    for name, value in (("tau", tau), ("seed", seed), ("disorder", disorder)):
        object.__setattr__(lat, name, value)
    return lat
