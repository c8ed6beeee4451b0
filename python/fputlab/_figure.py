"""What every figure function returns, and where it writes (shared by fputlab.figures and
fputlab.figures_reduction).

Every figure function has the signature ``figN(out_dir=".", *, full=False, **options)`` and
returns a `Figure`: the path of the PNG it wrote, which also carries the numbers the figure
shows (``fig.numbers``, or ``fig["key"]``)."""
from __future__ import annotations

import os
import pathlib


class Figure(type(pathlib.Path())):
    """Path of a PNG written by a figure function, with the numbers the figure shows.

    ``fig.numbers`` is a dict (empty when the figure reports none); ``fig[key]`` reads it, and
    ``fig["path"]`` is the path as a string."""

    numbers: dict = {}

    def __getitem__(self, key):
        if key == "path":
            return str(self)
        return self.numbers[key]


def target(out_dir, name: str) -> str:
    """The file a figure is written to: `name` inside the directory `out_dir` (created if
    needed), or `out_dir` itself when it is a file name ending in .png."""
    out = os.fspath(out_dir)
    if out.lower().endswith(".png"):
        parent = os.path.dirname(out)
    else:
        parent, out = out, os.path.join(out, name)
    if parent:
        os.makedirs(parent, exist_ok=True)
    return out


def save(fig, path: str, numbers: dict | None = None) -> Figure:
    """Write `fig` to `path` (a PNG), close it, return the `Figure`."""
    import matplotlib.pyplot as plt
    fig.savefig(path, dpi=110)
    plt.close(fig)
    result = Figure(path)
    result.numbers = {k: v for k, v in (numbers or {}).items() if k != "path"}
    return result
