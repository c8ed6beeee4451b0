"""What every figure function returns, where and how it writes, and the house style the paper's
figures share (shared by fputlab.figures and fputlab.figures_reduction).

Every figure function has the signature ``figN(out_dir=".", *, full=False, **options)`` and
returns a `Figure`: the path of the file it wrote, which also carries the numbers the figure
shows (``fig.numbers``, or ``fig["key"]``). The file format and resolution are those of the
enclosing `figure_output` block (default PNG at 110 dpi), or the suffix of `out_dir` when that
is a file name (.png, .pdf, .svg)."""
from __future__ import annotations

import contextlib
import math
import os
import pathlib

#: file formats a figure can be written in (vector: pdf, svg)
FORMATS = ("png", "pdf", "svg")
#: format and resolution of the figures written now (changed only by `figure_output`)
_OUTPUT = {"format": "png", "dpi": 110.0}


class Figure(type(pathlib.Path())):
    """Path of a figure file written by a figure function, with the numbers the figure shows.

    ``fig.numbers`` is a dict (empty when the figure reports none); ``fig[key]`` reads it, and
    ``fig["path"]`` is the path as a string."""

    numbers: dict = {}

    def __getitem__(self, key):
        if key == "path":
            return str(self)
        return self.numbers[key]


@contextlib.contextmanager
def figure_output(format: str | None = None, dpi: float | None = None):
    """Write the figures made inside the ``with`` block as `format` at `dpi`.

    Parameters
    ----------
    format : {"png", "pdf", "svg"}, optional
        File format (default: unchanged, PNG outside any block); pdf and svg are vector
        formats for papers.
    dpi : float, optional
        Resolution of raster output (PNG; default 110), and of any rasterised part of a
        vector figure.

    Raises
    ------
    ValueError, TypeError
        An unknown format or a dpi that is not a positive number.

    Examples
    --------
    >>> from fputlab.figures import fig5, figure_output
    >>> with figure_output("pdf"):
    ...     fig5("paper/")                       # doctest: +SKIP
    """
    new = dict(_OUTPUT)
    if format is not None:
        if not isinstance(format, str):
            raise TypeError(f"format must be a string, got {type(format).__name__}")
        if format.lower() not in FORMATS:
            raise ValueError(f"format {format!r} is unknown (known: {', '.join(FORMATS)})")
        new["format"] = format.lower()
    if dpi is not None:
        if isinstance(dpi, bool) or not isinstance(dpi, (int, float)):
            raise TypeError(f"dpi must be a number, got {type(dpi).__name__}")
        if not (math.isfinite(dpi) and dpi > 0):
            raise ValueError(f"dpi must be a positive number (got {dpi})")
        new["dpi"] = float(dpi)
    old = dict(_OUTPUT)
    _OUTPUT.update(new)
    try:
        yield dict(_OUTPUT)
    finally:
        _OUTPUT.clear()
        _OUTPUT.update(old)


def add_output_options(parser) -> None:
    """--format and --dpi on an argparse parser (the example scripts and ``fputlab figures``);
    pass the parsed values to `figure_output`."""
    parser.add_argument("--format", choices=FORMATS, default=None,
                        help="file format: png, or pdf/svg (vector) for a paper (default png)")
    parser.add_argument("--dpi", type=float, default=None,
                        help=f"resolution of raster output (default {_OUTPUT['dpi']:g})")


def target(out_dir, name: str) -> str:
    """The file a figure is written to: `name` (its suffix set to the current format) inside
    the directory `out_dir` (created if needed), or `out_dir` itself when it is a file name
    ending in .png, .pdf or .svg."""
    out = os.fspath(out_dir)
    if os.path.splitext(out)[1].lower().lstrip(".") in FORMATS:
        parent = os.path.dirname(out)
    else:
        stem = os.path.splitext(name)[0]
        parent, out = out, os.path.join(out, f"{stem}.{_OUTPUT['format']}")
    if parent:
        os.makedirs(parent, exist_ok=True)
    return out


def sci(x: float, digits: int = 2) -> str:
    """A number for a title or label in one style everywhere: 10⁸ or 2.5×10⁴ (mathtext) for
    large or small magnitudes, plain below 10⁴ ('2545', '0.05')."""
    x = float(x)
    if x == 0 or not math.isfinite(x) or 1e-3 <= abs(x) < 1e4:
        return f"{x:.{digits + 2}g}"
    exponent = math.floor(math.log10(abs(x)))
    mantissa = round(x / 10.0 ** exponent, digits)
    if abs(mantissa) >= 10:
        mantissa, exponent = mantissa / 10, exponent + 1
    if mantissa == 1:
        return f"$10^{{{exponent}}}$"
    return f"${mantissa:g}\\times 10^{{{exponent}}}$"


def tidy(fig) -> None:
    """House style applied to every figure before it is written: linear axes whose tick labels
    would run to five or more digits (t up to 1.5×10⁵) get short labels with a common ×10ⁿ
    factor, so neighbouring labels cannot collide."""
    from matplotlib.ticker import ScalarFormatter
    for ax in fig.axes:
        for axis, scale in ((ax.xaxis, ax.get_xscale()), (ax.yaxis, ax.get_yscale())):
            if scale != "linear" or not isinstance(axis.get_major_formatter(), ScalarFormatter):
                continue
            lo, hi = axis.get_view_interval()
            if max(abs(lo), abs(hi)) >= 1e4:
                formatter = ScalarFormatter(useMathText=True)
                formatter.set_powerlimits((-3, 3))
                axis.set_major_formatter(formatter)


def save(fig, path: str, numbers: dict | None = None) -> Figure:
    """Write `fig` to `path` (format from its suffix, the current dpi), close it, return the
    `Figure`."""
    import matplotlib.pyplot as plt
    tidy(fig)
    fig.savefig(path, dpi=_OUTPUT["dpi"])
    plt.close(fig)
    result = Figure(path)
    result.numbers = {k: v for k, v in (numbers or {}).items() if k != "path"}
    return result
