"""Initial states for thermalization studies: several-mode excitations, random-phase states
(energy spread over a band of modes, as in Onorato et al. 2015 and Lvov & Onorato 2018) and
canonical (thermal) states.

Every random state comes from a numpy ``Generator(PCG64(seed))`` built from the `seed` argument
alone, so the same seed gives the same state on every machine and numpy >= 1.17 (the lattice's
disorder uses GSL's mt19937 in C; the states use numpy, whose streams are documented as stable).

Modes. A fixed chain (x_0 = x_{N+1} = 0) uses its sine modes k = 1..N (docs/conventions.md).
A periodic chain (``lattice.boundary == "periodic"``, x_{j+N} = x_j) uses the complex wave
amplitudes of the papers::

    a_k = (omega_k X_k + i P_k) / sqrt(2 omega_k),   X_k = N^{-1/2} sum_j x_j e^{-2 pi i jk/N},

with omega_k = 2 sin(pi k/N), k = 1..N-1 (k and N-k are the waves travelling right and left;
the k = 0 translation mode carries no energy and is left at zero), so the harmonic energy is
``sum_k omega_k |a_k|^2`` and ``e_k = omega_k |a_k|^2`` is the energy of wave k. P_k is built from the
velocities x' (for model 2, p = v x').
"""
from __future__ import annotations

import math

import numpy as np

from ._validate import C_U64, _int, _real
from .lattice import MODELS, Lattice

__all__ = ["mode_excitation", "random_phases", "thermal", "wave_energies", "boundary_of"]


# -- helpers ------------------------------------------------------------------------------------
def boundary_of(lattice) -> str:
    """The lattice's boundary, "fixed" or "periodic" (no `boundary` attribute: fixed)."""
    return getattr(lattice, "boundary", "fixed")


def _check_lattice(lattice):
    if not isinstance(lattice, Lattice):
        raise TypeError(f"lattice must be a fputlab.Lattice, got {type(lattice).__name__}")
    return lattice


def _generator(seed) -> np.random.Generator:
    seed = _int(seed, "seed", C_U64)
    if seed < 0:
        raise ValueError(f"seed must be in [0, 2**64), got {seed}")
    return np.random.Generator(np.random.PCG64(seed))


def _masses(lattice) -> np.ndarray:
    """m_j with x'_j = p_j / m_j (v_j for model 2, 1 otherwise), asked of the lattice."""
    N = lattice.N
    return 1.0 / lattice.velocity(np.concatenate([np.zeros(N), np.ones(N)]))


def _periodic_omega(N: int) -> np.ndarray:
    return 2.0 * np.sin(np.pi * np.arange(N) / N)


def _modes_of(lattice, modes, name="modes") -> np.ndarray:
    """Mode numbers as an int array, checked against the lattice's mode range."""
    N = lattice.N
    hi = N if boundary_of(lattice) == "fixed" else N - 1
    if isinstance(modes, (int, np.integer)) and not isinstance(modes, bool):
        modes = [modes]
    try:
        ks = [_int(k, name) for k in modes]
    except TypeError:
        raise TypeError(f"{name} must be an integer or a sequence of integers, "
                        f"got {type(modes).__name__}") from None
    if not ks:
        raise ValueError(f"{name} is empty")
    if len(set(ks)) != len(ks):
        raise ValueError(f"{name} has repeated modes: {ks}")
    bad = [k for k in ks if not 1 <= k <= hi]
    if bad:
        raise ValueError(f"{name}: mode(s) {bad} out of range 1..{hi} for this "
                         f"{boundary_of(lattice)} chain of N = {N}")
    return np.array(ks, dtype=int)


def wave_energies(lattice, y) -> np.ndarray:
    """Harmonic energies of the normal modes for state(s) y of shape (..., 2N).

    Fixed chain: E_k = (P_k^2 + omega_k^2 Q_k^2)/2, k = 1..N (`Lattice.mode_energies`).
    Periodic chain: ``e_k = omega_k |a_k|^2``, k = 1..N-1 (the module docstring), one entry per
    travelling wave, the k = 0 translation mode left out, as the papers and nlchains do."""
    _check_lattice(lattice)
    y = np.asarray(y, dtype=float)
    N = lattice.N
    if y.shape[-1] != 2 * N:
        raise ValueError(f"y has shape {y.shape}, expected (..., 2N) with 2N = {2 * N}")
    if boundary_of(lattice) == "fixed":
        return lattice.mode_energies(y)
    flat = y.reshape(-1, 2 * N)
    vel = flat[:, N:] / _masses(lattice)
    X = np.fft.fft(flat[:, :N], axis=-1) / math.sqrt(N)
    P = np.fft.fft(vel, axis=-1) / math.sqrt(N)
    w = _periodic_omega(N)[1:]
    a = (w * X[:, 1:] + 1j * P[:, 1:]) / np.sqrt(2.0 * w)
    return (w * np.abs(a) ** 2).reshape(y.shape[:-1] + (N - 1,))


def _state_from_modes(lattice, modes, energies, phases) -> np.ndarray:
    """The state with harmonic energy energies[i] in mode modes[i] at phase phases[i]."""
    N = lattice.N
    m = _masses(lattice)
    if boundary_of(lattice) == "fixed":
        w = lattice.omega
        Q = np.zeros(N)
        P = np.zeros(N)
        amp = np.sqrt(2.0 * energies)
        Q[modes - 1] = amp * np.cos(phases) / w[modes - 1]
        P[modes - 1] = -amp * np.sin(phases)
        x = lattice.from_modes(Q)
        vel = lattice.from_modes(P)
    else:
        w = _periodic_omega(N)
        a = np.zeros(N, dtype=complex)
        a[modes] = np.sqrt(energies / w[modes]) * np.exp(1j * phases)
        a_minus = np.conj(np.roll(a[::-1], 1))        # a*_{N-k}, k = 0..N-1
        X = np.zeros(N, dtype=complex)
        Pk = np.zeros(N, dtype=complex)
        X[1:] = (a[1:] + a_minus[1:]) / np.sqrt(2.0 * w[1:])
        Pk[1:] = -1j * np.sqrt(w[1:] / 2.0) * (a[1:] - a_minus[1:])
        x = np.fft.ifft(X).real * math.sqrt(N)
        vel = np.fft.ifft(Pk).real * math.sqrt(N)
    return np.concatenate([x, m * vel])


# -- several-mode excitations ------------------------------------------------------------------
def mode_excitation(lattice, modes, energies, phases=None) -> np.ndarray:
    """A deterministic several-mode state: harmonic energy `energies[i]` in mode `modes[i]`.

    Fixed chain: Q_k = sqrt(2E_k) cos(phi_k)/omega_k, P_k = -sqrt(2E_k) sin(phi_k), so phase 0
    puts all of it in the positions (p = 0, like `Lattice.mode_state`). Periodic chain: the
    wave amplitude a_k = sqrt(E_k/omega_k) e^{i phi_k} (k and N - k travel in opposite
    directions; excite both for a standing wave).

    Parameters
    ----------
    lattice : Lattice
    modes : int or sequence of int
        Mode numbers: 1..N (fixed) or 1..N-1 (periodic).
    energies : float or sequence of float
        Harmonic energy of each mode (>= 0); a scalar is used for every mode.
    phases : float or sequence of float, optional
        Phases phi_k (0 by default).

    Returns
    -------
    numpy.ndarray
        The state y = [x, p], length 2N.
    """
    _check_lattice(lattice)
    ks = _modes_of(lattice, modes)
    e = np.broadcast_to(np.asarray(energies, dtype=float), ks.shape).copy() \
        if np.ndim(energies) == 0 else np.asarray(energies, dtype=float)
    if e.shape != ks.shape:
        raise ValueError(f"energies has {e.size} entries for {ks.size} modes")
    if not np.all(np.isfinite(e)) or np.any(e < 0):
        raise ValueError("energies must be finite and >= 0")
    ph = np.zeros(ks.size) if phases is None else np.asarray(phases, dtype=float)
    if ph.ndim == 0:
        ph = np.full(ks.size, float(ph))
    if ph.shape != ks.shape:
        raise ValueError(f"phases has {ph.size} entries for {ks.size} modes")
    if not np.all(np.isfinite(ph)):
        raise ValueError("phases must be finite")
    return _state_from_modes(lattice, ks, e, ph)


# -- random phases -------------------------------------------------------------------------------
def _scale_to_energy(lattice, y, energy) -> np.ndarray:
    """s y with H(s y) = energy (the smallest such s > 0), by bisection on a bracket."""
    if energy == 0.0:
        return np.zeros_like(y)
    h = lambda s: lattice.energy(s * y) - energy
    lo, hi = 0.0, 1.0
    # H grows with s near 0; past an alpha barrier it may turn, so look for the first crossing
    for _ in range(200):
        val = h(hi)
        if not math.isfinite(val):
            break
        if val > 0:
            break
        lo, hi = hi, 2.0 * hi if hi < 1e6 else math.inf
    if not (math.isfinite(hi) and h(hi) > 0):
        raise ValueError(f"energy = {energy:g} cannot be reached by scaling this state "
                         "(an alpha-FPUT chain past its barrier?)")
    # a few-step refinement: grow s in small increments so the first crossing is found
    grid = np.linspace(lo, hi, 33)
    vals = np.array([h(s) for s in grid])
    i = int(np.argmax(vals > 0))
    lo, hi = grid[i - 1], grid[i]
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if h(mid) > 0:
            hi = mid
        else:
            lo = mid
        if hi - lo <= 1e-15 * hi:
            break
    return 0.5 * (lo + hi) * y


def random_phases(lattice, *, energy=None, energy_density=None, modes, seed) -> np.ndarray:
    """Energy spread equally over a band of modes with independent uniform random phases.

    The harmonic energies of the band's modes are equal and their phases are drawn uniformly
    in [0, 2 pi) from ``Generator(PCG64(seed))``; the state is then scaled so that its total
    energy ``lattice.energy(y)`` (harmonic plus anharmonic) equals `energy` exactly. On a
    periodic chain mode k means both travelling waves k and N - k (wave numbers +-k), each with
    its own phase, as in the random-phase ensembles of Onorato et al. (PNAS 2015) and Lvov &
    Onorato (PRL 2018).

    Parameters
    ----------
    lattice : Lattice
    energy : float, optional
        Total energy H of the state (> 0). Give this or `energy_density`.
    energy_density : float, optional
        Energy per particle E/N.
    modes : int or sequence of int
        The band: 1..N (fixed) or 1..N//2 (periodic; both +-k are excited).
    seed : int
        Seed of the phases (0 <= seed < 2**64).

    Returns
    -------
    numpy.ndarray
        y = [x, p], length 2N.
    """
    _check_lattice(lattice)
    if (energy is None) == (energy_density is None):
        raise ValueError("give exactly one of energy and energy_density")
    E = (_real(energy, "energy") if energy is not None
         else _real(energy_density, "energy_density") * lattice.N)
    name = "energy" if energy is not None else "energy_density"
    if not (math.isfinite(E) and E > 0):
        raise ValueError(f"{name} must be finite and > 0")
    rng = _generator(seed)
    if boundary_of(lattice) == "periodic":
        band = _modes_of(lattice, modes)
        if np.any(band > lattice.N // 2):
            raise ValueError(f"modes: a periodic band lists wave numbers 1..N//2 = "
                             f"{lattice.N // 2} (both +-k are excited), got {band.tolist()}")
        ks = np.unique(np.concatenate([band, lattice.N - band]))
    else:
        ks = _modes_of(lattice, modes)
    phases = rng.uniform(0.0, 2.0 * np.pi, ks.size)
    y = _state_from_modes(lattice, ks, np.full(ks.size, 1.0 / ks.size), phases)
    return _scale_to_energy(lattice, y, E)


# -- canonical states ----------------------------------------------------------------------------
def _bond_scale(lattice) -> np.ndarray:
    """c_j with bond stretch r = c_{j+1} x_{j+1} - c_j x_j (v_j for model 2, 1 otherwise)."""
    return lattice.v if lattice.model == "hamiltonian" else np.ones(lattice.N)


def _stretches(lattice, x) -> np.ndarray:
    y = _bond_scale(lattice) * x
    if boundary_of(lattice) == "periodic":
        return np.roll(y, -1) - y
    return np.diff(np.concatenate([[0.0], y, [0.0]]))


def _barrier(lattice) -> float | None:
    """The stretch r* = -1/alpha where an alpha-only FPUT bond potential turns over: the
    canonical measure exists only on the side r > r* (alpha > 0) of every bond."""
    if lattice.model == "toda" or lattice.alpha == 0.0 or lattice.beta > 0.0:
        return None
    return -1.0 / lattice.alpha


def _potential(lattice, x) -> float:
    return lattice.energy(np.concatenate([x, np.zeros(lattice.N)]))


def thermal(lattice, *, temperature, seed, size=None, burn_in: int = 100, thin: int = 4):
    """Canonical states at temperature T: density proportional to exp(-H/T).

    Momenta are exact Maxwell draws p_j ~ N(0, m_j T) (m_j = v_j for model 2, else 1).
    Positions: when the potential is harmonic (alpha = beta = 0, not Toda) the Gaussian is
    sampled exactly in the eigenbasis of the stiffness matrix K = -dF/dx(0). Otherwise the
    bond stretches do not factorise, because they are tied by a constraint (fixed chain: the
    N + 1 stretches sum to x_{N+1} - x_0 = 0; periodic: the N stretches sum to 0), so the
    positions come from a Metropolis-corrected Hamiltonian Monte Carlo chain (exact in its
    stationary law) preconditioned by K, which samples the harmonic part in one trajectory;
    the chain starts from an exact draw of that Gaussian. On a periodic chain the translation
    mode has no potential: the centre of mass and the total momentum are set to 0, so there
    are N - 1 degrees of freedom in x and in p. For alpha-only FPUT (beta = 0) the potential
    is unbounded below past the barrier r* = -1/alpha and the canonical measure exists only on
    r > r* (alpha > 0) for every bond: the chain is restricted to it (an exponentially small
    correction at T << 1/(6 alpha^2)).

    Random numbers: ``Generator(PCG64(seed))``; the same arguments give the same states.

    Parameters
    ----------
    lattice : Lattice
        Models 1 (homogeneous), 2 (hamiltonian) and Toda; model 3 has no Hamiltonian, so no
        canonical measure (ValueError).
    temperature : float
        T > 0 (k_B = 1).
    seed : int
        Seed (0 <= seed < 2**64).
    size : int, optional
        Number of states; None returns one state of length 2N, an int an array (size, 2N).
    burn_in, thin : int, optional
        HMC trajectories before the first state and between states (unused when exact).

    Returns
    -------
    numpy.ndarray
    """
    _check_lattice(lattice)
    if lattice.model_code == MODELS["nonlinear"]:
        raise ValueError("lattice: model 3 ('nonlinear') is not Hamiltonian and has no "
                         "canonical measure; thermal() takes models 1, 2 and Toda")
    T = _real(temperature, "temperature")
    if not (math.isfinite(T) and T > 0):
        raise ValueError(f"temperature must be finite and > 0 (got {T:g})")
    count = 1 if size is None else _int(size, "size")
    if count < 1:
        raise ValueError(f"size must be >= 1 (got {count})")
    burn_in, thin = _int(burn_in, "burn_in"), _int(thin, "thin")
    if burn_in < 0 or thin < 1:
        raise ValueError("burn_in must be >= 0 and thin >= 1")
    rng = _generator(seed)
    N = lattice.N
    # stiffness K = -dF/dx(0), from the first-order system's dense Jacobian (every model and
    # boundary has it): its lower-left block is dF/dx
    K = -lattice.jacobian(np.zeros(2 * N))[N:, :N]
    K = 0.5 * (K + K.T)
    lam, U = np.linalg.eigh(K)
    keep = lam > 1e-10 * lam.max()          # drops the periodic translation mode
    zero_modes = U[:, ~keep]                # its direction u in x (1/v for model 2)
    lam, U = lam[keep], U[:, keep]
    m = _masses(lattice)

    def gaussian():
        return U @ (rng.standard_normal(lam.size) * np.sqrt(T / lam))

    exact = (lattice.alpha == 0.0 and lattice.beta == 0.0 and lattice.model != "toda")
    r_star = _barrier(lattice)

    def allowed(x):
        if r_star is None:
            return True
        r = _stretches(lattice, x)
        return bool(np.all(r > r_star) if r_star < 0 else np.all(r < r_star))

    xs = np.empty((count, N))
    if exact:
        for i in range(count):
            xs[i] = gaussian()
    else:
        x = gaussian()
        tries = 0
        while not allowed(x):             # a start inside the barrier (always so at low T)
            x, tries = gaussian(), tries + 1
            if tries > 1000:
                raise ValueError(f"temperature = {T:g} is too high for this alpha-FPUT chain: "
                                 "its bonds do not stay inside the barrier r > -1/alpha")
        u_x = _potential(lattice, x)
        h = 0.35                             # step in K-preconditioned time (harmonic omega = 1)

        def trajectory(x, u_x):
            # leapfrog for H = p K^+ p / 2 + U(x): harmonic modes all have frequency 1
            # momenta of the auxiliary dynamics: p ~ N(0, T K), kinetic energy p K^+ p / 2
            z = rng.standard_normal(lam.size)
            p = U @ (np.sqrt(T * lam) * z)
            kin0 = 0.5 * T * float(z @ z)
            steps = int(rng.integers(3, 7))   # jittered length ~ a quarter period
            xn = x.copy()
            pn = p + 0.5 * h * lattice.force(xn)
            for s in range(steps):
                xn = xn + h * (U @ ((U.T @ pn) / lam))
                if not allowed(xn):
                    return x, u_x, False
                f = lattice.force(xn)
                pn = pn + (h if s < steps - 1 else 0.5 * h) * f
            kin1 = 0.5 * float(((U.T @ pn) ** 2 / lam).sum())
            u_n = _potential(lattice, xn)
            dh = (u_n + kin1 - u_x - kin0) / T
            if math.isfinite(dh) and (dh <= 0 or rng.random() < math.exp(-dh)):
                return xn, u_n, True
            return x, u_x, False

        for _ in range(burn_in):
            x, u_x, _acc = trajectory(x, u_x)
        for i in range(count):
            for _ in range(thin):
                x, u_x, _acc = trajectory(x, u_x)
            xs[i] = x
    ps = rng.standard_normal((count, N)) * np.sqrt(m * T)
    # xs has no component along a translation mode u (the sampler lives on K's range); its
    # conserved momentum u.p (sum p for unit masses) is set to 0 by the exact conditional
    # Gaussian: p <- p - M u (u.p)/(u.M u)
    for u in zero_modes.T:
        ps -= np.outer(ps @ u, m * u) / float(u @ (m * u))
    out = np.concatenate([xs, ps], axis=1)
    return out[0] if size is None else out
