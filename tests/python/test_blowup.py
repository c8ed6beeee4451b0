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
    out = blowup.blowup_sweep([0.0, 20.0], Ns=(32,), realisations=3, t_end=5e3, workers=2)
    assert out["probability"].shape == (2, 1)
    assert out["probability"][0, 0] == 0.0
    assert len(out["records"]) == 6
    # each realisation carries its own two-mode threshold, checked against the reduction module
    from fputlab.reduction import realisation_quadratics
    for tau, N, seed, blew, t, tau_c in out["records"]:
        assert tau_c == pytest.approx(realisation_quadratics(32, 0.25, R=1, seed0=seed).critical_tolerances()[0])
    assert 0.0 <= out["prediction_accuracy"] <= 1.0
    from fputlab.plotting import plot_blowup_sweep_figure
    fig = plot_blowup_sweep_figure(out)
    assert len(fig.axes) == 2 and fig.axes[1].get_title() == f"{sum(r[3] for r in out['records'])} of 6 runs blew up"


def test_bad_criteria():
    lat = Lattice(8)
    with pytest.raises(ValueError, match="unknown"):
        blowup.blowup_time(lat, 10.0, criteria=[("temperature", 1.0)])
    with pytest.raises(ValueError, match="threshold"):
        blowup.blowup_time(lat, 10.0, criteria=[("energy", -1.0)])
    with pytest.raises(ValueError, match="mode"):
        blowup.blowup_time(lat, 10.0, criteria=[("mode_energy", 1.0, 9)])
    with pytest.raises(ValueError, match="t_end"):
        blowup.blowup_time(lat, -1.0)
    # the old spelling still works, with a warning, for one release
    with pytest.warns(DeprecationWarning, match="t_max is deprecated: use t_end"):
        old = blowup.blowup_time(lat, t_max=10.0)
    assert old.t_reached == blowup.blowup_time(lat, 10.0).t_reached


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


# ---- every criterion: the splitting locator, ARKODE and CVODE root-finding agree ----------
# N = 64, tau = 20 %, seed 1 blows up at t = 2545 (stretch > 1/alpha). To keep the tests short
# every run starts from the state at t = 2300 (Yoshida 4, dt = 0.01), where the amplitudes
# grow towards the blow-up: the thresholds below are crossed 165-245 time units later, at
# different times (energy, E_1 and max_k E_k, max |x_j|, max bond stretch).
CRITERIA = [
    ("energy", 4.0),
    ("mode_energy", 1.0, 1),
    ("mode_energy", 1.0, 0),          # k = 0: the largest mode energy
    ("displacement", 5.0),
    ("stretch", 3.0),
    ("stretch", 4.0),                 # the default criterion: the escape over the barrier
]
CRIT_IDS = ["energy", "E1", "maxEk", "displacement", "stretch3", "stretch4"]


@pytest.fixture(scope="module")
def late_state():
    lat = Lattice(64, 0.25, "nonlinear", tau=20.0, seed=1)
    integ = fputlab.Integrator(lat, lat.mode_state(), dt=0.01)
    integ.advance(2300.0)
    return lat, integ.state[0].copy()


_reference = {}


def _dop853_event(late_state, crit):
    """DOP853 (ARKODE root-finding) at tight tolerances, computed once per criterion."""
    if crit not in _reference:
        lat, y0 = late_state
        _reference[crit] = blowup.blowup_time(lat, 1e3, y0=y0, criteria=[crit], method="dop853",
                                              rtol=1e-11, atol=1e-13)
    return _reference[crit]


def _criterion_value(crit, y):
    """The criterion's quantity on a state, with numpy (not the library's event code)."""
    N = y.size // 2
    x, p = y[:N], y[N:]
    d = np.diff(np.concatenate([[0.0], x, [0.0]]))
    if crit[0] == "energy":       # Eq. (Hamilt), model 3: p = velocity
        return 0.5 * np.sum(p**2) + np.sum(d**2 / 2 + 0.25 * d**3 / 3)
    if crit[0] == "displacement":
        return np.abs(x).max()
    if crit[0] == "stretch":
        return np.abs(d).max()
    j = np.arange(1, N + 1)
    A = np.sqrt(2 / (N + 1)) * np.sin(np.outer(j, j) * np.pi / (N + 1))
    omega = 2 * np.sin(j * np.pi / (2 * (N + 1)))
    E = 0.5 * ((A @ p) ** 2 + omega**2 * (A @ x) ** 2)
    return E.max() if crit[2] == 0 else E[crit[2] - 1]


@pytest.mark.parametrize("crit", CRITERIA, ids=CRIT_IDS)
def test_every_criterion_same_event_time_splitting_arkode_cvode(late_state, crit):
    lat, y0 = late_state
    assert _criterion_value(crit, y0) < 0.8 * crit[1]          # not crossed at the start
    ark = _dop853_event(late_state, crit)
    assert ark.blew_up and 100.0 < ark.time < 300.0
    # the state at the event sits on the threshold (independent evaluation)
    assert _criterion_value(crit, ark.state) == pytest.approx(crit[1], rel=1e-9)
    split = blowup.blowup_time(lat, 1e3, y0=y0, criteria=[crit])           # yoshida4, dt = 0.01
    cv = blowup.blowup_time(lat, 1e3, y0=y0, criteria=[crit], method="cvode-adams",
                            rtol=1e-10, atol=1e-12)
    for res in (split, cv):
        assert res.blew_up and res.criterion == ark.criterion, (res.method, res.criterion)
        assert abs(res.time - ark.time) < 1e-6 * ark.time, (res.method, res.time, ark.time)
        assert _criterion_value(crit, res.state) == pytest.approx(crit[1], rel=1e-7)


@pytest.mark.parametrize("crit", CRITERIA, ids=CRIT_IDS)
@pytest.mark.parametrize("method,dt", [("leapfrog", 0.002), ("aba864", 0.05),
                                       ("srkn14a6", 0.1), ("aba864-harmonic", 0.05)])
def test_in_step_locator_every_scheme(late_state, crit, method, dt):
    # the event falls inside a step: a locator returning the step's end would be off by up to
    # dt (> 1e-6 relative here for every scheme)
    lat, y0 = late_state
    ark = _dop853_event(late_state, crit)
    res = blowup.blowup_time(lat, 1e3, y0=y0, criteria=[crit], method=method, dt=dt)
    assert res.blew_up and res.criterion == ark.criterion
    assert abs(res.time - ark.time) < 1e-6 * ark.time, (res.time, ark.time)
    assert _criterion_value(crit, res.state) == pytest.approx(crit[1], rel=1e-7)
