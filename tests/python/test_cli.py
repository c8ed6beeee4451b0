"""The command line: each workflow runs, writes what it says, and rejects bad input clearly."""
import json

import h5py
import numpy as np

from fputlab.cli import main


def test_simulate_writes_hdf5(tmp_path, capsys):
    out = tmp_path / "run.h5"
    assert main(["simulate", "--N", "16", "--t-end", "50", "--out", str(out), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["completed"] and summary["samples"] == 1001
    with h5py.File(out) as f:
        assert f.attrs["N"] == 16 and f.attrs["model"] == "nonlinear"
        assert f["mode_energies"].shape == (1001, 16)
        assert np.all(np.isfinite(f["mode_energies"][...]))


def test_blowup_and_chaos_json(capsys):
    assert main(["blowup", "--json"]) == 0                 # tau = 20 %, N = 64, seed 1
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
    assert main(["figures", "--out", str(tmp_path), "--only", "3", "7"]) == 0
    assert (tmp_path / "fig03_blowup.png").stat().st_size > 10_000
    assert (tmp_path / "fig07_bifurcation.png").stat().st_size > 10_000
