"""The study engine (fputlab.engine, fputlab.io.store): a study on disk continues bit for bit,
a changed spec or a second runner is refused, creation is atomic, temporaries are cleaned, the
labelled result reads back with xarray, and a SIGKILL at any moment loses nothing but time."""
import json
import os
import random
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from fputlab import Lattice, chaos
from fputlab.engine import run_study, wilson_interval
from fputlab.io.atomic import DirectoryBusy, DirectoryLock

xr = pytest.importorskip("xarray")

SMALL = dict(Ns=(4, 8), realisations=3, tau=20.0, workers=2, samples_per_decade=10)


def _same(a, b):
    """Two labelled results hold the same numbers, bit for bit (NaN where NaN)."""
    assert set(a.data_vars) == set(b.data_vars) and a.sizes == b.sizes
    for v in a.data_vars:
        x, y = a[v].values, b[v].values
        if x.dtype.kind == "f":
            assert np.array_equal(x, y, equal_nan=True), v
        else:
            assert np.array_equal(x, y), v


def test_a_larger_t_end_continues_every_orbit_bit_for_bit(tmp_path):
    whole = chaos.chaotic_fraction(t_end=2000.0, **SMALL).to_xarray()
    first = chaos.chaotic_fraction(t_end=300.0, work_dir=tmp_path, **SMALL)
    assert first.computed == 6 and first.reused == 0
    more = chaos.chaotic_fraction(t_end=2000.0, work_dir=tmp_path, **SMALL)
    _same(whole, more.to_xarray())
    again = chaos.chaotic_fraction(t_end=2000.0, work_dir=tmp_path, **SMALL)
    assert again.computed == 0 and again.reused == 6
    # one orbit against fpl_chaos alone on the study's grid (10 per decade from t = 1 to 1e4):
    # the samples up to t_end are the same numbers
    o = whole.sel(N=8, tau=20.0, seed=2)
    direct = chaos.lyapunov(Lattice(8, 0.25, "nonlinear", tau=20.0, seed=2), 1e4,
                            n_samples=41, method=chaos.ENSEMBLE_METHOD, dt=chaos.ENSEMBLE_DT,
                            stop_when_chaotic=True)
    k = int(np.sum(direct.t <= 2000.0))
    np.testing.assert_array_equal(o["t_sample"].values[:k], direct.t[:k])
    np.testing.assert_array_equal(o["mle_t"].values[:k], direct.mle[:k])
    np.testing.assert_array_equal(o["sali_t"].values[:k], direct.sali[:k])


def test_lanes_and_single_orbits_give_the_same_study():
    # the batched kernel (srkn14a6: orbits of one N in lanes) and one orbit at a time (workers
    # see groups of one when every orbit is its own chunk) agree bit for bit
    lanes = chaos.chaotic_fraction(t_end=500.0, **{**SMALL, "workers": 1}).to_xarray()
    alone = run_study("chaos", {"N": [4, 8], "tau": [20.0], "seed": [1, 2, 3]},
                      {"samples_per_decade": 10}, 500.0, workers=8).to_xarray()
    _same(lanes, alone)


def test_the_labelled_result_reads_back_with_units(tmp_path):
    out = chaos.chaotic_fraction(t_end=300.0, work_dir=tmp_path, **SMALL)
    assert repr(out).count("\n") == 0 and "N=2 x tau=1 x seed=3" in repr(out)
    with xr.open_dataset(tmp_path / "result.nc") as disk:
        _same(out.to_xarray(), disk.load())
        assert disk["orbit_class"].dtype.kind in "UO"
        assert disk["tau"].attrs["units"] == "percent"
        assert all("long_name" in disk[v].attrs for v in disk.data_vars)
        assert disk.attrs["kind"] == "chaos" and disk.attrs["t_end"] == 300.0


def test_summary_counts_and_wilson_intervals():
    # independent values: the Wilson score interval of 3/10 at 95 % is 0.1078..0.6032 and of
    # 0/5 is 0..0.4345 (Brown, Cai & DasGupta 2001, eq. 4)
    lo, hi = wilson_interval(3, 10)
    assert (round(lo, 4), round(hi, 4)) == (0.1078, 0.6032)
    lo, hi = wilson_interval(0, 5)
    assert lo == 0.0 and round(hi, 4) == 0.4345
    out = chaos.chaotic_fraction(t_end=300.0, **SMALL)
    classes = out.to_xarray()["orbit_class"].values
    for i, row in enumerate(out.summary()):
        assert row["n"] == 3 and sum(row[c] for c in chaos.CLASSES) == 3
        assert row["chaotic"] == int(np.sum(classes[i] == "chaotic"))
        assert (row["fraction_chaotic_low"], row["fraction_chaotic_high"]) == \
            wilson_interval(row["chaotic"], 3)


def test_a_changed_spec_is_refused_unless_overwritten(tmp_path):
    chaos.chaotic_fraction(t_end=100.0, work_dir=tmp_path, **SMALL)
    with pytest.raises(ValueError, match="another study.*tau"):
        chaos.chaotic_fraction(t_end=100.0, work_dir=tmp_path, **{**SMALL, "tau": 10.0})
    with pytest.raises(ValueError, match="t_end = 50 is below"):
        chaos.chaotic_fraction(t_end=50.0, work_dir=tmp_path, **SMALL)
    out = chaos.chaotic_fraction(t_end=100.0, work_dir=tmp_path, overwrite=True,
                                 **{**SMALL, "tau": 10.0})
    assert out.computed == 6
    assert json.loads((tmp_path / "study.json").read_text())["grid"]["tau"] == [10.0]


def test_a_second_runner_is_refused(tmp_path):
    tmp_path.mkdir(exist_ok=True)
    with DirectoryLock(tmp_path):
        with pytest.raises(DirectoryBusy, match=f"in use by another runner \\(pid {os.getpid()}"):
            chaos.chaotic_fraction(t_end=100.0, work_dir=tmp_path, **SMALL)
    chaos.chaotic_fraction(t_end=100.0, work_dir=tmp_path, **SMALL)     # free again


CREATE = """
import sys
from fputlab.engine import run_study
from fputlab.io.atomic import DirectoryBusy
try:
    run_study("chaos", {"N": [int(sys.argv[2])], "tau": [10.0], "seed": [1]}, {}, 50.0,
              work_dir=sys.argv[1], workers=1)
    print("ok")
except (ValueError, DirectoryBusy) as err:
    print(type(err).__name__, err)
"""


def test_racing_creators_one_wins_the_directory_stays_usable(tmp_path):
    for trial in range(3):
        path = str(tmp_path / f"race{trial}")
        procs = [subprocess.Popen([sys.executable, "-c", CREATE, path, str(N)],
                                  stdout=subprocess.PIPE, text=True) for N in (4, 8)]
        got = [p.communicate(timeout=120)[0].strip() for p in procs]
        assert [g == "ok" for g in got].count(True) == 1, got
        loser, = [g for g in got if g != "ok"]
        assert "in use by another runner" in loser or "holds another study" in loser
        winner = json.loads((tmp_path / f"race{trial}" / "study.json").read_text())["grid"]["N"][0]
        # the winner's study opens and is complete; no temporaries are left
        again = run_study("chaos", {"N": [winner], "tau": [10.0], "seed": [1]}, {}, 50.0,
                          work_dir=path, workers=1)
        assert again.reused == 1
        assert not [p for p in os.listdir(path) if p.endswith("tmp")]


def test_temporaries_of_a_killed_writer_are_removed_and_damage_is_reported(tmp_path):
    chaos.chaotic_fraction(t_end=100.0, work_dir=tmp_path, **SMALL)
    left = tmp_path / "tasks" / ".N4_tau20.0_seed1.h5.999.0123abcd.fputlab-tmp"
    left.write_bytes(b"half")
    chaos.chaotic_fraction(t_end=100.0, work_dir=tmp_path, **SMALL)
    assert not left.exists()
    task = tmp_path / "tasks" / "N4_tau20.0_seed1.h5"
    task.write_bytes(b"not hdf5")
    with pytest.raises(ValueError, match="N4_tau20.0_seed1.h5: unreadable task result"):
        chaos.chaotic_fraction(t_end=100.0, work_dir=tmp_path, **SMALL)


KILL_RUN = """
import sys
from fputlab.chaos import chaotic_fraction
chaotic_fraction(Ns=(4, 8, 16), realisations=4, tau=20.0, t_end=3e4, workers=2,
                 samples_per_decade=10, work_dir=sys.argv[1])
"""


def test_sigkill_at_a_random_moment_then_rerun_is_bit_identical(tmp_path):
    kw = dict(Ns=(4, 8, 16), realisations=4, tau=20.0, t_end=3e4, workers=2,
              samples_per_decade=10)
    started = time.monotonic()
    whole = chaos.chaotic_fraction(**kw).to_xarray()
    cost = time.monotonic() - started
    rng = random.Random(os.getpid())
    work = tmp_path / "study"
    proc = subprocess.Popen([sys.executable, "-c", KILL_RUN, str(work)])
    time.sleep(rng.uniform(0.3, 0.3 + 1.5 * cost))
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    resumed = chaos.chaotic_fraction(work_dir=work, **kw)
    _same(whole, resumed.to_xarray())
