"""Integration (fputlab.integrate, Lattice.integrate, Integrator, iter_samples): accuracy against
independent computations (observed order, energy conservation, scipy's DOP853, the FPUT
recurrence), blow-ups, and the one integration API (deviation vectors against nearby orbits,
exact sample times, streaming, linear maps, checkpoints)."""
import numpy as np
import pytest

import fputlab
from fputlab import Integrator, Lattice


# ---- runs: conservation, order, recurrence, an independent integrator, blow-ups -------------

def test_yoshida4_energy_error_homogeneous_and_hamiltonian():
    # paper Sec. 5: dt = 0.01 keeps the relative energy error below 1e-9 (here to t = 1e4)
    lat1 = Lattice(64, 0.25)
    run1 = lat1.integrate(1e4, dt=0.01, sample_every=100)
    assert run1.relative_energy_error.max() < 1e-9
    lat2 = Lattice(64, 0.25, "hamiltonian", tau=10.0, seed=7)
    run2 = lat2.integrate(1e4, dt=0.01, sample_every=100, y0=lat2.mode_state(coupled=True))
    assert run2.relative_energy_error.max() < 1e-9
    # x = sin itself at tau = 10% carries high-frequency energy: error falls as dt^4
    run3 = lat2.integrate(1e4, dt=0.005, sample_every=100)
    assert run3.relative_energy_error.max() < 1e-9


@pytest.mark.parametrize("method,order", [("leapfrog", 2), ("yoshida4", 4)])
@pytest.mark.parametrize("model", ["homogeneous", "nonlinear"])
def test_observed_convergence_order(method, order, model):
    lat = Lattice(8, 0.25, model, v=1 + 0.05 * np.sin(np.arange(8.0)))
    y0 = lat.mode_state(1, 1.5)
    ref = lat.integrate(5.0, dt=0.1 / 64, times=[5.0], y0=y0, method=method, store_states=True).states[0]
    errs = []
    for dt in (0.1, 0.05, 0.025):
        y = lat.integrate(5.0, dt=dt, times=[5.0], y0=y0, method=method, store_states=True).states[0]
        errs.append(np.abs(y - ref).max())
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(np.abs(orders - order) < 0.3), orders


def test_against_scipy_dop853_nonlinear_model():
    # an independent integrator (scipy's DOP853 on our rhs written in numpy) for model 3
    from scipy.integrate import solve_ivp
    N = 16
    lat = Lattice(N, 0.25, "nonlinear", tau=10.0, seed=2)
    v = lat.v
    V = np.concatenate([[1.0], v, [1.0]])

    def f(t, y):
        X = np.concatenate([[0.0], y[:N], [0.0]])
        bond = np.diff(X) + 0.25 * np.diff(V * X) ** 2
        return np.concatenate([y[N:], np.diff(bond)])

    y0 = lat.mode_state()
    sol = solve_ivp(f, (0, 100), y0, method="DOP853", rtol=1e-13, atol=1e-13)
    ours = lat.integrate(100.0, dt=0.002, times=[100.0], store_states=True).states[0]
    np.testing.assert_allclose(ours, sol.y[:, -1], atol=1e-8)


@pytest.mark.parametrize("method,dt", [("dprkn8", 0.1), ("dprkn12", 0.25)])
def test_rkn_methods_against_scipy_dop853_with_deviation_vectors(method, dt):
    # the explicit RKN methods (not symplectic, high order) on model 3 with two deviation
    # vectors, against scipy's DOP853 on the orbit + variational equations written in numpy
    from scipy.integrate import solve_ivp
    N, a = 16, 0.25
    lat = Lattice(N, a, "nonlinear", tau=10.0, seed=2)
    V = np.concatenate([[1.0], lat.v, [1.0]])

    def f(t, y):
        x, p = y[:N], y[N:2 * N]
        X = np.concatenate([[0.0], x, [0.0]])
        r, R = np.diff(X), np.diff(V * X)
        out = [p, np.diff(r + a * R ** 2)]
        for m in (1, 2):
            dx, dp = y[2 * N * m:2 * N * m + N], y[2 * N * m + N:2 * N * (m + 1)]
            dX = np.concatenate([[0.0], dx, [0.0]])
            out += [dp, np.diff(np.diff(dX) + 2 * a * R * np.diff(V * dX))]
        return np.concatenate(out)

    W = np.random.default_rng(3).standard_normal((2, 2 * N))
    y0 = np.vstack([lat.mode_state(1, 2.0), W])
    sol = solve_ivp(f, (0, 50), y0.reshape(-1), method="DOP853", rtol=1e-13, atol=1e-13)
    ours = Integrator(lat, y0, method=method, dt=dt).advance(50.0)
    np.testing.assert_allclose(ours.reshape(-1), sol.y[:, -1], atol=2e-9)


def test_rkn_method_events_samples_and_restart():
    # dprkn12 goes through the fixed-step back end like the compositions: off-grid samples one
    # partial step from the grid, a stopping criterion located inside a step, bit-for-bit restart
    lat = Lattice(16, 0.25)
    y0 = lat.mode_state(1, 2.0)
    a = lat.integrate(7.3, method="dprkn12", dt=0.25, times=[7.3], store_states=True).states[0]
    b = lat.integrate(7.3, method="yoshida4", dt=0.001, times=[7.3], store_states=True).states[0]
    np.testing.assert_allclose(a, b, atol=1e-10)
    full = Integrator(lat, y0, method="dprkn12", dt=0.25)
    ref = full.advance(40.1)
    first = Integrator(lat, y0, method="dprkn12", dt=0.25)
    first.advance(20.1)
    second = Integrator(lat, y0, method="dprkn12", dt=0.25)
    second.restore(first.steps, first.t, first.state)
    np.testing.assert_array_equal(second.advance(40.1), ref)
    # the quadratic coupling feeds mode 2 at once: E_2 > 1e-4 E fires early, inside a step;
    # located by both methods at the same time
    crit = [("mode_energy", 1e-4 * lat.energy(y0), 2)]
    fired = []
    for method, step in (("dprkn12", 0.25), ("yoshida4", 0.001)):
        integ = Integrator(lat, y0, method=method, dt=step, criteria=crit)
        integ.advance(50.0)
        assert integ.event is not None and 0 < integ.event["time"] < 50.0
        fired.append(integ.event["time"])
    assert abs(fired[0] - fired[1]) < 1e-8, fired


def test_samples_off_the_grid_are_exact():
    lat = Lattice(8, 0.25)
    a = lat.integrate(1.234567, dt=0.01, times=[1.234567], store_states=True).states[0]
    b = lat.integrate(1.234567, dt=0.01 / 7, times=[1.234567], store_states=True).states[0]
    # the trajectory stays on the dt grid; the sample is one partial step from it
    np.testing.assert_allclose(a, b, atol=1e-9)


def test_fpu_recurrence_fig1b():
    # paper Fig. 1(b): almost all energy returns to mode 1 near t = 6e4
    lat = Lattice(64, 0.25)
    run = lat.integrate(7e4, times=np.arange(4e4, 7e4 + 1, 10.0))
    frac = run.mode_energies[:, 0] / lat.energy(lat.mode_state())
    assert frac.max() > 0.95
    assert 5e4 < run.t[np.argmax(frac)] < 6.5e4


def test_blowup_ends_cleanly_with_finite_samples():
    lat = Lattice(4, 0.25)
    with pytest.raises(fputlab.IntegrationError, match="between t =") as info:
        lat.integrate(50.0, y0=lat.mode_state(1, 30.0), sample_every=0.5)
    partial = info.value.result
    assert not partial.completed and partial.t.size < 101
    assert np.all(np.isfinite(partial.mode_energies)) and np.all(np.isfinite(partial.energy))
    run = lat.integrate(50.0, y0=lat.mode_state(1, 30.0), sample_every=0.5, on_failure="return")
    assert not run.completed and "non-finite" in run.message


@pytest.mark.parametrize("method", ["cvode-bdf", "cvode-adams", "gsl-rk8pd", "dop853", "yoshida4",
                                    "dprkn12"])
def test_blowup_keeps_the_finite_samples_for_every_back_end(method):
    """A blow-up ends the run with every finite sample before it, whichever back end failed
    (NaN/Inf for the splitting schemes, a step-size failure for CVODE/GSL)."""
    lat = fputlab.Lattice(4, 0.25)
    y0 = lat.mode_state(1, 30.0)        # far beyond the cubic barrier: escapes at once
    run = lat.integrate(50.0, method=method, y0=y0, sample_every=0.05, on_failure="return")
    assert not run.completed and run.message
    assert 0 < run.t.size < 1001 and np.isfinite(run.mode_energies).all()
    with pytest.raises(fputlab.IntegrationError) as err:
        lat.integrate(50.0, method=method, y0=y0, sample_every=0.05)
    assert err.value.result.t.size == run.t.size and not err.value.result.completed


# ---- the Integrator: deviation vectors, time on the grid, streaming, linear maps, restart ----

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
