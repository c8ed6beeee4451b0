"""A real Dask cluster on 127.0.0.1 (a `dask scheduler` and two `dask worker` processes): a
study survives a killed worker (complete, unduplicated, identical to the process-pool run), a
lost scheduler raises a clear error and leaves a store that a rerun completes, and an
unreachable scheduler fails within the connect timeout, naming the address."""
import contextlib
import os
import shutil
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("dask.distributed")
xr = pytest.importorskip("xarray")

from fputlab import _engine, chaos  # noqa: E402

DASK = Path(sys.executable).with_name("dask")
STUDY = dict(Ns=(4, 8, 16), realisations=4, tau=20.0, t_end=3e4, samples_per_decade=10)


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _same(a, b):
    assert a.sizes == b.sizes
    for v in a.data_vars:
        x, y = a[v].values, b[v].values
        assert (np.array_equal(x, y, equal_nan=True) if x.dtype.kind == "f"
                else np.array_equal(x, y)), v


@pytest.fixture
def cluster(tmp_path):
    if not DASK.exists() and shutil.which("dask") is None:
        pytest.skip("the dask command is not installed")
    exe = str(DASK) if DASK.exists() else shutil.which("dask")
    address = f"tcp://127.0.0.1:{_free_port()}"
    env = {**os.environ, "DASK_DISTRIBUTED__WORKER__DAEMON": "False"}
    quiet = dict(stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env, cwd=tmp_path)
    procs = {"scheduler": subprocess.Popen(
        [exe, "scheduler", "--host", "127.0.0.1", "--port", address.rsplit(":", 1)[1],
         "--no-dashboard"], **quiet)}
    for i in range(2):
        procs[f"worker{i}"] = subprocess.Popen(
            [exe, "worker", address, "--nthreads", "1", "--no-nanny", "--no-dashboard",
             "--memory-limit", "0", "--name", f"w{i}"], **quiet)
    from dask.distributed import Client
    try:
        with Client(address, timeout=30) as c:
            c.wait_for_workers(2, timeout=30)
        yield address, procs
    finally:
        for p in procs.values():
            if p.poll() is None:
                p.kill()
            p.wait()


@contextlib.contextmanager
def _kill_on_first_report(proc, tasks_dir):
    """SIGKILL `proc` as soon as the study's first task file appears (mid-run, whatever the
    machine's speed), from a thread watching `tasks_dir` while the body runs."""
    done = threading.Event()

    def watch():
        while not done.is_set() and proc.poll() is None:
            if tasks_dir.is_dir() and any(tasks_dir.iterdir()):
                proc.send_signal(signal.SIGKILL)
                return
            time.sleep(0.005)

    killer = threading.Thread(target=watch, daemon=True)
    killer.start()
    try:
        yield
    finally:
        done.set()
        killer.join()


def test_a_killed_worker_changes_nothing_a_lost_scheduler_leaves_a_resumable_store(cluster,
                                                                                    tmp_path):
    address, procs = cluster
    local = chaos.chaotic_fraction(workers=2, **STUDY).to_xarray()
    # the cluster's threads size the tasks: 2 threads, not this machine's cores
    assert _engine.total_threads(scheduler=address) == 2

    # the worker dies as soon as the first group of orbits has reported (a fixed delay raced
    # the run on a quiet machine): the others are still running or waiting then
    with _kill_on_first_report(procs["worker1"], tmp_path / "a" / "tasks"):
        out = chaos.chaotic_fraction(scheduler=address, work_dir=tmp_path / "a", **STUDY)
    assert procs["worker1"].poll() is not None          # killed during the run, not after
    tasks = sorted(os.listdir(tmp_path / "a" / "tasks"))
    assert len(tasks) == len(set(tasks)) == 12 and out.computed == 12
    _same(local, out.to_xarray())

    # the scheduler goes away mid-run: a clear error, and the store continues locally
    with _kill_on_first_report(procs["scheduler"], tmp_path / "b" / "tasks"):
        with pytest.raises((_engine.SchedulerLost, OSError), match="scheduler"):
            chaos.chaotic_fraction(scheduler=address, work_dir=tmp_path / "b", **STUDY)
    resumed = chaos.chaotic_fraction(workers=2, work_dir=tmp_path / "b", **STUDY)
    _same(local, resumed.to_xarray())


def test_an_unreachable_scheduler_fails_in_time_naming_the_address(monkeypatch):
    monkeypatch.setattr(_engine, "CONNECT_TIMEOUT", 2.0)
    address = f"tcp://127.0.0.1:{_free_port()}"
    started = time.monotonic()
    with pytest.raises(OSError, match=f"cannot reach the Dask scheduler at {address}"):
        chaos.chaotic_fraction(Ns=(4,), realisations=2, t_end=10.0, scheduler=address)
    assert time.monotonic() - started < 15
