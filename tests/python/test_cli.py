"""The command line: each workflow runs, writes what it says, and rejects bad input clearly."""
import json

import h5py
import numpy as np

import fputlab
from fputlab.cli import main


def test_simulate_writes_hdf5(tmp_path, capsys):
    out = tmp_path / "run.h5"
    assert main(["simulate", "--model", "nonlinear", "--tau", "10", "--N", "16", "--t-end", "50",
                 "--out", str(out), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["status"] == "completed" and summary["samples"] == 1001
    with h5py.File(out) as f:
        assert f.attrs["N"] == 16 and f.attrs["model"] == 3
        assert f.attrs["model_name"] == "nonlinear" and f.attrs["status"] == "completed"
        assert f["mode_energies"].shape == (1001, 16)
        assert np.all(np.isfinite(f["mode_energies"][...]))
    ref = fputlab.Lattice(16, 0.25, "nonlinear", tau=10, seed=1).integrate(50.0, sample_every=0.05)
    np.testing.assert_allclose(fputlab.load(out).mode_energies, ref.mode_energies, rtol=1e-12,
                               atol=1e-18)


def test_simulate_checkpoint_and_resume(tmp_path, capsys):
    out, ck = str(tmp_path / "run.h5"), str(tmp_path / "run.ckpt")
    args = ["simulate", "--model", "nonlinear", "--tau", "10", "--N", "8", "--t-end", "200", "--sample-every", "1", "--out", out,
            "--checkpoint", ck, "--checkpoint-steps", "5000", "--json"]
    assert main(args) == 0
    first = json.loads(capsys.readouterr().out)
    assert first["checkpoints_written"] >= 4 and first["resumed_from"] is None
    t_ck, steps = fputlab.io.checkpoint_time(ck)
    assert t_ck == 200.0 and steps == 20000
    assert main(args) == 0                       # finished: resumes at the end, nothing to do
    again = json.loads(capsys.readouterr().out)
    assert again["resumed_from"] == 200.0 and again["samples"] == 201
    assert main(["simulate", "--model", "nonlinear", "--tau", "10", "--N", "8", "--seed", "2",
                 "--t-end", "200", "--out", out,
                 "--checkpoint", ck]) == 2
    assert "v differs" in capsys.readouterr().err
    assert main(["simulate", "--checkpoint", ck]) == 2
    assert "--checkpoint needs --out" in capsys.readouterr().err


def test_chaos_out_writes_the_indicators(tmp_path, capsys):
    out = str(tmp_path / "chaos.h5")
    assert main(["chaos", "--N", "8", "--model", "homogeneous", "--t-end", "500", "--samples", "20",
                 "--out", out, "--checkpoint", str(tmp_path / "c.ckpt"), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    direct = fputlab.chaos.lyapunov(fputlab.Lattice(8, 0.25), 500.0, n_samples=20)
    r = fputlab.load(out)
    np.testing.assert_array_equal(r.chaos["mle"], direct.mle)
    assert summary["mle"] == direct.mle_final and summary["status"] == "completed"


def test_ensembles_refuse_options_they_cannot_honour(capsys):
    assert main(["blowup", "--tau", "10", "20", "--beta", "0.5"]) == 2
    assert "--beta" in capsys.readouterr().err
    assert main(["chaos", "--realisations", "3", "--disorder", "uniform"]) == 2
    assert "--disorder" in capsys.readouterr().err


def test_blowup_and_chaos_json(capsys):
    assert main(["blowup", "--tau", "20", "--json"]) == 0     # model 3, N = 64, seed 1
    out = json.loads(capsys.readouterr().out)
    assert out["blew_up"] and 1000 < out["time"] < 1e4
    assert main(["chaos", "--N", "8", "--model", "homogeneous", "--t-end", "500", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["class"] == "regular"


def test_bad_input_is_reported_not_raised(capsys):
    assert main(["simulate", "--N", "1"]) == 2
    assert "N must be >= 2" in capsys.readouterr().err
    assert main(["simulate", "--method", "euler"]) == 2
    assert "euler" in capsys.readouterr().err


def test_figures_quick(tmp_path):
    assert main(["figures", "--out-dir", str(tmp_path), "--only", "2", "3", "7", "11"]) == 0
    assert (tmp_path / "fig02_disorder_recurrence.png").stat().st_size > 10_000
    assert (tmp_path / "fig11_chaos_homogeneous.png").stat().st_size > 10_000
    assert (tmp_path / "fig03_blowup.png").stat().st_size > 10_000
    assert (tmp_path / "fig07_bifurcation.png").stat().st_size > 10_000


def test_progress_bars_change_nothing():
    """The progress paths run the same computation in segments: identical numbers."""
    lat = fputlab.Lattice(16, 0.25, "nonlinear", tau=10, seed=1)
    a, b = (fputlab.chaos.lyapunov(lat, 300.0, n_samples=30, progress=p) for p in (False, True))
    assert a.mle.tobytes() == b.mle.tobytes() and a.sali.tobytes() == b.sali.tobytes()
    r1, r2 = (lat.integrate(200.0, sample_every=0.5, progress=p) for p in (False, True))
    assert r1.mode_energies.tobytes() == r2.mode_energies.tobytes()
    big = fputlab.Lattice(64, 0.25, "nonlinear", tau=20, seed=1)
    e1, e2 = (fputlab.blowup.blowup_time(big, 4000.0, progress=p) for p in (False, True))
    assert e1.blew_up and e1.time == e2.time and e1.criterion == e2.criterion


def test_tauc_and_bifurcation_write_hdf5(tmp_path, capsys):
    out = tmp_path / "b.h5"
    assert main(["bifurcation", "--A-tilde", "3.63", "--B-tilde", "0.91", "--out", str(out)]) == 0
    with h5py.File(out) as f:
        eqs = json.loads(f.attrs["equilibria"])
        assert [round(e["delta"], 2) for e in eqs] == [5.09, 4.34]
    out = tmp_path / "t.h5"
    assert main(["tauc", "--realisations", "20", "--out", str(out)]) == 0
    with h5py.File(out) as f:
        assert abs(f.attrs["tau_c_exact"] - 10.2578) < 1e-3      # closed-form expectation


def test_chaos_figures_from_a_resumable_study(tmp_path):
    # Figs. 12-14 continue the chaos study in the work directory; a second call with the same
    # horizon redraws from the stored orbits without advancing any of them
    work = tmp_path / "study"
    args = ["figures", "--out-dir", str(tmp_path), "--only", "12", "13", "14", "--t-end", "300",
            "--work-dir", str(work), "--workers", "2"]
    assert main(args) == 0
    for name in ("fig12_chaos_N4_8_16.png", "fig13_chaos_N32_64.png",
                 "fig14_chaotic_fraction.png"):
        assert (tmp_path / name).stat().st_size > 10_000
    stamps = {p.name: p.stat().st_mtime_ns for p in work.glob("tasks/*.h5")}
    assert len(stamps) == 150                      # 30 realisations x N = 4, 8, 16, 32, 64
    assert main(args) == 0
    assert stamps == {p.name: p.stat().st_mtime_ns for p in work.glob("tasks/*.h5")}
    from fputlab.chaos.study import ChaosStudy
    assert ChaosStudy(work).reached() == 300.0
