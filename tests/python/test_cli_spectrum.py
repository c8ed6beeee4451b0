"""`fputlab spectrum`: the numbers of fputlab.chaos.lyapunov_spectrum, its files, its errors."""
import json

import h5py
import numpy as np

import fputlab
from fputlab.chaos import lyapunov_spectrum
from fputlab.cli import main

ARGS = ["spectrum", "--N", "4", "--beta", "1", "--initial-amplitude", "3", "--t-end", "100",
        "--samples", "10"]


def test_spectrum_command_gives_the_api_numbers_and_writes_its_files(capsys, tmp_path):
    out, plot = tmp_path / "s.h5", tmp_path / "s.png"
    assert main(ARGS + ["--json", "--out", str(out), "--plot", str(plot)]) == 0
    got = json.loads(capsys.readouterr().out)
    lat = fputlab.Lattice(4, beta=1.0)
    ref = lyapunov_spectrum(lat, 100.0, y0=lat.mode_state(1, 3.0), n_samples=10)
    np.testing.assert_array_equal(got["exponents"], ref.exponents)
    assert got["k"] == 8 and abs(got["sum"]) < 1e-12
    assert got["ks_entropy"] == ref.ks_entropy
    with h5py.File(out) as f:
        assert f.attrs["kind"] == "spectrum"
        np.testing.assert_array_equal(f["exponents"][:], ref.exponents)
        assert f["history"].shape == (8, f["t"].shape[0])
    assert plot.stat().st_size > 1000


def test_spectrum_command_errors_are_one_line(capsys, tmp_path):
    assert main(["spectrum", "--N", "4", "--k", "9", "--t-end", "1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "k must be" in err
    assert main(["spectrum", "--t-end", "-1"]) == 2
    assert "--t-end" in capsys.readouterr().err
    (tmp_path / "x.h5").write_text("")
    assert main(ARGS + ["--out", str(tmp_path / "x.h5")]) == 2
    assert "--overwrite" in capsys.readouterr().err
