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
the final files equal those of an uninterrupted run. The schema is in docs/hdf5.md.

Two modules: `fputlab.io.files` (results files and checkpoints, written and read) and
`fputlab.io.runs` (the one checkpointed-run driver behind `simulate_to_file` and
`chaos_to_file`); every name is importable from here."""
from __future__ import annotations

from .files import (STATUSES, VERIFY_TIMEOUT, Results, ResultsFile, checkpoint_time, load,
                    load_checkpoint, write_checkpoint)
from .runs import RunSummary, chaos_to_file, simulate_to_file

__all__ = ["simulate_to_file", "chaos_to_file", "load", "Results", "RunSummary", "ResultsFile",
           "write_checkpoint", "load_checkpoint", "checkpoint_time", "STATUSES", "VERIFY_TIMEOUT"]
