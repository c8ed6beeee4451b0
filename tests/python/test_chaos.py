"""Chaos indicators from Python: the paper's regular homogeneous orbits, a chaotic orbit,
classification, ensembles, bad input."""
import numpy as np
import pytest

from fputlab import Lattice, chaos


@pytest.mark.parametrize("N", [4, 8, 16, 32, 64])
def test_homogeneous_paper_orbits_are_regular(N):
    # paper Fig. 11: the mode-1 initial condition is regular for every N (here to t = 1e4)
    res = chaos.lyapunov(Lattice(N, 0.25), 1e4, n_samples=40)
    assert res.completed and not res.chaotic
    assert res.sali.min() > 1e-3
    assert np.all(res.mle * res.t < 10.0)          # lambda follows the 1/t law
    assert res.classify() == "regular"


def test_chaotic_orbit_and_early_stop():
    lat = Lattice(8, 0.0, beta=1.0)                 # FPUT-beta: no escape at any energy
    y0 = 1.5 * np.random.default_rng(0).standard_normal(16)
    res = chaos.lyapunov(lat, 3e3, y0=y0, n_samples=30)
    assert res.chaotic and res.sali[-1] < 1e-8 and res.classify() == "chaotic"
    assert res.mle[-1] > 0.05
    assert np.all(np.diff(res.t) > 0) and res.t[-1] == 3e3
    stopped = chaos.lyapunov(lat, 3e3, y0=y0, stop_when_chaotic=True)
    # chaos is confirmed one renormalisation after SALI first fell below the threshold
    assert stopped.t_final == stopped.t_chaotic + 1.0 < 3e3 and stopped.completed
    w0 = np.eye(16)[:3]
    three = chaos.lyapunov(lat, 100.0, y0=y0, w0=w0, n_dev=3)
    assert np.all((three.gali >= 0) & (three.gali <= 1.0 + 1e-12))


def test_sali_gali_closed_forms():
    a = np.array([1.0, 2.0, 3.0])
    assert chaos.sali(a, 2 * a) < 1e-15
    assert chaos.sali(a, np.array([2.0, -1.0, 0.0])) == pytest.approx(np.sqrt(2))
    assert chaos.gali(np.eye(3)) == pytest.approx(1.0)
    assert chaos.gali(np.array([[1.0, 0, 0], [1.0, 1e-9, 0]])) == pytest.approx(1e-9, rel=1e-6)


def test_chaotic_fraction_runs_realisations_in_parallel():
    out = chaos.chaotic_fraction(Ns=(4, 8), realisations=2, t_end=200.0, workers=2, n_samples=10)
    ds = out.to_xarray()
    assert list(ds["N"].values) == [4, 8] and list(ds["seed"].values) == [1, 2]
    assert [row["N"] for row in out.summary()] == [4, 8]
    assert all(len(out.orbits(N)) == 2 for N in (4, 8))
    assert {r.params["seed"] for r in out.orbits(4)} == {1, 2}
    # the dict it used to be still answers, with a warning
    with pytest.warns(DeprecationWarning, match="summary"):
        assert out["N"] == [4, 8]


@pytest.mark.parametrize("kwargs,word", [
    (dict(t_end=-1.0), "t_end"),
    (dict(t_end=10.0, renorm_interval=0.0), "renorm_interval"),
    (dict(t_end=10.0, n_dev=0), "n_dev"),
    (dict(t_end=10.0, w0=np.ones((3, 8))), "w0 has shape"),
    (dict(t_end=10.0, method="nope"), "nope"),
])
def test_bad_input(kwargs, word):
    with pytest.raises(ValueError, match=word):
        chaos.lyapunov(Lattice(4), **kwargs)


def test_tangent_map_and_variational_equations_agree():
    # the same chaotic orbit by Yoshida 4's tangent map and by DOP853 on the variational
    # equations (ARKODE): the exponents agree within a few percent
    lat = Lattice(8, 0.0, beta=1.0)
    y0 = 1.5 * np.random.default_rng(0).standard_normal(16)
    split = chaos.lyapunov(lat, 5e3, y0=y0, renorm_interval=10.0)
    var = chaos.lyapunov(lat, 5e3, y0=y0, method="dop853", rtol=1e-10, atol=1e-12,
                         renorm_interval=10.0)
    assert split.chaotic and var.chaotic
    # (finite-time estimates on two numerically different chaotic trajectories: ~1-4 % apart)
    assert abs(split.mle_final - var.mle_final) < 0.05 * var.mle_final


def test_chaotic_fraction_percent_is_the_share_of_chaotic_records():
    # N = 4, tau = 20 %, mode-1 amplitude 3: a mix of regular, undecided and blown-up orbits over
    # 12 realisations (the escapes used to be reported as chaotic: their deviation vectors align
    # with the runaway). The percentages are 100 x (records of that class) / R, each record's
    # class following from its own flags: blow-up = stopped at the barrier before t_end.
    N, R, T = 4, 12, 3000.0
    y0 = Lattice(N).mode_state(1, 3.0)
    out = chaos.chaotic_fraction(Ns=(N,), realisations=R, tau=20.0, t_end=T, workers=2,
                                 samples_per_decade=8, y0=y0, stop_when_chaotic=True)
    recs = out.orbits(N)
    assert [r.params["seed"] for r in recs] == list(range(1, R + 1))
    assert all(r.params["tau"] == 20.0 and r.params["model"] == "nonlinear" for r in recs)
    classes = [r.classify() for r in recs]
    assert classes.count("blow-up") >= 2 and classes.count("regular") >= 2    # a real mix
    row, = out.summary()
    assert row["fraction_chaotic"] == pytest.approx(classes.count("chaotic") / R, abs=1e-12)
    assert row["blow-up"] == classes.count("blow-up") and row["n"] == R
    assert list(out.to_xarray()["orbit_class"].values.ravel()) == classes
    for r, c in zip(recs, classes):
        if c == "blow-up":   # ended at the barrier, never flagged chaotic, samples kept
            assert r.blew_up and not r.chaotic and r.t_final < r.t_blowup < T
            assert np.all(np.isfinite(r.mle)) and r.t[-1] <= r.t_blowup
        else:
            assert r.completed and r.t_final == T and not r.blew_up
    # a record is the same orbit as a serial run of that realisation, on the study's sample
    # grid: 8 per decade from t = 1 (the first renormalisation) to the decade past T, 1e4
    k = classes.index("blow-up")
    lat = Lattice(N, 0.25, "nonlinear", tau=20.0, seed=k + 1)
    # ensembles default to the validated fast scheme and early stop
    assert recs[k].method == chaos.ENSEMBLE_METHOD and recs[k].params["dt"] == chaos.ENSEMBLE_DT
    direct = chaos.lyapunov(lat, 1e4, y0=y0, n_samples=4 * 8 + 1, stop_when_chaotic=True,
                            method=chaos.ENSEMBLE_METHOD, dt=chaos.ENSEMBLE_DT)
    np.testing.assert_array_equal(direct.mle, recs[k].mle)
    np.testing.assert_array_equal(direct.t, recs[k].t)
    assert direct.t_blowup == recs[k].t_blowup


CHAOS_MODELS = {
    "homogeneous": lambda: Lattice(8, 0.0, beta=1.0),
    "hamiltonian": lambda: Lattice(8, 0.25, "hamiltonian", beta=1.0, tau=20.0, seed=1),
    "nonlinear": lambda: Lattice(8, 0.25, "nonlinear", beta=1.0, tau=20.0, seed=1),
}


# aba864-harmonic (normal-mode rotation + anharmonic kick) applies to models 1 and 3 only
TANGENT_CASES = [(model, method, "yoshida4") for model in CHAOS_MODELS
                 for method in ("dop853", "cvode-adams")]
TANGENT_CASES += [(model, "dop853", "aba864-harmonic") for model in ("homogeneous", "nonlinear")]


@pytest.mark.parametrize("model,method,split_method", TANGENT_CASES)
def test_tangent_map_and_variational_equations_agree_every_model(model, method, split_method):
    # Each model with a quartic term (no escape) on a chaotic orbit (SALI < 1e-8 by t ~ 700-800
    # with the tangent map). Over the first 60 time units, before round-off differences between
    # the two chaotic trajectories grow (they decorrelate near t ~ 100-200, after which the
    # finite-time exponents differ by 2-13 %), lambda(t), SALI(t) and GALI(t) from Yoshida 4's
    # tangent map (dt = 0.002) and from the variational equations must coincide: measured
    # agreement 4e-8..2e-6 for lambda; a wrong tangent map would miss by far more than 1e-4.
    lat = CHAOS_MODELS[model]()
    y0 = 1.5 * np.random.default_rng(0).standard_normal(16)
    long = chaos.lyapunov(lat, 3000.0, y0=y0, stop_when_chaotic=True)
    assert long.chaotic and long.t_chaotic < 3000.0
    assert long.mle_final > 0.05
    T = 60.0
    split = chaos.lyapunov(lat, T, y0=y0, method=split_method, dt=0.002, renorm_interval=1.0,
                           n_samples=30)
    var = chaos.lyapunov(lat, T, y0=y0, method=method, rtol=1e-12, atol=1e-14,
                         renorm_interval=1.0, n_samples=30)
    np.testing.assert_array_equal(split.t, var.t)
    assert var.mle_final > 0.05
    assert np.abs(split.mle - var.mle).max() < 1e-4 * var.mle_final
    assert np.abs(np.log(split.sali / var.sali)).max() < 1e-3
    assert np.abs(np.log(split.gali / var.gali)).max() < 1e-3


@pytest.mark.parametrize("seed", [1, 2, 3])
@pytest.mark.parametrize("blowup_stretch", [None, -1.0])
def test_blowup_is_never_chaos(seed, blowup_stretch):
    # tau = 20 % > tau_c: these orbits escape over the cubic barrier near t ~ 2e3 (paper Fig. 3).
    # Just before the overflow the runaway direction aligns the deviation vectors (SALI < 1e-8 at
    # the last finite renormalisation), which used to be reported as chaos. With the barrier
    # check (default) or only the non-finite state (-1: check off), the class is blow-up.
    lat = Lattice(64, 0.25, "nonlinear", tau=20.0, seed=seed)
    res = chaos.lyapunov(lat, 1e4, blowup_stretch=blowup_stretch)
    assert res.blew_up and not res.chaotic and np.isnan(res.t_chaotic)
    assert res.classify() == "blow-up"
    assert 1e3 < res.t_blowup < 1e4 and not res.completed
    assert "blow-up" in res.message and f"{res.t_blowup:g}" in res.message
    # before the blow-up the orbit was regular-looking, after it it is blow-up: dated classes
    assert res.classify(t_eval=res.t_blowup - 1) in ("regular", "undecided")
    # the sweep record and the chaotic fraction agree
    out = chaos.chaotic_fraction(Ns=(64,), realisations=1, tau=20.0, t_end=1e4,
                                 first_seed=seed, workers=1, blowup_stretch=blowup_stretch,
                                 method="yoshida4", dt=0.01)
    row, = out.summary()
    assert row["chaotic"] == 0 and row["blow-up"] == 1


@pytest.mark.parametrize("method,dt", [("yoshida4", 0.01), ("srkn14a6", 0.1)])
def test_known_chaotic_orbit_two_integrators(method, dt):
    # homogeneous N = 8 with mode 1 at 4x the paper's amplitude: chaotic near t ~ 4e4 (two
    # integrators of different order and step agree on the class and roughly on the time)
    lat = Lattice(8, 0.25)
    res = chaos.lyapunov(lat, 8e4, y0=4 * lat.mode_state(), method=method, dt=dt,
                         stop_when_chaotic=True, n_samples=60)
    assert res.classify() == "chaotic" and not res.blew_up
    assert 2e4 < res.t_chaotic < 7e4
    assert res.classify(t_eval=1e3) == "regular"      # the class is dated


def test_classes_are_exactly_four_and_dated():
    t = np.logspace(0, 4, 41)
    regular = dict(chaotic=False, t_chaotic=np.nan, blew_up=False, t_blowup=np.nan, t_final=1e4)
    # lambda = 2/t: ln||w|| constant, the 1/t law of regular orbits
    assert chaos.classify_orbit(t, 2.0 / t, **regular) == "regular"
    # lambda = 0.01 for all t: lambda t grows linearly, not regular, yet SALI never fell
    assert chaos.classify_orbit(t, np.full_like(t, 0.01), **regular) == "undecided"
    # blow-up wins over a later chaos flag and vice versa: whichever came first
    both = dict(regular, blew_up=True, t_blowup=500.0, t_final=499.0)
    assert chaos.classify_orbit(t[t < 500], 2.0 / t[t < 500], **both) == "blow-up"
    assert chaos.classify_orbit(t[t < 500], 2.0 / t[t < 500], **both, t_eval=100.0) == "regular"
    ch = dict(regular, chaotic=True, t_chaotic=2e3)
    assert chaos.classify_orbit(t, 2.0 / t, **ch) == "chaotic"
    assert chaos.classify_orbit(t, 2.0 / t, **ch, t_eval=1e3) == "regular"
    # a run that has not reached t_eval is not yet regular
    assert chaos.classify_orbit(t[t <= 1e3], 2.0 / t[t <= 1e3], **dict(regular, t_final=1e3),
                                t_eval=1e4) == "undecided"
    assert set(chaos.CLASSES) == {"chaotic", "regular", "blow-up", "undecided"}


@pytest.mark.parametrize("kwargs,word", [
    (dict(t_end=1e300), "renormalisations"),
    (dict(t_end=10.0, renorm_interval=1e-3), "renorm_interval"),      # below dt = 0.01
    (dict(t_end=10.0, blowup_stretch=float("nan")), "blowup_stretch"),
    (dict(t_end=1e14, dt=1e-3, renorm_interval=1e3), "step counter"),
])
def test_bad_chaos_options(kwargs, word):
    with pytest.raises(ValueError, match=word):
        chaos.lyapunov(Lattice(4), **kwargs)
