"""Short reprs and xarray conversion shared by the result dataclasses (Run, ChaosResult, Blowup,
...). Written against `dataclasses.fields`, so a result class that gains or loses a field keeps
a sensible one-line summary without touching this module."""
from __future__ import annotations

import dataclasses
import json
import math

import numpy as np

#: Long names, units and descriptions of the quantities in results (dimensionless units of the
#: paper: unit masses and linear spring constant; see docs/conventions.md). The long name is
#: what xarray puts on a plot axis, so it is short and in words; the formula goes in the
#: description. Units "1" mark a dimensionless quantity.
VARIABLES = {
    "t": ("time", "1", "time in units of the inverse linear coupling"),
    "t_chaos": ("time", "1", "times of the chaos-indicator samples"),
    "energy": ("energy", "1", "total energy H (Eq. Hamilt; not conserved for model 3)"),
    "relative_energy_error": ("relative energy error", "1", "|H(t) - H(0)| / |H(0)|"),
    "mode_energies": ("mode energy", "1", "normal-mode energy E_k = (P_k^2 + omega_k^2 Q_k^2) / 2"),
    "states": ("state", "1", "y = [x_1..x_N, p_1..p_N] (orbit, then deviation vectors)"),
    "x": ("displacement", "1", "displacement x_j"),
    "p": ("momentum", "1", "canonical momentum p_j"),
    "v": ("variability", "1", "variability v_j = 1 + (tau/300) z_j"),
    "mle": ("Lyapunov exponent", "1/time", "finite-time maximum Lyapunov exponent lambda(t)"),
    "sali": ("SALI", "1", "smaller alignment index SALI(t)"),
    "gali": ("GALI", "1", "generalised alignment index GALI_k(t)"),
    "megno": ("MEGNO", "1", "MEGNO <Y>(t) (Cincotta & Simo 2000)"),
    "exponents": ("Lyapunov exponent", "1/time", "Lyapunov exponents lambda_i (QR order)"),
    "history": ("Lyapunov exponent", "1/time", "finite-time Lyapunov exponents lambda_i(t)"),
    "exponent": ("exponent index", "1", "exponent index i"),
    "mode": ("mode", "1", "normal-mode number k"),
    "site": ("particle", "1", "particle index j"),
    "vector": ("vector", "1", "0: the orbit, 1..k: deviation vectors"),
    "component": ("component", "1", "state component (x_1..x_N, p_1..p_N)"),
}


def fmt(value) -> str:
    """A number in at most 4 significant digits; other values by repr."""
    if isinstance(value, (bool, np.bool_)):
        return str(bool(value))
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        return f"{float(value):.4g}"
    return repr(value)


def time_span(t: np.ndarray) -> str:
    """'t=0..8e+04, 801 samples' (or 'no samples')."""
    t = np.asarray(t)
    if t.size == 0:
        return "no samples"
    return f"t={fmt(t[0])}..{fmt(t[-1])}, {t.size} sample{'s' if t.size != 1 else ''}"


def _shape(a: np.ndarray) -> str:
    return "x".join(str(n) for n in a.shape) if a.ndim else "scalar"


def dataclass_repr(obj, lead=(), skip=(), max_len: int = 220) -> str:
    """One-line summary of a result dataclass: `lead` parts first, then every field with
    repr=True that is not in `skip` -- flags, then numbers, then strings (cut), then arrays (as
    their shape) and dicts (their scalar items) -- leaving out empty, None and NaN values, so a
    cut at `max_len` loses the least telling parts."""
    flags, numbers, texts, rest = [], [], [], []
    for f in dataclasses.fields(obj):
        if not f.repr or f.name in skip:
            continue
        value = getattr(obj, f.name)
        if value is None or (isinstance(value, (str, dict, list, tuple)) and not value):
            continue
        if isinstance(value, np.ndarray):
            rest.append(f"{f.name}[{_shape(value)}]")
        elif isinstance(value, dict):
            items = [f"{k}={fmt(v)}" for k, v in value.items()
                     if v is not None and (isinstance(v, (str, bool, int, float, np.generic)))]
            if items:
                rest.append(f"{f.name}={{{', '.join(items)}}}")
        elif isinstance(value, str):
            texts.append(f"{f.name}={shorten(value, 60)!r}")
        elif isinstance(value, (bool, np.bool_)):
            flags.append(f"{f.name}={fmt(value)}")
        elif isinstance(value, (int, float, np.generic)):
            if isinstance(value, (float, np.floating)) and math.isnan(value):
                continue
            numbers.append(f"{f.name}={fmt(value)}")
        else:
            text = repr(value)
            rest.append(f"{f.name}={text if len(text) <= 60 else type(value).__name__}")
    return join_parts(type(obj).__name__, list(lead) + flags + numbers + texts + rest, max_len)


def shorten(text: str, width: int) -> str:
    """`text` in at most `width` characters, cut at a word boundary and marked with '...'
    (never mid-word, unless a single word is longer than `width`)."""
    text = " ".join(str(text).split())
    if len(text) <= width:
        return text
    cut = text[:width - 3]
    if " " in cut and text[width - 3] != " ":
        cut = cut[:cut.rindex(" ")]
    return cut.rstrip(" ,;:") + "..."


def join_parts(name: str, parts: list, max_len: int = 220) -> str:
    """'name(part, part, ...)' within `max_len` characters: whole parts only, the ones that do
    not fit left out and marked by a final '...' (a repr is never cut inside a part)."""
    text = f"{name}({', '.join(parts)})"
    if len(text) <= max_len:
        return text
    kept = list(parts)
    while kept and len(f"{name}({', '.join(kept + ['...'])})") > max_len:
        kept.pop()
    return f"{name}({', '.join(kept + ['...'])})"


def require_xarray():
    """Import xarray, or raise an ImportError that names the extra to install."""
    try:
        import xarray
    except ImportError as err:
        raise ImportError("to_xarray() needs xarray: pip install 'fputlab[xarray]' "
                          "(or pip install xarray)") from err
    return xarray


def variable(dims, data, name: str, **attrs):
    """(dims, data, attrs) for an xarray Dataset: long_name and description from VARIABLES, and
    units for dimensional quantities only (CF lets a dimensionless one omit them; xarray would
    label its axes "time [1]")."""
    long_name, units, description = VARIABLES.get(name, (name, "1", name))
    meta = {"long_name": long_name, "description": description}
    if units != "1":
        meta["units"] = units
    return dims, data, {**meta, **attrs}


def scalar_attrs(obj, skip=()) -> dict:
    """The scalar fields of a dataclass (and of its `params` dict) as netCDF-safe attributes."""
    attrs = {}
    for f in dataclasses.fields(obj):
        if f.name in skip:
            continue
        value = getattr(obj, f.name)
        items = value.items() if isinstance(value, dict) else [(f.name, value)]
        for k, v in items:
            if isinstance(v, (bool, np.bool_)):
                attrs[k] = int(v)
            elif isinstance(v, (int, float, str, np.integer, np.floating)):
                attrs[k] = v.item() if isinstance(v, np.generic) else v
    return attrs


class ResultMixin:
    """Short `__repr__` and `to_xarray()` for a result dataclass (declare it with
    ``@dataclass(repr=False)`` so the dataclass does not replace this repr).

    The summary names the lattice (from a ``params`` dict when there is one), the sampled time
    span, the last value of every per-sample array and the scalar fields."""

    #: name of the field holding the sample times (None: no time axis)
    _time_field = "t"

    def _time(self):
        name = self._time_field
        value = getattr(self, name, None) if name else None
        return value if isinstance(value, np.ndarray) and value.ndim == 1 else None

    def __repr__(self) -> str:
        lead, skip = [], {"params"}
        params = getattr(self, "params", None)
        if isinstance(params, dict):
            lead += [f"{k}={fmt(params[k])}" for k in ("N", "model") if params.get(k) is not None]
            if params.get("seed") is not None:
                lead.append(f"tau={fmt(params.get('tau'))}, seed={fmt(params['seed'])}")
        t = self._time()
        if t is not None:
            lead.append(time_span(t).replace("t=", f"{self._time_field}=", 1))
        classify = getattr(self, "classify", None)
        if callable(classify):      # a result that can name its class says it first
            try:
                lead.append(f"class={classify()!r}")
            except Exception:       # a repr never raises
                pass
        if t is not None:
            skip.add(self._time_field)
            last = []
            for f in dataclasses.fields(self):
                value = getattr(self, f.name)
                if (f.name != self._time_field and isinstance(value, np.ndarray)
                        and value.ndim == 1 and value.size == t.size):
                    skip.add(f.name)
                    if value.size:
                        last.append(f"{f.name}={fmt(value[-1])}")
            if last:
                lead.append(f"last: {', '.join(last)}")
        return dataclass_repr(self, lead, skip)

    def to_xarray(self):
        """The result as an ``xarray.Dataset`` with units and long names.

        Arrays sampled at the times of the time field share its dimension; other arrays get
        their own dimensions; scalar fields (and the ``params`` dict) become attributes.

        Returns
        -------
        xarray.Dataset

        Raises
        ------
        ImportError
            If xarray is not installed (``pip install 'fputlab[xarray]'``).
        """
        xr = require_xarray()
        t = self._time()
        name_t = self._time_field
        data, coords = {}, {}
        if t is not None:
            coords[name_t] = variable(name_t, t, name_t)
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            if f.name == name_t or not isinstance(value, np.ndarray) or value.dtype == object:
                continue
            if t is not None and value.ndim >= 1 and value.shape[0] == t.size:
                dims = (name_t,) + tuple(f"{f.name}_dim{i}" for i in range(1, value.ndim))
            else:
                dims = tuple(f"{f.name}_dim{i}" for i in range(value.ndim))
            data[f.name] = variable(dims, value, f.name)
        return xr.Dataset(data, coords=coords, attrs=scalar_attrs(self))


def _json_safe(x):
    """x with numpy scalars/arrays as Python numbers/lists and non-finite floats as None, so that
    the output is strict JSON (RFC 8259 has no NaN or Infinity)."""
    if isinstance(x, dict):
        return {str(k): _json_safe(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_json_safe(v) for v in x]
    if isinstance(x, np.ndarray):
        return _json_safe(x.tolist())
    if isinstance(x, (bool, np.bool_)):
        return bool(x)
    if isinstance(x, (int, np.integer)):
        return int(x)
    if isinstance(x, (float, np.floating)):
        return float(x) if math.isfinite(x) else None
    if x is None or isinstance(x, str):
        return x
    return str(x)


def dumps_strict(obj, **kw) -> str:
    """json.dumps of _json_safe(obj); never writes NaN/Infinity."""
    return json.dumps(_json_safe(obj), allow_nan=False, **kw)
