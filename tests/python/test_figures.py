"""Every figure function has one signature, figN(out_dir=".", *, full=False, ...), and returns
the path of the PNG it wrote (a Figure: a pathlib.Path carrying the figure's numbers)."""
import inspect
import pathlib

import pytest

from fputlab import figures, figures_reduction
from fputlab._figure import Figure, target

# Figs. 11-14 are being reworked separately; they join this list when they take the signature.
FIGURE_FUNCTIONS = {1: figures.fig1, 2: figures.fig2, 3: figures.fig3, **figures_reduction.FIGURES,
                    11: figures.fig11, 12: figures.fig12, 13: figures.fig13, 14: figures.fig14}


@pytest.mark.parametrize("number", sorted(FIGURE_FUNCTIONS))
def test_one_signature(number):
    params = list(inspect.signature(FIGURE_FUNCTIONS[number]).parameters.values())
    assert params[0].name == "out_dir" and params[0].default == "."
    assert params[0].kind is inspect.Parameter.POSITIONAL_OR_KEYWORD
    full = inspect.signature(FIGURE_FUNCTIONS[number]).parameters["full"]
    assert full.kind is inspect.Parameter.KEYWORD_ONLY and full.default is False
    # everything else is a keyword-only option
    assert all(p.kind in (inspect.Parameter.KEYWORD_ONLY, inspect.Parameter.VAR_KEYWORD)
               for p in params[1:])


def test_target_is_a_directory_or_a_png(tmp_path):
    assert target(tmp_path / "a" / "b", "fig.png") == str(tmp_path / "a" / "b" / "fig.png")
    assert (tmp_path / "a" / "b").is_dir()
    assert target(tmp_path / "c" / "mine.PNG", "fig.png") == str(tmp_path / "c" / "mine.PNG")
    assert (tmp_path / "c").is_dir()


def test_figure_functions_return_the_png_path_with_numbers(tmp_path):
    fig = figures_reduction.fig7(tmp_path, N=64)
    assert isinstance(fig, Figure) and isinstance(fig, pathlib.Path)
    assert fig == tmp_path / "fig07_bifurcation.png" and fig.read_bytes()[:4] == b"\x89PNG"
    assert fig["path"] == str(fig) and fig["r1sq"] == pytest.approx(65 / 8)
    assert fig.numbers == {"r1sq": pytest.approx(65 / 8)}


def test_fig3_title_shows_formulas_not_markup(tmp_path):
    fig = figures.fig3(tmp_path)
    assert fig.numbers["blowup_time"] == pytest.approx(2545, abs=1)
    assert figures._criterion_mathtext("max |x_{j+1} - x_j| > 4") == r"$\max |x_{j+1} - x_j| > 4$"


def test_mode_energy_legend_keeps_off_a_dominant_E1():
    # Fig. 2(d): E_1 runs along the top of the panel and the others near zero; the legend
    # must not sit on E_1 (it used to be pinned to the upper right)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    from types import SimpleNamespace

    from fputlab.plotting import plot_mode_energies
    t = np.linspace(0, 8e4, 801)
    E = np.zeros((t.size, 64))
    E[:, 0] = 0.075 + 0.04 * np.sin(2 * np.pi * t / 4e4 - np.pi / 2) * -1
    E[:, 1:4] = 1e-4 * (1 + np.sin(t / 1e4))[:, None]
    run = SimpleNamespace(t=t, mode_energies=E, energy=E.sum(axis=1))
    fig, ax = plt.subplots(figsize=(6, 4))
    plot_mode_energies(run, ax=ax)
    fig.canvas.draw()
    box = ax.get_legend().get_window_extent()
    e1 = ax.transData.transform(np.column_stack([t, E[:, 0]]))
    inside = (box.x0 <= e1[:, 0]) & (e1[:, 0] <= box.x1) & (box.y0 <= e1[:, 1]) & (e1[:, 1] <= box.y1)
    assert not inside.any()
    plt.close(fig)


def test_fig14_has_wilson_intervals_from_the_stored_study(tmp_path):
    """Fig. 14 of the paper's study (studies/fig12_14) draws 95 % intervals: they agree with
    scipy's Wilson interval of each count and contain the point."""
    stats = pytest.importorskip("scipy.stats")
    from fputlab.chaos.study import ChaosStudy
    root = pathlib.Path(__file__).resolve().parents[2] / "studies" / "fig12_14"
    fig = figures.fig14(tmp_path, study=ChaosStudy(root))
    nums = fig.numbers
    R = 30
    for key in ("chaotic", "blowup"):
        pct = nums[f"percent_{key}"]
        for p, (lo, hi) in zip(pct, nums[f"percent_{key}_interval"]):
            ci = stats.binomtest(round(p * R / 100), R).proportion_ci(method="wilson")
            assert lo == pytest.approx(100 * ci.low, abs=1e-9)
            assert hi == pytest.approx(100 * ci.high, abs=1e-9)
            assert lo <= p <= hi
