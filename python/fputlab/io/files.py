"""Results files and checkpoints: writing a results file as a run goes (`ResultsFile`, the C
writer `fpl_results`), atomic checkpoints of a run (`write_checkpoint`, `load_checkpoint`),
the checks that keep a resume from destroying data, and reading a results file back (`load`).
The schema is in docs/hdf5.md."""
from __future__ import annotations

import os
import signal
import stat
import time
from dataclasses import dataclass

import numpy as np

from .. import _lowlevel as ll
from .._errors import check, last_error
from .._validate import _path
from ..integrate import method_info
from ..lattice import MODELS, Lattice

__all__ = ["load", "Results", "ResultsFile", "write_checkpoint", "load_checkpoint",
           "checkpoint_time", "STATUSES", "VERIFY_TIMEOUT"]

#: how a run ended, as written to the file's `status` attribute
STATUSES = ("running", "completed", "event", "failed", "interrupted")


def _RunInfo(lattice: Lattice, kind: str, method: str, dt: float, rtol: float, atol: float,
             t0: float, n_dev: int, store_states: bool = False,
             chunk_rows: int = 0) -> ll.RunInfo:
    """The run description a results file and a checkpoint carry (fpl_run_info)."""
    # as the checkpoint records them: the options the method actually uses, NaN for the others
    adaptive = method_info(method)["adaptive"]
    nan = float("nan")
    # a homogeneous chain has no disorder: no tau, seed or kind in its files (NaN, -1 and ""
    # are "not written")
    ordered = lattice.model == "homogeneous"
    return ll.RunInfo(
        kind=kind, method=method, dt=nan if adaptive else dt,
        rtol=rtol if adaptive else nan, atol=atol if adaptive else nan, t0=t0, n_dev=n_dev,
        tau=nan if ordered or lattice.tau is None else lattice.tau,
        seed=-1 if ordered or lattice.seed is None else int(lattice.seed),
        disorder="" if ordered else (lattice.disorder if lattice.tau is not None else "user"),
        store_states=int(bool(store_states)), chunk_rows=chunk_rows)


class ResultsFile:
    """A results file being written (C `fpl_results`); use as a context manager.

    Parameters
    ----------
    path : str or path-like
        The HDF5 file: created, or with `resume_from` reopened.
    lattice : Lattice
        The lattice of the run (its parameters and v go into the file).
    info : fputlab._lowlevel.RunInfo
        The run description (kind, method, options) written as attributes.
    resume_from : str or path-like, optional
        A checkpoint written with this results file: the file is cut back to it and the rows
        then pending are restored.

    Raises
    ------
    OSError
        The file cannot be created, or does not match the checkpoint.
    ValueError
        Invalid run description.
    """

    def __init__(self, path, lattice: Lattice, info: ll.RunInfo, *, resume_from=None):
        self.path, self.lattice, self._info = _path(path, "path"), lattice, info
        self._h = ll.ResultsHandle(self.path, lattice._h, info, resume_from)

    @property
    def count(self) -> int:
        return self._h.count()

    def append(self, t: float, y: np.ndarray) -> None:
        self._h.append(float(t), y)

    def append_chaos(self, t: float, mle: float, sali: float, gali: float) -> None:
        self._h.append_chaos(float(t), mle, sali, gali)

    def set_status(self, status: str, message: str = "") -> None:
        self._h.set_status(status, message)

    def set_event(self, t: float, criterion: str) -> None:
        self._h.set_event(float(t), criterion)

    def flush(self) -> None:
        self._h.flush()

    def close(self) -> None:
        self._h.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def write_checkpoint(path, integ_handle: ll.IntegratorHandle, info: ll.RunInfo, extra=(),
                     results: ResultsFile | None = None) -> None:
    """Write a checkpoint of an integrator, atomically (a temporary file, then a rename).

    Parameters
    ----------
    path : str or path-like
        The checkpoint file.
    integ_handle : fputlab._lowlevel.IntegratorHandle
        The integrator: step count, time and state (with deviation vectors) are saved.
    info : fputlab._lowlevel.RunInfo
        The run description a later `load_checkpoint` checks against.
    extra : array_like, optional
        Further values to keep (accumulators, the run's sampling).
    results : ResultsFile, optional
        The results file being written: where it stands (rows on disk and pending) is saved.

    Raises
    ------
    OSError
        The checkpoint cannot be written.
    """
    ll.checkpoint_write(_path(path, "path"), integ_handle, info, np.ascontiguousarray(extra, dtype=np.float64),
                        results._h if results is not None else None)


def load_checkpoint(path, integ_handle: ll.IntegratorHandle, info: ll.RunInfo,
                    max_extra: int = 0) -> np.ndarray:
    """Check a checkpoint against the run and restore the integrator from it (the file is only
    read).

    Parameters
    ----------
    path : str or path-like
        The checkpoint file.
    integ_handle : fputlab._lowlevel.IntegratorHandle
        The integrator to restore (same lattice, method, options and t0 as when it was written).
    info : fputlab._lowlevel.RunInfo
        The run description the checkpoint must match.
    max_extra : int, optional
        Most extra values to read back.

    Returns
    -------
    numpy.ndarray
        The extra values written with the checkpoint.

    Raises
    ------
    ValueError
        The checkpoint belongs to another run (the message says what differs).
    OSError
        The checkpoint is unreadable or corrupt.
    """
    return ll.checkpoint_load(_path(path, "path"), integ_handle, info, max_extra)


def checkpoint_time(path) -> tuple[float, int]:
    """The time and step count stored in a checkpoint.

    Parameters
    ----------
    path : str or path-like
        The checkpoint file.

    Returns
    -------
    t : float
        The time the checkpoint was written at.
    steps : int
        The integrator's step count then.

    Raises
    ------
    OSError
        The checkpoint is unreadable or corrupt.
    """
    return ll.checkpoint_peek(_path(path, "path"))


def _same_file(a, b) -> bool:
    """True if two paths name the same file (also through symlinks, hard links, '..')."""
    if os.path.realpath(a) == os.path.realpath(b):
        return True
    try:
        return os.path.samefile(a, b)
    except OSError:
        return False


def _describe_existing(path) -> str:
    """What an existing file is, in a few words (for refusals)."""
    try:
        size = os.path.getsize(path)
    except OSError:
        return "unreadable"
    try:
        import h5py
        with h5py.File(path, "r") as f:
            attrs = f.attrs
            schema = _attr(attrs.get("schema", ""))
            if not str(schema).startswith("fputlab-results/"):
                return f"{size} bytes, not an fputlab results file"
            status = _attr(attrs.get("status", "?"))
            n = f["t"].shape[0] if "t" in f else 0
            t_last = float(f["t"][n - 1]) if n else 0.0
            return (f"an fputlab {_attr(attrs.get('kind', ''))} results file, status {status!r}, "
                    f"{n} samples up to t = {t_last:.10g}")
    except Exception:           # noqa: BLE001 - a description only; the refusal is what matters
        return f"{size} bytes, not a readable HDF5 file"


def _regular_or_absent(path: str, name: str) -> None:
    """An output is a regular file or nothing yet: a device, FIFO or socket (/dev/null, a
    pipe) cannot hold an HDF5 file, and writing to one fails late or blocks."""
    try:
        mode = os.stat(path).st_mode
    except OSError:
        return
    if not stat.S_ISREG(mode) and not stat.S_ISDIR(mode):
        raise ValueError(f"{name}: {path!r} is not a regular file (a device, FIFO or socket "
                         "cannot hold an HDF5 file)")


def _check_output_paths(out, checkpoint, resume: bool, overwrite: bool) -> bool:
    """Refuse output paths that would destroy data, before anything is written. Returns whether
    the run resumes from `checkpoint`."""
    out = _path(out, "out")
    if os.path.isdir(out):
        raise ValueError(f"out: {out!r} is a directory, not a results file")
    _regular_or_absent(out, "out")
    if checkpoint is not None:
        checkpoint = _path(checkpoint, "checkpoint")
        _regular_or_absent(checkpoint, "checkpoint")
        if _same_file(out, checkpoint):
            raise ValueError(f"checkpoint: {checkpoint!r} is the results file itself (out); "
                             "give the checkpoint its own name")
        if os.path.isdir(checkpoint):
            raise ValueError(f"checkpoint: {checkpoint!r} is a directory")
    resuming = checkpoint is not None and resume and os.path.exists(checkpoint)
    if not resuming and os.path.exists(out) and not overwrite:
        if checkpoint is None:
            how = "give the checkpoint it was written with to continue it"
        elif not resume:
            how = "restarting from t = 0 replaces it"
        elif os.path.islink(checkpoint):
            how = (f"its checkpoint {checkpoint!r} is a symbolic link to the missing "
                   f"{os.path.realpath(checkpoint)!r}, so it cannot be continued")
        else:
            how = f"its checkpoint {checkpoint!r} does not exist, so it cannot be continued"
        raise FileExistsError(f"out: {out!r} exists ({_describe_existing(out)}); {how}. Not "
                              "overwritten: pass overwrite=True (command line: --overwrite) to "
                              "replace it, or choose another file")
    return resuming


#: seconds a child process gets to read a results file and its checkpoint back before a resume
VERIFY_TIMEOUT = 120.0


def _verify_resume(out, lattice: Lattice, info: _RunInfo, checkpoint) -> None:
    """fpl_results_verify (reads back everything a resume keeps) in a child process, so that a
    damaged file that crashes or hangs libhdf5 costs the child, not this process: a crash or a
    hang becomes an OSError naming the files. Then the resume itself (same reads) is safe."""
    if not hasattr(os, "fork"):
        check(ll.results_verify(out, lattice._h, info, checkpoint))
        return
    import select
    rfd, wfd = os.pipe()
    pid = os.fork()
    if pid == 0:                                     # child: C only, then _exit
        try:
            os.close(rfd)
            import faulthandler
            faulthandler.disable()                   # a crash here is reported by the parent
            signal.signal(signal.SIGINT, signal.SIG_DFL)
            signal.signal(signal.SIGTERM, signal.SIG_DFL)
            st = ll.results_verify(out, lattice._h, info, checkpoint)
            msg = last_error() if st < 0 else ""
            os.write(wfd, f"{st}\n{msg}".encode()[:60000])
        finally:
            os._exit(0)
    os.close(wfd)
    chunks, deadline = [], time.monotonic() + VERIFY_TIMEOUT
    try:
        while True:
            left = deadline - time.monotonic()
            if left <= 0:
                os.kill(pid, signal.SIGKILL)
                os.waitpid(pid, 0)
                pid = 0
                raise OSError(f"checking {os.fspath(out)!r} against its checkpoint "
                              f"{os.fspath(checkpoint)!r} did not finish in {VERIFY_TIMEOUT:g} s "
                              "(a damaged file can make libhdf5 loop); nothing was changed")
            ready, _, _ = select.select([rfd], [], [], min(left, 0.5))
            if ready:
                b = os.read(rfd, 65536)
                if not b:
                    break
                chunks.append(b)
        _, wstatus = os.waitpid(pid, 0)
        pid = 0
    finally:
        os.close(rfd)
        if pid:                                      # interrupted while waiting
            os.kill(pid, signal.SIGKILL)
            os.waitpid(pid, 0)
    if os.WIFSIGNALED(wstatus):
        name = signal.Signals(os.WTERMSIG(wstatus)).name
        raise OSError(f"{os.fspath(out)!r} or its checkpoint {os.fspath(checkpoint)!r} is corrupt: "
                      f"reading them crashed libhdf5 ({name}, in a child process); nothing was "
                      "changed")
    text = b"".join(chunks).decode(errors="replace")
    head, _, msg = text.partition("\n")
    try:
        st = int(head)
    except ValueError:
        raise OSError(f"checking {os.fspath(out)!r} for a resume failed without a status "
                      "(child process)") from None
    if st < 0:
        if st in ll.ARG_ERRORS:
            raise ValueError(msg)
        raise OSError(msg)


# ---- reading ---------------------------------------------------------------------------------
def _attr_text(value) -> str:
    """An HDF5 attribute for a repr: bytes decoded, numbers short, strings quoted."""
    from .._display import fmt
    if isinstance(value, bytes):
        value = value.decode("utf-8", "replace")
    if isinstance(value, np.ndarray) and value.size == 1:
        value = value.item()
    return repr(value) if isinstance(value, str) else fmt(value)


@dataclass(repr=False)
class Results:
    """Contents of a results file as numpy arrays (`attrs`: the run description)."""
    attrs: dict
    v: np.ndarray
    t: np.ndarray
    energy: np.ndarray
    mode_energies: np.ndarray
    states: np.ndarray | None = None
    chaos: dict | None = None           # {'t', 'mle', 'sali', 'gali'}
    path: str = ""

    @property
    def status(self) -> str:
        return self.attrs.get("status", "")

    def __repr__(self) -> str:
        # one line, like Run: the file, the lattice, the time span and the shapes, never the
        # arrays themselves (v alone has N numbers)
        from .._display import fmt, join_parts, time_span
        a = self.attrs
        parts = [repr(self.path)] if self.path else []
        parts.append(f"N={self.v.size}")
        model = a.get("model")
        names = {code: name for name, code in MODELS.items()}
        if isinstance(model, (int, np.integer)) and int(model) in names:
            model = names[int(model)]
        if model is not None:
            parts.append(f"model={_attr_text(model)}")
        parts += [f"{k}={_attr_text(a[k])}" for k in ("tau", "seed", "method", "dt")
                  if k in a and _attr_text(a[k]) not in ("''", "-1")]
        if self.status:
            parts.append(f"status={self.status!r}")
        parts.append(time_span(self.t))
        parts.append("mode_energies[" + "x".join(map(str, self.mode_energies.shape)) + "]")
        if self.states is not None:
            parts.append("states[" + "x".join(map(str, self.states.shape)) + "]")
        if self.chaos:
            n = np.size(self.chaos.get("t", ()))
            last = {k: self.chaos[k][-1] for k in ("mle", "sali") if np.size(self.chaos.get(k, ()))}
            parts.append(f"chaos: {n} samples" + "".join(f", {k}={fmt(v)}" for k, v in last.items()))
        return join_parts("Results", parts)

    def to_xarray(self):
        """The results as an xarray Dataset (needs xarray)."""
        import xarray as xr
        data = {"energy": ("t", self.energy), "mode_energies": (("t", "mode"), self.mode_energies),
                "v": ("site", self.v)}
        coords = {"t": self.t, "mode": np.arange(1, self.mode_energies.shape[1] + 1),
                  "site": np.arange(1, self.v.size + 1)}
        if self.states is not None:
            data["states"] = (("t", "component"), self.states)
        if self.chaos is not None:
            coords["t_chaos"] = self.chaos["t"]
            for k in ("mle", "sali", "gali"):
                data[k] = ("t_chaos", self.chaos[k])
        return xr.Dataset(data, coords=coords, attrs=self.attrs)


def _attr(v, name: str = "attribute", path: str = ""):
    if isinstance(v, (bytes, np.bytes_)):
        try:
            return bytes(v).decode()
        except UnicodeDecodeError:
            raise ValueError(f"{path}: attribute {name!r} is not valid UTF-8 text (corrupt file?)") \
                from None
    if isinstance(v, np.generic):
        return v.item()
    return v


def _dataset(f, name: str, path: str, ndim: int, cols: int | None = None, rows: int | None = None,
             required: bool = True):
    """A float dataset read whole, with its shape checked; None if absent and not required."""
    if name not in f:
        if required:
            raise ValueError(f"{path}: dataset {name!r} is missing (incomplete or damaged results "
                             "file)")
        return None
    d = f[name]
    import h5py
    if not isinstance(d, h5py.Dataset) or d.dtype.kind not in "fiu" or d.ndim != ndim or (
            cols is not None and d.shape[1] != cols) or (rows is not None and d.shape[0] != rows):
        want = f"{ndim}-D" + (f" with {cols} columns" if cols is not None else "") + (
            f" and {rows} rows" if rows is not None else "")
        got = f"shape {getattr(d, 'shape', None)}, dtype {getattr(d, 'dtype', None)}"
        raise ValueError(f"{path}: dataset {name!r} has {got}, expected a numeric {want} dataset")
    return np.asarray(d[()], dtype=np.float64)


def load(path, *, as_xarray: bool = False):
    """Read a results file written by fputlab (C writer, `simulate_to_file`, `chaos_to_file`,
    the command line).

    Parameters
    ----------
    path : str or path-like
        The results file.
    as_xarray : bool, optional
        Return an ``xarray.Dataset`` instead (needs xarray).

    Returns
    -------
    Results or xarray.Dataset
        The samples as numpy arrays, with the run description in ``attrs``.

    Raises
    ------
    FileNotFoundError
        No such file.
    ValueError
        Not an fputlab results file, a dataset missing or of the wrong shape (the message names
        the file and what is wrong).
    OSError
        Not a readable HDF5 file, or damaged data (checksums).
    """
    import h5py
    path = _path(path, "path")
    if not os.path.exists(path):
        raise FileNotFoundError(f"path: no such file {path!r}")
    if not stat.S_ISREG(os.stat(path).st_mode):   # a FIFO would block h5py's open for ever
        raise ValueError(f"path: {path!r} is not a regular file (an HDF5 file is one)")
    try:
        f = h5py.File(path, "r")
    except OSError as err:
        raise OSError(f"{path} is not a readable HDF5 file (damaged or another format): {err}") \
            from None
    try:
        with f:
            attrs = {k: _attr(v, k, path) for k, v in f.attrs.items()}
            if not str(attrs.get("schema", "")).startswith("fputlab-results/"):
                raise ValueError(f"{path} is not an fputlab results file "
                                 f"(schema {attrs.get('schema')!r})")
            v = _dataset(f, "v", path, 1)
            if attrs.get("kind") == "chaos" and "t" not in f:
                # a chaos file keeps every sample in /chaos: no empty orbit series at the root
                t, energy, mode_energies = np.empty(0), np.empty(0), np.empty((0, v.size))
            else:
                t = _dataset(f, "t", path, 1)
                energy = _dataset(f, "energy", path, 1, rows=t.size)
                mode_energies = _dataset(f, "mode_energies", path, 2, cols=v.size, rows=t.size)
            states = _dataset(f, "states", path, 2, rows=t.size, required=False)
            if states is not None and states.shape[1] % (2 * v.size):
                raise ValueError(f"{path}: dataset 'states' has {states.shape[1]} columns, not a "
                                 f"multiple of 2N = {2 * v.size}")
            chaos = None
            if "chaos" in f:
                tc = _dataset(f, "chaos/t", path, 1)
                chaos = {"t": tc, **{k: _dataset(f, f"chaos/{k}", path, 1, rows=tc.size)
                                     for k in ("mle", "sali", "gali")}}
    except UnicodeDecodeError as err:
        raise ValueError(f"{path}: a text attribute is not valid UTF-8 (corrupt file?): {err}") \
            from None
    except (OSError, RuntimeError, KeyError) as err:     # h5py: checksum, decompression, ...
        raise OSError(f"{path} is damaged: reading it failed ({err})") from None
    res = Results(attrs=attrs, v=v, t=t, energy=energy, mode_energies=mode_energies,
                  states=states, chaos=chaos, path=path)
    return res.to_xarray() if as_xarray else res
