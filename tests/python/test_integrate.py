"""Yoshida 4 / leapfrog runs: conservation, order, recurrence, and an independent integrator."""
import numpy as np
import pytest

import fputlab
from fputlab import Lattice


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


@pytest.mark.parametrize("method", ["cvode-bdf", "cvode-adams", "gsl-rk8pd", "dop853", "yoshida4"])
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
