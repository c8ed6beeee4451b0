"""The plotting API: each function draws what it says into the Axes it returns (Agg backend)."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import fputlab  # noqa: E402
from fputlab import plotting, reduction  # noqa: E402
from fputlab.chaos import ChaosResult  # noqa: E402


@pytest.fixture(autouse=True)
def close_figures():
    yield
    plt.close("all")


def fake_chaos(scale, n=30, seed=0):
    """A ChaosResult-like object built by hand (no integration): lambda = scale / t."""
    t = np.logspace(0, 4, n)
    sali = np.exp(-np.random.default_rng(seed).uniform(0, 1, n).cumsum())
    return ChaosResult(t=t, mle=scale / t, sali=sali, gali=sali**2, chaotic=False,
                       t_chaotic=float("nan"), t_final=t[-1], steps=0, method="none")


def test_plot_mle_draws_each_result_and_the_1_over_t_guide():
    results = [fake_chaos(2.0), fake_chaos(3.0, seed=1)]
    ax = plotting.plot_mle(results, labels=["a", "b"], colors=["r", "g"])
    assert isinstance(ax, matplotlib.axes.Axes)
    lines = ax.get_lines()
    assert [ln.get_label() for ln in lines] == ["a", "b", "$1/t$"]
    np.testing.assert_allclose(lines[0].get_ydata(), 2.0 / results[0].t)
    assert lines[1].get_color() == "g"
    guide = lines[2]
    np.testing.assert_allclose(guide.get_ydata(), 1.0 / guide.get_xdata())
    assert guide.get_xdata()[0] == pytest.approx(1.0) and guide.get_xdata()[-1] == pytest.approx(1e4)
    assert ax.get_xscale() == "log" and ax.get_yscale() == "log"


def test_plot_mle_accepts_one_result_dicts_and_an_existing_axes():
    fig, ax = plt.subplots()
    one = {"t": np.array([1.0, 10.0]), "mle": np.array([-0.5, 0.05])}
    assert plotting.plot_mle(one, ax=ax, guide=False) is ax
    np.testing.assert_allclose(ax.get_lines()[0].get_ydata(), [0.5, 0.05])   # |lambda|
    with pytest.raises(ValueError, match="labels"):
        plotting.plot_mle([one, one], labels=["only one"], ax=ax)
    with pytest.raises(ValueError, match="results"):
        plotting.plot_mle([], ax=ax)


def test_plot_sali_with_threshold():
    r = fake_chaos(1.0)
    ax = plotting.plot_sali([r], colors="k", threshold=1e-8)
    lines = ax.get_lines()
    np.testing.assert_allclose(lines[0].get_ydata(), r.sali)
    assert lines[1].get_ydata()[0] == 1e-8           # the horizontal threshold line


def test_plot_sali_of_a_real_chaos_result():
    res = fputlab.chaos.lyapunov(fputlab.Lattice(8, 0.25), 50.0, n_samples=20)
    ax = plotting.plot_sali(res, labels="N = 8")
    np.testing.assert_allclose(ax.get_lines()[0].get_ydata(), res.sali)
    assert ax.get_legend().get_texts()[0].get_text() == "N = 8"


@pytest.fixture(scope="module")
def run():
    return fputlab.Lattice(16, 0.25).integrate(500.0, sample_every=1.0, store_states=True)


def test_plot_mode_energies(run):
    ax = plotting.plot_mode_energies(run, modes=(1, 3), relative=True)
    lines = ax.get_lines()
    assert [ln.get_label() for ln in lines] == ["$E_{1}$", "$E_{3}$"]
    np.testing.assert_allclose(lines[1].get_ydata(), run.mode_energies[:, 2] / run.energy[0])
    with pytest.raises(ValueError, match="modes"):
        plotting.plot_mode_energies(run, modes=(17,))
    assert plotting.plot_mode_energies(run, log=True).get_yscale() == "log"


def test_plot_envelope_is_the_block_maximum(run):
    ax = plotting.plot_envelope(run, 50)
    image = ax.get_images()[0].get_array()
    assert image.shape == (16, 10)
    x = np.abs(run.states[:50, :16])
    np.testing.assert_allclose(image[:, 0], x.max(axis=0))


def test_plot_two_mode_with_envelopes():
    c = reduction.two_mode_coefficients(64, 0.25)
    run = reduction.two_mode_run(c, 2000.0, sample_every=1.0)
    env = reduction.envelope_run(c.A_tilde, c.B_tilde, c.eps * 2000.0, N=64, dT=1e-3)
    ax = plotting.plot_two_mode(run, env, c.eps)
    lines = ax.get_lines()
    assert len(lines) == 2 + 4
    np.testing.assert_allclose(lines[0].get_ydata(), run.Q[:, 0])
    # the upper envelope of Q_1 lies above |Q_1| to leading order
    top = np.interp(run.t, lines[2].get_xdata(), lines[2].get_ydata())
    assert np.mean(np.abs(run.Q[:, 0]) <= 1.05 * top) > 0.99
    with pytest.raises(ValueError, match="eps"):
        plotting.plot_two_mode(run, env)


def test_plot_blowup_sweep():
    sweep = {"tau": [0.0, 20.0], "N": [64], "probability": np.array([[0.0], [0.5]]),
             "t_max": 1e4,
             "records": [(0.0, 64, 1, False, np.nan, 10.0), (0.0, 64, 2, False, np.nan, 12.0),
                         (20.0, 64, 1, True, 2545.0, 10.0), (20.0, 64, 2, False, np.nan, 25.0)]}
    ax = plotting.plot_blowup_sweep(sweep)
    prob, pred = ax.get_lines()
    np.testing.assert_allclose(prob.get_ydata(), [0.0, 0.5])
    np.testing.assert_allclose(pred.get_ydata(), [0.0, 0.5])     # tau > own tau_c: 1 of 2 at 20
    ax = plotting.plot_blowup_sweep(sweep, kind="times")
    assert sum(p.get_height() for p in ax.patches) == 1
    with pytest.raises(ValueError, match="kind"):
        plotting.plot_blowup_sweep(sweep, kind="pie")


def test_plot_bifurcation_regions_match_classify():
    ax = plotting.plot_bifurcation(N=64, extent=(-1, 1, -1, 1), n=51)
    codes = ax.get_images()[0].get_array()
    A, B = np.meshgrid(np.linspace(-1, 1, 51), np.linspace(-1, 1, 51))
    np.testing.assert_array_equal(codes, reduction.classify(A, B, reduction.r1_squared(64)))
    assert len(ax.get_legend().get_texts()) == 8


def fake_spectrum(N, seed=0):
    """A SpectrumResult built by hand: a linear spectrum lambda_i = 1 - 2 (i - 1/2)/(2N)."""
    from fputlab.chaos import SpectrumResult
    lam = 1 - 2 * (np.arange(2 * N) + 0.5) / (2 * N)
    t = np.logspace(0, 3, 12)
    hist = lam[:, None] * (1 + 1 / t)[None, :]
    return SpectrumResult(exponents=lam, t=t, history=hist, t_final=1e3, steps=0,
                          method="none", params={"N": N})


def test_plot_spectrum_collapses_sizes_on_i_over_2N():
    ax = plotting.plot_spectrum([fake_spectrum(4), fake_spectrum(8)])
    lines = [ln for ln in ax.get_lines() if len(ln.get_xdata()) > 2]
    assert len(lines) == 2
    np.testing.assert_allclose(lines[0].get_xdata(), np.arange(1, 9) / 8)
    np.testing.assert_allclose(lines[1].get_ydata(), fake_spectrum(8).exponents)
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["$N = 4$", "$N = 8$"]


def test_plot_spectrum_convergence_draws_every_exponent():
    res = fake_spectrum(3)
    ax = plotting.plot_spectrum_convergence(res)
    curves = [ln for ln in ax.get_lines() if len(ln.get_xdata()) == res.t.size]
    assert len(curves) == 6
    np.testing.assert_allclose(curves[0].get_ydata(), res.history[0])
    assert curves[0].get_linestyle() == "-" and curves[-1].get_linestyle() == "--"
    assert len(plotting.plot_spectrum_convergence(res, every=2).get_lines()) == 3 + 1


def test_plot_megno_and_clv_localisation():
    res = fake_chaos(1.0)
    res.megno = 2 - 1 / res.t
    ax = plotting.plot_megno(res, labels="orbit")
    np.testing.assert_allclose(ax.get_lines()[0].get_ydata(), res.megno)

    class FakeCLV:
        ipr = np.array([[0.25, 0.5], [0.25, 1.0]])
        params = {"N": 1}
    ax = plotting.plot_clv_localisation(FakeCLV())
    np.testing.assert_allclose(ax.get_lines()[0].get_ydata(), [4.0, 1.5])
