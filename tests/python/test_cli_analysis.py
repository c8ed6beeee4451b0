"""The analysis subcommands: sweep, coefficients, tauc, bifurcation (paper values, files written,
bad input -> exit status 2 naming the parameter)."""
import json

import h5py
import numpy as np
import pytest

import fputlab
from fputlab.cli import main
from fputlab.reduction import two_mode_coefficients


def _json(capsys, argv):
    assert main(argv + ["--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_coefficients_paper_values(capsys):
    out = _json(capsys, ["coefficients", "--tau", "0"])
    assert round(out["A_tilde"], 5) == 3.62805
    assert round(out["B_tilde"], 5) == 0.90728
    assert out["N"] == 64 and out["alpha"] == 0.25
    # raw vs paper-normalised: A_i = a_i/eps, A~ = A_3/(2 omega_1)
    assert out["A3"] == pytest.approx(out["a3"] / out["eps"], rel=1e-14)
    assert out["A_tilde"] == pytest.approx(out["A3"] / (2 * out["omega1"]), rel=1e-14)
    assert out["B_tilde"] == pytest.approx(out["B1"] / (2 * out["omega2"]), rel=1e-14)


def test_coefficients_over_taus_to_hdf5(tmp_path, capsys):
    path = tmp_path / "c.h5"
    out = _json(capsys, ["coefficients", "--tau", "0", "5", "10", "--seed", "3", "--N", "32",
                         "--out", str(path)])
    assert [r["tau"] for r in out["rows"]] == [0.0, 5.0, 10.0]
    ref = two_mode_coefficients(fputlab.Lattice(32, 0.25, "nonlinear", tau=10.0, seed=3))
    assert out["rows"][2]["B_tilde"] == ref.B_tilde
    with h5py.File(path) as f:
        assert f["raw"].shape == (3, 6) and f["A"].shape == (3, 3)
        np.testing.assert_array_equal(f["raw"][2], ref.raw)
        assert f.attrs["N"] == 32 and f.attrs["seed"] == 3


def test_tauc_three_ways(capsys):
    out = _json(capsys, ["tauc"])
    assert out["tau_c_exact"] == pytest.approx(10.2578, abs=1e-4)
    assert out["tau_c_fit"] == pytest.approx(10.20, abs=0.01)
    assert out["tau_c_per_realisation"]["mean"] == pytest.approx(10.85, abs=0.01)


def _eq(out):
    return [(e["theta"], round(e["delta"], 4), e["type"]) for e in out["equilibria"]]


def test_bifurcation_paper_equilibria(capsys):
    out = _json(capsys, ["bifurcation", "--A-tilde", "3.63", "--B-tilde", "0.91"])
    (t1, d1, k1), (t2, d2, k2) = _eq(out)
    assert (round(d1, 2), round(d2, 2)) == (5.09, 4.34) and k1 == k2 == "centre"
    assert (t1, t2) == (0.0, pytest.approx(np.pi / 2))
    assert out["C"] == pytest.approx(8.125 * (1 - (3.63 - 0.91) / (3.63 + 0.91)))
    assert all(abs(ev[0]) == 0 for e in out["equilibria"] for ev in e["eigenvalues"])
    out = _json(capsys, ["bifurcation", "--A-tilde", "5.3932", "--B-tilde", "-0.0015"])
    assert [(d, k) for _, d, k in _eq(out)] == [(9.1274, "centre"), (15.4383, "saddle")]
    sad = out["equilibria"][1]
    assert sad["lambda_squared"] > 0 and sad["eigenvalues"][0][1] == 0


def test_bifurcation_plot(tmp_path, capsys):
    png = tmp_path / "fig7.png"
    out = _json(capsys, ["bifurcation", "--plot", str(png)])
    assert out["plot"] == str(png) and png.stat().st_size > 10_000


def test_sweep_cli_resumes(tmp_path, capsys):
    argv = ["sweep", "--tau", "10", "--N", "8", "--realisations", "2", "--t-end", "200",
            "--out", str(tmp_path / "s.h5"), "--workers", "2"]
    out = _json(capsys, argv)
    assert (out["tasks"], out["computed"], out["skipped"], out["failed"]) == (2, 2, 0, 0)
    assert out["work_dir"] == str(tmp_path / "s.h5") + ".tasks"
    # the merged file is not rewritten without --overwrite (issue 26): refused, nothing run
    before = (tmp_path / "s.h5").read_bytes()
    assert main(argv) == 2 and "--overwrite" in capsys.readouterr().err
    assert (tmp_path / "s.h5").read_bytes() == before
    out = _json(capsys, argv + ["--overwrite"])
    assert (out["computed"], out["skipped"]) == (0, 2)
    assert out["fraction_blew_up"] == [{"tau": 10.0, "N": 8, "n": 2, "fraction": 0.0}]
    out = _json(capsys, ["sweep", "--kind", "chaos", "--tau", "10", "--N", "8",
                         "--realisations", "1", "--t-end", "100", "--samples", "10",
                         "--out", str(tmp_path / "c.h5"), "--work-dir", str(tmp_path / "cw")])
    assert out["computed"] == 1 and (tmp_path / "cw").is_dir()
    with h5py.File(tmp_path / "c.h5") as f:
        assert f["mle_t"].shape[0] == 1 and f.attrs["kind"] == "chaos"


@pytest.mark.parametrize("cmd", ["sweep", "coefficients", "tauc", "bifurcation"])
def test_help(cmd, capsys):
    with pytest.raises(SystemExit) as e:
        main([cmd, "--help"])
    assert e.value.code == 0
    assert "--json" in capsys.readouterr().out


@pytest.mark.parametrize("argv, name", [
    (["sweep", "--realisations", "0"], "realisations"),
    (["sweep", "--t-end", "0"], "--t-end"),
    (["sweep", "--N", "1"], "--N must be >= 2"),
    (["sweep", "--N", "2147483648"], "--N"),
    (["sweep", "--dt", "0"], "--dt must be finite and > 0"),
    (["sweep", "--seed", str(2**64 - 1)], "--seed + --realisations"),
    (["sweep", "--seed", "-1"], "--seed must be >= 0"),
    (["sweep", "--realisations", "2147483648"], "--realisations"),
    (["sweep", "--realisations", "2000000000"], "tasks"),
    (["simulate", "--seed", "-1"], "--seed"),
    (["simulate", "--seed", str(2**64)], "--seed"),
    (["simulate", "--seed", "5"], "homogeneous model has no disorder"),
    (["simulate", "--out", ""], "--out: empty file name"),
    (["simulate", "--out", "/dev/null", "--overwrite"], "not a regular file"),
    (["simulate", "--t-end", "10", "--dt", "1e308"], "not one step fits"),
    (["blowup", "--tau", "10", "--out", "/dev/null", "--overwrite"], "not a regular file"),
    (["tauc", "--fit-taus", "1", "1", "1"], "at least 3 distinct"),
    (["tauc", "--fit-taus", "0"], "at least 3 distinct"),
    (["sweep", "--samples", "10"], "--samples"),
    (["coefficients", "--N", "1"], "N must be >= 2"),
    (["coefficients", "--model", "homogeneous", "--tau", "5"], "tau"),
    (["tauc", "--realisations", "0"], "--realisations must be >= 1"),
    (["bifurcation", "--B-tilde", "0"], "B_tilde"),
    (["bifurcation", "--A-tilde", "nan"], "A_tilde"),
])
def test_bad_input_exit_2(tmp_path, capsys, argv, name):
    if argv[0] == "sweep":
        argv = argv + ["--out", str(tmp_path / "x.h5")]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert name in err and err.count("\n") == 1


def test_unknown_kind_is_a_usage_error(capsys):
    with pytest.raises(SystemExit) as e:
        main(["sweep", "--kind", "lyapunov"])
    assert e.value.code == 2
    assert "--kind" in capsys.readouterr().err


def test_blowup_text_summary_counts_records_and_one_realisation_refuses_plot(tmp_path, capsys):
    assert main(["blowup", "--tau", "0", "40", "--N", "8", "--realisations", "3", "--t-end",
                 "100", "--workers", "1"]) == 0
    text = capsys.readouterr().out
    assert "records: 6 (write them with --out FILE)" in text and "'seed'" not in text
    assert text.count("\n") < 12
    for extra in (["--plot", str(tmp_path / "p.png")], ["--out", str(tmp_path / "b.h5")]):
        assert main(["blowup", "--tau", "10", "--t-end", "10", *extra]) == 2
        assert "only for a sweep" in capsys.readouterr().err
    assert not any(tmp_path.iterdir())


def test_unknown_option_shows_the_subcommands_usage(capsys):
    with pytest.raises(SystemExit) as e:
        main(["simulate", "--Ns", "8"])
    assert e.value.code == 2
    err = capsys.readouterr().err
    assert err.startswith("usage: fputlab simulate") and "unrecognized arguments: --Ns" in err


def test_simulate_summary_says_what_a_user_needs(tmp_path, capsys):
    out = _json(capsys, ["simulate", "--N", "8", "--t-end", "50", "--out",
                         str(tmp_path / "r.h5"), "--checkpoint", str(tmp_path / "r.ck")])
    assert out["t_end"] == 50 and out["samples"] == 1001 and out["checkpoint"].endswith("r.ck")
    ref = fputlab.load(tmp_path / "r.h5").energy
    assert out["max_relative_energy_error"] == pytest.approx(
        np.max(np.abs(ref - ref[0])) / abs(ref[0]))
    out = _json(capsys, ["simulate", "--N", "8", "--t-end", "50"])
    assert out["sample_every"] == pytest.approx(0.05) and out["steps"] == 5000


def test_default_sampling_that_aliases_is_said(capsys):
    assert main(["simulate", "--N", "4", "--t-end", "2e4", "--dt", "0.5", "--json"]) == 0
    err = capsys.readouterr().err
    assert "undersampled" in err and "--sample-every" in err
    assert main(["simulate", "--N", "4", "--t-end", "2e4", "--dt", "0.5", "--sample-every", "1",
                 "--json"]) == 0
    assert capsys.readouterr().err == ""


def test_figures_checks_t_end_and_the_study_before_drawing(tmp_path, capsys):
    from fputlab.chaos.study import ChaosStudy
    ChaosStudy(tmp_path / "other", Ns=(4,), realisations=1, t_end=100.0)
    for argv, msg in ((["--t-end", "nan"], "--t-end must be finite"),
                      (["--t-end", "-1"], "--t-end must be finite"),
                      (["--work-dir", str(tmp_path / "other")], "other parameters")):
        assert main(["figures", "--out-dir", str(tmp_path / "figs"), *argv]) == 2
        assert msg in capsys.readouterr().err
    assert not (tmp_path / "figs").exists()


def test_figures_report_each_figure_as_it_goes(tmp_path, capsys):
    assert main(["figures", "--out-dir", str(tmp_path), "--only", "7", "9"]) == 0
    cap = capsys.readouterr()
    assert cap.err.splitlines() == ["fputlab: figure 7 (1/2) ...", "fputlab: figure 9 (2/2) ..."]
    assert cap.out.split() == [str(tmp_path / "fig07_bifurcation.png"),
                               str(tmp_path / "fig09_phase_portraits.png")]
