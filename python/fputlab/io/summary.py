"""The HDF5 files of the command line's summaries: attributes and datasets, or a whole summary
(numbers and strings as attributes, numeric lists as datasets, dicts as groups). Written
atomically (fputlab.io.atomic): a file is whole or absent."""
from __future__ import annotations

import json

import numpy as np

from .._lowlevel import VERSION
from .atomic import write_h5_atomic

__all__ = ["write_h5", "write_summary_h5"]


def write_h5(path, attrs: dict, datasets: dict) -> None:
    """`attrs` as attributes and `datasets` as gzip-compressed datasets (None: left out), with
    the fputlab version."""

    def fill(f):
        f.attrs["fputlab_version"] = VERSION
        for k, v in attrs.items():
            if v is not None:
                f.attrs[k] = v
        for k, v in datasets.items():
            if v is not None:
                f.create_dataset(k, data=np.asarray(v), compression="gzip")
    write_h5_atomic(path, fill)


def write_summary_h5(path, summary: dict) -> None:
    """A command's summary: numbers and strings as attributes, numeric lists as datasets, dicts
    as groups, anything else as a JSON string attribute."""

    def put(g, d):
        for k, v in d.items():
            if isinstance(v, dict):
                put(g.create_group(k), v)
            elif isinstance(v, (list, tuple, np.ndarray)):
                try:
                    g.create_dataset(k, data=np.asarray(v, dtype=float))
                except (TypeError, ValueError):
                    g.attrs[k] = json.dumps(v, default=float)
            elif v is not None:
                g.attrs[k] = v

    def fill(f):
        f.attrs["fputlab_version"] = VERSION
        put(f, summary)
    write_h5_atomic(path, fill)
