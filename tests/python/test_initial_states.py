"""Initial states: several-mode excitations, random phases, canonical states. Checked against
mode energies computed independently (the explicit sine matrix, numpy's FFT), statistics of
the draws (uniform phases, equipartition, the virial) and a quadrature of the canonical
density of a two-particle chain."""
import math

import numpy as np
import pytest

import fputlab
from fputlab import initial_states as ist
from fputlab.modes import mode_matrix


def _periodic_supported():
    try:
        fputlab.Lattice(8, 0.25, boundary="periodic")
    except (TypeError, ValueError, NotImplementedError, fputlab.FputlabError):
        return False
    return True


periodic = pytest.mark.skipif(not _periodic_supported(),
                              reason="periodic lattices are not available in this build")


def _sine_energies(lat, y):
    """E_k from the explicit orthogonal sine matrix (not the library's FFT)."""
    N = lat.N
    A = mode_matrix(N)
    w = 2 * np.sin(np.arange(1, N + 1) * np.pi / (2 * (N + 1)))
    Q, P = A @ y[:N], A @ (y[N:] / ist._masses(lat))
    return 0.5 * (P**2 + (w * Q) ** 2)


def test_mode_excitation_puts_the_energies_in_the_modes():
    lat = fputlab.Lattice(16, 0.25)
    y = ist.mode_excitation(lat, [1, 3, 7], [0.1, 0.02, 0.3], phases=[0.0, 1.0, 2.5])
    e = _sine_energies(lat, y)
    want = np.zeros(16)
    want[[0, 2, 6]] = [0.1, 0.02, 0.3]
    np.testing.assert_allclose(e, want, atol=1e-14)
    # phase 0: all in the positions, the paper's single-mode state up to its amplitude
    y1 = ist.mode_excitation(lat, 1, 0.05)
    np.testing.assert_array_equal(y1[16:], 0.0)
    ref = lat.mode_state(1)
    np.testing.assert_allclose(y1[:16] / y1[0], ref[:16] / ref[0], rtol=1e-12)


def test_mode_excitation_model2_uses_velocities():
    lat = fputlab.Lattice(12, 0.25, "hamiltonian", tau=10, seed=3)
    y = ist.mode_excitation(lat, [2], [0.2], phases=[math.pi / 2])
    np.testing.assert_allclose(lat.mode_energies(y)[1], 0.2, rtol=1e-12)
    np.testing.assert_allclose(lat.mode_energies(y).sum(), 0.2, rtol=1e-12)


def test_random_phases_energy_band_and_seed():
    lat = fputlab.Lattice(32, 0.25)
    y = ist.random_phases(lat, energy=0.7, modes=range(1, 5), seed=11)
    assert abs(lat.energy(y) - 0.7) < 1e-12
    e = _sine_energies(lat, y)
    assert e[4:].sum() == 0 or e[4:].max() < 1e-25
    y2 = ist.random_phases(lat, energy_density=0.7 / 32, modes=range(1, 5), seed=11)
    np.testing.assert_allclose(y2, y, rtol=0, atol=1e-15)
    assert not np.allclose(ist.random_phases(lat, energy=0.7, modes=range(1, 5), seed=12), y)
    # harmonic chain: the band's energies are exactly equal
    lin = fputlab.Lattice(32, 0.0)
    e = _sine_energies(lin, ist.random_phases(lin, energy=2.0, modes=[2, 5, 9], seed=1))
    np.testing.assert_allclose(e[[1, 4, 8]], 2.0 / 3, rtol=1e-12)


def test_random_phases_are_uniform():
    lat = fputlab.Lattice(8, 0.0)
    w = lat.omega
    z = []
    for seed in range(400):
        y = ist.random_phases(lat, energy=1.0, modes=[3], seed=seed)
        Q = mode_matrix(8) @ y[:8]
        P = mode_matrix(8) @ y[8:]
        z.append(complex(w[2] * Q[2], -P[2]))
    phase = np.angle(np.array(z))
    # the first two circular moments of a uniform angle vanish: |mean| ~ 1/sqrt(n)
    for m in (1, 2):
        assert abs(np.exp(1j * m * phase).mean()) < 4 / math.sqrt(len(z))


@pytest.mark.parametrize("kw, err, word", [
    (dict(energy=1.0, energy_density=0.1, modes=[1], seed=1), ValueError, "exactly one"),
    (dict(energy=-1.0, modes=[1], seed=1), ValueError, "energy"),
    (dict(energy=1.0, modes=[0], seed=1), ValueError, "modes"),
    (dict(energy=1.0, modes=[1, 1], seed=1), ValueError, "modes"),
    (dict(energy=1.0, modes="a", seed=1), TypeError, "modes"),
    (dict(energy=1.0, modes=[1], seed=-1), ValueError, "seed"),
    (dict(energy=1.0, modes=[1], seed=1.5), TypeError, "seed"),
])
def test_random_phases_bad_input(kw, err, word):
    with pytest.raises(err, match=word):
        ist.random_phases(fputlab.Lattice(8, 0.25), **kw)


def test_thermal_harmonic_is_exact_equipartition():
    # harmonic chain: every mode has <E_k> = T (kinetic T/2 + potential T/2)
    lat = fputlab.Lattice(12, 0.0)
    T, n = 0.3, 4000
    ys = ist.thermal(lat, temperature=T, seed=5, size=n)
    e = np.array([_sine_energies(lat, y) for y in ys])
    mean, sem = e.mean(axis=0), e.std(axis=0) / math.sqrt(n)
    assert np.all(np.abs(mean - T) < 5 * sem)
    np.testing.assert_array_equal(ist.thermal(lat, temperature=T, seed=5, size=n), ys)


def test_thermal_anharmonic_equipartition_and_virial():
    # alpha + beta FPUT, fixed ends: <p_j^2/m_j> = T per particle (Maxwell) and the virial
    # <sum_j x_j dU/dx_j> = N T (generalised equipartition; no boundary terms as beta > 0)
    lat = fputlab.Lattice(8, 0.5, beta=0.5)
    T, n = 0.4, 1500
    ys = ist.thermal(lat, temperature=T, seed=7, size=n, thin=3)
    x, p = ys[:, :8], ys[:, 8:]
    kin = (p**2).sum(axis=1)
    assert abs(kin.mean() - 8 * T) < 5 * kin.std() / math.sqrt(n)
    vir = np.array([-(xi @ lat.force(xi)) for xi in x])
    assert abs(vir.mean() - 8 * T) < 5 * vir.std() / math.sqrt(n)
    # and not the harmonic answer: the potential energy differs from N T/2 at this T
    u = np.array([lat.energy(np.concatenate([xi, np.zeros(8)])) for xi in x])
    assert abs(u.mean() - 4 * T) > 5 * u.std() / math.sqrt(n)


def test_thermal_matches_quadrature_for_two_particles():
    # N = 2, fixed ends, alpha-FPUT: <U> and <x_1^2> against a quadrature of exp(-U/T)
    lat = fputlab.Lattice(2, 0.25)
    T = 0.5
    g = np.linspace(-3.9, 6.0, 801)
    X1, X2 = np.meshgrid(g, g, indexing="ij")
    V = lambda r: r**2 / 2 + 0.25 * r**3 / 3
    r0, r1, r2 = X1, X2 - X1, -X2
    inside = (r0 > -4) & (r1 > -4) & (r2 > -4)
    U = np.where(inside, V(r0) + V(r1) + V(r2), np.inf)
    w = np.exp(-U / T)
    u_q = (U[inside] * w[inside]).sum() / w.sum()
    x1_q = (X1**2 * w).sum() / w.sum()
    n = 3000
    ys = ist.thermal(lat, temperature=T, seed=2, size=n, thin=3)
    u = np.array([lat.energy(np.concatenate([y[:2], [0, 0]])) for y in ys])
    assert abs(u.mean() - u_q) < 5 * u.std() / math.sqrt(n)
    assert abs((ys[:, 0] ** 2).mean() - x1_q) < 5 * (ys[:, 0] ** 2).std() / math.sqrt(n)


def test_thermal_model2_maxwell_momenta():
    lat = fputlab.Lattice(10, 0.25, "hamiltonian", tau=30, seed=4)
    T, n = 0.1, 800
    ys = ist.thermal(lat, temperature=T, seed=3, size=n)
    kin = (ys[:, 10:] ** 2 / lat.v).sum(axis=1)
    assert abs(kin.mean() - 10 * T) < 5 * kin.std() / math.sqrt(n)


def test_thermal_refuses_model3_and_bad_input():
    with pytest.raises(ValueError, match="model 3"):
        ist.thermal(fputlab.Lattice(8, 0.25, "nonlinear", tau=5, seed=1), temperature=1, seed=1)
    lat = fputlab.Lattice(8, 0.25)
    with pytest.raises(ValueError, match="temperature"):
        ist.thermal(lat, temperature=0.0, seed=1)
    with pytest.raises(TypeError, match="temperature"):
        ist.thermal(lat, temperature="hot", seed=1)
    with pytest.raises(ValueError, match="size"):
        ist.thermal(lat, temperature=1.0, seed=1, size=0)


@periodic
def test_periodic_wave_energies_and_random_phases():
    lat = fputlab.Lattice(16, 0.0, boundary="periodic")
    y = ist.random_phases(lat, energy=1.0, modes=[1, 2], seed=3)
    e = ist.wave_energies(lat, y)
    assert e.shape == (15,)
    # independent: the harmonic energy from the positions and velocities in real space
    x, v = y[:16], y[16:]
    h2 = 0.5 * (v @ v) + 0.5 * ((np.roll(x, -1) - x) ** 2).sum()
    np.testing.assert_allclose(e.sum(), h2, rtol=1e-12)
    np.testing.assert_allclose(e[[0, 1, 13, 14]], 0.25, rtol=1e-12)
    assert e[2:13].max() < 1e-25
    assert abs(x.sum()) < 1e-12 and abs(v.sum()) < 1e-12


@periodic
def test_periodic_thermal_equipartition():
    lat = fputlab.Lattice(10, 0.0, boundary="periodic")
    T, n = 0.2, 3000
    ys = ist.thermal(lat, temperature=T, seed=9, size=n)
    e = ist.wave_energies(lat, ys)
    # each travelling wave carries <e_k> = T ... over the N - 1 = 9 non-zero modes
    mean, sem = e.mean(axis=0), e.std(axis=0) / math.sqrt(n)
    assert np.all(np.abs(mean - T) < 5 * sem)
    np.testing.assert_allclose(ys[:, 10:].sum(axis=1), 0.0, atol=1e-12)
