"""The thermalization study driver: one task against an independent integration (scipy's
DOP853 and the explicit sine-mode matrix), bit-for-bit continuation of an interrupted study,
atomic per-task files, refusal to mix studies, and the CLI's one-line errors."""
import math
from dataclasses import replace

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from fputlab import initial_states as ist
from fputlab.cli import main
from fputlab.modes import mode_matrix
from fputlab.thermalization_study import (STUDIES, ThermalizationStudy, check_spec,
                                          load_summary, run_segment)

TINY = STUDIES["tiny"]


def _fput_rhs(alpha, N):
    def f(t, y):
        x, v = y[:N], y[N:]
        r = np.diff(np.concatenate([[0.0], x, [0.0]]))
        g = r + alpha * r**2
        return np.concatenate([v, g[1:] - g[:-1]])
    return f


def test_one_task_matches_an_independent_integration():
    spec = replace(TINY, t_first=40.0, t_max=40.0)
    res = run_segment(spec, 0, 1, 0, None)
    lat = spec.lattice(1)
    y0 = ist.random_phases(lat, energy=spec.energy(spec.eps[0]), modes=spec.band,
                           seed=spec.seed * 1_000_003 + 1)
    N, w = spec.N, spec.window_length()
    back = w * (np.arange(spec.sub_samples) + 1.0) / spec.sub_samples
    A = mode_matrix(N)
    om = 2 * np.sin(np.arange(1, N + 1) * np.pi / (2 * (N + 1)))
    sol = solve_ivp(_fput_rhs(spec.alpha, N), (0, res["t"][-1]), y0, method="DOP853",
                    rtol=1e-12, atol=1e-14, dense_output=True)
    for t, e in zip(res["t"], res["e"]):
        ys = sol.sol(np.maximum(t - w + back, 0.0))
        Q, P = A @ ys[:N], A @ ys[N:]
        ref = (0.5 * (P**2 + (om[:, None] * Q) ** 2)).mean(axis=1)
        np.testing.assert_allclose(e, ref, rtol=1e-6, atol=1e-9 * ref.sum())
    assert abs(res["energy"].max() / res["E0"] - 1) < 1e-8


def test_interrupted_study_continues_bit_for_bit(tmp_path):
    whole = ThermalizationStudy(tmp_path / "whole", TINY)
    assert whole.run() is True
    piece = ThermalizationStudy(tmp_path / "piece", TINY)
    assert piece.run(t_until=50.0) is False
    # a task in flight when the run was killed leaves only a temporary file behind
    (tmp_path / "piece" / "p00" / ".o0000_s02.npz.123.tmp").write_bytes(b"half")
    again = ThermalizationStudy(tmp_path / "piece")          # spec read from study.json
    assert again.run() is True
    a, b = whole.results(), again.results()
    for pa, pb in zip(a["points"], b["points"]):
        np.testing.assert_array_equal(pa["eta"], pb["eta"])
        assert pa["t_eq"] == pb["t_eq"]
    assert a["fit"]["exponent"] == b["fit"]["exponent"]
    assert all(p["cpu"] > 0 and p["wall"] > 0 for p in a["points"])
    ranged = again.results(fit_ranges=[(0.0, 1.0), (0.18, 1.0)])
    assert ranged["range_fits"][0]["exponent"] == b["fit"]["exponent"]
    assert len(ranged["range_fits"]) == 1            # one point in (0.18, 1): no fit
    summary = load_summary(tmp_path / "piece" / "summary.json")
    for pa, ps in zip(a["points"], summary["points"]):
        np.testing.assert_array_equal(pa["eta"], ps["eta"])
        assert pa["t_eq"] == ps["t_eq"] and pa["interval"] == ps["interval"]
    assert summary["fit"]["exponent"] == a["fit"]["exponent"]
    assert tuple(summary["fit"]["interval"]) == a["fit"]["interval"]


def test_a_larger_t_max_continues_the_study(tmp_path):
    short = replace(TINY, eps=(0.05,), t_max=200.0)        # eps = 0.05 does not cross by 200
    study = ThermalizationStudy(tmp_path / "s", short)
    study.run()
    assert not math.isfinite(study.results()["points"][0]["t_eq"])
    longer = ThermalizationStudy(tmp_path / "s", replace(short, t_max=800.0))
    assert longer.spec.segment_ends() == [50.0, 100.0, 200.0, 400.0, 800.0]
    assert longer.spec.earlier_t_max == (200.0,)
    longer.run()
    # the same as a study made with that history from the start
    direct = ThermalizationStudy(tmp_path / "d", replace(short, t_max=800.0,
                                                         earlier_t_max=(200.0,)))
    direct.run()
    a, b = longer.results()["points"][0], direct.results()["points"][0]
    np.testing.assert_array_equal(a["eta"], b["eta"])
    assert a["t_reached"] == b["t_reached"] > 200.0
    # a smaller t_max than stored changes nothing; an uneven grid is refused
    assert ThermalizationStudy(tmp_path / "s", short).spec.t_max == 800.0
    assert replace(TINY, t_max=150.0).segment_ends() == [50.0, 100.0, 150.0]
    assert replace(TINY, t_max=600.0, earlier_t_max=(150.0,)).segment_ends() == \
        [50.0, 100.0, 150.0, 300.0, 600.0]
    with pytest.raises(ValueError, match="earlier_t_max"):
        check_spec(replace(TINY, earlier_t_max=(900.0,)))


def test_study_directory_holds_one_study(tmp_path):
    ThermalizationStudy(tmp_path / "s", TINY)
    with pytest.raises(ValueError, match="different study"):
        ThermalizationStudy(tmp_path / "s", replace(TINY, orbits=5))
    # more eps may be added: the stored points keep their index (and orbits)
    grown = ThermalizationStudy(tmp_path / "s", replace(TINY, eps=TINY.eps + (0.1,)))
    assert grown.spec.eps == TINY.eps + (0.1,)
    assert ThermalizationStudy(tmp_path / "s").spec.eps == TINY.eps + (0.1,)
    with pytest.raises(ValueError, match="different study"):
        ThermalizationStudy(tmp_path / "s", replace(TINY, eps=(0.1,) + TINY.eps))
    (tmp_path / "other").mkdir()
    (tmp_path / "other" / "x.txt").write_text("mine")
    with pytest.raises(ValueError, match="not a study directory"):
        ThermalizationStudy(tmp_path / "other", TINY)
    with pytest.raises(ValueError, match="holds no study"):
        ThermalizationStudy(tmp_path / "empty")


@pytest.mark.parametrize("change, word", [
    (dict(eps=()), "eps"), (dict(eps=(-0.1,)), "eps"), (dict(orbits=1), "orbits"),
    (dict(t_max=1.0), "t_max"), (dict(threshold=1.5), "threshold"),
    (dict(method="dop853"), "adaptive"), (dict(eps_kind="gamma"), "eps_kind"),
    (dict(eps_kind="beta"), "beta"), (dict(model="quartic"), "model"),
])
def test_bad_specs_are_refused(change, word):
    with pytest.raises((ValueError, TypeError), match=word):
        check_spec(replace(TINY, **change))


def test_cli_runs_reports_and_refuses(tmp_path, capsys):
    work = str(tmp_path / "w")
    png = str(tmp_path / "teq.png")
    assert main(["thermalization", "tiny", "--work-dir", work, "--figure", png]) == 0
    out = capsys.readouterr().out
    assert "fit: T_eq ~ eps^-a" in out and "wrote" in out
    assert main(["thermalization", "tiny", "--work-dir", work, "--figure", png]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "exists" in err
    assert main(["thermalization", "tiny", "--work-dir", work, "--orbits", "3"]) == 2
    assert "different study" in capsys.readouterr().err
    assert main(["thermalization", "tiny", "--work-dir", work, "--report-only"]) == 0
    assert main(["thermalization", "tiny", "--work-dir", str(tmp_path / "x"),
                 "--t-until", "-1"]) == 2
    assert "--t-until" in capsys.readouterr().err


def test_example_draws_from_summaries(tmp_path):
    import shutil
    import subprocess
    import sys
    from pathlib import Path
    study = ThermalizationStudy(tmp_path / "w", TINY)
    study.run()
    shutil.copy(tmp_path / "w" / "summary.json", tmp_path / "tiny.json")
    script = Path(__file__).resolve().parents[2] / "examples" / "thermalization_teq.py"
    out = subprocess.run([sys.executable, str(script), "--summaries", str(tmp_path), "--studies",
                          "tiny", "--out", str(tmp_path / "t.png")], capture_output=True,
                         text=True, check=True, timeout=120).stdout
    fit = study.results()["fit"]
    assert f"tiny: T_eq ~ eps^-{fit['exponent']:.2f}" in out
    assert (tmp_path / "t.png").stat().st_size > 10_000
