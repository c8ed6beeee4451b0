"""Ensembles (fputlab.ensemble): the local pool and a Dask cluster give the same results task by
task, sweeps resume from their work directory, and the merged file holds what blowup_time and
lyapunov compute when called directly."""
import math
import os

import h5py
import numpy as np
import pytest

import fputlab
from fputlab.blowup import blowup_time, realisation_tau_c
from fputlab.chaos import lyapunov
from fputlab.ensemble import COLUMNS, SERIES, load_sweep, run_sweep

# tau = 50 % makes some of the tiny lattices blow up before t = 500, tau = 10 % none
BLOWUP = dict(kind="blowup", tau=[10.0, 50.0], Ns=[8, 16], realisations=3, t_end=500.0)
CHAOS = dict(kind="chaos", tau=[10.0], Ns=[8], realisations=2, t_end=300.0, n_samples=30)


def _sweep(tmp_path, name, spec, **kw):
    return run_sweep(spec["kind"], spec["tau"], spec["Ns"], spec["realisations"],
                     t_end=spec["t_end"], work_dir=tmp_path / f"{name}.d",
                     out=tmp_path / f"{name}.h5", progress=False,
                     **{k: v for k, v in spec.items()
                        if k not in ("kind", "tau", "Ns", "realisations", "t_end")}, **kw)


def _assert_same(a: dict, b: dict, ignore_attrs=()):
    assert sorted(a) == sorted(b)
    for k in a:
        if k == "attrs":
            for name in set(a[k]) | set(b[k]):
                if name in ignore_attrs:
                    continue
                x, y = a[k][name], b[k][name]
                assert np.array_equal(np.asarray(x), np.asarray(y)), name
        elif a[k].dtype.kind in "fc":
            np.testing.assert_array_equal(a[k], b[k], err_msg=k)    # NaN == NaN here
        else:
            assert np.array_equal(a[k], b[k]), k


@pytest.fixture(scope="module")
def dask_cluster():
    distributed = pytest.importorskip("dask.distributed")
    try:
        cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                           dashboard_address=None)
    except Exception:          # e.g. process spawning not possible here: threads still test Dask
        cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                                           dashboard_address=None)
    client = distributed.Client(cluster)
    yield cluster, client
    client.close()
    cluster.close()


@pytest.mark.parametrize("spec", [BLOWUP, CHAOS], ids=["blowup", "chaos"])
def test_local_pool_equals_dask(tmp_path, dask_cluster, spec):
    cluster, client = dask_cluster
    local = _sweep(tmp_path, "local", spec, workers=2)
    # a Client for the blow-up sweep, the scheduler's tcp:// address for the chaos sweep
    sched = client if spec["kind"] == "blowup" else cluster.scheduler_address
    remote = _sweep(tmp_path, "dask", spec, scheduler=sched)
    n = len(spec["tau"]) * len(spec["Ns"]) * spec["realisations"]
    assert local["n_tasks"] == remote["n_tasks"] == n
    assert local["computed"] == remote["computed"] == n and not local["failed"] and not remote["failed"]
    for r1, r2 in zip(local["records"], remote["records"]):     # task by task
        assert r1.keys() == r2.keys()
        for k in r1:
            if isinstance(r1[k], np.ndarray):
                np.testing.assert_array_equal(r1[k], r2[k])
            elif isinstance(r1[k], float) and math.isnan(r1[k]):
                assert math.isnan(r2[k])
            else:
                assert r1[k] == r2[k], k
    _assert_same(load_sweep(tmp_path / "local.h5"), load_sweep(tmp_path / "dask.h5"))
    if spec["kind"] == "blowup":   # the chosen parameters give both outcomes
        assert 0 < sum(r["blew_up"] for r in local["records"]) < n


def test_resume_recomputes_only_missing_tasks(tmp_path):
    first = _sweep(tmp_path, "s", BLOWUP, workers=2)
    work = tmp_path / "s.d"
    files = sorted((work / "tasks").glob("*.h5"))         # the study engine's task files
    assert len(files) == first["n_tasks"] == 12 and first["skipped"] == 0
    merged1 = load_sweep(tmp_path / "s.h5")
    victim = files[5]
    victim.unlink()
    mtimes = {p: p.stat().st_mtime_ns for p in files if p != victim}
    second = _sweep(tmp_path, "s", BLOWUP, workers=2)
    assert (second["computed"], second["skipped"]) == (1, 11)
    assert victim.exists()
    assert all(p.stat().st_mtime_ns == m for p, m in mtimes.items())   # the others untouched
    _assert_same(merged1, load_sweep(tmp_path / "s.h5"), ignore_attrs=())
    # a file that does not read back (truncated) is reported, never silently recomputed over
    victim.write_bytes(b"not hdf5")
    with pytest.raises(ValueError, match="unreadable task result"):
        _sweep(tmp_path, "s", BLOWUP, workers=1)
    victim.unlink()
    third = _sweep(tmp_path, "s", BLOWUP, workers=1)
    assert (third["computed"], third["skipped"]) == (1, 11)
    _assert_same(merged1, load_sweep(tmp_path / "s.h5"))
    assert not [p for p in work.rglob("*") if ".tmp" in p.name]   # no temporaries left behind
    # another sweep in the same directory is refused (a new work_dir, or overwrite=True)
    with pytest.raises(ValueError, match="another study"):
        run_sweep("blowup", [10.0], [8], 1, t_end=200.0, work_dir=work,
                  out=tmp_path / "o.h5", progress=False)
    other = run_sweep("blowup", [10.0], [8], 1, t_end=200.0, work_dir=tmp_path / "o.d",
                      out=tmp_path / "o.h5", progress=False)
    assert other["skipped"] == 0 and other["computed"] == 1


def test_a_larger_t_end_continues_the_sweep(tmp_path):
    """A sweep run to t1 and then to t2 holds the blow-up times of one run straight to t2, bit
    for bit (yoshida4: fixed step), and the unfinished runs continue from their saved state."""
    spec = dict(BLOWUP, t_end=200.0)
    short = _sweep(tmp_path, "g", spec, workers=2)
    longer = _sweep(tmp_path, "g", BLOWUP, workers=2)
    straight = _sweep(tmp_path, "h", BLOWUP, workers=2)
    assert longer["skipped"] == sum(r["blew_up"] for r in short["records"])
    assert longer["study"].resumed == 12 - longer["skipped"]
    _assert_same(load_sweep(tmp_path / "g.h5"), load_sweep(tmp_path / "h.h5"))


def test_a_work_dir_of_the_old_run_sweep_is_refused(tmp_path):
    work = tmp_path / "old.d"
    work.mkdir()
    old = work / "blowup_N64_tau10.0_seed1_0123456789.h5"
    old.write_bytes(b"a task of run_sweep before the study engine")
    with pytest.raises(ValueError, match="older run_sweep.*blowup_N64_tau10.0_seed1_"):
        run_sweep("blowup", [10.0], [8], 1, t_end=10.0, work_dir=work, out=tmp_path / "o.h5",
                  progress=False)
    assert old.read_bytes() == b"a task of run_sweep before the study engine"
    assert sorted(p.name for p in work.iterdir()) == [old.name]     # nothing added
    assert not (tmp_path / "o.h5").exists()


def test_merged_blowup_matches_direct_call(tmp_path):
    _sweep(tmp_path, "b", BLOWUP, workers=2)
    m = load_sweep(tmp_path / "b.h5")
    assert m["attrs"]["fputlab_version"] == fputlab.__version__
    assert m["attrs"]["kind"] == "blowup" and m["attrs"]["realisations"] == 3
    np.testing.assert_array_equal(m["attrs"]["tau"], [10.0, 50.0])
    assert m["attrs"]["model"] == "nonlinear" and m["attrs"]["alpha"] == 0.25
    assert list(m["kind"]) == ["blowup"] * 12
    assert set(COLUMNS["blowup"]) <= set(m)
    # rows in the order tau, N, seed
    assert list(m["tau"][:6]) == [10.0] * 6 and list(m["N"][:3]) == [8] * 3
    assert list(m["seed"][:3]) == [1, 2, 3]
    i = int(np.flatnonzero(m["blew_up"])[0])
    N, tau, seed = int(m["N"][i]), float(m["tau"][i]), int(m["seed"][i])
    ref = blowup_time(fputlab.Lattice(N, 0.25, "nonlinear", tau=tau, seed=seed), 500.0)
    assert ref.blew_up
    assert m["time"][i] == ref.time and m["t_reached"][i] == ref.t_reached
    assert m["criterion"][i] == ref.criterion
    assert m["tau_c"][i] == realisation_tau_c(N, seed, 0.25)
    j = int(np.flatnonzero(~m["blew_up"])[0])
    assert np.isnan(m["time"][j]) and m["t_reached"][j] == 500.0 and m["criterion"][j] == ""


def test_merged_chaos_matches_direct_call(tmp_path):
    _sweep(tmp_path, "c", CHAOS, workers=2)
    m = load_sweep(tmp_path / "c.h5")
    assert set(COLUMNS["chaos"]) | set(SERIES["chaos"]) <= set(m)
    assert m["mle_t"].shape == m["sali_t"].shape == m["t"].shape and m["t"].shape[0] == 2
    i = 1
    # chaos sweeps default to the validated fast scheme with early stop (fputlab.chaos)
    from fputlab.chaos import ENSEMBLE_DT, ENSEMBLE_METHOD
    ref = lyapunov(fputlab.Lattice(8, 0.25, "nonlinear", tau=10.0, seed=int(m["seed"][i])),
                   300.0, n_samples=30, method=ENSEMBLE_METHOD, dt=ENSEMBLE_DT,
                   stop_when_chaotic=True)
    k = int(m["n_samples"][i])
    assert k == ref.t.size
    np.testing.assert_array_equal(m["t"][i, :k], ref.t)
    np.testing.assert_array_equal(m["mle_t"][i, :k], ref.mle)
    np.testing.assert_array_equal(m["sali_t"][i, :k], ref.sali)
    assert np.all(np.isnan(m["mle_t"][i, k:]))
    assert m["mle"][i] == ref.mle_final and m["sali"][i] == ref.sali[-1]
    assert m["classification"][i] == ref.classify() and m["t_final"][i] == ref.t_final
    with h5py.File(tmp_path / "c.h5") as f:
        assert f.attrs["task_options"] == '{"dt": 0.5, "n_samples": 30, "stop_when_chaotic": true}'


@pytest.mark.parametrize("change, name", [
    (dict(tau=[]), "tau"),
    (dict(Ns=[]), "Ns"),
    (dict(Ns=[1]), "Ns"),
    (dict(realisations=0), "realisations"),
    (dict(kind="lyapunov"), "kind"),
    (dict(t_end=0.0), "t_end"),
    (dict(t_end=-5.0), "t_end"),
    (dict(t_end=float("inf")), "t_end"),
    (dict(tau=[-1.0]), "tau"),
    (dict(model="quadratic"), "model"),
    (dict(workers=0), "workers"),
    (dict(n_samplez=5), "n_samplez"),
    (dict(method="euler"), "euler"),
])
def test_bad_input_names_the_parameter(tmp_path, change, name):
    args = dict(kind="blowup", tau=[10.0], Ns=[8], realisations=1, t_end=100.0,
                work_dir=tmp_path / "w", out=tmp_path / "o.h5")
    args.update(change)
    kind, taus, Ns, R = (args.pop(k) for k in ("kind", "tau", "Ns", "realisations"))
    with pytest.raises(ValueError, match=name):
        run_sweep(kind, taus, Ns, R, **args)
    assert not os.path.exists(tmp_path / "o.h5")


@pytest.mark.parametrize("engine", ["local", "dask"])
def test_failed_tasks_are_reported_and_retried(tmp_path, dask_cluster, engine):
    """Without a stopping criterion two of these lattices overflow (IntegrationError in
    blowup_time): the sweep goes on, reports them, writes no file for them, and retries them."""
    kw = dict(workers=2) if engine == "local" else dict(scheduler=dask_cluster[1])
    args = ("blowup", [50.0], [16], 3)
    opts = dict(t_end=500.0, work_dir=tmp_path / "w", out=tmp_path / "f.h5", progress=False,
                criteria=[])
    out = run_sweep(*args, **opts, **kw)
    assert out["computed"] == 1 and [f.task.seed for f in out["failed"]] == [1, 3]
    assert all(f.message.startswith("IntegrationError: state became non-finite")
               for f in out["failed"])
    # nothing finished is stored of the failed tasks (at most a good piece before the failure)
    reached = out["study"].to_xarray()["t_reached"].values.ravel()
    assert reached[1] == 500.0 and np.all(np.nan_to_num(reached[[0, 2]]) < 500.0)
    m = load_sweep(tmp_path / "f.h5")
    assert list(m["seed"]) == [2] and m["attrs"]["n_failed"] == 2 and m["attrs"]["n_tasks"] == 3
    again = run_sweep(*args, **opts, **kw)
    assert again["skipped"] == 1 and len(again["failed"]) == 2


def test_the_command_line_refuses_an_old_work_dir_in_one_line(tmp_path, capsys):
    from fputlab.cli import main
    work = tmp_path / "s.h5.tasks"
    work.mkdir()
    (work / "blowup_N8_tau10.0_seed1_0123456789.h5").write_bytes(b"old")
    assert main(["sweep", "--out", str(tmp_path / "s.h5"), "--tau", "10", "--N", "8",
                 "--realisations", "1", "--t-end", "5", "--workers", "1", "--json"]) == 2
    err = capsys.readouterr().err.strip()
    assert "older run_sweep" in err and "\n" not in err and "Traceback" not in err
    assert not (tmp_path / "s.h5").exists()
