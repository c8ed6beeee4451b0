"""The checkpointed-run driver: one loop, shared by `simulate_to_file` and `chaos_to_file`,
that advances a run piece by piece, writes its results file as it goes, checkpoints it on a
cadence (steps and/or seconds), at the end and on SIGINT/SIGTERM, and records how it ended.
A run restarted from its checkpoint continues bit for bit (fixed-step methods)."""
from __future__ import annotations

import math
import os
import signal
import threading
import time
from dataclasses import dataclass, field

import numpy as np

from .. import _lowlevel as ll
from .._arrays import as_float_array
from .._errors import FputlabError, last_error
from .._validate import C_LONG, _int, _path, _positive_real, _real, _seed
from ..integrate import Integrator, _compensated_sums, check_steps, method_info
from ..lattice import Lattice
from .files import (ResultsFile, _check_output_paths, _RunInfo, _verify_resume,
                    load_checkpoint, write_checkpoint)

__all__ = ["simulate_to_file", "chaos_to_file", "RunSummary"]

#: the C defaults of the chaos options (fpl_chaos_options_init)
_C = ll.CHAOS_DEFAULTS


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


def _progress(total, desc, enabled, initial=0.0):
    if not enabled:
        return None
    from tqdm.auto import tqdm
    return tqdm(total=total, initial=initial, desc=desc, unit="t", disable=None,
                bar_format="{l_bar}{bar}| {n:.4g}/{total:.4g} [{elapsed}<{remaining}]")


class _CheckpointedRun:
    """What the driver needs of a run. `pieces(stopped)` advances it a piece at a time and
    yields after each (it returns when the run is over); `integrator` and `info` are what a
    checkpoint saves, `extra()` the values it keeps with them; `steps()` counts the steps the
    checkpoint cadence goes by, `t()` the time reached; `done()` says the run has nothing left
    to do; `finish(summary)` fills in the summary at the end."""
    integrator: ll.IntegratorHandle
    info: ll.RunInfo

    def pieces(self, stopped):
        raise NotImplementedError

    def extra(self) -> np.ndarray:
        raise NotImplementedError

    def steps(self) -> int:
        raise NotImplementedError

    def t(self) -> float:
        raise NotImplementedError

    def done(self) -> bool:
        raise NotImplementedError

    def finish(self, summary: RunSummary) -> None:
        raise NotImplementedError


def _drive(run: _CheckpointedRun, results: ResultsFile, summary: RunSummary, *, checkpoint,
           every_steps: int | None, every_seconds: float | None, progress: bool, total: float,
           desc: str) -> RunSummary:
    """Run `run` to its end, or until SIGINT/SIGTERM: after every piece the progress bar moves
    and a checkpoint is written when due; a failure of the integration ends the run as
    "failed"; a run that completed or was interrupted writes a last checkpoint; the results file
    gets the final status."""
    with results, _Stopper() as stopper:
        bar = _progress(total, desc, progress, run.t())
        cadence = _Cadence(checkpoint, every_steps, every_seconds, run.steps())

        def save():
            write_checkpoint(checkpoint, run.integrator, run.info, run.extra(), results)
            summary.checkpoints += 1
            cadence.mark(run.steps())

        try:
            for _ in run.pieces(lambda: stopper.signum is not None):
                if bar is not None:
                    bar.update(run.t() - bar.n)
                if cadence.due(run.steps()):
                    save()
                if stopper.signum is not None:
                    break
        except FputlabError as err:   # a blow-up without an event, a back-end failure
            summary.status, summary.message = "failed", str(err)
        finally:
            if bar is not None:
                bar.close()
        if stopper.signum is not None and summary.status == "completed" and not run.done():
            summary.status = "interrupted"
            summary.message = (f"stopped by {signal.Signals(stopper.signum).name} at "
                               f"t = {run.t():.10g}")
        if checkpoint is not None and summary.status in ("completed", "interrupted"):
            save()
        run.finish(summary)
        results.set_status(summary.status, summary.message)
    return summary


class _SimulateRun(_CheckpointedRun):
    """Samples every `every` up to t_end (mode energies, energy, optionally states); long gaps
    between samples go in segments of `seg` (fixed-step grid states do not depend on where a
    run pauses)."""

    def __init__(self, integ: Integrator, info: ll.RunInfo, results: ResultsFile,
                 summary: RunSummary, every: float, t_end: float, seg: float):
        self.integ, self.integrator, self.info = integ, integ._h, info
        self.results, self.summary = results, summary
        self.every, self.t_end, self.seg = every, t_end, seg
        self.n_samples = int(math.floor(t_end / every * (1 + 1e-12))) + 1
        self.i = results.count

    def pieces(self, stopped):
        integ = self.integ
        while self.i < self.n_samples:
            target = min(self.i * self.every, self.t_end)
            while target - integ.t > self.seg and not stopped():
                integ.advance(integ.t + self.seg)
                yield
            if stopped():
                return
            y = integ.advance(target)
            ev = integ.event
            self.results.append(ev["time"] if ev else target, y)
            self.i += 1
            if ev:
                s = self.summary
                s.status, s.event = "event", ev
                s.message = f"{ev['criterion']} at t = {ev['time']:.10g}"
                self.results.set_event(ev["time"], ev["criterion"])
                return
            yield

    def extra(self) -> np.ndarray:
        # the sampling a resume continues with: sample spacing and final time
        return np.array([self.every, self.t_end])

    def steps(self) -> int:
        return self.integ.steps

    def t(self) -> float:
        return self.integ.t

    def done(self) -> bool:
        return self.i >= self.n_samples

    def finish(self, summary: RunSummary) -> None:
        summary.t_reached = self.integ.t if summary.status != "event" else summary.event["time"]
        summary.samples = self.results.count


class _ChaosRun(_CheckpointedRun):
    """Chaos indicators (fpl_chaos) in segments of `seg`, every new sample appended to /chaos."""

    def __init__(self, c: ll.ChaosHandle, info: ll.RunInfo, results: ResultsFile,
                 summary: RunSummary, settings: dict, n_samples: int, seg: float):
        self.c, self.integrator, self.info = c, c.integrator(), info
        self.results, self.summary, self.settings, self.seg = results, summary, settings, seg
        self.arrays = [np.full(n_samples, np.nan) for _ in range(4)]
        self.res = c.get_result()

    def pieces(self, stopped):
        c, res = self.c, self.res
        while not c.done() and not stopped():
            before = res.n_samples
            if c.advance(self.integrator.time() + self.seg, *self.arrays) > 0:
                self.summary.message = last_error()      # a blow-up: when and why
            c.get_result(res)
            for j in range(before, res.n_samples):
                self.results.append_chaos(*(a[j] for a in self.arrays))
            yield

    def extra(self) -> np.ndarray:
        # the accumulators, then what fixes the sample times and the classification
        return np.concatenate([self.c.save(), list(self.settings.values())])

    def steps(self) -> int:
        return self.integrator.counters()[0]

    def t(self) -> float:
        return self.res.t_final

    def done(self) -> bool:
        return self.c.done()

    def finish(self, summary: RunSummary) -> None:
        res = self.c.get_result(self.res)
        summary.t_reached, summary.samples = res.t_final, res.n_samples
        summary.extra = {"mle": res.mle, "sali": res.sali, "gali": res.gali,
                         "chaotic": bool(res.chaotic), "t_chaotic": res.t_chaotic,
                         "blew_up": bool(res.blew_up), "t_blowup": res.t_blowup}


def simulate_to_file(lattice: Lattice, t_end: float, out, *, method: str = "yoshida4",
                     dt: float | None = None, rtol: float = ll.RTOL, atol: float = ll.ATOL,
                     sample_every: float | None = None, y0=None, deviations=None,
                     store_states: bool = False, stop_on=None, checkpoint=None,
                     checkpoint_every_steps: int | None = None,
                     checkpoint_every_seconds: float | None = 600.0, resume: bool = True,
                     chunk_rows: int = 256, progress: bool = False,
                     max_steps_per_segment: int = 100_000, overwrite: bool = False,
                     compensated_sums: bool = False) -> RunSummary:
    """Integrate from t = 0 to t_end, writing samples (t, mode energies, energy, optionally the
    states) to the HDF5 file `out` as the run goes.

    With `checkpoint`, a checkpoint is written every `checkpoint_every_steps` steps and/or
    `checkpoint_every_seconds` seconds, at the end, and on SIGINT/SIGTERM (then the run stops
    with status "interrupted"). If the checkpoint exists and `resume`, the run continues from
    it (after checking it belongs to this lattice, method and options) and `out` is cut back to
    the checkpoint's time. A resume keeps the checkpoint's sample spacing (a different
    `sample_every` is refused) and runs to the new `t_end`: a finished run can be extended.

    Parameters
    ----------
    lattice : Lattice
        The lattice.
    t_end : float
        Final time (finite, > 0).
    out : str or path-like
        The results file (schema in docs/hdf5.md).
    method : str, optional
        Integrator name (`fputlab.methods()`).
    dt : float, optional
        Step of the fixed-step methods (default 0.01, from C); an initial step for adaptive ones.
    rtol, atol : float, optional
        Tolerances of the adaptive methods.
    sample_every : float, optional
        Sampling interval (default t_end/1000, never below dt for fixed-step methods).
    y0 : array_like, optional
        Initial state, length 2N (default: the paper's mode-1 state).
    deviations : array_like, optional
        Initial deviation vectors, shape (k, 2N), carried along (and stored with the states).
    store_states : bool, optional
        Write the full state at every sample.
    stop_on : list of tuple, optional
        Stopping criteria as in `fputlab.integrate` (the run ends with status "event").
    checkpoint : str or path-like, optional
        The checkpoint file (must differ from `out`); None: no checkpoints, no resume.
    checkpoint_every_steps : int, optional
        Write a checkpoint every this many integrator steps.
    checkpoint_every_seconds : float or None, optional
        Write a checkpoint every this many seconds of wall time (default 600).
    resume : bool, optional
        Continue from an existing `checkpoint` (False: start again at t = 0).
    chunk_rows : int, optional
        Samples per HDF5 chunk (the most held in memory before being written).
    progress : bool, optional
        A progress bar with ETA (tqdm.auto).
    max_steps_per_segment : int, optional
        Most fixed steps between two looks at the clock and the signals.
    overwrite : bool, optional
        Replace an existing `out` that is not continued from its checkpoint.
    compensated_sums : bool, optional
        SPRKStep methods (``sprk-*``) only: compensated summation. It is kept in the checkpoint
        with the summation's carry, so that a restart continues bit for bit; a resume must give
        the same value.

    Returns
    -------
    RunSummary
        How the run ended ("completed", "event", "failed", "interrupted"), the time reached,
        the samples in the file, the checkpoint it resumed from and the checkpoints written.

    Raises
    ------
    ValueError, TypeError
        Invalid arguments, or a checkpoint that does not belong to this run (nothing changed).
    FileExistsError
        `out` exists and would be replaced (without `overwrite`).
    OSError
        The files cannot be written, or `out` and its checkpoint are damaged.
    """
    if not isinstance(lattice, Lattice):
        raise TypeError(f"lattice must be a fputlab.Lattice, got {type(lattice).__name__}")
    t_end = _positive_real(t_end, "t_end")
    adaptive = method_info(method)["adaptive"]
    _compensated_sums(compensated_sums, method)
    if dt is None and not adaptive:
        dt = ll.DT
    every = t_end / 1000 if sample_every is None else _real(sample_every, "sample_every")
    if sample_every is None and not adaptive:
        every = max(every, _real(dt, "dt"))    # never below what a fixed step can resolve
    if not (math.isfinite(every) and every > 0):
        raise ValueError(f"sample_every must be finite and > 0 (got {every:g})")
    if not adaptive:
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

    integ = Integrator(lattice, state0, method=method, dt=dt, rtol=rtol, atol=atol,
                       criteria=stop_on, compensated_sums=compensated_sums)
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
    seg = math.inf if adaptive else max_steps_per_segment * dt
    summary = RunSummary("completed", integ.t, 0, resumed, 0, path=_path(out, "out"))
    run = _SimulateRun(integ, info, results, summary, every, t_end, seg)
    return _drive(run, results, summary, checkpoint=checkpoint, every_steps=k_steps,
                  every_seconds=k_seconds, progress=progress, total=t_end,
                  desc=f"simulate N={N}")


def chaos_to_file(lattice: Lattice, t_end: float, out, *, method: str = "yoshida4",
                  dt: float | None = None, rtol: float = ll.RTOL, atol: float = ll.ATOL,
                  y0=None, n_dev: int = _C["n_dev"], renorm_interval: float = _C["renorm_interval"],
                  n_samples: int = _C["n_samples"], sali_threshold: float = _C["sali_threshold"],
                  stop_when_chaotic: bool = False, seed: int = _C["seed"],
                  checkpoint=None, checkpoint_every_steps: int | None = None,
                  checkpoint_every_seconds: float | None = 600.0, resume: bool = True,
                  progress: bool = False, segment: float | None = None,
                  overwrite: bool = False) -> RunSummary:
    """mLE, SALI and GALI (`fputlab.chaos.lyapunov`) written to /chaos of the HDF5 file `out` as
    the run goes, with checkpoints of the orbit, the deviation vectors and the accumulated
    log-norms; a restart continues bit for bit (fixed-step methods).

    A resume must use the checkpoint's t_end, n_samples, renorm_interval, sali_threshold and
    stop_when_chaotic (they fix the sample times and the classification); others are refused
    before anything changes.

    Parameters
    ----------
    lattice : Lattice
        The lattice.
    t_end : float
        Final time (finite, > 0).
    out : str or path-like
        The results file (schema in docs/hdf5.md).
    method : str, optional
        Integrator name (`fputlab.methods()`).
    dt : float, optional
        Step of the fixed-step methods (default 0.01, from C).
    rtol, atol : float, optional
        Tolerances of the adaptive methods.
    y0 : array_like, optional
        Initial orbit state, length 2N (default: the paper's mode-1 state).
    n_dev : int, optional
        Number of deviation vectors (Gaussian random from `seed`).
    renorm_interval : float, optional
        Time between renormalisations of the deviation vectors.
    n_samples : int, optional
        Number of log-spaced sample times.
    sali_threshold : float, optional
        SALI below this marks the orbit chaotic.
    stop_when_chaotic : bool, optional
        End the run once the orbit is found chaotic.
    seed : int, optional
        Seed of the random initial deviation vectors.
    checkpoint : str or path-like, optional
        The checkpoint file (must differ from `out`); None: no checkpoints, no resume.
    checkpoint_every_steps : int, optional
        Write a checkpoint every this many integrator steps.
    checkpoint_every_seconds : float or None, optional
        Write a checkpoint every this many seconds of wall time (default 600).
    resume : bool, optional
        Continue from an existing `checkpoint` (False: start again at t = 0).
    progress : bool, optional
        A progress bar with ETA (tqdm.auto).
    segment : float, optional
        Time advanced between two looks at the clock and the signals (default: about 1e5
        steps, a multiple of `renorm_interval`).
    overwrite : bool, optional
        Replace an existing `out` that is not continued from its checkpoint.

    Returns
    -------
    RunSummary
        How the run ended, the time reached and the samples written; ``extra`` holds the final
        mle, sali, gali, whether and when the orbit was found chaotic or blew up.

    Raises
    ------
    ValueError, TypeError
        Invalid arguments, or a checkpoint that does not belong to this run (nothing changed).
    FileExistsError
        `out` exists and would be replaced (without `overwrite`).
    OSError
        The files cannot be written, or `out` and its checkpoint are damaged.
    """
    if not isinstance(lattice, Lattice):
        raise TypeError(f"lattice must be a fputlab.Lattice, got {type(lattice).__name__}")
    t_end = _positive_real(t_end, "t_end")
    k_steps, k_seconds = _check_every(checkpoint_every_steps, checkpoint_every_seconds)
    if segment is not None:
        segment = _positive_real(segment, "segment")
    resuming = _check_output_paths(out, checkpoint, resume, overwrite)
    adaptive = method_info(method)["adaptive"]
    if dt is None and not adaptive:
        dt = ll.DT
    N = lattice.N
    orbit = lattice.mode_state() if y0 is None else as_float_array(y0, "y0", (2 * N,))
    iopt = ll.integrator_options(0.0 if dt is None else _real(dt, "dt"), _real(rtol, "rtol"),
                                 _real(atol, "atol"))
    copt = ll.chaos_options(
        t_end, renorm_interval=_real(renorm_interval, "renorm_interval"),
        n_samples=_int(n_samples, "n_samples"), n_dev=_int(n_dev, "n_dev"),
        sali_threshold=_real(sali_threshold, "sali_threshold"),
        stop_when_chaotic=int(bool(stop_when_chaotic)), seed=_seed(seed))
    c = ll.ChaosHandle(lattice._h, method, iopt, 0.0, orbit, None, copt)
    ih = c.integrator()
    info = _RunInfo(lattice, "chaos", method, iopt.dt, iopt.rtol, iopt.atol, 0.0, copt.n_dev)
    n_acc = ll.CHAOS_N_ACCUMULATORS
    # what fixes the sample times and the classification: a resume must agree on all of it
    settings = {"t_end": t_end, "n_samples": copt.n_samples,
                "renorm_interval": copt.renorm_interval, "sali_threshold": copt.sali_threshold,
                "stop_when_chaotic": float(copt.stop_when_chaotic)}
    resumed = None
    if resuming:
        acc = load_checkpoint(checkpoint, ih, info, n_acc + len(settings))
        if acc.size not in (n_acc, n_acc + len(settings)):  # fpl_chaos_save grew (MEGNO)
            raise ValueError(f"checkpoint: {checkpoint} holds {acc.size} chaos accumulators, this "
                             f"version needs {n_acc} (written by an older fputlab; refused, "
                             "nothing changed)")
        if acc.size == n_acc + len(settings):
            for (name, want), have in zip(settings.items(), acc[n_acc:]):
                if have != want:
                    raise ValueError(f"{name}: the checkpoint's run has {name} = {have:.17g}, "
                                     f"this run {want:.17g}; a chaos run cannot change it when "
                                     "resuming (it fixes the sample times; refused, nothing "
                                     "changed)")
        c.restore(np.ascontiguousarray(acc[:n_acc]))
        resumed = ih.time()
        _verify_resume(out, lattice, info, checkpoint)
        results = ResultsFile(out, lattice, info, resume_from=checkpoint)
    else:
        results = ResultsFile(out, lattice, info)
    seg = segment if segment is not None else (
        renorm_interval * max(1, round(1e5 * (dt or ll.DT) / renorm_interval)))
    summary = RunSummary("completed", ih.time(), 0, resumed, 0, path=_path(out, "out"))
    run = _ChaosRun(c, info, results, summary, settings, copt.n_samples, seg)
    return _drive(run, results, summary, checkpoint=checkpoint, every_steps=k_steps,
                  every_seconds=k_seconds, progress=progress, total=t_end, desc=f"chaos N={N}")
