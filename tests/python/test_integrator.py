"""The one integration API: deviation vectors, exact sample times, streaming, linear maps."""
import numpy as np
import pytest

import fputlab
from fputlab import Integrator, Lattice


@pytest.mark.parametrize("model", ["homogeneous", "hamiltonian", "nonlinear"])
def test_deviation_vectors_match_nearby_orbits(model):
    N = 12
    lat = Lattice(N, 0.25, model, beta=0.1, v=1 + 0.1 * np.cos(np.arange(N)))
    rng = np.random.default_rng(4)
    y0 = 0.5 * rng.standard_normal(2 * N)
    W = rng.standard_normal((2, 2 * N))
    integ = Integrator(lat, np.vstack([y0, W]), method="yoshida4", dt=0.01)
    out = integ.advance(3.0)
    eps = 1e-6
    for m in range(2):
        plus = Integrator(lat, y0 + eps * W[m], dt=0.01).advance(3.0)[0]
        minus = Integrator(lat, y0 - eps * W[m], dt=0.01).advance(3.0)[0]
        fd = (plus - minus) / (2 * eps)
        np.testing.assert_allclose(out[1 + m], fd, rtol=1e-6, atol=1e-6 * np.abs(fd).max())
    np.testing.assert_array_equal(out[0], Integrator(lat, y0, dt=0.01).advance(3.0)[0])


def test_time_is_n_dt_not_accumulated():
    lat = Lattice(4, 0.25)
    integ = Integrator(lat, lat.mode_state(), dt=0.01)
    for i in range(1, 10001):
        integ.advance(i * 1.0)          # 1e6 steps in 1e4 calls
    naive = 0.0
    for _ in range(1_000_000):
        naive += 0.01
    assert abs(naive - 1e4) > 1e-9       # what accumulation would have given
    assert integ.t == pytest.approx(1e4, abs=1e-11)
    assert integ.counters["steps"] == 1_000_000


def test_iter_samples_streams_the_same_states_as_integrate():
    lat = Lattice(16, 0.25, "nonlinear", tau=10, seed=3)
    times = np.linspace(0, 50, 11)
    streamed = [y[0] for _, y in fputlab.iter_samples(lat, times)]
    run = lat.integrate(50.0, times=times, store_states=True)
    np.testing.assert_array_equal(np.array(streamed), run.states)


def test_linear_maps_of_deviation_vectors_commute_with_the_flow():
    lat = Lattice(10, 0.25, "nonlinear", tau=10, seed=5)
    rng = np.random.default_rng(0)
    W = rng.standard_normal((2, 20))
    M = np.array([[2.0, -1.0], [0.5, 3.0]])
    a = Integrator(lat, np.vstack([lat.mode_state(), W]), dt=0.01)
    a.advance(1.0)
    a.transform_deviations(M)
    ya = a.advance(2.0)
    b = Integrator(lat, np.vstack([lat.mode_state(), M @ W]), dt=0.01)
    yb = b.advance(2.0)
    np.testing.assert_allclose(ya, yb, rtol=1e-12, atol=1e-12)


def test_integrate_returns_deviation_vectors_and_counters():
    lat = Lattice(8, 0.25)
    dev = np.eye(16)[:2]
    run = lat.integrate(1.0, deviations=dev, store_states=True, sample_every=0.5)
    assert run.states.shape == (3, 3, 16)
    assert run.counters["steps"] == 100 and run.counters["force_evals"] == 300
    assert set(["leapfrog", "yoshida4"]) <= set(fputlab.methods())
    assert fputlab.method_info("yoshida4") == {"order": 4, "adaptive": False}


def test_integrator_bad_input():
    lat = Lattice(4)
    with pytest.raises(ValueError, match="y0 has shape"):
        Integrator(lat, np.zeros(7))
    with pytest.raises(ValueError, match="rk4-magic"):
        Integrator(lat, np.zeros(8), method="rk4-magic")
    integ = Integrator(lat, lat.mode_state())
    integ.advance(1.0)
    with pytest.raises(ValueError, match="t_target"):
        integ.advance(0.5)
    with pytest.raises(ValueError, match="m has shape"):
        integ.transform_deviations(np.eye(2))
    with pytest.raises(ValueError, match="deviations has shape"):
        lat.integrate(1.0, deviations=np.zeros((2, 5)))


def test_restore_from_checkpoint_is_bit_for_bit():
    lat = Lattice(16, 0.25, "nonlinear", tau=10, seed=2)
    W = np.random.default_rng(1).standard_normal((2, 32))
    full = Integrator(lat, np.vstack([lat.mode_state(), W]), dt=0.01)
    ref = full.advance(123.456)
    first = Integrator(lat, np.vstack([lat.mode_state(), W]), dt=0.01)
    first.advance(50.005)                        # stops on the grid at t = 50.0
    steps, t, state = first.steps, first.t, first.state
    second = Integrator(lat, np.vstack([lat.mode_state(), W]), dt=0.01)
    second.restore(steps, t, state)
    np.testing.assert_array_equal(second.advance(123.456), ref)
    with pytest.raises(ValueError, match="t0 \\+ n_steps dt"):
        second.restore(steps, t + 0.001, state)
