"""The ensemble engine: independent calls fn(*args) on a local process pool whose workers die
with their parent, or on a Dask cluster, yielded as they complete (`run_calls`). Every sweep of
fputlab runs on it: `fputlab.blowup.blowup_sweep`, `fputlab.chaos.chaotic_fraction`,
`fputlab.ensemble.run_sweep` and `fputlab.chaos.study`. It knows nothing of lattices or
integrators, so the analysis modules may use it."""
from __future__ import annotations

import math
import os
from concurrent.futures import ProcessPoolExecutor, as_completed

import numpy as np

from ._validate import _int


def check_ensemble(taus, Ns, realisations) -> tuple[list[float], list[int], int]:
    """The taus, Ns and realisations of an ensemble, checked (an empty ensemble would give NaN
    fractions without a word).

    Parameters
    ----------
    taus : float or sequence of float
        Variabilities in percent (finite, >= 0, at least one).
    Ns : int or sequence of int
        Lattice sizes (>= 2, at least one).
    realisations : int
        Realisations per (tau, N) (>= 1).

    Returns
    -------
    tuple
        ``(taus, Ns, realisations)`` as a list of float, a list of int and an int.

    Raises
    ------
    ValueError
        An empty or invalid value; the message names the parameter.
    """
    taus = [float(t) for t in np.atleast_1d(np.asarray(taus, dtype=float))]
    if not taus or not all(math.isfinite(t) and t >= 0 for t in taus):
        raise ValueError(f"taus must be a non-empty list of finite values >= 0 (got {taus})")
    Ns = [_int(n, "Ns") for n in np.atleast_1d(Ns).tolist()]
    if not Ns or min(Ns) < 2:
        raise ValueError(f"Ns must be a non-empty list of sizes >= 2 (got {Ns})")
    realisations = _int(realisations, "realisations")
    if realisations < 1:
        raise ValueError(f"realisations must be >= 1 (got {realisations})")
    return taus, Ns, realisations


def _die_with_parent(parent_pid: int) -> None:
    """Pool worker initializer: the worker gets SIGKILL when its parent dies, whatever killed it
    (SIGKILL included), instead of living on and holding pipes such as `| tee` open. Linux:
    prctl(PR_SET_PDEATHSIG); elsewhere a thread watching the parent."""
    import signal
    # Ctrl-C in the terminal reaches the whole process group: the parent handles it (and stops
    # the workers); a worker interrupted on its own would only print a traceback
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        import ctypes
        libc = ctypes.CDLL(None, use_errno=True)
        PR_SET_PDEATHSIG = 1
        if libc.prctl(PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0) != 0:
            raise OSError(ctypes.get_errno(), "prctl")
    except (OSError, AttributeError):
        import threading
        import time

        def watch():
            while os.getppid() == parent_pid:
                time.sleep(0.5)
            os._exit(1)
        threading.Thread(target=watch, daemon=True, name="fputlab-parent-watch").start()
    if os.getppid() != parent_pid:         # the parent died before prctl took effect
        os._exit(1)


class _Pool(ProcessPoolExecutor):
    """ProcessPoolExecutor that, left by an exception (Ctrl-C included), kills its workers
    instead of waiting for the tasks they are running."""

    def terminate(self) -> None:
        for proc in list((getattr(self, "_processes", None) or {}).values()):
            try:
                proc.kill()
            except (OSError, AttributeError):
                pass
        self.shutdown(wait=False, cancel_futures=True)

    def __exit__(self, exc_type, exc, tb):
        if exc_type is not None:
            self.terminate()
        return super().__exit__(exc_type, exc, tb)


def process_pool(workers: int | None = None) -> ProcessPoolExecutor:
    """A process pool whose workers die with this process and are stopped at once when the pool
    is left by an exception (Ctrl-C).

    Parameters
    ----------
    workers : int, optional
        Worker processes (>= 1; default: all cores).

    Returns
    -------
    concurrent.futures.ProcessPoolExecutor
        Use it as a context manager.

    Raises
    ------
    ValueError
        `workers` < 1.
    """
    if workers is not None:
        workers = _int(workers, "workers")
        if workers < 1:
            raise ValueError(f"workers must be >= 1 (got {workers})")
    return _Pool(max_workers=workers, initializer=_die_with_parent, initargs=(os.getpid(),))


def _dask_client(scheduler):
    """(client, owned): a Client for an address, a Client as given, or one for a Cluster."""
    from dask.distributed import Client
    if isinstance(scheduler, Client):
        return scheduler, False
    if isinstance(scheduler, str):
        return Client(scheduler), True
    if hasattr(scheduler, "scheduler_address"):          # a LocalCluster, SLURMCluster, ...
        return Client(scheduler), True
    raise ValueError(f"scheduler must be an address 'tcp://host:port', a dask.distributed.Client "
                     f"or a cluster (got {type(scheduler).__name__})")


def run_calls(fn, calls, *, workers=None, scheduler=None, keys=None):
    """The ensemble engine: ``fn(*call)`` for every call, on a local process pool or a Dask
    cluster, yielded in completion order. Every sweep of fputlab runs on it.

    Parameters
    ----------
    fn : callable
        A picklable (module-level) function.
    calls : iterable of tuple
        The positional arguments of each call (picklable).
    workers : int, optional
        Local worker processes (default: all cores); ignored with `scheduler`.
    scheduler : str, dask.distributed.Client or cluster, optional
        Run on Dask instead: an address "tcp://host:port", a Client, or a cluster object.
    keys : list of str, optional
        Dask task keys, one per call (default: random keys).

    Yields
    ------
    tuple
        ``(call, result, error)``: exactly one of `result` and `error` (the exception the call
        raised) is None.

    Examples
    --------
    >>> from operator import add
    >>> sorted(r for _, r, _ in run_calls(add, [(1, 2), (3, 4)], workers=2))  # doctest: +SKIP
    [3, 7]
    """
    calls = list(calls)
    if scheduler is None:
        pool = process_pool(workers)
        try:
            futs = {pool.submit(fn, *c): c for c in calls}
            for fut in as_completed(futs):
                err = fut.exception()
                yield futs[fut], (None if err else fut.result()), err
        except BaseException:                 # Ctrl-C, or the caller stopped: workers go now
            pool.terminate()
            raise
        pool.shutdown(wait=True)
        return
    from dask.distributed import as_completed as dask_as_completed
    client, owned = _dask_client(scheduler)
    try:
        futs = {}
        for i, c in enumerate(calls):
            kw = {"key": keys[i]} if keys is not None else {"pure": False}
            futs[client.submit(fn, *c, **kw)] = c
        for fut in dask_as_completed(list(futs)):
            try:
                yield futs[fut], fut.result(), None
            except Exception as err:          # the call's own exception, re-raised by Dask
                yield futs[fut], None, err
            finally:
                fut.release()
    finally:
        if owned:
            client.close()
