"""Observables of thermalization against closed forms (equipartition, one mode, a flat band),
an independent entropy (scipy.stats.entropy), an exactly known crossing time and a synthetic
power law."""
import math

import numpy as np
import pytest
from scipy import stats

from fputlab import thermalization as th


def test_equipartition_and_single_mode_closed_forms():
    M = 31
    flat = np.full(M, 0.7)
    assert th.information_entropy(flat) == pytest.approx(0.0, abs=1e-14)
    assert th.wave_turbulence_entropy(flat) == pytest.approx(0.0, abs=1e-13)
    assert th.effective_modes(flat) == pytest.approx(1.0, abs=1e-14)
    one = np.zeros(M)
    one[4] = 2.0
    assert th.information_entropy(one) == pytest.approx(M * math.log(M), rel=1e-14)
    assert th.effective_modes(one) == pytest.approx(1.0 / M, rel=1e-14)
    assert th.wave_turbulence_entropy(one) == math.inf
    # eta: 1 for the single mode, 0 at equipartition, relative to the single-mode start
    np.testing.assert_allclose(th.eta(np.stack([one, flat])), [1.0, 0.0], atol=1e-14)
    # a flat band of b modes: S = M ln(M/b), n_eff = b/M
    band = np.zeros(M)
    band[:4] = 1.0
    assert th.information_entropy(band) == pytest.approx(M * math.log(M / 4), rel=1e-14)
    assert th.effective_modes(band) == pytest.approx(4 / M, rel=1e-14)


def test_entropy_against_scipy_shannon(rng):
    e = rng.exponential(size=(5, 20))
    shannon = stats.entropy(e, axis=-1)
    np.testing.assert_allclose(th.information_entropy(e), 20 * (math.log(20) - shannon),
                               rtol=1e-12)
    np.testing.assert_allclose(th.effective_modes(e), np.exp(shannon) / 20, rtol=1e-12)
    f = 20 * e / e.sum(axis=-1, keepdims=True)
    np.testing.assert_allclose(th.wave_turbulence_entropy(e), -np.log(f).sum(-1), rtol=1e-12)


def test_bad_spectra_are_refused():
    with pytest.raises(ValueError, match="negative"):
        th.information_entropy([1.0, -1.0, 2.0])
    with pytest.raises(ValueError, match="zero total"):
        th.effective_modes([0.0, 0.0])
    with pytest.raises(ValueError, match="non-finite"):
        th.information_entropy([1.0, np.nan])
    with pytest.raises(ValueError, match="entropy"):
        th.eta(np.ones((2, 3)), entropy="boltzmann")


def test_first_crossing_of_a_known_decay():
    # eta = exp(-t/tau) crosses 0.1 at tau ln 10; log-spaced samples, log-interpolated
    tau = 37.0
    t = np.geomspace(1, 1e4, 400)
    y = np.exp(-t / tau)
    assert th.first_crossing(t, y, 0.1) == pytest.approx(tau * math.log(10), rel=2e-3)
    assert math.isnan(th.first_crossing(t, y + 1, 0.1))


def _synthetic_ensemble(R, taus, t, M=16, band=2):
    """Orbits whose spectra relax exponentially from a flat band to equipartition:
    e_k(t) = 1 + (b_k - 1) exp(-t/tau_r)."""
    b = np.zeros(M)
    b[:band] = M / band
    decay = np.exp(-t[None, :, None] / np.asarray(taus)[:, None, None])
    return 1 + (b - 1) * decay


def test_equipartition_time_of_identical_orbits():
    # every orbit the same: T_eq solves S(e(t))/S(e(0)) = threshold, found here by bisection
    t = np.concatenate([[0.0], np.geomspace(1, 1e4, 300)])
    e = _synthetic_ensemble(8, [200.0] * 8, t)
    res = th.equipartition_time(t, e, threshold=0.1, n_boot=50)

    def eta_at(s):
        spec = _synthetic_ensemble(1, [200.0], np.array([0.0, s]))[0]
        s_ = th.information_entropy(spec)
        return s_[1] / s_[0] - 0.1
    lo, hi = 1.0, 1e4
    for _ in range(100):
        mid = math.sqrt(lo * hi)
        lo, hi = (mid, hi) if eta_at(mid) > 0 else (lo, mid)
    assert res["t_eq"] == pytest.approx(lo, rel=2e-3)
    assert res["interval"][0] == pytest.approx(res["t_eq"], rel=1e-12)
    assert res["interval"][1] == pytest.approx(res["t_eq"], rel=1e-12)


def test_bootstrap_interval_covers_the_population_value():
    # orbits with random relaxation times: the population T_eq (from a huge ensemble) lies in
    # the 90 % bootstrap interval of a 32-orbit ensemble in most repetitions
    t = np.concatenate([[0.0], np.geomspace(1, 1e5, 200)])
    gen = np.random.default_rng(3)
    pop = th.equipartition_time(t, _synthetic_ensemble(4000, gen.lognormal(5, 0.8, 4000), t),
                                n_boot=0)["t_eq"]
    hits = 0
    for rep in range(20):
        taus = gen.lognormal(5, 0.8, 32)
        res = th.equipartition_time(t, _synthetic_ensemble(32, taus, t), n_boot=200, seed=rep)
        lo, hi = res["interval"]
        hits += lo <= pop <= hi
    assert hits >= 14           # nominal 18 of 20; binomial(20, 0.9) >= 14 with p > 0.99


def test_fit_power_law_recovers_a_synthetic_exponent():
    gen = np.random.default_rng(1)
    eps = np.geomspace(0.05, 0.2, 6)
    truth = 3.0 * eps**-8.0
    noisy = truth * np.exp(0.1 * gen.standard_normal(6))
    boot = noisy[:, None] * np.exp(0.1 * gen.standard_normal((6, 300)))
    fit = th.fit_power_law(eps, noisy, boot)
    lo, hi = fit["interval"]
    assert lo < 8.0 < hi and hi - lo < 1.5
    fit = th.fit_power_law(eps, noisy)
    lo, hi = fit["interval"]
    assert lo < 8.0 < hi
    with pytest.raises(ValueError, match="at least 2"):
        th.fit_power_law([0.1, 0.2], [np.nan, 1.0])


def test_consistent_with_the_analysis_module(rng):
    # fputlab.analysis uses the Shannon entropy S_Sh and exp(S_Sh) modes: S = M (ln M - S_Sh)
    from fputlab import analysis
    e = rng.exponential(size=(7, 12))
    np.testing.assert_allclose(th.information_entropy(e),
                               12 * (math.log(12) - analysis.spectral_entropy(e)), rtol=1e-12)
    np.testing.assert_allclose(12 * th.effective_modes(e), analysis.effective_modes(e),
                               rtol=1e-12)
