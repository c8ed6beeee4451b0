"""The "blowup" and "run" study kinds of the study engine and its calls cut short
(max_call_seconds): each task holds what blowup_time / integrate compute when called directly,
a study run to t1 and then to t2 holds the numbers of one run straight to t2 (bit for bit: the
fixed-step methods), and a study whose calls are cut into many pieces holds the numbers of one
call per task."""
import math

import numpy as np
import pytest

import fputlab
from fputlab import Lattice
from fputlab.blowup import blowup_sweep, blowup_time, realisation_tau_c
from fputlab.engine import load_study, run_study, wilson_interval

xr = pytest.importorskip("xarray")

# tau = 50 % makes some of these tiny lattices blow up before t = 400, tau = 10 % none
GRID = {"N": [8, 16], "tau": [10.0, 50.0], "seed": [1, 2, 3]}


def _same(a, b, skip=()):
    """Two labelled results hold the same numbers, bit for bit (NaN where NaN)."""
    assert set(a.data_vars) == set(b.data_vars) and a.sizes == b.sizes
    for v in a.data_vars:
        if v in skip:
            continue
        x, y = a[v].values, b[v].values
        if x.dtype.kind == "f":
            assert np.array_equal(x, y, equal_nan=True), v
        else:
            assert np.array_equal(x, y), v


# ---- blowup -----------------------------------------------------------------------------------

def test_blowup_study_holds_blowup_times_of_direct_runs():
    r = run_study("blowup", GRID, {}, 400.0, workers=2)
    ds = r.to_xarray()
    assert 0 < int(ds["blew_up"].sum()) < 12          # both outcomes
    for N in GRID["N"]:
        for tau in GRID["tau"]:
            for seed in GRID["seed"]:
                o = ds.sel(N=N, tau=tau, seed=seed)
                ref = blowup_time(Lattice(N, 0.25, "nonlinear", tau=tau, seed=seed), 400.0)
                assert bool(o["blew_up"]) == ref.blew_up
                assert float(o["t_reached"]) == ref.t_reached
                assert str(o["criterion"].values) == ref.criterion
                assert (math.isnan(ref.time) and math.isnan(float(o["time"]))) or \
                    float(o["time"]) == ref.time
                assert float(o["tau_c"]) == realisation_tau_c(N, seed, 0.25)
    # labelled: CF long_name everywhere, units where there are any
    assert all("long_name" in ds[v].attrs for v in ds.data_vars)
    assert ds["tau"].attrs["units"] == "percent" and ds["tau_c"].attrs["units"] == "percent"
    assert ds["criterion"].dtype.kind in "UO"
    # the summary: counts per (N, tau), the probability and its Wilson 95 % interval
    rows = r.summary()
    assert len(rows) == 4
    for row in rows:
        k = int(ds["blew_up"].sel(N=row["N"], tau=row["tau"]).sum())
        assert (row["n"], row["blew_up"]) == (3, k) and row["probability"] == k / 3
        assert (row["probability_low"], row["probability_high"]) == wilson_interval(k, 3)


def test_blowup_study_continues_bit_for_bit(tmp_path):
    straight = run_study("blowup", GRID, {}, 400.0, workers=2).to_xarray()
    first = run_study("blowup", GRID, {}, 150.0, workers=2, work_dir=tmp_path)
    n_done = int(first.to_xarray()["blew_up"].sum())
    more = run_study("blowup", GRID, {}, 400.0, workers=2, work_dir=tmp_path)
    assert (more.reused, more.resumed) == (n_done, 12 - n_done)
    _same(straight, more.to_xarray())
    with xr.open_dataset(tmp_path / "result.nc") as disk:
        _same(straight, disk.load())


def test_blowup_sweep_on_the_engine_keeps_its_study(tmp_path):
    kw = dict(Ns=[8], realisations=3, t_end=300.0, workers=2)
    out = blowup_sweep([10.0, 50.0], work_dir=tmp_path, **kw)
    study = out["study"]
    assert study.computed == 6 and study.work_dir == str(tmp_path)
    assert out["probability"].shape == (2, 1)
    for row in study.summary():
        i = [10.0, 50.0].index(row["tau"])
        assert out["probability"][i, 0] == row["probability"]
    again = blowup_sweep([10.0, 50.0], work_dir=tmp_path, **kw)
    assert again["study"].reused == 6
    np.testing.assert_array_equal(np.array(again["records"], float), np.array(out["records"], float))
    with pytest.raises(ValueError, match="another study"):
        blowup_sweep([20.0], work_dir=tmp_path, **kw)


def test_a_failed_run_is_reported_not_stored_and_tried_again(tmp_path):
    """Without a stopping criterion two of these lattices overflow: the study lists them as
    failed, stores nothing of them, and the next run tries them again; blowup_sweep raises."""
    grid = {"N": [16], "tau": [50.0], "seed": [1, 2, 3]}
    r = run_study("blowup", grid, {"criteria": []}, 500.0, workers=2, work_dir=tmp_path)
    assert [c["seed"] for c, _ in r.failed] == [1, 3] and r.computed == 1
    assert all(m.startswith("IntegrationError: state became non-finite") for _, m in r.failed)
    # of a failed run at most its last good piece is kept (the probe before the failure,
    # unfinished): the next run continues from there
    ds = load_study(tmp_path).to_xarray()
    reached = ds["t_reached"].values.ravel()
    assert reached[1] == 500.0 and np.all(np.nan_to_num(reached[[0, 2]]) < 500.0)
    again = run_study("blowup", grid, {"criteria": []}, 500.0, workers=2, work_dir=tmp_path)
    assert again.reused == 1 and len(again.failed) == 2 and "failed=2" in repr(again)
    with pytest.raises(fputlab.IntegrationError, match="2 run.*seed = 1.*non-finite"):
        blowup_sweep([50.0], Ns=[16], realisations=3, t_end=500.0, workers=2, criteria=[])


@pytest.mark.parametrize("settings, name", [
    ({"criteria": [("wobble", 1.0)]}, "wobble"),
    ({"method": "euler"}, "euler"),
    ({"dt": -1.0}, "dt"),
    ({"colour": 1}, "colour"),
    ({"y0": [0.0, 1.0]}, "y0"),
])
def test_blowup_study_names_a_bad_setting(settings, name):
    with pytest.raises((ValueError, TypeError), match=name):
        run_study("blowup", GRID, settings, 10.0)


# ---- run --------------------------------------------------------------------------------------

RUN_GRID = {"N": [8, 16], "tau": [0.0, 50.0], "seed": [1, 3]}
RUN_SETTINGS = {"sample_every": 5.0, "dt": 0.05}


def test_run_study_holds_the_samples_of_integrate():
    ds = run_study("run", RUN_GRID, RUN_SETTINGS, 300.0, workers=2).to_xarray()
    assert ds.sizes["mode"] == 16 and ds.sizes["sample"] == 61
    np.testing.assert_array_equal(ds["t"].values, 5.0 * np.arange(61))
    stopped = 0
    for N in RUN_GRID["N"]:
        for tau in RUN_GRID["tau"]:
            for seed in RUN_GRID["seed"]:
                o = ds.sel(N=N, tau=tau, seed=seed)
                lat = Lattice(N, 0.25, "nonlinear", tau=tau, seed=seed)
                lower, upper = lat.barrier
                ref = fputlab.integrate(lat, 300.0, dt=0.05, sample_every=5.0,
                                        stop_on=[("stretch", min(-lower, upper))],
                                        on_failure="return")
                k = ref.t.size
                np.testing.assert_array_equal(o["E"].values[:k, :N], ref.mode_energies)
                np.testing.assert_array_equal(o["energy"].values[:k], ref.energy)
                assert np.all(np.isnan(o["E"].values[k:])) and np.all(np.isnan(o["E"].values[:, N:]))
                assert bool(o["blew_up"]) == (ref.event is not None or not ref.completed)
                assert float(o["t_reached"]) == (ref.t[-1] if o["blew_up"] else 300.0)
                stopped += bool(o["blew_up"])
    assert 0 < stopped < 8                   # a blow-up ends a run, the others go on
    # the total energy of the ordered chain is conserved to the scheme's accuracy
    e = ds["energy"].sel(tau=0.0).values
    assert np.nanmax(np.abs(e / e[..., :1] - 1)) < 1e-4


def test_run_study_continues_bit_for_bit(tmp_path):
    straight = run_study("run", RUN_GRID, RUN_SETTINGS, 300.0, workers=2).to_xarray()
    run_study("run", RUN_GRID, RUN_SETTINGS, 120.0, workers=2, work_dir=tmp_path)
    more = run_study("run", RUN_GRID, RUN_SETTINGS, 300.0, workers=2, work_dir=tmp_path)
    assert more.resumed > 0
    _same(straight, more.to_xarray())


def test_run_study_needs_its_sampling_interval():
    with pytest.raises(ValueError, match="sample_every"):
        run_study("run", RUN_GRID, {}, 10.0)
    with pytest.raises(ValueError, match="sample_every"):
        run_study("run", RUN_GRID, {"sample_every": 0.001}, 10.0)    # below dt


# ---- calls cut short ---------------------------------------------------------------------------

@pytest.mark.parametrize("kind, grid, settings, t_end", [
    ("blowup", GRID, {}, 400.0),
    ("run", RUN_GRID, RUN_SETTINGS, 300.0),
    ("chaos", {"N": [4, 8], "tau": [20.0], "seed": [1, 2, 3]}, {"samples_per_decade": 10},
     500.0),
], ids=["blowup", "run", "chaos"])
def test_calls_cut_short_report_more_often_with_the_same_numbers(kind, grid, settings, t_end):
    whole = run_study(kind, grid, settings, t_end, workers=2, max_call_seconds=None)
    cut = run_study(kind, grid, settings, t_end, workers=2, max_call_seconds=1e-4)
    assert cut.calls > 2 * whole.calls
    a, b = whole.to_xarray(), cut.to_xarray()
    _same(a, b, skip=("t_reached",) if kind == "chaos" else ())
    # the engine's own t_reached of an orbit decided early (chaotic) is the end of the call it
    # was decided in: the one number that depends on the cuts
    going = ~a["finished"].values
    assert np.array_equal(a["t_reached"].values[going], b["t_reached"].values[going])


def test_max_call_seconds_is_checked():
    with pytest.raises(ValueError, match="max_call_seconds"):
        run_study("blowup", GRID, {}, 10.0, max_call_seconds=0)
    with pytest.raises(ValueError, match="max_call_seconds"):
        run_study("blowup", GRID, {}, 10.0, max_call_seconds="soon")


def test_recurrence_is_the_run_kind_reduced_to_shares():
    """The recurrence kind is a specialisation of the run kind: its shares are the run's
    E_1..E_4 over the sum of all E_k, and the committed recurrence studies keep their key."""
    from pathlib import Path

    from fputlab.engine import load_study
    grid = {"N": [16], "tau": [0.0, 50.0], "seed": [3]}
    settings = {"sample_every": 5.0, "dt": 0.05, "method": "yoshida4"}
    rec = run_study("recurrence", grid, settings, 300.0, workers=1).to_xarray()
    run = run_study("run", grid, settings, 300.0, workers=1).to_xarray()
    E = run["E"].values
    np.testing.assert_array_equal(rec["share"].values, E[..., :4] / E.sum(-1, keepdims=True))
    np.testing.assert_array_equal(rec["blew_up"].values, run["blew_up"].values)
    studies = Path(__file__).resolve().parents[2] / "studies" / "open_questions"
    for d in sorted(studies.glob("recurrence_*")):
        assert load_study(d).to_xarray().attrs["kind"] == "recurrence"   # the key still matches


def test_an_orbit_saved_alone_continues_in_lanes_bit_for_bit():
    """Chunks change between calls (an orbit decided early leaves its chunk; calls cut short
    at max_call_seconds): an orbit advanced alone (fpl_chaos) and then in the lanes of the
    batched kernel, or the other way round, gives the numbers of the lanes all the way."""
    from fputlab.chaos.ensemble import CHAOS_KIND
    grid, s = CHAOS_KIND.normalise({"N": [4], "tau": [20.0], "seed": [1, 2, 3, 4]},
                                   {"samples_per_decade": 10, "stop_when_chaotic": False})
    coords = [{"N": 4, "tau": 20.0, "seed": seed} for seed in grid["seed"]]
    straight = CHAOS_KIND.run(s, coords, [None] * 4, 400.0)
    first = CHAOS_KIND.run(s, coords[:3], [None] * 3, 100.0) + \
        CHAOS_KIND.run(s, coords[3:], [None], 100.0)           # the last one alone
    assert np.ndim(first[3]["state"]["y"]) != np.ndim(first[0]["state"]["y"])
    more = CHAOS_KIND.run(s, coords, first, 400.0)
    alone = CHAOS_KIND.run(s, coords[:1], first[:1], 400.0)     # saved in lanes, then alone
    for a, b in zip(straight + straight[:1], more + alone):
        for name, v in a["values"].items():
            x, y = np.asarray(v), np.asarray(b["values"][name])
            assert np.array_equal(x, y, equal_nan=x.dtype.kind == "f"), name
