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


#: seconds to reach a Dask scheduler before giving up (an unreachable address must not hang)
CONNECT_TIMEOUT = 20.0


class SchedulerLost(RuntimeError):
    """The Dask scheduler went away during a run (what finished is kept by the caller)."""


def _dask_client(scheduler, timeout: float | None = None):
    """(client, owned): a Client for an address, a Client as given, or one for a Cluster. An
    address that does not answer within `timeout` seconds (default `CONNECT_TIMEOUT`) raises
    OSError naming it."""
    from dask.distributed import Client
    timeout = CONNECT_TIMEOUT if timeout is None else timeout
    if isinstance(scheduler, Client):
        return scheduler, False
    if isinstance(scheduler, str) or hasattr(scheduler, "scheduler_address"):
        address = scheduler if isinstance(scheduler, str) else scheduler.scheduler_address
        try:
            return Client(scheduler, timeout=timeout), True
        except (OSError, TimeoutError) as err:
            raise OSError(f"cannot reach the Dask scheduler at {address} within {timeout:g} s "
                          f"({type(err).__name__}: {' '.join(str(err).split())[:200]})") from None
    raise ValueError(f"scheduler must be an address 'tcp://host:port', a dask.distributed.Client "
                     f"or a cluster (got {type(scheduler).__name__})")


def total_threads(workers=None, scheduler=None) -> int:
    """The threads that run tasks: the local pool's processes (`workers`, default all cores),
    or the sum of the Dask workers' threads (`client.scheduler_info()`), at least 1. Task sizes
    follow it, not the client's core count: 60 orbits on a 100-node cluster are 60 tasks, not 4."""
    if scheduler is None:
        return max(1, int(workers or os.cpu_count() or 1))
    client, owned = _dask_client(scheduler)
    try:
        info = client.scheduler_info()
        return max(1, sum(int(w.get("nthreads", 1)) for w in info.get("workers", {}).values()))
    finally:
        if owned:
            client.close()


def chunks(items: list, threads: int, minimum: int = 1) -> list[list]:
    """`items` cut into consecutive pieces, one per thread (so every thread has work), each of at
    least `minimum` items (a batched kernel gains nothing below its lane count): the one
    chunking rule of every ensemble."""
    if not items:
        return []
    per = max(int(minimum), -(-len(items) // max(1, int(threads))))
    return [items[i:i + per] for i in range(0, len(items), per)]


def run_calls(fn, calls, *, workers=None, scheduler=None, keys=None, window: int | None = None,
              pool=None):
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
        Run on Dask instead: an address "tcp://host:port", a Client, or a cluster object. An
        address that does not answer within `CONNECT_TIMEOUT` raises OSError naming it.
    keys : list of str, optional
        Dask task keys, one per call (default: random keys).
    window : int, optional
        At most this many calls submitted and not yet finished (default: twice the threads):
        the client holds a bounded number of futures, whatever the number of calls.
    pool : process_pool, optional
        A pool to reuse (it stays open; the caller closes it); default: one for this call.

    Yields
    ------
    tuple
        ``(call, result, error)``: exactly one of `result` and `error` (the exception the call
        raised) is None.

    Raises
    ------
    SchedulerLost
        The Dask scheduler went away during the run (the calls yielded so far are complete).

    Examples
    --------
    >>> from operator import add
    >>> sorted(r for _, r, _ in run_calls(add, [(1, 2), (3, 4)], workers=2))  # doctest: +SKIP
    [3, 7]
    """
    calls = list(calls)
    if scheduler is None:
        owned = pool is None
        pool = process_pool(workers) if owned else pool
        limit = window or 2 * max(1, int(workers or os.cpu_count() or 1))
        try:
            pending, it = {}, iter(enumerate(calls))
            for i, c in it:
                pending[pool.submit(fn, *c)] = c
                if len(pending) >= limit:
                    break
            while pending:
                done = next(as_completed(pending))
                c = pending.pop(done)
                err = done.exception()
                yield c, (None if err else done.result()), err
                for i, nc in it:
                    pending[pool.submit(fn, *nc)] = nc
                    break
        except BaseException:                 # Ctrl-C, or the caller stopped: workers go now
            pool.terminate()
            raise
        if owned:
            pool.shutdown(wait=True)
        return
    from dask.distributed import as_completed as dask_as_completed
    client, owned = _dask_client(scheduler)
    try:
        threads = max(1, sum(int(w.get("nthreads", 1))
                             for w in client.scheduler_info().get("workers", {}).values()))
        limit = window or 2 * threads

        def submit(i):
            kw = {"key": keys[i]} if keys is not None else {"pure": False}
            return client.submit(fn, *calls[i], **kw)
        futs, nxt = {}, 0
        while nxt < len(calls) and len(futs) < limit:
            futs[submit(nxt)] = calls[nxt]
            nxt += 1
        ac = dask_as_completed(list(futs))
        for fut in ac:
            c = futs.pop(fut)
            try:
                result, err = fut.result(), None
            except Exception as exc:          # the call's own exception, or the cluster's
                result, err = None, exc
                if _scheduler_gone(client, exc):
                    raise SchedulerLost(
                        f"lost the Dask scheduler {client.scheduler.address} during the run "
                        f"({type(exc).__name__}); what finished is kept: rerun to continue"
                    ) from None
            finally:
                fut.release()
            yield c, result, err
            if nxt < len(calls):
                f = submit(nxt)
                futs[f] = calls[nxt]
                ac.add(f)
                nxt += 1
    finally:
        if owned:
            try:
                client.close(timeout=5)
            except Exception:                 # noqa: BLE001 - a dead scheduler cannot be closed
                pass


def _scheduler_gone(client, exc) -> bool:
    """Whether a failed future means the scheduler is gone, not the task's own error: Dask
    cancels every future it holds when it loses the scheduler (a lost worker's tasks are
    rescheduled, not cancelled), and no fputlab task cancels itself."""
    from concurrent.futures import CancelledError
    return isinstance(exc, CancelledError) or type(exc).__name__ in (
        "FutureCancelledError", "CancelledError", "CommClosedError")
