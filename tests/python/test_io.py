"""HDF5 results and checkpoint/restart: a run killed at a random moment (SIGKILL) or stopped by
SIGTERM and restarted from its checkpoint ends with files bit-for-bit equal to an uninterrupted
run; mismatched and corrupt checkpoints are refused without touching any file."""
import hashlib
import os
import random
import signal
import subprocess
import sys
import time

import h5py
import numpy as np
import pytest

import fputlab
from fputlab.io import chaos_to_file, load, simulate_to_file
from fputlab._display import VARIABLES

N, T_END = 16, 30000.0
RUN = dict(sample_every=10.0, store_states=True, checkpoint_every_steps=5000,
           checkpoint_every_seconds=None, chunk_rows=16)


def lattice(seed=1):
    return fputlab.Lattice(N, 0.25, "nonlinear", tau=10.0, seed=seed)


def arrays(path):
    r = load(path)
    out = {"t": r.t, "energy": r.energy, "mode_energies": r.mode_energies, "v": r.v}
    if r.states is not None:
        out["states"] = r.states
    if r.chaos is not None:
        out.update({"chaos_" + k: v for k, v in r.chaos.items()})
    return out, r


def assert_bitwise_equal(a, b):
    assert a.keys() == b.keys()
    for k in a:
        assert a[k].shape == b[k].shape, k
        assert a[k].tobytes() == b[k].tobytes(), f"{k} differs"


def sha(path):
    return hashlib.sha256(open(path, "rb").read()).hexdigest()


SCRIPT = """
import sys, fputlab
from fputlab.io import simulate_to_file, chaos_to_file
lat = fputlab.Lattice({N}, 0.25, "nonlinear", tau=10.0, seed=1)
kind, out, ck = sys.argv[1:4]
if kind == "simulate":
    s = simulate_to_file(lat, {T}, out, checkpoint=ck, **{RUN!r})
else:
    s = chaos_to_file(lat, {T_CHAOS}, out, checkpoint=ck, checkpoint_every_steps=5000,
                      checkpoint_every_seconds=None, n_samples=60, segment=5.0)
print(s.status, flush=True)
"""
T_CHAOS = 30000.0


def start(kind, out, ck):
    code = SCRIPT.format(N=N, T=T_END, RUN=RUN, T_CHAOS=T_CHAOS)
    return subprocess.Popen([sys.executable, "-c", code, kind, str(out), str(ck)],
                            stdout=subprocess.PIPE, text=True)


def wait_for(path, proc, timeout=60):
    t0 = time.time()
    while not os.path.exists(path):
        assert proc.poll() is None, "the run ended before writing a checkpoint"
        assert time.time() - t0 < timeout
        time.sleep(0.01)


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    d = tmp_path_factory.mktemp("ref")
    s = simulate_to_file(lattice(), T_END, d / "ref.h5", **RUN)
    assert s.status == "completed"
    return arrays(d / "ref.h5")


def test_results_match_an_independent_in_memory_run(reference):
    a, r = reference
    run = lattice().integrate(T_END, sample_every=10.0)       # fpl_integrator_sample, no file
    assert r.status == "completed" and r.attrs["N"] == N and r.attrs["model_name"] == "nonlinear"
    assert r.attrs["method"] == "yoshida4" and r.attrs["dt"] == 0.01 and r.attrs["seed"] == 1
    assert r.attrs["fputlab_version"] == fputlab.__version__
    np.testing.assert_array_equal(a["t"], run.t)
    np.testing.assert_allclose(a["mode_energies"], run.mode_energies, rtol=1e-13, atol=1e-18)
    np.testing.assert_allclose(a["energy"], run.energy, rtol=1e-13)
    np.testing.assert_array_equal(a["v"], lattice().v)
    assert a["states"].shape == (run.t.size, 2 * N)
    # the file is chunked and compressed, as documented
    with h5py.File(r.path) as f:
        assert f["mode_energies"].chunks is not None and f["mode_energies"].compression == "gzip"
        assert f["t"].maxshape == (None,)


@pytest.mark.parametrize("trial", range(2))
def test_sigkill_at_a_random_moment_then_restart_is_bit_for_bit(tmp_path, reference, trial):
    out, ck = tmp_path / "run.h5", tmp_path / "run.ckpt"
    proc = start("simulate", out, ck)
    wait_for(ck, proc)
    time.sleep(random.uniform(0.0, 0.4))
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    t_ck, _ = fputlab.io.checkpoint_time(ck)
    assert 0 < t_ck < T_END
    s = simulate_to_file(lattice(), T_END, out, checkpoint=ck, **RUN)
    assert s.status == "completed" and s.resumed_from == t_ck
    assert_bitwise_equal(arrays(out)[0], reference[0])


def test_sigterm_writes_a_checkpoint_and_stops_cleanly(tmp_path, reference):
    out, ck = tmp_path / "run.h5", tmp_path / "run.ckpt"
    proc = start("simulate", out, ck)
    wait_for(ck, proc)
    proc.send_signal(signal.SIGTERM)
    stdout, _ = proc.communicate(timeout=60)
    assert stdout.strip() == "interrupted" and proc.returncode == 0
    assert load(out).status == "interrupted"
    s = simulate_to_file(lattice(), T_END, out, checkpoint=ck, **RUN)
    assert s.status == "completed"
    assert_bitwise_equal(arrays(out)[0], reference[0])


def test_chaos_run_killed_and_restarted_is_bit_for_bit(tmp_path):
    ref = tmp_path / "ref.h5"
    s = chaos_to_file(lattice(), T_CHAOS, ref, n_samples=60)
    direct = fputlab.chaos.lyapunov(lattice(), T_CHAOS, n_samples=60)   # fpl_chaos_run, no file
    a, r = arrays(ref)
    np.testing.assert_array_equal(a["chaos_t"], direct.t)
    np.testing.assert_array_equal(a["chaos_mle"], direct.mle)
    np.testing.assert_array_equal(a["chaos_sali"], direct.sali)
    assert s.extra["mle"] == direct.mle_final
    out, ck = tmp_path / "run.h5", tmp_path / "run.ckpt"
    proc = start("chaos", out, ck)
    wait_for(ck, proc)
    time.sleep(random.uniform(0.0, 0.3))
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    s2 = chaos_to_file(lattice(), T_CHAOS, out, checkpoint=ck, n_samples=60,
                       checkpoint_every_steps=5000, checkpoint_every_seconds=None, segment=5.0)
    assert s2.status == "completed" and s2.resumed_from is not None
    assert_bitwise_equal(arrays(out)[0], a)


def test_mismatched_or_corrupt_checkpoint_is_refused_and_nothing_is_overwritten(tmp_path):
    out, ck = tmp_path / "run.h5", tmp_path / "run.ckpt"
    short = dict(RUN, checkpoint_every_steps=1000)
    simulate_to_file(lattice(), 50.0, out, checkpoint=ck, **short)
    before = sha(out), sha(ck)
    with pytest.raises(ValueError, match="v differs"):
        simulate_to_file(lattice(seed=2), 100.0, out, checkpoint=ck, **short)
    with pytest.raises(ValueError, match="method"):
        simulate_to_file(lattice(), 100.0, out, checkpoint=ck, method="leapfrog", **short)
    with pytest.raises(ValueError, match="N = 16"):
        simulate_to_file(fputlab.Lattice(8, 0.25), 100.0, out, checkpoint=ck, **short)
    with pytest.raises(ValueError, match="chaos"):
        chaos_to_file(lattice(), 100.0, out, checkpoint=ck)
    assert (sha(out), sha(ck)) == before
    data = bytearray(open(ck, "rb").read())
    data[len(data) // 2:len(data) // 2 + 64] = bytes(64)
    open(ck, "wb").write(bytes(data))
    with pytest.raises(OSError, match="checkpoint"):
        simulate_to_file(lattice(), 100.0, out, checkpoint=ck, **short)
    assert sha(out) == before[0]


def test_blowup_ends_cleanly_with_the_event_and_finite_data(tmp_path):
    lat = fputlab.Lattice(64, 0.25, "nonlinear", tau=20.0, seed=1)
    s = simulate_to_file(lat, 1e4, tmp_path / "b.h5", sample_every=10.0,
                         stop_on=[("stretch", 4.0)])
    assert s.status == "event" and 2000 < s.event["time"] < 3000
    r = load(tmp_path / "b.h5")
    assert r.status == "event" and r.attrs["event_time"] == s.event["time"]
    assert r.attrs["event_criterion"] == "max |x_{j+1} - x_j| > 4"
    assert np.isfinite(r.mode_energies).all() and r.t[-1] == s.event["time"]
    # without criteria the state overflows: a failure, reported as such, nothing NaN written
    s = simulate_to_file(lat, 1e4, tmp_path / "f.h5", sample_every=10.0)
    r = load(tmp_path / "f.h5")
    assert s.status == "failed" and r.status == "failed" and "t =" in r.attrs["message"]
    assert np.isfinite(r.mode_energies).all() and np.isfinite(r.energy).all()


def test_bad_input(tmp_path):
    with pytest.raises(ValueError, match="checkpoint_every_steps"):
        simulate_to_file(lattice(), 10.0, tmp_path / "x.h5", checkpoint_every_steps=0)
    with pytest.raises(ValueError, match="t_end"):
        simulate_to_file(lattice(), -1.0, tmp_path / "x.h5")
    with pytest.raises(ValueError, match="sample_every"):
        simulate_to_file(lattice(), 10.0, tmp_path / "x.h5", sample_every=float("nan"))
    with pytest.raises(OSError, match="no/such"):
        simulate_to_file(lattice(), 10.0, tmp_path / "no/such/x.h5")
    with pytest.raises(FileNotFoundError, match="path"):
        load(tmp_path / "missing.h5")
    with h5py.File(tmp_path / "other.h5", "w") as f:
        f["x"] = 1
    with pytest.raises(ValueError, match="not an fputlab results file"):
        load(tmp_path / "other.h5")


def test_xarray_view_when_installed(tmp_path, reference):
    xr = pytest.importorskip("xarray")
    ds = load(reference[1].path, as_xarray=True)
    assert isinstance(ds, xr.Dataset) and ds["mode_energies"].shape == reference[0]["mode_energies"].shape


# ---- issue 26, item 5: files a netCDF/xarray user can read -----------------------------------

def test_string_attributes_are_str_and_variables_carry_cf_attributes(tmp_path):
    import h5py
    from fputlab.io import simulate_to_file as sim
    sim(fputlab.Lattice(8, 0.25, "nonlinear", tau=10.0, seed=3), 5.0, tmp_path / "r.h5",
        store_states=True)
    with h5py.File(tmp_path / "r.h5") as f:
        for k in ("schema", "kind", "model_name", "method", "status", "disorder"):
            assert isinstance(f.attrs[k], str), (k, f.attrs[k])
        assert f.attrs["disorder"] == "gaussian" and f.attrs["seed"] == 3
        assert f.attrs["tau"] == 10.0
        # the C writer's CF attributes are those of to_xarray() (_display.VARIABLES): a short
        # long name, the formula in description, no units on a dimensionless quantity
        for name in ("t", "energy", "mode_energies", "states", "v", "mode", "site", "component"):
            long_name, units, description = VARIABLES[name]
            assert f[name].attrs["long_name"] == long_name, name
            assert f[name].attrs["description"] == description, name
            assert "units" not in f[name].attrs and units == "1", name
    xr = pytest.importorskip("xarray")
    ds = xr.open_dataset(tmp_path / "r.h5", engine="h5netcdf")
    assert ds["mode_energies"].attrs["long_name"] == "mode energy"
    assert "units" not in ds["t"].attrs and ds.attrs["model_name"] == "nonlinear"
    ds.close()


def test_a_homogeneous_run_stores_no_disorder(tmp_path):
    import h5py
    from fputlab.io import simulate_to_file as sim
    sim(fputlab.Lattice(8, 0.25), 5.0, tmp_path / "h.h5", checkpoint=tmp_path / "h.ck")
    for name in ("h.h5", "h.ck"):
        with h5py.File(tmp_path / name) as f:
            assert not {"tau", "seed", "disorder"} & set(f.attrs), (name, dict(f.attrs))
    assert fputlab.load(tmp_path / "h.h5").attrs["model_name"] == "homogeneous"


def test_a_chaos_file_has_no_empty_root_datasets_and_resumes(tmp_path):
    import h5py
    from fputlab.io import chaos_to_file as chaos
    out, ck = tmp_path / "c.h5", tmp_path / "c.ck"
    chaos(fputlab.Lattice(8, 0.25), 50.0, out, checkpoint=ck, n_samples=10)
    with h5py.File(out) as f:
        assert sorted(f) == ["chaos", "site", "v"]
        assert sorted(f["chaos"]) == ["gali", "mle", "sali", "t"]
        for name, key in (("chaos/t", "t_chaos"), ("chaos/mle", "mle"), ("chaos/sali", "sali"),
                          ("chaos/gali", "gali")):
            long_name, units, description = VARIABLES[key]
            assert f[name].attrs["long_name"] == long_name, name
            assert f[name].attrs["description"] == description, name
            assert f[name].attrs.get("units", "1") == units, name
        assert f["chaos/mle"].attrs["units"] == "1/time"
    r = fputlab.load(out)
    assert r.t.shape == (0,) and r.mode_energies.shape == (0, 8) and r.chaos["t"].size == 10
    s = chaos(fputlab.Lattice(8, 0.25), 50.0, out, checkpoint=ck, n_samples=10)
    assert s.status == "completed" and fputlab.load(out).chaos["t"].size == 10


def test_files_with_fixed_length_strings_still_resume(tmp_path):
    """fputlab 0.1 wrote fixed-length string attributes: the C reader takes both kinds."""
    import h5py
    import numpy as np
    from fputlab.io import simulate_to_file as sim
    out, ck = tmp_path / "r.h5", tmp_path / "r.ck"
    lat = fputlab.Lattice(8, 0.25, "nonlinear", tau=10.0, seed=3)
    sim(lat, 5.0, out, checkpoint=ck, sample_every=0.5)
    with h5py.File(out, "r+") as f:
        for k, v in list(f.attrs.items()):
            if isinstance(v, str):
                del f.attrs[k]
                f.attrs.create(k, np.bytes_(v.encode() or b"\0"))
        assert isinstance(f.attrs["method"], bytes)
    s = sim(lat, 10.0, out, checkpoint=ck, sample_every=0.5)
    assert s.status == "completed" and fputlab.load(out).t.size == 21
