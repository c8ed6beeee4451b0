"""Blow-up detection by root-finding, and recurrence/localisation measures."""
import numpy as np
import pytest

import fputlab
from fputlab import Lattice, analysis, blowup


def test_escape_time_of_two_particle_chain_matches_quadrature():
    # N = 2, antisymmetric motion x1 = -x2 = u obeys u'' = -3u + 3 alpha u^2 (potential
    # W = 3u^2/2 - alpha u^3, barrier 1/(2 alpha^2) = 8). With energy above the barrier u escapes;
    # the time to reach |x_j| = X is the quadrature of du / sqrt(2 (e - W(u))).
    from scipy.integrate import quad
    a, v0, X = 0.25, 4.2, 20.0
    e = v0**2 / 2
    T_exact = quad(lambda u: 1 / np.sqrt(2 * (e - 1.5 * u * u + a * u**3)), 0.0, X,
                   epsabs=1e-13, epsrel=1e-13, limit=400)[0]
    lat = Lattice(2, a)
    y0 = np.array([0.0, 0.0, v0, -v0])
    res = blowup.blowup_time(lat, 100.0, y0=y0, criteria=[("displacement", X)], dt=1e-3)
    assert res.blew_up and res.criterion == "max |x_j| > 20"
    assert abs(res.time - T_exact) < 1e-8
    assert abs(abs(res.state[0]) - X) < 1e-9 and np.all(np.isfinite(res.state))
    # the criteria were removed from the lattice afterwards
    assert lat.integrate(1.0, y0=y0).event is None


def test_disorder_20_percent_blows_up_same_time_with_arkode_root_finding():
    # paper Fig. 3: tau = 20 % > tau_c, N = 64, model 3: finite-time blow-up. The splitting
    # scheme's in-step locator and ARKODE's root-finding (DOP853) must agree on the time.
    for seed in range(1, 11):
        lat = Lattice(64, 0.25, "nonlinear", tau=20.0, seed=seed)
        split = blowup.blowup_time(lat, 1e4)
        assert split.blew_up and split.time < 1e4, seed
        assert np.all(np.isfinite(split.state))
        ark = blowup.blowup_time(lat, 1e4, method="dop853", rtol=1e-10, atol=1e-12)
        assert ark.blew_up and ark.criterion == split.criterion
        assert abs(ark.time - split.time) < 1e-6 * ark.time, (seed, ark.time, split.time)
    cv = blowup.blowup_time(lat, 1e4, method="cvode-adams", rtol=1e-10, atol=1e-12)
    assert abs(cv.time - split.time) < 1e-6 * split.time
    with pytest.raises(ValueError, match="gsl-rk8pd does not support"):
        blowup.blowup_time(lat, 1e4, method="gsl-rk8pd")


def test_no_event_without_disorder():
    res = blowup.blowup_time(Lattice(64, 0.25, "nonlinear", tau=0.0, seed=1), 1e5,
                             criteria=[("stretch", 4.0), ("energy", 1.0)])
    assert not res.blew_up and res.t_reached == 1e5


def test_integrate_stops_at_event_and_keeps_arrays_finite():
    lat = Lattice(64, 0.25, "nonlinear", tau=20.0, seed=1)
    run = lat.integrate(1e4, sample_every=10.0, stop_on=[("stretch", 4.0)])
    assert run.event is not None and run.event["time"] < 1e4
    assert run.t[-1] <= run.event["time"]
    assert np.all(np.isfinite(run.mode_energies)) and np.all(np.isfinite(run.energy))
    assert np.abs(np.diff(np.concatenate([[0.0], run.final_state[:64], [0.0]]))).max() \
        == pytest.approx(4.0, abs=1e-9)


def test_nan_without_event_is_a_failure_not_success():
    lat = Lattice(4, 0.25)
    y0 = lat.mode_state(1, 30.0)
    with pytest.raises(fputlab.IntegrationError, match="non-finite"):
        blowup.blowup_time(lat, 50.0, y0=y0, criteria=[("energy", 1e300)])


def test_blowup_sweep_counts_realisations():
    out = blowup.blowup_sweep([0.0, 20.0], Ns=(32,), realisations=3, t_max=5e3, workers=2)
    assert out["probability"].shape == (2, 1)
    assert out["probability"][0, 0] == 0.0
    assert len(out["records"]) == 6
    # each realisation carries its own two-mode threshold, checked against the reduction module
    from fputlab.reduction import realisation_quadratics
    for tau, N, seed, blew, t, tau_c in out["records"]:
        assert tau_c == pytest.approx(realisation_quadratics(32, 0.25, R=1, seed0=seed).critical_tolerances()[0])
    assert 0.0 <= out["prediction_accuracy"] <= 1.0
    fig = blowup.plot_sweep(out)
    assert len(fig.axes) == 2 and fig.axes[1].get_title() == f"{sum(r[3] for r in out['records'])} of 6 runs blew up"


def test_bad_criteria():
    lat = Lattice(8)
    with pytest.raises(ValueError, match="unknown"):
        blowup.blowup_time(lat, 10.0, criteria=[("temperature", 1.0)])
    with pytest.raises(ValueError, match="threshold"):
        blowup.blowup_time(lat, 10.0, criteria=[("energy", -1.0)])
    with pytest.raises(ValueError, match="mode"):
        blowup.blowup_time(lat, 10.0, criteria=[("mode_energy", 1.0, 9)])
    with pytest.raises(ValueError, match="t_max"):
        blowup.blowup_time(lat, -1.0)


def test_recurrence_and_localisation_measures():
    lat = Lattice(32, 0.25)
    run = lat.integrate(3e4, sample_every=10.0)
    times, fractions = analysis.recurrences(run)
    # homogeneous chain: a recurrence with most of the energy back in mode 1
    assert len(times) >= 1 and fractions.max() > 0.9
    share = analysis.energy_share(run, 4)
    assert share[0] == pytest.approx(1.0) and np.all(share <= 1 + 1e-12)
    eta = analysis.normalised_entropy(run)
    assert eta[0] == pytest.approx(0.0, abs=1e-9) and np.all((eta >= 0) & (eta <= 1))
    n_eff = analysis.effective_modes(run)
    assert n_eff[0] == pytest.approx(1.0) and n_eff.max() <= 32
    # closed form: equal energy in m modes gives exactly m effective modes
    fake = np.zeros((1, 8))
    fake[0, :3] = 1.0
    assert analysis.effective_modes(fake)[0] == pytest.approx(3.0)
