"""fputlab.chaos.batch.lyapunov_batch: each orbit as fputlab.chaos.lyapunov computes it, blow-ups
never chaotic, a known chaotic orbit, early exit, bad input."""
import math

import numpy as np
import pytest

import fputlab
from fputlab import chaos
from fputlab.chaos.batch import lyapunov_batch


def _same(a, b, rtol=1e-12):
    assert a.shape == b.shape
    np.testing.assert_allclose(a, b, rtol=rtol, atol=0)


@pytest.mark.parametrize("method,dt", [("yoshida4", 0.01), ("srkn14a6", 0.4)])
def test_lanes_match_single_orbit_runs(method, dt):
    lats = [fputlab.Lattice(8, 0.25, "nonlinear", tau=10.0, seed=s) for s in range(1, 7)]
    T = 3000.0
    batch = lyapunov_batch(lats, T, method=method, dt=dt, n_samples=40)
    assert len(batch) == len(lats)
    for lat, b in zip(lats, batch):
        s = chaos.lyapunov(lat, T, method=method, dt=dt, n_samples=40)
        assert isinstance(b, chaos.ChaosResult)
        np.testing.assert_array_equal(b.t, s.t)
        _same(b.mle, s.mle)
        _same(b.sali, s.sali)
        _same(b.gali, s.gali)
        assert b.steps == s.steps and b.t_final == s.t_final == T
        assert b.completed and b.chaotic == s.chaotic and b.classify() == s.classify()
        assert b.params["seed"] == lat.seed and b.params["blew_up"] is False


def test_given_states_and_deviation_vectors():
    lat = fputlab.Lattice(16, 0.25, "hamiltonian", tau=10.0, seed=3)
    rng = np.random.default_rng(5)
    y0 = np.stack([lat.mode_state(amplitude=a) for a in (0.5, 1.0, 2.0)])
    w0 = rng.standard_normal((3, 3, 32))
    batch = lyapunov_batch([lat] * 3, 500.0, y0=y0, w0=w0, n_dev=3, n_samples=20,
                           renorm_interval=2.0)
    for r in range(3):
        s = chaos.lyapunov(lat, 500.0, y0=y0[r], w0=w0[r], n_dev=3, n_samples=20,
                           renorm_interval=2.0)
        _same(batch[r].mle, s.mle)
        _same(batch[r].gali, s.gali)


def test_blowup_lane_is_blowup_never_chaotic():
    """Model 3, tau = 20 %, N = 64, seed 1 blows up near t = 2547 (Yoshida 4, dt = 0.01); its
    SALI collapses at the last renormalisation before the overflow, which must not count. Each
    way of ending it (stretch check, non-finite state, criterion) agrees with lyapunov."""
    lats = [fputlab.Lattice(64, 0.25, "nonlinear", tau=20.0, seed=1),
            fputlab.Lattice(64, 0.25, "nonlinear", tau=10.0, seed=2)]
    for stretch, reason in ((None, "stretch"), (-1.0, "non-finite")):
        for stop in (False, True):
            bad, good = lyapunov_batch(lats, 3000.0, n_samples=30, stop_when_chaotic=stop,
                                       blowup_stretch=stretch)
            single = chaos.lyapunov(lats[0], 3000.0, n_samples=30, stop_when_chaotic=stop,
                                    blowup_stretch=stretch)
            assert not bad.completed and not bad.chaotic and math.isnan(bad.t_chaotic)
            assert bad.blew_up and bad.params["blowup_reason"] == reason
            assert 2000 < bad.t_blowup < 2600 and bad.t_blowup == single.t_blowup
            assert bad.classify() == single.classify() == "blow-up"
            _same(bad.mle, single.mle)
            assert good.completed and good.t_final == 3000.0
    _same(good.mle, chaos.lyapunov(lats[1], 3000.0, n_samples=30).mle)
    # with the bond-stretch criterion the event stops the lane first, placed in time as a
    # single-orbit blow-up run places it
    bad, good = lyapunov_batch(lats, 3000.0, n_samples=30, criteria=[("stretch", 4.0)])
    assert bad.classify() == "blow-up" and not bad.chaotic
    assert bad.params["blowup_reason"] == "event" and "x_{j+1} - x_j" in bad.message
    ref = fputlab.blowup.blowup_time(fputlab.Lattice(64, 0.25, "nonlinear", tau=20.0, seed=1), 3000.0)
    assert ref.blew_up and abs(bad.t_blowup - ref.time) < 1e-6
    assert good.completed


def test_known_chaotic_orbit_and_early_exit():
    """Homogeneous N = 8, mode 1 at amplitude 4: SALI < 1e-8 near t = 5.4e4 (the single-orbit
    path finds the same time); it stops early and the regular orbit beside it is unaffected."""
    lat = fputlab.Lattice(8, 0.25)
    y0 = np.stack([lat.mode_state(amplitude=4.0), lat.mode_state(amplitude=1.0)])
    T = 6e4
    chaotic, regular = lyapunov_batch([lat, lat], T, y0=y0, stop_when_chaotic=True, n_samples=50)
    single = chaos.lyapunov(lat, T, y0=y0[0], stop_when_chaotic=True, n_samples=50)
    assert single.chaotic
    assert chaotic.chaotic and chaotic.t_chaotic == single.t_chaotic
    assert chaotic.classify() == "chaotic" and chaotic.completed
    assert chaotic.t_final == chaotic.t_chaotic + 1.0 < T    # confirmed one interval later
    assert chaotic.sali[-1] < 1e-7
    assert regular.t_final == T and not regular.chaotic
    alone = lyapunov_batch([lat], T, y0=y0[1], n_samples=50)[0]
    np.testing.assert_array_equal(regular.mle, alone.mle)
    np.testing.assert_array_equal(regular.sali, alone.sali)


@pytest.mark.parametrize("kwargs,match", [
    ({"t_end": 1e300}, "t_end"),
    ({"renorm_interval": 0.0}, "renorm_interval"),
    ({"renorm_interval": -1.0}, "renorm_interval"),
    ({"renorm_interval": 0.001}, "renorm_interval = 0.001 must be >= dt"),
    ({"method": "dop853"}, "not supported"),
    ({"method": "nope"}, "unknown"),
    ({"dt": 0.0}, "dt"),
    ({"n_dev": 0}, "n_dev"),
    ({"y0": np.zeros(5)}, "y0"),
    ({"criteria": [("mode_energy", 1.0, 1)]}, "mode energy"),
])
def test_bad_input_names_the_parameter(kwargs, match):
    lats = [fputlab.Lattice(8, 0.25), fputlab.Lattice(8, 0.25)]
    args = {"t_end": 10.0, **kwargs}
    t_end = args.pop("t_end")
    with pytest.raises(ValueError, match=match):
        lyapunov_batch(lats, t_end, **args)


def test_bad_lattices():
    with pytest.raises(ValueError, match="n_orbits >= 1"):
        lyapunov_batch([], 10.0)
    with pytest.raises(TypeError, match=r"lattices\[1\]"):
        lyapunov_batch([fputlab.Lattice(8), "x"], 10.0)
    with pytest.raises(ValueError, match=r"lattices\[1\]: N = 6"):
        lyapunov_batch([fputlab.Lattice(8), fputlab.Lattice(6)], 10.0)
    with pytest.raises(ValueError, match=r"lattices\[1\]: model"):
        lyapunov_batch([fputlab.Lattice(8), fputlab.Lattice(8, 0.25, "nonlinear", tau=10, seed=1)],
                       10.0)


@pytest.mark.parametrize("kind,factor", [("energy", 1.001), ("displacement", 1.001),
                                          ("stretch", 1.05)])
def test_criteria_fire_as_in_a_single_orbit_blowup_run(kind, factor):
    """Each lane stops where fputlab.blowup.blowup_time (the single-orbit event location) puts
    the event, or not at all if it does not fire there."""
    y = fputlab.Lattice(16, 0.25).mode_state(amplitude=2.0)
    lats = [fputlab.Lattice(16, 0.25, "nonlinear", tau=20.0, seed=s) for s in (4, 5, 6, 7)]
    value = {"energy": lats[0].energy(y), "displacement": np.abs(y[:16]).max(),
             "stretch": np.abs(np.diff(np.r_[0.0, y[:16], 0.0])).max()}[kind]
    crit = [(kind, factor * value)]
    batch = lyapunov_batch(lats, 300.0, y0=y, criteria=crit, n_samples=20)
    for seed, res in zip((4, 5, 6, 7), batch):
        ref = fputlab.blowup.blowup_time(fputlab.Lattice(16, 0.25, "nonlinear", tau=20.0, seed=seed),
                                         300.0, y0=y, criteria=crit)
        assert res.params["blew_up"] == ref.blew_up
        if ref.blew_up:
            assert res.params["blowup_reason"] == "event" and not res.completed
            assert abs(res.params["t_blowup"] - ref.time) < 1e-9 * max(ref.time, 1.0)
        else:
            assert res.completed and res.t_final == 300.0


@pytest.mark.parametrize("model,boundary", [("homogeneous", "periodic"),
                                            ("hamiltonian", "periodic"),
                                            ("nonlinear", "periodic"),
                                            ("toda", "fixed"), ("toda", "periodic")])
def test_rings_and_toda_lanes_match_single_orbit_runs(model, boundary):
    """Periodic chains and the Toda lattice run in the lanes (issue 22): each lane's mLE, SALI,
    GALI and MEGNO are those of fputlab.chaos.lyapunov on the same orbit. The disordered rings
    drift over the barrier from t ~ 15 on (a translation stretches their bonds), so T = 10."""
    disordered = model in ("hamiltonian", "nonlinear")
    lats = [fputlab.Lattice(8, 0.5 if model == "toda" else 0.25, model, boundary=boundary,
                            tau=10.0 if disordered else 0.0, seed=s if disordered else None)
            for s in range(1, 6)]
    rng = np.random.default_rng(11)
    y0 = 0.2 * rng.standard_normal((5, 16))
    T = 10.0 if disordered else 300.0
    batch = lyapunov_batch(lats, T, y0=y0, n_samples=20)
    for r, (lat, b) in enumerate(zip(lats, batch)):
        s = chaos.lyapunov(lat, T, y0=y0[r], n_samples=20)
        np.testing.assert_array_equal(b.t, s.t)
        _same(b.mle, s.mle)
        _same(b.sali, s.sali)
        _same(b.gali, s.gali)
        _same(b.megno, s.megno)
        assert b.completed and b.steps == s.steps and b.t_final == s.t_final == T


@pytest.mark.parametrize("model", ["homogeneous", "toda"])
def test_criteria_on_rings_fire_as_in_a_single_orbit_blowup_run(model):
    """A ring's criteria (the stretch with the wrap-around bond; the displacement, which the
    ring's drifting centre makes grow) are evaluated lane by lane as events.c does: each lane
    stops where fputlab.blowup.blowup_time puts the event (some lanes fire, some do not)."""
    lat = fputlab.Lattice(12, 0.5 if model == "toda" else 0.25, model, boundary="periodic")
    rng = np.random.default_rng(3)
    y0 = 0.3 * rng.standard_normal((4, 24))
    fired = 0
    for kind in ("stretch", "displacement"):
        value = {"displacement": lambda y: np.abs(y[:12]).max(),
                 "stretch": lambda y: np.abs(np.diff(np.r_[y[11], y[:12]])).max()}[kind]
        crit = [(kind, 1.05 * max(value(y) for y in y0))]
        batch = lyapunov_batch([lat] * 4, 200.0, y0=y0, criteria=crit, n_samples=10)
        for r, res in enumerate(batch):
            ref = fputlab.blowup.blowup_time(lat, 200.0, y0=y0[r], criteria=crit)
            assert res.params["blew_up"] == ref.blew_up
            fired += ref.blew_up
            if ref.blew_up:
                assert abs(res.params["t_blowup"] - ref.time) < 1e-9 * max(ref.time, 1.0)
            else:
                assert res.completed
    assert 0 < fired < 8
