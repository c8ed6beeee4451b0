"""The lattice: N particles with fixed ends or on a ring, one of four models, and its evaluation
API."""
from __future__ import annotations

import os

import numpy as np

from . import _lowlevel as ll
from ._arrays import as_float_array, check_memory
from ._validate import C_INT, C_LONG, C_U64, _int, _real  # noqa: F401 (C_INT, C_LONG: public here)
from .modes import omega as _omega

__all__ = ["Lattice", "draw_disorder", "MODELS", "DISORDERS"]

#: model names (and the paper's equations) -> C model codes
MODELS = {
    "homogeneous": ll.MODEL_CODES["homogeneous"],   # Eqs. (Hamilt), (eqnmotions)
    "hamiltonian": ll.MODEL_CODES["hamiltonian"],   # Eqs. (dis1), (Hamilt2mod): v in both couplings
    "nonlinear": ll.MODEL_CODES["nonlinear"],       # Eq. (varnonlin): v in the nonlinear terms only
    "toda": ll.MODEL_CODES["toda"],                 # V(r) = (e^{2 alpha r} - 1 - 2 alpha r)/(4 alpha^2)
}
#: names of the distributions of the disorder draws z (`draw_disorder`) -> C codes
DISORDERS = dict(ll.DISORDER_CODES)
#: boundary-condition names -> C codes ("fixed": walls at both ends; "periodic": a ring)
BOUNDARIES = dict(ll.BOUNDARY_CODES)


def _model_code(model) -> int:
    if isinstance(model, str):
        if model not in MODELS:
            raise ValueError(f"model {model!r} is unknown (known: {', '.join(MODELS)})")
        return MODELS[model]
    if isinstance(model, (int, np.integer)) and not isinstance(model, bool):
        if int(model) not in MODELS.values():
            raise ValueError(f"model {model} is unknown (1 homogeneous, 2 hamiltonian, "
                             "3 nonlinear, 4 toda)")
        return int(model)
    raise TypeError(f"model must be a name or 1, 2, 3, 4, got {type(model).__name__}")


def _boundary_code(boundary) -> int:
    if not isinstance(boundary, str):
        raise TypeError(f"boundary must be 'fixed' or 'periodic', got {type(boundary).__name__}")
    if boundary not in BOUNDARIES:
        raise ValueError(f"boundary {boundary!r} is unknown (known: {', '.join(BOUNDARIES)})")
    return BOUNDARIES[boundary]


#: parameters a Lattice is built from: fixed once built (the C lattice holds copies)
_PARAMETERS = frozenset({"N", "alpha", "beta", "model", "model_code", "tau", "seed", "disorder",
                         "boundary"})

#: bytes of memory per site of a lattice (C arrays, modes, Python copies; the mode transform's
#: FFT scratch takes up to ~36 doubles a site where it uses Bluestein's algorithm), for the estimate
_BYTES_PER_SITE = 8 * 60


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
    return ll.disorder_draw(DISORDERS[kind], _real(tau, "tau"), seed, N)


class Lattice:
    """An FPUT lattice with bond potential s^2/2 + alpha s^3/3 + beta s^4/4 (or the Toda chain's),
    fixed ends x_0 = x_{N+1} = 0 or periodic (x_N = x_0).

    States are flat arrays y = [x, p] of length 2N (p = v x' for model 2, x' otherwise); with
    deviation vectors, y = [x, p, dx1, dp1, ...] of length 2N(1+k) or shape (1+k, 2N).
    Conventions (α = 0.25, normal modes, σ = τ/300) are in docs/conventions.md.

    Parameters
    ----------
    N : int, optional
        Number of particles (>= 2).
    alpha : float, optional
        Cubic coupling α (the paper's value is 0.25).
    model : {"homogeneous", "hamiltonian", "nonlinear", "toda"} or {1, 2, 3, 4}, optional
        "homogeneous" (1; Eqs. Hamilt/eqnmotions); "hamiltonian" (2; v in the linear and
        nonlinear couplings, masses v; Eqs. dis1/Hamilt2mod); "nonlinear" (3; v in the
        nonlinear terms only, not Hamiltonian; Eq. varnonlin); "toda" (4; the integrable Toda
        chain V(r) = (e^{2αr} - 1 - 2αr)/(4α²), homogeneous, β must be 0).
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
    boundary : {"fixed", "periodic"}, optional
        "fixed": walls x_0 = x_{N+1} = 0 (N + 1 bonds, the paper); "periodic": a ring of N
        particles and N bonds (x_N = x_0), normal modes are Fourier modes (docs/conventions.md).

    Raises
    ------
    ValueError, TypeError
        Invalid arguments; the message names the parameter.
    """

    def __init__(self, N: int = 64, alpha: float = 0.25, model="homogeneous", *,
                 beta: float = 0.0, tau: float = 0.0, seed: int | None = None,
                 disorder: str = "gaussian", v=None, boundary: str = "fixed"):
        self.N = _int(N, "N")
        self.alpha = _real(alpha, "alpha")
        self.beta = _real(beta, "beta")
        self.model_code = _model_code(model)
        self.model = ll.model_name(self.model_code)
        boundary_code = _boundary_code(boundary)
        self.boundary = boundary
        self.tau = _real(tau, "tau")
        if not isinstance(disorder, str):
            raise TypeError(f"disorder must be a string, got {type(disorder).__name__}")
        if disorder not in DISORDERS:
            raise ValueError(f"disorder {disorder!r} is unknown (known: {', '.join(DISORDERS)})")
        self.disorder = disorder
        if self.N < 2:
            raise ValueError(f"N must be >= 2 (got {self.N})")
        check_memory(_BYTES_PER_SITE * self.N, f"a lattice of N = {self.N}")
        if v is not None:
            if self.tau != 0.0 or seed is not None:
                raise ValueError("give either v or (tau, seed), not both")
            self.seed = None
            v_arr = as_float_array(v, "v", (self.N,))
        elif self.tau != 0.0 or seed is not None:
            if self.model_code in (MODELS["homogeneous"], MODELS["toda"]) and self.tau != 0.0:
                raise ValueError(f"tau: the {self.model} model has no disorder; "
                                 "use model='hamiltonian' or 'nonlinear'")
            self.seed = (int.from_bytes(os.urandom(4), "little") if seed is None
                         else _int(seed, "seed", C_U64))
            v_arr = draw_disorder(self.N, self.tau, self.seed, disorder)
        else:
            self.seed = None
            v_arr = np.ones(self.N)
        self._h = ll.LatticeHandle(self.N, self.alpha, self.beta, self.model_code, v_arr,
                                   boundary_code)
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
        return self._h.get_v()

    @property
    def barrier(self) -> tuple[float, float]:
        """(lower, upper): the tops of the bond potential's barrier on either side of r = 0, the
        nearest non-zero roots of V'(r); -inf / inf where there is none (C: fpl_lattice_barrier).
        FPUT-α: (-1/α, inf) for α > 0; α² <= 4β: none; Toda: none."""
        return self._h.barrier()

    @property
    def omega(self) -> np.ndarray:
        """Normal-mode frequencies in the order of `mode_energies`: omega_k = 2 sin(k pi /
        (2(N+1))), k = 1..N (fixed ends), or omega_k = 2 sin(pi k/N), k = 0..N-1 (periodic)."""
        if self.boundary == "fixed":
            return _omega(self.N)
        return self._h.modes_frequencies()

    @property
    def mode_numbers(self) -> np.ndarray:
        """The mode index k of each column of `mode_energies`: 1..N (fixed ends, sine modes) or
        the wavenumbers 0..N-1 (periodic; k = 0 is the centre-of-mass motion)."""
        first = 1 if self.boundary == "fixed" else 0
        return np.arange(first, first + self.N)

    def __repr__(self) -> str:
        dis = f", tau={self.tau:g}, seed={self.seed}" if self.seed is not None else ""
        bnd = f", boundary={self.boundary!r}" if self.boundary != "fixed" else ""
        return (f"Lattice(N={self.N}, alpha={self.alpha:g}, model={self.model!r}"
                f"{', beta=%g' % self.beta if self.beta else ''}{dis}{bnd})")

    # -- helpers ------------------------------------------------------------------------------
    def _state(self, y, name="y"):
        """(array (1+k, 2N), k) from a flat or 2-D state with k deviation vectors."""
        arr = as_float_array(y, name)
        two_n = 2 * self.N
        if arr.ndim == 1 and arr.size % two_n == 0 and arr.size > 0:
            arr = arr.reshape(-1, two_n)
        if arr.ndim != 2 or arr.shape[1] != two_n or arr.shape[0] == 0:
            raise ValueError(f"{name} has shape {np.shape(y)}, expected (2N(1+k),) or (1+k, 2N) "
                             f"with 2N = {two_n}: the orbit, then k >= 0 deviation vectors")
        return arr, arr.shape[0] - 1

    # -- evaluation ---------------------------------------------------------------------------
    def force(self, x) -> np.ndarray:
        """F(x) = p' (length N)."""
        x = as_float_array(x, "x", (self.N,))
        return self._h.force(x)

    def force_jacobian(self, x, dense: bool = False):
        """dF/dx at x: (lower, diag, upper) of the tridiagonal, or the dense N x N matrix (the
        only form for a periodic chain, whose wrap-around bond couples x_0 and x_{N-1})."""
        x = as_float_array(x, "x", (self.N,))
        if self.boundary == "periodic":
            if not dense:
                raise ValueError("dense: the force Jacobian of a periodic chain is not "
                                 "tridiagonal; use force_jacobian(x, dense=True)")
            y = np.concatenate([x, np.zeros(self.N)])
            return self._h.jacobian_dense(y, 0)[self.N:, :self.N].copy()
        lo, di, up = self._h.force_jacobian(x)
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
            self._h.tangent_force(x, k, dx, out)
        return out

    def rhs(self, y) -> np.ndarray:
        """y' of the first-order system (with the variational equations for deviation vectors);
        same shape as y."""
        arr, k = self._state(y)
        return self._h.rhs(arr, k).reshape(np.shape(y))

    def jacobian(self, y) -> np.ndarray:
        """Dense Jacobian of the first-order system at y (with deviation vectors if present)."""
        arr, k = self._state(y)
        return self._h.jacobian_dense(arr, k)

    def energy(self, y) -> float | np.ndarray:
        """H for models 1-2; for model 3 the energy of Eq. (Hamilt) (not conserved). y of shape
        (2N,) or (S, 2N)."""
        arr = as_float_array(y, "y", last=2 * self.N)
        flat = arr.reshape(-1, 2 * self.N)
        out = np.empty(flat.shape[0])
        for i, row in enumerate(flat):
            out[i] = self._h.energy(row)
        return float(out[0]) if arr.ndim == 1 else out.reshape(arr.shape[:-1])

    def velocity(self, y) -> np.ndarray:
        """x' = p/m from a state (2N,)."""
        arr = as_float_array(y, "y", (2 * self.N,))
        return self._h.velocity(arr)

    # -- modes --------------------------------------------------------------------------------
    def to_modes(self, x) -> np.ndarray:
        """Q = A x (A^{-1} = A, so this also maps Q back to x). x of shape (N,) or (S, N).

        Fixed ends: the sine transform A_jk = sqrt(2/(N+1)) sin(jk pi/(N+1)); periodic: the
        orthonormal Hartley transform A_jk = N^{-1/2} (cos + sin)(2 pi jk/N), the Fourier modes
        as real standing waves (docs/conventions.md)."""
        arr = as_float_array(x, "x", last=self.N)
        flat = arr.reshape(-1, self.N)
        out = np.empty_like(flat)
        for i in range(flat.shape[0]):
            self._h.modes_transform(flat[i], out[i])
        return out.reshape(arr.shape)

    from_modes = to_modes

    def mode_energies(self, y) -> np.ndarray:
        """E_k = (P_k^2 + omega_k^2 Q_k^2)/2 for a state (2N,) or states (S, 2N): k = 1..N for
        fixed ends, wavenumbers k = 0..N-1 for a periodic chain (`mode_numbers`; E_0 is the
        kinetic energy of the centre of mass). O(N log N) for every N."""
        arr = as_float_array(y, "y", last=2 * self.N)
        flat = arr.reshape(-1, 2 * self.N)
        out = np.empty((flat.shape[0], self.N))
        for i in range(flat.shape[0]):
            self._h.modes_energies(flat[i], out[i])
        return out.reshape(arr.shape[:-1] + (self.N,))

    def mode_state(self, k: int = 1, amplitude: float = 1.0, coupled: bool = False) -> np.ndarray:
        """Single-mode state: x_j = amplitude sin(pi k j/(N+1)), p = 0 (paper Eq. initxi for k = 1,
        amplitude 1); periodic: x_j = amplitude sin(2 pi k j/N + pi/4), k = 1..N-1, the single
        Hartley mode k. coupled=True puts the shape in v_j x_j instead (model 2's smooth mode)."""
        return self._h.initial_state(_int(k, "k"), _real(amplitude, "amplitude"), bool(coupled))

    def with_deviation_vectors(self, y, k: int = ll.CHAOS_DEFAULTS["n_dev"], *,
                               seed: int = ll.CHAOS_DEFAULTS["seed"]) -> np.ndarray:
        """The state `y` with `k` random unit deviation vectors: the (1+k, 2N) array that
        `Integrator` and `iter_samples` take (row 0 the orbit, rows 1..k the vectors).

        The vectors are those `fputlab.chaos.lyapunov` starts from with the same `seed` (to
        rounding): 2Nk standard normal draws from GSL's mt19937 (the generator of
        `draw_disorder`), row by row, each row scaled to unit Euclidean norm.

        Parameters
        ----------
        y : array_like
            The orbit's state [x, p], length 2N.
        k : int, optional
            Number of deviation vectors (>= 1; default the chaos default, 2).
        seed : int, optional
            Seed of the draws (>= 0; default the chaos default, 1): the same seed gives the same
            vectors.

        Returns
        -------
        numpy.ndarray
            Shape (1+k, 2N), a new array.

        Raises
        ------
        ValueError, TypeError
            `y` of the wrong length or not finite, `k` < 1, `seed` < 0; the message names the
            parameter.

        Examples
        --------
        >>> lat = Lattice(N=8)
        >>> y = lat.with_deviation_vectors(lat.mode_state(1), 2, seed=1)
        >>> y.shape
        (3, 16)
        """
        two_n = 2 * self.N
        orbit = as_float_array(y, "y", (two_n,))
        if not np.all(np.isfinite(orbit)):
            raise ValueError("y must be finite")
        k = _int(k, "k")
        if k < 1:
            raise ValueError(f"k must be >= 1 (got {k})")
        seed = _int(seed, "seed", C_U64)
        if seed < 0:
            raise ValueError(f"seed must be >= 0 (got {seed})")
        out = np.empty((1 + k, two_n))
        out[0] = orbit
        draws = np.empty(two_n * k)
        ll.disorder_standard(DISORDERS["gaussian"], seed, draws.size, draws)
        w = draws.reshape(k, two_n)
        out[1:] = w / np.linalg.norm(w, axis=1, keepdims=True)
        return out

    # -- integration: Lattice.integrate(t_end, ...) = fputlab.integrate(lattice, t_end, ...) is
    # installed by fputlab.integrate, the layer above (the model does not import its integrators)

    def __reduce__(self):
        # Picklable for process pools: rebuilt from its parameters (v passed explicitly).
        return (_rebuild, (self.N, self.alpha, self.model, self.beta, self.v, self.tau, self.seed,
                           self.disorder, self.boundary))


def _rebuild(N, alpha, model, beta, v, tau, seed, disorder, boundary="fixed"):
    lat = Lattice(N, alpha, model, beta=beta, v=v, boundary=boundary)
    for name, value in (("tau", tau), ("seed", seed), ("disorder", disorder)):
        object.__setattr__(lat, name, value)
    return lat
