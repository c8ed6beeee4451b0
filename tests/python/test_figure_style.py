"""Figures fit for a paper: vector output and a chosen dpi, one number format, short tick
labels that cannot collide, one colour per mode, a log energy axis floored above round-off,
blow-ups marked in the chaos panels (Figs. 12-13) whose SALI axis fits the data, and distinct
markers for the two equilibria of Fig. 9."""
from types import SimpleNamespace

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from fputlab import figures, figures_reduction  # noqa: E402
from fputlab._figure import figure_output, save, sci, target  # noqa: E402
from fputlab.plotting import mode_color, plot_mode_energies, plot_two_mode  # noqa: E402


@pytest.mark.parametrize("fmt, magic", [("pdf", b"%PDF"), ("svg", b"<?xml"), ("png", b"\x89PNG")])
def test_figure_output_writes_the_format(tmp_path, fmt, magic):
    with figure_output(fmt):
        fig = figures_reduction.fig7(tmp_path, N=64)
    assert fig == tmp_path / f"fig07_bifurcation.{fmt}" and fig.read_bytes()[:len(magic)] == magic
    assert fig.numbers["r1sq"] == pytest.approx(65 / 8)
    # a file name chooses the format itself; outside the block it is PNG again
    assert target(tmp_path / "x.svg", "fig.png").endswith("x.svg")
    assert target(tmp_path, "fig.png").endswith("fig.png")


def test_dpi_sets_the_pixel_size(tmp_path):
    fig, ax = plt.subplots(figsize=(2, 1))
    with figure_output(dpi=50):
        path = save(fig, target(tmp_path, "a.png"))
    width = int.from_bytes(path.read_bytes()[16:20], "big")     # PNG IHDR width
    assert width == 100


@pytest.mark.parametrize("kwargs, name", [({"format": "jpg"}, "format"), ({"dpi": 0}, "dpi"),
                                          ({"dpi": "high"}, "dpi"), ({"format": 3}, "format")])
def test_figure_output_rejects_bad_values(kwargs, name):
    with pytest.raises((ValueError, TypeError), match=name):
        with figure_output(**kwargs):
            pass


def test_one_number_format():
    assert sci(1e8) == "$10^{8}$" and sci(1e-8) == "$10^{-8}$"
    assert sci(2.5e4) == r"$2.5\times 10^{4}$" and sci(99999) == "$10^{5}$"
    assert sci(2545) == "2545" and sci(0.05) == "0.05" and sci(0) == "0"


def test_long_linear_tick_labels_get_a_common_factor(tmp_path):
    fig, axes = plt.subplots(1, 3, figsize=(12, 3), sharex=True, constrained_layout=True)
    for ax in axes:
        ax.plot([0, 1.5e5], [0, 0.04])
    save(fig, target(tmp_path, "ticks.png"))
    fig.canvas.draw()
    for ax in axes:
        labels = [t for t in ax.get_xticklabels() if t.get_text()]
        texts = [t.get_text().replace("\\mathdefault{", "").strip("$}") for t in labels]
        assert all(len(text) <= 5 for text in texts), texts        # "1.50", not "150000"
        assert "10^{5}" in ax.xaxis.get_offset_text().get_text()
        boxes = [t.get_window_extent() for t in labels]
        assert not any(a.overlaps(b) for a, b in zip(boxes, boxes[1:]))


def test_a_mode_has_one_colour_everywhere():
    assert [mode_color(k) for k in (1, 2, 3, 4)] == ["C0", "C1", "C2", "C3"]
    t = np.linspace(0, 10, 11)
    run = SimpleNamespace(t=t, mode_energies=np.ones((11, 4)), energy=np.full(11, 4.0))
    ax = plot_mode_energies(run, modes=(4, 2))
    assert [line.get_color() for line in ax.get_lines()] == [mode_color(4), mode_color(2)]
    two = SimpleNamespace(t=t, Q=np.ones((11, 2)))
    ax = plot_two_mode(two)
    assert [line.get_color() for line in ax.get_lines()[:2]] == [mode_color(1), mode_color(2)]
    with pytest.raises(ValueError, match="k"):
        mode_color(0)
    plt.close("all")


def test_log_energy_axis_is_floored_above_round_off():
    t = np.linspace(0, 100, 101)
    E = np.full((101, 4), 1e-32)                 # modes that start at 0: round-off
    E[:, 0] = 0.04
    E[50:, 1] = np.logspace(-9, -2, 51)
    run = SimpleNamespace(t=t, mode_energies=E, energy=E.sum(axis=1))
    ax = plot_mode_energies(run, log=True, relative=True)
    lo, hi = ax.get_ylim()
    top = (E / E[0].sum()).max()
    assert lo >= top * 1e-13 and lo < 1e-9 / E[0].sum() and hi >= top
    plt.close("all")


def _fake_study(tmp_path):
    """Two N, three realisations each: regular, chaotic (stops at the threshold), blow-up."""
    t = np.logspace(0, 5, 60)

    def orbit(seed, kind):
        n = {"regular": 60, "chaotic": 45, "blow-up": 30}[kind]
        sali = np.ones(n)
        if kind == "chaotic":                  # falls to the threshold, stops just below it
            sali[30:] = np.logspace(-1, np.log10(5e-9), 15)
        return SimpleNamespace(t=t[:n], mle=1 / t[:n], sali=sali, blew_up=kind == "blow-up",
                               params={"seed": seed})
    res = {N: [orbit(1, "regular"), orbit(2, "chaotic"), orbit(3, "blow-up")] for N in (32, 64)}
    spec = SimpleNamespace(realisations=3, sali_threshold=1e-8, tau=10.0, method="srkn14a6",
                           dt=0.5, Ns=(32, 64))
    counts = {"chaotic": 1, "regular": 1, "blow-up": 1, "undecided": 0, "not reached": 0}
    return SimpleNamespace(results=lambda: res, reached=lambda: 1e5, spec=spec,
                           classes=lambda t: {N: dict(counts) for N in (32, 64)})


def test_chaos_panels_mark_blow_ups_and_fit_the_sali_axis(tmp_path, monkeypatch):
    drawn = {}
    monkeypatch.setattr(plt, "close", lambda fig: drawn.setdefault("fig", fig))
    path = figures.fig13(tmp_path, study=_fake_study(tmp_path))
    assert path.exists() and path.numbers["t"] == 1e5
    fig = drawn["fig"]
    mle_ax, sali_ax = fig.axes[0], fig.axes[1]
    for ax in (mle_ax, sali_ax):
        markers = [line for line in ax.get_lines() if line.get_marker() == "X"]
        assert len(markers) == 1                           # the one blow-up, at its last point
        assert markers[0].get_xdata()[0] == pytest.approx(np.logspace(0, 5, 60)[29])
        legend = [t.get_text() for t in ax.get_legend().get_texts()]
        assert any("blow-up" in text for text in legend), legend
    lo, hi = sali_ax.get_ylim()
    assert 5e-9 / 10 <= lo < 5e-9 and hi <= 10          # fits the data: not down to 1e-16
    # a sequential palette, one colour per seed, and a colour bar that names it
    assert figures.REALISATION_CMAP in ("viridis", "cividis", "plasma", "magma", "inferno")
    assert any("seed" in ax.get_ylabel() for ax in fig.axes)
    # one number format in the titles
    titles = " ".join(ax.get_title(loc="left") for ax in fig.axes) + fig._suptitle.get_text()
    assert "e+" not in titles and "1e5" not in titles and "$10^{5}$" in titles


def test_fig9_equilibria_have_distinct_markers():
    fig, ax = plt.subplots()
    figures_reduction._phase_portrait(ax, 3.63, 0.91, N=64, T_end=0.5, label="(a)")
    eq = {line.get_label()[:2]: line.get_marker() for line in ax.get_lines()
          if line.get_label().startswith("Δ")}
    assert set(eq) == {"Δ1", "Δ2"} and eq["Δ1"] != eq["Δ2"]
    plt.close(fig)
