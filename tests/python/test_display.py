"""Notebook use: short reprs of the result objects, conversion to xarray with units and long
names, HDF5 results whose dimensions netCDF readers can name, progress bars that work in Jupyter."""
import re
import sys

import h5py
import numpy as np
import pytest

import fputlab
from fputlab import blowup, chaos, io, reduction


@pytest.fixture(scope="module")
def run():
    return fputlab.Lattice(16, 0.25).integrate(200.0, sample_every=2.0, store_states=True)


@pytest.fixture(scope="module")
def chaos_result():
    return chaos.lyapunov(fputlab.Lattice(8, 0.25, "nonlinear", tau=10.0, seed=2), 100.0,
                          n_samples=40)


def test_run_repr_is_a_short_summary(run):
    text = repr(run)
    assert len(text) < 250 and "\n" not in text
    assert text.startswith("Run(N=16, model='homogeneous'")
    assert "t=0..200, 101 samples" in text and "method='yoshida4'" in text
    # the energy error it quotes is the one computed independently from the energies
    e = run.energy
    quoted = float(re.search(r"max rel. energy error ([0-9.e+-]+)", text).group(1))
    assert quoted == pytest.approx(np.max(np.abs(e - e[0]) / abs(e[0])), rel=1e-3)


def test_model3_run_repr_quotes_no_energy_error():
    run = fputlab.Lattice(8, 0.25, "nonlinear", tau=10.0, seed=1).integrate(10.0)
    assert "energy error" not in repr(run) and "tau=10, seed=1" in repr(run)


def test_result_reprs_are_short(chaos_result):
    b = blowup.blowup_time(fputlab.Lattice(64, 0.25, "nonlinear", tau=20.0, seed=1), 3000.0)
    modal = reduction.two_mode_run(reduction.two_mode_coefficients(64, 0.25), 50.0)
    for obj in (chaos_result, b, modal):
        text = repr(obj)
        assert len(text) <= 220 and "\n" not in text, text      # two lines at most
        assert text.startswith(type(obj).__name__ + "(")
        assert "array(" not in text
    assert "N=8" in repr(chaos_result) and f"{chaos_result.t.size} samples" in repr(chaos_result)
    assert f"mle={chaos_result.mle[-1]:.4g}" in repr(chaos_result)
    assert f"class={chaos_result.classify()!r}" in repr(chaos_result)
    assert "blew_up=True" in repr(b) and "time=2545" in repr(b)


def test_run_to_xarray_has_dimensions_units_and_values(run):
    xr = pytest.importorskip("xarray")
    ds = run.to_xarray()
    assert isinstance(ds, xr.Dataset)
    assert ds.sizes == {"t": 101, "mode": 16, "site": 16, "component": 32}
    np.testing.assert_array_equal(ds["t"].values, run.t)
    np.testing.assert_array_equal(ds["mode_energies"].sel(mode=1).values, run.mode_energies[:, 0])
    np.testing.assert_array_equal(ds["states"].values, run.states)
    for name in ("t", "energy", "mode_energies", "states", "relative_energy_error", "v"):
        # dimensionless: a short long name in words (xarray's axis label), no units attribute
        # (xarray would print "time [1]"), the formula in the description
        attrs = ds[name].attrs
        assert attrs["long_name"] and attrs["description"] and "units" not in attrs, name
        assert "(" not in attrs["long_name"] and "=" not in attrs["long_name"], name
    from xarray.plot.utils import label_from_attrs
    assert label_from_attrs(ds["t"]) == "time"
    assert label_from_attrs(ds["mode_energies"]) == "mode energy"
    assert ds.attrs["N"] == 16 and ds.attrs["method"] == "yoshida4"


def test_chaos_result_to_xarray(chaos_result):
    pytest.importorskip("xarray")
    ds = chaos_result.to_xarray()
    assert dict(ds.sizes) == {"t": chaos_result.t.size}
    np.testing.assert_array_equal(ds["mle"].values, chaos_result.mle)
    np.testing.assert_array_equal(ds["sali"].values, chaos_result.sali)
    assert ds["mle"].attrs["units"] == "1/time"
    from xarray.plot.utils import label_from_attrs
    assert label_from_attrs(ds["mle"]) == "Lyapunov exponent [1/time]"
    assert ds.attrs["N"] == 8 and ds.attrs["method"] == chaos_result.method


def test_to_xarray_without_xarray_names_the_extra(run, chaos_result, monkeypatch):
    monkeypatch.setitem(sys.modules, "xarray", None)      # import xarray -> ImportError
    for obj in (run, chaos_result):
        with pytest.raises(ImportError, match=r"fputlab\[xarray\]"):
            obj.to_xarray()


def test_results_file_has_dimension_scales(tmp_path):
    lat = fputlab.Lattice(8, 0.25, "hamiltonian", tau=5.0, seed=3)
    path = tmp_path / "run.h5"
    io.simulate_to_file(lat, 20.0, path, sample_every=1.0, store_states=True, deviations=np.eye(1, 16))
    with h5py.File(path, "r") as f:
        assert f["t"].is_scale and f["mode"].is_scale and f["site"].is_scale
        for name in ("energy", "mode_energies", "states"):
            assert f[name].dims[0].keys() == ["t"], name
        assert f["mode_energies"].dims[1].keys() == ["mode"]
        assert f["states"].dims[1].keys() == ["component"]
        assert f["v"].dims[0].keys() == ["site"]
        np.testing.assert_array_equal(f["mode"][()], np.arange(1, 9))
        assert f["component"].shape == (32,)
    xr = pytest.importorskip("xarray")
    pytest.importorskip("h5netcdf")
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        assert not [d for d in ds.sizes if str(d).startswith("phony_dim")]
        assert ds["mode_energies"].dims == ("t", "mode")
        assert ds["states"].dims == ("t", "component")
        np.testing.assert_array_equal(ds["v"].values, lat.v)
        assert ds.sizes["t"] == 21


def test_chaos_file_has_dimension_scales(tmp_path):
    path = tmp_path / "chaos.h5"
    io.chaos_to_file(fputlab.Lattice(8, 0.25), 50.0, path, n_samples=20)
    with h5py.File(path, "r") as f:
        assert f["chaos/t"].is_scale
        samples = f["chaos/t"].shape[0]
        for name in ("mle", "sali", "gali"):
            assert f["chaos"][name].dims[0].keys() == ["t"]
    xr = pytest.importorskip("xarray")
    pytest.importorskip("h5netcdf")
    with xr.open_dataset(path, engine="h5netcdf", group="chaos") as ds:
        assert ds["mle"].dims == ("t",) and ds.sizes["t"] == samples


def test_progress_bars_use_tqdm_auto():
    # tqdm.auto picks the Jupyter widget in a notebook and the text bar elsewhere
    from pathlib import Path
    src = Path(fputlab.__file__).parent
    plain = [p.name for p in src.glob("*.py") if "from tqdm import tqdm" in p.read_text()]
    assert plain == []
