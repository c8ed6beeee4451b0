"""Normal modes for both boundaries against direct O(N^2) sums, at awkward N (N + 1 or N prime:
the lengths that took the FFT O(N^2) before Bluestein), and the periodic chain's Fourier modes
against the harmonic ring's closed forms."""
import numpy as np
import pytest

import fputlab
from fputlab import Lattice


def direct_modes(N, boundary):
    """(A, omega) written out: sine modes, or the orthonormal Hartley (cas) modes of the ring."""
    if boundary == "fixed":
        j = np.arange(1, N + 1)
        A = np.sqrt(2.0 / (N + 1)) * np.sin(np.outer(j, j) * np.pi / (N + 1))
        return A, 2 * np.sin(j * np.pi / (2 * (N + 1)))
    j = np.arange(N)
    theta = 2 * np.pi * np.outer(j, j) / N
    return (np.cos(theta) + np.sin(theta)) / np.sqrt(N), 2 * np.sin(np.pi * j / N)


def direct_energies(N, boundary, y, v=None):
    A, w = direct_modes(N, boundary)
    Q, P = A @ y[:N], A @ y[N:]
    return 0.5 * (P**2 + w**2 * Q**2)


# fixed: N + 1 prime (102, 1020: Bluestein), 2 (N + 1) smooth (1023); periodic: N prime (211,
# 1021: Bluestein), N = 2 x prime (998), smooth (1024), tiny N
@pytest.mark.parametrize("N,boundary", [(2, "fixed"), (102, "fixed"), (1020, "fixed"),
                                        (1023, "fixed"), (2, "periodic"), (3, "periodic"),
                                        (211, "periodic"), (998, "periodic"),
                                        (1021, "periodic"), (1024, "periodic")])
def test_mode_energies_match_direct_sum(N, boundary, rng):
    lat = Lattice(N, boundary=boundary)
    y = rng.standard_normal(2 * N)
    ref = direct_energies(N, boundary, y)
    np.testing.assert_allclose(lat.mode_energies(y), ref, rtol=0, atol=1e-12 * ref.max())
    A, w = direct_modes(N, boundary)
    np.testing.assert_allclose(lat.to_modes(y[:N]), A @ y[:N], atol=1e-12 * np.abs(y).max())
    np.testing.assert_allclose(lat.omega, w, rtol=1e-14, atol=1e-15)


@pytest.mark.parametrize("N", [7, 1021])
def test_ring_transform_is_orthogonal_and_self_inverse(N, rng):
    lat = Lattice(N, boundary="periodic")
    x = rng.standard_normal(N)
    q = lat.to_modes(x)
    assert np.dot(q, q) == pytest.approx(np.dot(x, x), rel=1e-12)
    np.testing.assert_allclose(lat.from_modes(q), x, atol=1e-12)


@pytest.mark.parametrize("N", [8, 9])
def test_ring_mode_energies_sum_to_harmonic_energy(N, rng):
    lat = Lattice(N, boundary="periodic")
    y = rng.standard_normal(2 * N)
    x, p = y[:N], y[N:]
    harmonic = 0.5 * p @ p + 0.5 * np.sum((np.roll(x, -1) - x) ** 2)
    assert lat.mode_energies(y).sum() == pytest.approx(harmonic, rel=1e-13)
    # the zero mode is the centre of mass: E_0 = (sum p)^2 / (2N)
    assert lat.mode_energies(y)[0] == pytest.approx(p.sum() ** 2 / (2 * N), rel=1e-12)
    np.testing.assert_array_equal(lat.mode_numbers, np.arange(N))


@pytest.mark.parametrize("N,k", [(8, 1), (8, 4), (9, 3)])
def test_ring_single_mode_state(N, k):
    lat = Lattice(N, boundary="periodic")
    y = lat.mode_state(k, 0.3)
    np.testing.assert_allclose(y[:N], 0.3 * np.sin(2 * np.pi * k * np.arange(N) / N + np.pi / 4),
                               atol=1e-15)
    q = lat.to_modes(y[:N])
    expected = np.zeros(N)
    expected[k] = 0.3 * np.sqrt(N / 2)   # also for k = N/2, where x_j = 0.3 (-1)^j / sqrt(2)
    np.testing.assert_allclose(q, expected, atol=1e-14)
    with pytest.raises(ValueError, match="1..N-1"):
        lat.mode_state(0)


def test_harmonic_ring_conserves_every_mode_energy(rng):
    """alpha = beta = 0: each Hartley mode is an exact normal mode of frequency 2 sin(pi k/N)."""
    N = 12
    lat = Lattice(N, 0.0, boundary="periodic")
    y0 = rng.standard_normal(2 * N)
    it = fputlab.Integrator(lat, y0, method="dop853", rtol=1e-12, atol=1e-14)
    _, _, ek, _ = it.sample([3.7, 11.1])
    e0 = lat.mode_energies(y0)
    np.testing.assert_allclose(ek, np.broadcast_to(e0, ek.shape), atol=1e-9 * e0.max())


def test_ring_zero_mode_constant_in_a_nonlinear_run(rng):
    N = 10
    lat = Lattice(N, 0.5, "nonlinear", boundary="periodic", tau=10, seed=2)
    y0 = 0.3 * rng.standard_normal(2 * N)
    _, _, ek, _ = fputlab.Integrator(lat, y0).sample([5.0, 10.0])
    assert np.allclose(ek[:, 0], lat.mode_energies(y0)[0], rtol=1e-10)


def test_ring_mode_energy_criterion_uses_wavenumbers():
    N = 8
    lat = Lattice(N, 0.25, boundary="periodic")
    y0 = lat.mode_state(2, 0.5)
    e2 = lat.mode_energies(y0)[2]
    it = fputlab.Integrator(lat, y0, criteria=[("mode_energy", 1.01 * e2, 2)])
    assert it.event is None
    with pytest.raises(ValueError, match="wavenumber"):
        fputlab.Integrator(lat, y0, criteria=[("mode_energy", 1.0, N)])
