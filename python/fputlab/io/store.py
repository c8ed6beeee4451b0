"""The work directory of a study (`fputlab.engine`): what is on disk and how it is written::

    work_dir/
        study.json      the spec: kind, grid, settings, its key (a hash), the format; created
                        once, atomically, by exactly one process; t_end lives in progress.json
        progress.json   the t_end the study was last run to
        tasks/<id>.h5   one file per task, replaced atomically each time the task reports: its
                        grid coordinates, the time reached, whether it is finished, its values
                        (/values) and the state it continues from (/state)
        result.nc       the merged labelled result (netCDF-4/HDF5, `xarray.open_dataset`)
        .lock           the runner's fcntl lock (fputlab.io.atomic.DirectoryLock)

Only the standard library, numpy and h5py (xarray for result.nc), so the engine, below the
physics, can use it."""
from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np

from .atomic import (DirectoryLock, create_exclusive, remove_temporaries, write_atomic,
                     write_bytes_atomic, write_h5_atomic)

__all__ = ["StudyStore", "FORMAT"]

FORMAT = "fputlab-study-1"


def _canonical(doc) -> str:
    return json.dumps(doc, sort_keys=True, separators=(",", ":"), allow_nan=True)


class StudyStore:
    """An open, locked study directory. `spec_doc` is the study's description (a JSON-able dict
    with a "key"); an existing directory must hold the same key, or `overwrite` discards its
    results. Close it (or use ``with``) to release the lock."""

    def __init__(self, work_dir, spec_doc: dict, *, overwrite: bool = False):
        self.path = Path(work_dir)
        if self.path.exists() and not self.path.is_dir():
            raise ValueError(f"work_dir {str(self.path)!r} exists and is not a directory")
        self.path.mkdir(parents=True, exist_ok=True)
        self._lock = DirectoryLock(self.path, "study directory").acquire()
        try:
            self._open(spec_doc, overwrite)
        except BaseException:
            self._lock.release()
            raise

    def _open(self, spec_doc: dict, overwrite: bool) -> None:
        remove_temporaries(self.path)
        self.tasks_dir = self.path / "tasks"
        self.tasks_dir.mkdir(exist_ok=True)
        remove_temporaries(self.tasks_dir)
        doc = {"format": FORMAT, **spec_doc}
        text = _canonical(doc).encode()
        desc = self.path / "study.json"
        if create_exclusive(desc, text):
            return
        try:
            old = json.loads(desc.read_text())
        except (OSError, ValueError) as err:
            raise ValueError(f"{desc}: not a readable study description ({err}); remove it or "
                             "use another work_dir") from None
        if old.get("format") == FORMAT and old.get("key") == doc["key"]:
            return
        if not overwrite:
            diff = sorted(k for k in set(old) | set(doc)
                          if k != "key" and _canonical(old.get(k)) != _canonical(doc.get(k)))
            detail = "; ".join(f"{k}: {old.get(k)!r} there, {doc.get(k)!r} here"
                               for k in diff)[:600]
            raise ValueError(f"work_dir {str(self.path)!r} holds another study ({detail}); "
                             "use a new work_dir, or overwrite=True to discard its results")
        shutil.rmtree(self.tasks_dir)
        self.tasks_dir.mkdir()
        for name in ("result.nc", "progress.json"):
            (self.path / name).unlink(missing_ok=True)
        write_bytes_atomic(desc, text)

    @classmethod
    def reader(cls, work_dir) -> "StudyStore":
        """The study in `work_dir` opened for reading only: no lock (a runner may be at work:
        every file is whole, old or new), nothing created or removed. Its description is
        `doc`."""
        self = cls.__new__(cls)
        self.path = Path(work_dir)
        self.tasks_dir = self.path / "tasks"
        self._lock = None
        desc = self.path / "study.json"
        try:
            self.doc = json.loads(desc.read_text())
        except (OSError, ValueError) as err:
            raise ValueError(f"{desc}: no readable study description ({err})") from None
        if self.doc.get("format") != FORMAT:
            raise ValueError(f"{desc}: not a study of the study engine")
        return self

    # -- t_end -----------------------------------------------------------------------------
    def t_end(self) -> float | None:
        """The t_end the study was last run to (None: never)."""
        try:
            return float(json.loads((self.path / "progress.json").read_text())["t_end"])
        except (OSError, ValueError, KeyError, TypeError):
            return None

    def set_t_end(self, t_end: float) -> None:
        write_bytes_atomic(self.path / "progress.json",
                           _canonical({"t_end": float(t_end)}).encode())

    # -- tasks -----------------------------------------------------------------------------
    def task_path(self, task_id: str) -> Path:
        return self.tasks_dir / f"{task_id}.h5"

    def write_task(self, task_id: str, coords: dict, out: dict) -> None:
        """A task's report {t, done, message, cpu, values: {name: array}, state: {name: array}
        or None}, replacing its previous one atomically."""

        def fill(f):
            f.attrs["format"] = FORMAT
            f.attrs["coords"] = _canonical(coords)
            f.attrs["t"] = float(out["t"])
            f.attrs["done"] = bool(out["done"])
            f.attrs["message"] = str(out.get("message", ""))
            f.attrs["cpu"] = float(out.get("cpu", 0.0))
            for group in ("values", "state"):
                g = f.create_group(group)
                for name, v in (out.get(group) or {}).items():
                    arr = np.asarray(v)
                    if arr.dtype.kind in "US":
                        g.attrs[name] = str(arr)
                    elif arr.size >= 256:   # sample series: NaN-padded, they compress 3-10x
                        g.create_dataset(name, data=arr, compression="gzip", shuffle=True)
                    else:
                        g.create_dataset(name, data=arr)
        write_h5_atomic(self.task_path(task_id), fill)

    def fingerprint(self) -> tuple:
        """Changes whenever a task file or the t_end does (a reader's cache key)."""
        stamps = [(p.name, p.stat().st_mtime_ns) for p in self.tasks_dir.glob("*.h5")]
        prog = self.path / "progress.json"
        return (tuple(sorted(stamps)), prog.stat().st_mtime_ns if prog.exists() else 0)

    def read_task(self, task_id: str, coords: dict, state: bool = True) -> dict | None:
        """The task's last report (without its state unless `state`), None if it has none;
        ValueError for a damaged file or one of another task (never silently recomputed
        over)."""
        import h5py
        path = self.task_path(task_id)
        if not path.exists():
            return None
        try:
            with h5py.File(path, "r") as f:
                if f.attrs.get("format") != FORMAT or \
                        json.loads(f.attrs["coords"]) != json.loads(_canonical(coords)):
                    raise ValueError("belongs to another task")
                out = {"t": float(f.attrs["t"]), "done": bool(f.attrs["done"]),
                       "message": str(f.attrs["message"]), "cpu": float(f.attrs["cpu"])}
                for group in ("values", "state") if state else ("values",):
                    g = f[group]
                    d = {k: g[k][()] for k in g}
                    d.update({k: str(v) for k, v in g.attrs.items()})
                    out[group] = d
                if not out.get("state"):
                    out["state"] = None
                return out
        except (OSError, KeyError, ValueError, TypeError) as err:
            raise ValueError(f"{path}: unreadable task result ({type(err).__name__}: {err}); "
                             "remove it to recompute that task") from None

    # -- the merged result -----------------------------------------------------------------
    def write_result(self, dataset) -> Path:
        """The merged xarray Dataset as netCDF-4/HDF5 (result.nc), atomically."""
        path = self.path / "result.nc"
        write_atomic(path, lambda tmp: dataset.to_netcdf(tmp, engine="h5netcdf"))
        return path

    # -- closing ---------------------------------------------------------------------------
    def close(self) -> None:
        if self._lock is not None:
            self._lock.release()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
