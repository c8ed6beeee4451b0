"""Runs that last: HDF5 results written incrementally by the C core, atomic checkpoints, restart.

    >>> lat = fputlab.Lattice(64, 0.25, "nonlinear", tau=10, seed=1)
    >>> fputlab.io.simulate_to_file(lat, 1e6, "run.h5", checkpoint="run.ckpt")   # kill it ...
    >>> fputlab.io.simulate_to_file(lat, 1e6, "run.h5", checkpoint="run.ckpt")   # ... it goes on
    >>> res = fputlab.load("run.h5"); res.t, res.mode_energies

The results file never holds more than one chunk of samples in memory and only ever receives
whole new chunks (data on disk is never rewritten, so a kill cannot damage what a checkpoint
covers); a checkpoint (step count, time, state with deviation vectors, chaos accumulators, the
results rows on disk and those pending) is written every
`checkpoint_every_steps` steps or `checkpoint_every_seconds` seconds, atomically, and on
SIGINT/SIGTERM before stopping. Restarting from it continues bit for bit (fixed-step methods):
the final files equal those of an uninterrupted run. The schema is in docs/hdf5.md."""
from __future__ import annotations

import math
import os
import signal
import threading
import time
from dataclasses import dataclass, field

import numpy as np

from ._arrays import as_float_array, ptr
from ._errors import FputlabError, check, last_error
from ._native import ffi, lib
from .integrate import Integrator, method_info
from .lattice import C_LONG, C_U64, Lattice, _int, _real

#: how a run ended, as written to the file's `status` attribute
STATUSES = ("running", "completed", "event", "failed", "interrupted")


class _RunInfo:
    """fpl_run_info with the C strings it points to kept alive."""

    def __init__(self, lattice: Lattice, kind: str, method: str, dt: float, rtol: float,
                 atol: float, t0: float, n_dev: int, store_states: bool = False,
                 chunk_rows: int = 0):
        self._keep = []
        self.c = ffi.new("fpl_run_info *")
        lib.fpl_run_info_init(self.c)
        self.c.kind = self._str(kind)
        self.c.method = self._str(method)
        # as the checkpoint records them: the options the method actually uses, NaN for the others
        adaptive = method_info(method)["adaptive"]
        nan = float("nan")
        self.c.dt = nan if adaptive else dt
        self.c.rtol, self.c.atol = (rtol, atol) if adaptive else (nan, nan)
        self.c.t0 = t0
        self.c.n_dev = n_dev
        self.c.tau = float("nan") if lattice.tau is None else lattice.tau
        self.c.seed = -1 if lattice.seed is None else int(lattice.seed)
        self.c.disorder = self._str(lattice.disorder or ("user" if lattice.tau is None and
                                                         lattice.model != "homogeneous" else ""))
        self.c.store_states = int(bool(store_states))
        self.c.chunk_rows = chunk_rows

    def _str(self, s: str):
        b = ffi.new("char[]", s.encode())
        self._keep.append(b)
        return b


class ResultsFile:
    """A results file being written (C `fpl_results`); use as a context manager."""

    def __init__(self, path, lattice: Lattice, info: _RunInfo, *, resume_from=None):
        """Create the file, or with resume_from (a checkpoint written with this results file)
        reopen it cut back to the checkpoint, the rows then pending restored."""
        self.path, self.lattice, self._info = os.fspath(path), lattice, info
        out = ffi.new("fpl_results **")
        if resume_from is None:
            check(lib.fpl_results_create(self.path.encode(), lattice._h, info.c, out))
        else:
            check(lib.fpl_results_resume(self.path.encode(), lattice._h, info.c,
                                         os.fspath(resume_from).encode(), out))
        self._h = out[0]

    def _check(self, status):
        return check(status)

    @property
    def count(self) -> int:
        return int(lib.fpl_results_count(self._h))

    def append(self, t: float, y: np.ndarray) -> None:
        self._check(lib.fpl_results_append(self._h, float(t), ptr(y)))

    def append_chaos(self, t: float, mle: float, sali: float, gali: float) -> None:
        self._check(lib.fpl_results_append_chaos(self._h, float(t), mle, sali, gali))

    def set_status(self, status: str, message: str = "") -> None:
        self._check(lib.fpl_results_set_status(self._h, status.encode(), message.encode()))

    def set_event(self, t: float, criterion: str) -> None:
        self._check(lib.fpl_results_set_event(self._h, float(t), criterion.encode()))

    def flush(self) -> None:
        self._check(lib.fpl_results_flush(self._h))

    def close(self) -> None:
        if self._h is not None:
            h = ffi.new("fpl_results **", self._h)
            self._h = None
            check(lib.fpl_results_close(h))

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def write_checkpoint(path, integ_handle, info: _RunInfo, extra=(),
                     results: ResultsFile | None = None) -> None:
    """Write a checkpoint of the C integrator `integ_handle` (and of where `results` stands)
    atomically."""
    ex = np.ascontiguousarray(extra, dtype=np.float64)
    check(lib.fpl_checkpoint_write(os.fspath(path).encode(), integ_handle, info.c,
                                   ptr(ex) if ex.size else ffi.NULL, ex.size,
                                   results._h if results is not None else ffi.NULL))


def load_checkpoint(path, integ_handle, info: _RunInfo, max_extra: int = 0) -> np.ndarray:
    """Validate the checkpoint against the run and restore the integrator; returns the
    accumulators. Mismatch -> ValueError, unreadable/corrupt -> OSError; the file is only read."""
    ex = np.empty(max(max_extra, 1))
    n = ffi.new("int *")
    check(lib.fpl_checkpoint_load(os.fspath(path).encode(), integ_handle, info.c, ptr(ex),
                                  max_extra, n))
    return ex[:n[0]].copy()


def checkpoint_time(path) -> tuple[float, int]:
    """(t, step count) stored in a checkpoint."""
    t, n = ffi.new("double *"), ffi.new("long *")
    check(lib.fpl_checkpoint_peek(os.fspath(path).encode(), t, n))
    return t[0], int(n[0])


class _Stopper:
    """SIGINT/SIGTERM set a flag; the run writes a checkpoint and stops at the next segment."""

    def __init__(self):
        self.signum = None
        self._old = {}

    def __enter__(self):
        if threading.current_thread() is threading.main_thread():
            for s in (signal.SIGINT, signal.SIGTERM):
                self._old[s] = signal.signal(s, self._handle)
        return self

    def _handle(self, signum, frame):
        self.signum = signum

    def __exit__(self, *exc):
        for s, h in self._old.items():
            signal.signal(s, h)


class _Cadence:
    """When the next checkpoint is due: every `steps` integrator steps and/or `seconds`."""

    def __init__(self, path, steps: int | None, seconds: float | None, steps_now: int):
        self.path, self.steps, self.seconds = path, steps, seconds
        self.mark(steps_now)

    def mark(self, steps_now: int) -> None:
        self.last_steps, self.last_time = steps_now, time.monotonic()

    def due(self, steps_now: int) -> bool:
        return self.path is not None and bool(
            (self.steps and steps_now - self.last_steps >= self.steps) or
            (self.seconds and time.monotonic() - self.last_time >= self.seconds))


@dataclass
class RunSummary:
    """How a file-backed run ended."""
    status: str                 # completed, event, failed, interrupted
    t_reached: float
    samples: int
    resumed_from: float | None  # checkpoint time the run continued from (None: fresh start)
    checkpoints: int            # checkpoints written by this call
    message: str = ""
    event: dict | None = None
    path: str = ""
    extra: dict = field(default_factory=dict)

    @property
    def interrupted(self) -> bool:
        return self.status == "interrupted"


def _check_every(steps, seconds):
    if steps is not None:
        steps = _int(steps, "checkpoint_every_steps", C_LONG)
        if steps < 1:
            raise ValueError(f"checkpoint_every_steps must be >= 1 (got {steps})")
    if seconds is not None:
        seconds = _real(seconds, "checkpoint_every_seconds")
        if not (seconds > 0):
            raise ValueError(f"checkpoint_every_seconds must be > 0 (got {seconds:g})")
    return steps, seconds


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


def _check_output_paths(out, checkpoint, resume: bool, overwrite: bool) -> bool:
    """Refuse output paths that would destroy data, before anything is written. Returns whether
    the run resumes from `checkpoint`."""
    out = os.fspath(out)
    if not out:
        raise ValueError("out: empty file name")
    if os.path.isdir(out):
        raise ValueError(f"out: {out!r} is a directory, not a results file")
    if checkpoint is not None:
        checkpoint = os.fspath(checkpoint)
        if not checkpoint:
            raise ValueError("checkpoint: empty file name")
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
    out_b, ck_b = os.fspath(out).encode(), os.fspath(checkpoint).encode()
    if not hasattr(os, "fork"):
        check(lib.fpl_results_verify(out_b, lattice._h, info.c, ck_b))
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
            st = lib.fpl_results_verify(out_b, lattice._h, info.c, ck_b)
            msg = ffi.string(lib.fpl_last_error()).decode(errors="replace") if st < 0 else ""
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
        if st in (lib.FPL_ERR_ARG, lib.FPL_ERR_UNKNOWN):
            raise ValueError(msg)
        raise OSError(msg)


def _progress(total, desc, enabled, initial=0.0):
    if not enabled:
        return None
    from tqdm.auto import tqdm
    return tqdm(total=total, initial=initial, desc=desc, unit="t", disable=None,
                bar_format="{l_bar}{bar}| {n:.4g}/{total:.4g} [{elapsed}<{remaining}]")


def simulate_to_file(lattice: Lattice, t_end: float, out, *, method: str = "yoshida4",
                     dt: float | None = None, rtol: float = 1e-10, atol: float = 1e-12,
                     sample_every: float | None = None, y0=None, deviations=None,
                     store_states: bool = False, stop_on=None, checkpoint=None,
                     checkpoint_every_steps: int | None = None,
                     checkpoint_every_seconds: float | None = 600.0, resume: bool = True,
                     chunk_rows: int = 256, progress: bool = False,
                     max_steps_per_segment: int = 100_000, overwrite: bool = False,
                     compensated_sums: bool = False) -> RunSummary:
    """Integrate from t = 0 to t_end, writing samples (t, mode energies, energy, optionally the
    states) to the HDF5 file `out` as the run goes.

    With `checkpoint` (a path), a checkpoint is written every `checkpoint_every_steps` steps
    and/or `checkpoint_every_seconds` seconds, at the end, and on SIGINT/SIGTERM (then the run
    stops with status "interrupted"). If the checkpoint exists and `resume`, the run continues
    from it (after checking it belongs to this lattice, method and options) and `out` is
    truncated to the checkpoint's time. A resume keeps the checkpoint's sample spacing (a
    different `sample_every` is refused) and runs to the new `t_end`: a finished run can be
    extended. stop_on: stopping criteria as in fputlab.integrate.

    An existing `out` is never replaced unless `overwrite` (or continued from its checkpoint);
    `out` and `checkpoint` must be different files. `compensated_sums` (SPRKStep methods
    "sprk-*" only) is kept in the checkpoint with the summation's carry, so that a restart
    continues bit for bit; a resume must give the same value."""
    if not isinstance(lattice, Lattice):
        raise TypeError(f"lattice must be a fputlab.Lattice, got {type(lattice).__name__}")
    t_end = _real(t_end, "t_end")
    if not (math.isfinite(t_end) and t_end > 0):
        raise ValueError(f"t_end must be finite and > 0 (got {t_end:g})")
    adaptive = method_info(method)["adaptive"]
    from .integrate import _compensated_sums
    _compensated_sums(compensated_sums, method)
    if dt is None and not adaptive:
        dt = 0.01
    every = t_end / 1000 if sample_every is None else _real(sample_every, "sample_every")
    if sample_every is None and not adaptive:
        every = max(every, _real(dt, "dt"))    # never below what a fixed step can resolve
    if not (math.isfinite(every) and every > 0):
        raise ValueError(f"sample_every must be finite and > 0 (got {every:g})")
    if not adaptive:
        from .integrate import check_steps
        check_steps(t_end, _real(dt, "dt"), "t_end", t_end)
    if not adaptive and every < _real(dt, "dt") * (1 - 1e-9):
        raise ValueError(f"dt = {dt:g} is larger than the sample spacing {every:g}: a fixed-step "
                         "method only reaches multiples of dt (use a smaller dt or sample less "
                         "often)")
    k_steps, k_seconds = _check_every(checkpoint_every_steps, checkpoint_every_seconds)
    max_steps_per_segment = _int(max_steps_per_segment, "max_steps_per_segment", C_LONG)
    if max_steps_per_segment < 1:
        raise ValueError(f"max_steps_per_segment must be >= 1 (got {max_steps_per_segment})")
    chunk_rows = _int(chunk_rows, "chunk_rows")
    if not 1 <= chunk_rows <= 2**31 - 1:
        raise ValueError(f"chunk_rows must be in [1, 2**31) (got {chunk_rows})")
    resuming = _check_output_paths(out, checkpoint, resume, overwrite)
    N = lattice.N
    orbit = lattice.mode_state() if y0 is None else as_float_array(y0, "y0", (2 * N,))
    state0 = orbit[None, :] if deviations is None else np.concatenate(
        [orbit[None, :], as_float_array(deviations, "deviations", last=2 * N).reshape(-1, 2 * N)])

    from .blowup import set_criteria
    set_criteria(lattice, stop_on)
    try:
        integ = Integrator(lattice, state0, method=method, dt=dt, rtol=rtol, atol=atol,
                           compensated_sums=compensated_sums)
        info = _RunInfo(lattice, "simulate", method, integ.dt, rtol, atol, 0.0, integ.n_dev,
                        store_states, chunk_rows)
        resumed = None
        if resuming:
            # the checkpoint's own sampling (its extras: sample spacing, final time) decides
            # how the run continues; everything is checked before the results file is touched
            settings = load_checkpoint(checkpoint, integ._h, info, 2)
            if settings.size == 2:
                ck_every = float(settings[0])
                if sample_every is not None and every != ck_every:
                    raise ValueError(f"sample_every: the checkpoint's run samples every "
                                     f"{ck_every:.17g}, this run asks for {every:.17g}; the file "
                                     "cannot mix two sample grids (refused, nothing changed)")
                every = ck_every
            if t_end < integ.t:
                raise ValueError(f"t_end = {t_end:.17g} is before the checkpoint's time "
                                 f"t = {integ.t:.17g}: nothing to continue (refused, nothing "
                                 "changed)")
            resumed = integ.t
            _verify_resume(out, lattice, info, checkpoint)
            results = ResultsFile(out, lattice, info, resume_from=checkpoint)
        else:
            results = ResultsFile(out, lattice, info)
        settings = np.array([every, t_end])
        n_samples = int(math.floor(t_end / every * (1 + 1e-12))) + 1
        sample_t = lambda i: min(i * every, t_end)
        seg = math.inf if adaptive else max_steps_per_segment * dt
        summary = RunSummary("completed", integ.t, 0, resumed, 0, path=os.fspath(out))
        with results, _Stopper() as stopper:
            bar = _progress(t_end, f"simulate N={N}", progress, integ.t)
            cadence = _Cadence(checkpoint, k_steps, k_seconds, integ.steps)

            def save():
                write_checkpoint(checkpoint, integ._h, info, settings, results=results)
                summary.checkpoints += 1
                cadence.mark(integ.steps)

            i = results.count
            try:
                while i < n_samples:
                    target = sample_t(i)
                    # long gaps between samples go in segments (checkpoints, signals, progress);
                    # fixed-step grid states do not depend on where a run pauses
                    while target - integ.t > seg and stopper.signum is None:
                        integ.advance(integ.t + seg)
                        if bar is not None:
                            bar.update(integ.t - bar.n)
                        if cadence.due(integ.steps):
                            save()
                    if stopper.signum is not None:
                        break
                    y = integ.advance(target)
                    ev = integ.event
                    results.append(ev["time"] if ev else target, y)
                    i += 1
                    if ev:
                        summary.status, summary.event = "event", ev
                        summary.message = f"{ev['criterion']} at t = {ev['time']:.10g}"
                        results.set_event(ev["time"], ev["criterion"])
                        break
                    if bar is not None:
                        bar.update(integ.t - bar.n)
                    if cadence.due(integ.steps):
                        save()
            except FputlabError as err:   # blow-up without an event, back-end failure
                summary.status, summary.message = "failed", str(err)
            finally:
                if bar is not None:
                    bar.close()
            if stopper.signum is not None and summary.status == "completed":
                summary.status = "interrupted"
                summary.message = f"stopped by {signal.Signals(stopper.signum).name} at t = {integ.t:.10g}"
            if checkpoint is not None and summary.status in ("completed", "interrupted"):
                save()
            summary.t_reached = integ.t if summary.status != "event" else summary.event["time"]
            summary.samples = results.count
            results.set_status(summary.status, summary.message)
        return summary
    finally:
        if stop_on:
            set_criteria(lattice, None)


def chaos_to_file(lattice: Lattice, t_end: float, out, *, method: str = "yoshida4",
                  dt: float | None = None, rtol: float = 1e-10, atol: float = 1e-12, y0=None,
                  n_dev: int = 2, renorm_interval: float = 1.0, n_samples: int = 200,
                  sali_threshold: float = 1e-8, stop_when_chaotic: bool = False, seed: int = 1,
                  checkpoint=None, checkpoint_every_steps: int | None = None,
                  checkpoint_every_seconds: float | None = 600.0, resume: bool = True,
                  progress: bool = False, segment: float | None = None,
                  overwrite: bool = False) -> RunSummary:
    """mLE, SALI and GALI (fputlab.chaos.lyapunov) written to /chaos of the HDF5 file `out` as
    the run goes, with checkpoints of the orbit, the deviation vectors and the accumulated
    log-norms; restart continues bit for bit (fixed-step methods). A resume must use the
    checkpoint's t_end, n_samples, renorm_interval, sali_threshold and stop_when_chaotic (they
    fix the sample times and the classification); others are refused before anything changes.
    An existing `out` is never replaced unless `overwrite` (or continued from its checkpoint)."""
    if not isinstance(lattice, Lattice):
        raise TypeError(f"lattice must be a fputlab.Lattice, got {type(lattice).__name__}")
    t_end = _real(t_end, "t_end")
    if not (math.isfinite(t_end) and t_end > 0):
        raise ValueError(f"t_end must be finite and > 0 (got {t_end:g})")
    k_steps, k_seconds = _check_every(checkpoint_every_steps, checkpoint_every_seconds)
    if segment is not None:
        segment = _real(segment, "segment")
        if not (math.isfinite(segment) and segment > 0):
            raise ValueError(f"segment must be finite and > 0 (got {segment:g})")
    resuming = _check_output_paths(out, checkpoint, resume, overwrite)
    adaptive = method_info(method)["adaptive"]
    if dt is None and not adaptive:
        dt = 0.01
    N = lattice.N
    orbit = lattice.mode_state() if y0 is None else as_float_array(y0, "y0", (2 * N,))
    iopt = ffi.new("fpl_integrator_options *")
    lib.fpl_integrator_options_init(iopt)
    iopt.dt = 0.0 if dt is None else _real(dt, "dt")
    iopt.rtol, iopt.atol = _real(rtol, "rtol"), _real(atol, "atol")
    copt = ffi.new("fpl_chaos_options *")
    lib.fpl_chaos_options_init(copt)
    copt.t_end, copt.renorm_interval = t_end, _real(renorm_interval, "renorm_interval")
    copt.n_samples, copt.n_dev = _int(n_samples, "n_samples"), _int(n_dev, "n_dev")
    copt.sali_threshold = _real(sali_threshold, "sali_threshold")
    copt.stop_when_chaotic, copt.seed = int(bool(stop_when_chaotic)), _int(seed, "seed", C_U64)
    out_h = ffi.new("fpl_chaos **")
    check(lib.fpl_chaos_create(lattice._h, method.encode(), iopt, 0.0, ptr(orbit), ffi.NULL, copt,
                               out_h))
    c = ffi.gc(out_h[0], lambda h: lib.fpl_chaos_free(ffi.new("fpl_chaos **", h)))
    ih = lib.fpl_chaos_integrator(c)
    info = _RunInfo(lattice, "chaos", method, iopt.dt, iopt.rtol, iopt.atol, 0.0, copt.n_dev)
    n_acc = lib.FPL_CHAOS_N_ACCUMULATORS
    # what fixes the sample times and the classification: a resume must agree on all of it
    settings = {"t_end": t_end, "n_samples": copt.n_samples,
                "renorm_interval": copt.renorm_interval, "sali_threshold": copt.sali_threshold,
                "stop_when_chaotic": float(copt.stop_when_chaotic)}
    resumed = None
    if resuming:
        acc = load_checkpoint(checkpoint, ih, info, n_acc + len(settings))
        if acc.size == n_acc + len(settings):
            for (name, want), have in zip(settings.items(), acc[n_acc:]):
                if have != want:
                    raise ValueError(f"{name}: the checkpoint's run has {name} = {have:.17g}, "
                                     f"this run {want:.17g}; a chaos run cannot change it when "
                                     "resuming (it fixes the sample times; refused, nothing "
                                     "changed)")
        check(lib.fpl_chaos_restore(c, ptr(np.ascontiguousarray(acc[:n_acc]))))
        resumed = lib.fpl_integrator_time(ih)
        _verify_resume(out, lattice, info, checkpoint)
        results = ResultsFile(out, lattice, info, resume_from=checkpoint)
    else:
        results = ResultsFile(out, lattice, info)
    arrays = [np.full(copt.n_samples, np.nan) for _ in range(4)]
    res = ffi.new("fpl_chaos_result *")
    seg = segment if segment is not None else (
        renorm_interval * max(1, round(1e5 * (dt or 0.01) / renorm_interval)))
    summary = RunSummary("completed", lib.fpl_integrator_time(ih), 0, resumed, 0, path=os.fspath(out))
    steps = ffi.new("long *")
    with results, _Stopper() as stopper:
        bar = _progress(t_end, f"chaos N={N}", progress, summary.t_reached)
        lib.fpl_integrator_counters(ih, steps, ffi.NULL)
        cadence = _Cadence(checkpoint, k_steps, k_seconds, steps[0])

        def save():
            acc = np.empty(n_acc)
            check(lib.fpl_chaos_save(c, ptr(acc)))
            write_checkpoint(checkpoint, ih, info, np.concatenate([acc, list(settings.values())]),
                             results)
            summary.checkpoints += 1
            cadence.mark(steps[0])

        try:
            check(lib.fpl_chaos_get_result(c, res))
            while not lib.fpl_chaos_done(c) and stopper.signum is None:
                before = res.n_samples
                t_now = lib.fpl_integrator_time(ih)
                if check(lib.fpl_chaos_advance(c, t_now + seg, *(ptr(a) for a in arrays))) > 0:
                    summary.message = last_error()      # a blow-up: when and why
                check(lib.fpl_chaos_get_result(c, res))
                for j in range(before, res.n_samples):
                    results.append_chaos(*(a[j] for a in arrays))
                if bar is not None:
                    bar.update(res.t_final - bar.n)
                lib.fpl_integrator_counters(ih, steps, ffi.NULL)
                if cadence.due(steps[0]):
                    save()
        except FputlabError as err:
            summary.status, summary.message = "failed", str(err)
        finally:
            if bar is not None:
                bar.close()
        if stopper.signum is not None and not lib.fpl_chaos_done(c) and summary.status == "completed":
            summary.status = "interrupted"
            summary.message = f"stopped by {signal.Signals(stopper.signum).name}"
        if checkpoint is not None and summary.status in ("completed", "interrupted"):
            save()
        check(lib.fpl_chaos_get_result(c, res))
        summary.t_reached, summary.samples = res.t_final, res.n_samples
        summary.extra = {"mle": res.mle, "sali": res.sali, "gali": res.gali,
                         "chaotic": bool(res.chaotic), "t_chaotic": res.t_chaotic,
                         "blew_up": bool(res.blew_up), "t_blowup": res.t_blowup}

        results.set_status(summary.status, summary.message)
    return summary


# ---- reading ---------------------------------------------------------------------------------
@dataclass
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
    """Read a results file written by fputlab (C writer or CLI). Returns `Results` (numpy
    arrays), or an xarray Dataset with as_xarray=True.

    A file that is not an fputlab results file, lacks a dataset, has one of the wrong shape or
    holds damaged data (checksums) raises ValueError or OSError naming the file and what is wrong."""
    import h5py
    path = os.fspath(path)
    if not os.path.exists(path):
        raise FileNotFoundError(f"path: no such file {path!r}")
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
