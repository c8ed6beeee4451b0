"""One integration API for every method (splitting schemes, ARKODE, CVODE, GSL), with
deviation vectors, sampled without storing the trajectory."""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Iterator

import numpy as np

from . import _lowlevel as ll
from ._arrays import as_float_array, check_memory
from ._errors import FputlabError, IntegrationError, Interrupted
from ._pacing import Pacer, first_span
from ._validate import C_LONG, _int, _positive_real, _real
from .lattice import Lattice

__all__ = ["integrate", "Integrator", "Run", "iter_samples", "methods", "method_info", "CRITERIA"]


def methods() -> list[str]:
    """Names of all integration methods."""
    return ll.method_names()


def method_info(method: str) -> dict:
    """{'order': int, 'adaptive': bool} for a method name."""
    if not isinstance(method, str):
        raise TypeError(f"method must be a string, got {type(method).__name__}")
    if "\x00" in method:
        raise ValueError(f"method {method!r} is unknown (it contains a NUL character)")
    order, adaptive = ll.method_info(method)
    return {"order": order, "adaptive": adaptive}


def _compensated_sums(value, method: str) -> int:
    """The compensated_sums option as 0/1, refused for methods other than SPRKStep's."""
    if not isinstance(value, (bool, np.bool_)):
        raise TypeError(f"compensated_sums must be a bool, got {type(value).__name__}")
    if value and not method.startswith("sprk-"):
        raise ValueError(f"compensated_sums applies only to ARKODE's SPRKStep methods (sprk-*), "
                         f"not to {method!r}")
    return int(bool(value))


#: stopping-criterion names -> C kinds (the criteria of `stop_on` and `fputlab.blowup`)
CRITERIA = dict(ll.EVENT_KINDS)


def criteria_events(criteria):
    """The C event set of stopping criteria [(name, threshold) or ("mode_energy", threshold, k)]
    (None for None or []), each checked and named by its position. Criteria belong to a run
    (`Integrator(criteria=...)`), never to the lattice, so one lattice serves many runs."""
    criteria = list(criteria or [])
    if not criteria:
        return None
    if len(criteria) > ll.MAX_EVENTS:
        raise ValueError(f"criteria: at most {ll.MAX_EVENTS} (got {len(criteria)})")
    events = []
    for i, c in enumerate(criteria):
        if not isinstance(c, (tuple, list)) or len(c) not in (2, 3):
            raise TypeError(f"criteria[{i}] must be (name, threshold) or ('mode_energy', threshold, k)")
        name = c[0]
        if not isinstance(name, str) or name not in CRITERIA:
            raise ValueError(f"criteria[{i}]: {name!r} is unknown (known: {', '.join(CRITERIA)})")
        if (len(c) == 3) != (name == "mode_energy"):
            raise ValueError(f"criteria[{i}] = {tuple(c)!r}: {name!r} takes "
                             + ("(name, threshold, k)" if name == "mode_energy" else
                                "(name, threshold), without a third element"))
        events.append((CRITERIA[name], _real(c[1], f"criteria[{i}] threshold"),
                       _int(c[2], f"criteria[{i}] mode k") if len(c) == 3 else 0))
    return ll.event_set(events)


class Integrator:
    """An integrator positioned at (t, y), with deviation vectors carried along: advance it,
    sample it, checkpoint it; nothing is stored.

    Parameters
    ----------
    lattice : Lattice
        The lattice.
    y0 : array_like
        Initial state: length 2N (orbit only), or shape (1 + k, 2N) / length 2N(1 + k) with k
        deviation vectors after the orbit.
    method : str, optional
        Integrator name (`fputlab.methods()`). Fixed-step methods ("leapfrog", "yoshida4", ...)
        use `dt`; adaptive ones ("dop853", "cvode-adams", ...) use `rtol`/`atol`.
    t0 : float, optional
        Initial time.
    dt : float, optional
        Step of the fixed-step methods (required for them); an initial step for adaptive ones.
    rtol, atol : float, optional
        Tolerances of the adaptive methods.
    max_steps : int, optional
        Most steps per call of an adaptive back end (0: its default).
    criteria : list of tuple, optional
        Stopping criteria of this run, e.g. ``[("stretch", 4.0)]`` (see `fputlab.blowup`):
        when one fires, `advance` stops at the event and `event` says which and when.
    compensated_sums : bool, optional
        ARKODE SPRKStep methods (``sprk-*``) only: compensated summation of the increments, which
        removes most of the round-off growth (ValueError for any other method). The carry of
        the summation is part of the state: `compensation` reads it, `restore` takes it.
    """

    def __init__(self, lattice: Lattice, y0, *, method: str = "yoshida4", t0: float = 0.0,
                 dt: float | None = None, rtol: float = ll.RTOL, atol: float = ll.ATOL,
                 max_steps: int = ll.MAX_STEPS, criteria=None, compensated_sums: bool = False):
        if not isinstance(lattice, Lattice):
            raise TypeError(f"lattice must be a fputlab.Lattice, got {type(lattice).__name__}")
        info = method_info(method)
        y, n_dev = lattice._state(y0, "y0")
        self.lattice, self.method, self.n_dev = lattice, method, n_dev
        self.adaptive = info["adaptive"]
        # no dt: the C default for fixed-step methods, 0 (the back end's choice) for adaptive ones
        step = _real(dt, "dt") if dt is not None else 0.0 if self.adaptive else ll.DT
        opt = ll.integrator_options(step, _real(rtol, "rtol"), _real(atol, "atol"),
                                    _int(max_steps, "max_steps", C_LONG),
                                    _compensated_sums(compensated_sums, method))
        self.compensated_sums = bool(opt.compensated_sums)
        self.dt = opt.dt
        self._h = ll.IntegratorHandle(lattice._h, method, n_dev, opt, _real(t0, "t0"), y,
                                      criteria_events(criteria))
        self._shape = (1 + n_dev, 2 * lattice.N)

    @property
    def t(self) -> float:
        """Time of the internal state (fixed-step: the last grid point reached)."""
        return self._h.time()

    @property
    def state(self) -> np.ndarray:
        """Internal state, shape (1 + n_dev, 2N)."""
        return self._h.get_state()

    @property
    def counters(self) -> dict:
        steps, force_evals = self._h.counters()
        return {"steps": steps, "force_evals": force_evals}

    @property
    def steps(self) -> int:
        """Internal step count (a checkpoint keeps it with `t` and `state`)."""
        return self._h.steps()

    @property
    def compensation(self) -> np.ndarray | None:
        """With compensated sums: the carry of the compensated summation, shape (1 + n_dev, 2N),
        which a checkpoint keeps with `steps`, `t` and `state`; None without them."""
        if not self.compensated_sums:
            return None
        return self._h.get_compensation()

    def restore(self, steps: int, t: float, state, compensation=None) -> None:
        """Continue from a checkpoint (steps, t, state[, compensation]) of an integrator made
        with the same lattice, method, options and t0: bit-for-bit for fixed-step methods (with
        compensated sums only if `compensation` is given; otherwise the carry restarts at 0)."""
        y = as_float_array(state, "state", self._shape)
        c = None
        if compensation is not None:
            if not self.compensated_sums:
                raise ValueError("compensation: this integrator does not use compensated sums")
            c = as_float_array(compensation, "compensation", self._shape)
        self._h.restore(_int(steps, "steps", C_LONG), _real(t, "t"), y)
        if c is not None:
            self._h.set_compensation(c)

    def advance(self, t: float) -> np.ndarray:
        """Integrate to t and return the state there, shape (1 + n_dev, 2N)."""
        return self._h.advance_copy(_real(t, "t"))

    def transform_deviations(self, m) -> None:
        """w_i <- sum_j m[i, j] w_j (renormalisation, Gram-Schmidt)."""
        m = as_float_array(m, "m", (self.n_dev, self.n_dev))
        if self.n_dev:
            self._h.transform_deviations(m)

    def sample(self, times, *, states: bool = False, mode_energies: bool = True,
               energies: bool = True):
        """Advance through `times`, returning (done, states, mode_energies, energies) arrays for
        the samples taken; raises IntegrationError (with the partial arrays) on failure."""
        ts = as_float_array(times, "times")
        if ts.ndim != 1:
            raise ValueError(f"times has shape {ts.shape}, expected 1-D")
        S, N = ts.size, self.lattice.N
        st = np.empty((S,) + self._shape) if states else None
        ek = np.empty((S, N)) if mode_energies else None
        en = np.empty(S) if energies else None
        cut = lambda a, k: None if a is None else a[:k]
        try:
            self.last_status, k = self._h.sample(ts, st, ek, en)
        except FputlabError as err:   # NaN/Inf, or a back end (CVODE, GSL) giving up at a blow-up
            self.last_status, k = err.status, err.done
            err.partial = (k, cut(st, k), cut(ek, k), cut(en, k))
            raise
        return k, st, ek, en

    @property
    def event(self) -> dict | None:
        """{'time', 'criterion', 'index'} if a stopping criterion stopped the integrator."""
        fired = self._h.event()
        if fired is None:
            return None
        index, t = fired
        return {"time": t, "index": index, "criterion": self._h.event_describe(index)}


@dataclass
class Run:
    """Samples of one integration. `mode_energies[i, k-1]` is E_k at `t[i]`; `states[i]` has shape
    (1 + n_dev, 2N) when stored."""
    t: np.ndarray
    mode_energies: np.ndarray
    energy: np.ndarray
    states: np.ndarray | None
    lattice: Lattice
    method: str
    dt: float
    completed: bool = True
    message: str = ""
    y0: np.ndarray = field(default=None, repr=False)
    counters: dict = field(default_factory=dict)
    event: dict | None = None       # set when a stopping criterion ended the run
    final_state: np.ndarray | None = field(default=None, repr=False)

    @property
    def relative_energy_error(self) -> np.ndarray:
        """``|E(t) - E(0)| / |E(0)|`` at the samples (meaningful for the Hamiltonian models)."""
        e0 = self.lattice.energy(self.y0)
        return np.abs(self.energy - e0) / abs(e0)

    def __repr__(self) -> str:
        from ._display import fmt, join_parts, shorten, time_span
        lat = self.lattice
        parts = [f"N={lat.N}", f"model={lat.model!r}"]
        if lat.seed is not None:
            parts.append(f"tau={lat.tau:g}, seed={lat.seed}")
        parts += [time_span(self.t), f"method={self.method!r}"]
        if math.isfinite(self.dt):
            parts.append(f"dt={self.dt:g}")
        # model 3 conserves no energy: an "energy error" would mean nothing there
        if lat.model != "nonlinear" and self.t.size and self.y0 is not None:
            parts.append(f"max rel. energy error {fmt(float(np.max(self.relative_energy_error)))}")
        if self.states is not None:
            parts.append("states[" + "x".join(map(str, self.states.shape)) + "]")
        if self.event:
            parts.append(f"stopped by {self.event['criterion']!r} at t={fmt(self.event['time'])}")
        if not self.completed:
            parts.append(f"incomplete: {shorten(self.message, 80)!r}")
        return join_parts("Run", parts)

    def to_xarray(self):
        """The samples as an ``xarray.Dataset`` with units and long names.

        Dimensions ``t`` (sample times), ``mode`` (k = 1..N), ``site`` (j = 1..N) and, when states
        were stored, ``component`` (x_1..x_N, p_1..p_N) and ``vector`` (0 = orbit, then the
        deviation vectors). The lattice, method and step are attributes.

        Returns
        -------
        xarray.Dataset

        Raises
        ------
        ImportError
            If xarray is not installed (``pip install 'fputlab[xarray]'``).
        """
        from ._display import require_xarray, variable
        xr = require_xarray()
        lat = self.lattice
        data = {"energy": variable("t", self.energy, "energy"),
                "mode_energies": variable(("t", "mode"), self.mode_energies, "mode_energies")}
        if lat.model != "nonlinear" and self.y0 is not None:
            data["relative_energy_error"] = variable("t", self.relative_energy_error,
                                                     "relative_energy_error")
        coords = {"t": variable("t", self.t, "t"),
                  "mode": variable("mode", lat.mode_numbers, "mode"),
                  "site": variable("site", np.arange(1, lat.N + 1), "site"),
                  "v": variable("site", lat.v, "v")}
        if self.states is not None:
            dims = ("t", "component") if self.states.ndim == 2 else ("t", "vector", "component")
            data["states"] = variable(dims, self.states, "states")
        attrs = {"N": lat.N, "alpha": lat.alpha, "beta": lat.beta, "model": lat.model,
                 "tau": lat.tau, "method": self.method, "dt": self.dt,
                 "completed": int(self.completed), "message": self.message}
        if lat.seed is not None:
            attrs["seed"] = lat.seed
        if self.event:
            attrs.update({"event_time": self.event["time"], "event_criterion": self.event["criterion"]})
        return xr.Dataset(data, coords=coords, attrs=attrs)


#: the most fixed steps one run may ask for: 1e13 steps are days of CPU time even at N = 8
#: (~1e8 steps/s); more is a slip in dt or t_end, not a run (the C core's own limit is 9e18)
MAX_FIXED_STEPS = 1e13


def check_steps(span: float, dt: float | None, name: str, value: float) -> None:
    """Refuse, before it starts, a fixed-step run over `span` that no whole step of dt fits
    (it used to "complete" at t = 0) or that needs more than `MAX_FIXED_STEPS` steps (it would
    run, in segments, for months)."""
    if dt is None:
        return
    dt = _positive_real(dt, "dt")
    if span > 0 and dt > span:
        raise ValueError(f"dt = {dt:g} is longer than the whole run ({name} = {value:g}): not "
                         "one step fits; use a smaller dt")
    if span / dt > MAX_FIXED_STEPS:
        raise ValueError(f"{name} = {value:g} needs {span / dt:.3g} steps of dt = {dt:g}, more "
                         f"than {MAX_FIXED_STEPS:.0e}: a larger dt or a shorter run")


def _sample_times(t0: float, t_end: float, sample_every, times) -> np.ndarray:
    """The sample grid of a run (also of the modal systems in fputlab.reduction): `times`
    as given, or t0, t0 + every, ... up to t_end (every = sample_every, default (t_end - t0)/1000)."""
    if times is not None:
        if sample_every is not None:
            raise ValueError("give either times or sample_every, not both")
        ts = as_float_array(times, "times")
        if ts.ndim != 1:
            raise ValueError(f"times has shape {ts.shape}, expected 1-D")
        return ts
    if not (math.isfinite(t_end) and t_end >= t0):
        raise ValueError(f"t_end must be finite and >= t0 = {t0:g} (got {t_end:g})")
    if t_end == t0:
        return np.array([t0])
    every = (t_end - t0) / 1000 if sample_every is None else _real(sample_every, "sample_every")
    if not (math.isfinite(every) and every > 0):
        raise ValueError(f"sample_every must be finite and > 0 (got {every:g})")
    n = int(math.floor((t_end - t0) / every * (1 + 1e-12)))
    return t0 + every * np.arange(n + 1)


def integrate(lattice: Lattice, t_end: float, *, method: str = "yoshida4", dt: float | None = None,
              rtol: float = ll.RTOL, atol: float = ll.ATOL, sample_every: float | None = None,
              times=None, y0=None, deviations=None, t0: float = 0.0, store_states: bool = False,
              stop_on=None, chunk: int = 4096, on_failure: str = "raise",
              progress: bool = False, compensated_sums: bool = False) -> Run:
    """Integrate a lattice from `y0` to `t_end`, sampling mode energies and energy on the way.

    Parameters
    ----------
    lattice : Lattice
        The lattice (model, size, couplings, variability).
    t_end : float
        Final time (finite, >= `t0`).
    method : str, optional
        Integrator name (`fputlab.methods()`): a fixed-step splitting scheme ("yoshida4", the
        default and the paper's; "leapfrog", "aba864", "srkn14a6", "aba864-harmonic"), a
        fixed-step explicit Runge-Kutta-Nystrom method ("dprkn8", "dprkn12": not symplectic,
        for short precise runs) or an adaptive method ("dop853", "dopri5", "verner65", "fehlberg87", "cvode-adams",
        "cvode-bdf", "gsl-rk8pd").
    dt : float, optional
        Step of the fixed-step methods (default 0.01); an initial step for adaptive ones.
    rtol, atol : float, optional
        Relative and absolute tolerances of the adaptive methods.
    compensated_sums : bool, optional
        ARKODE SPRKStep methods (``sprk-*``, SUNDIALS >= 6.6 builds) only: compensated summation
        of the increments, less round-off growth (ValueError for other methods).
    sample_every : float, optional
        Sampling interval (default: (t_end - t0)/1000). Exclusive with `times`.
    times : array_like, optional
        Explicit increasing sample times.
    y0 : array_like, optional
        Initial state [x, p] of length 2N (default: the paper's mode-1 state, Eq. initxi:
        x_j = sin(πj/(N+1)), p = 0).
    deviations : array_like, optional
        Initial deviation vectors, shape (k, 2N), carried with the tangent map (splitting
        schemes) or the variational equations (adaptive methods); use ``store_states=True`` to
        get them back.
    t0 : float, optional
        Initial time.
    store_states : bool, optional
        Keep the full state at every sample in ``run.states``.
    stop_on : list of tuple, optional
        Stopping criteria, e.g. ``[("stretch", 4.0), ("energy", 1.0)]`` (see `fputlab.blowup`):
        the run ends at the first crossing, located by root-finding, with ``run.event`` set and
        the state there in ``run.final_state``.
    chunk : int, optional
        Samples computed per call into the C library (memory versus call overhead).
    on_failure : {"raise", "return"}, optional
        When the state becomes NaN/Inf (a blow-up) or an adaptive back end gives up: "raise"
        raises `IntegrationError` whose ``.result`` holds the finite samples before it;
        "return" returns them with ``completed=False``.
    progress : bool, optional
        A progress bar with ETA (tqdm.auto: a widget in Jupyter, text on a terminal, nothing
        in pipes).

    Returns
    -------
    Run
        Sample times, mode energies, energies (and states), with the integrator's counters.

    Raises
    ------
    ValueError, TypeError
        Invalid arguments (the message names the parameter).
    IntegrationError
        The integration failed and ``on_failure="raise"``.

    Examples
    --------
    >>> import fputlab
    >>> run = fputlab.integrate(fputlab.Lattice(64, 0.25), 7e4, sample_every=10.0)
    >>> run.mode_energies[:, :4]          # E_1..E_4, paper Fig. 1b  # doctest: +SKIP
    """
    if not isinstance(lattice, Lattice):
        raise TypeError(f"lattice must be a fputlab.Lattice, got {type(lattice).__name__}")
    if on_failure not in ("raise", "return"):
        raise ValueError(f"on_failure must be 'raise' or 'return', got {on_failure!r}")
    _compensated_sums(compensated_sums, method)
    t0, t_end = _real(t0, "t0"), _real(t_end, "t_end")
    if not math.isfinite(t0):
        raise ValueError(f"t0 must be finite (got {t0:g})")
    if not (math.isfinite(t_end) and t_end >= t0):
        raise ValueError(f"t_end must be finite and >= t0 = {t0:g} (got {t_end:g})")
    if dt is not None:
        dt = _positive_real(dt, "dt")
    elif not method_info(method)["adaptive"]:
        dt = ll.DT
    N = lattice.N
    fixed_step = dt is not None and not method_info(method)["adaptive"]
    if fixed_step:
        last = t_end if times is None else float(np.max(as_float_array(times, "times"), initial=t0))
        check_steps(last - t0, dt, "t_end" if times is None else "times", last)
    if times is None and sample_every is None and fixed_step and (t_end - t0) / 1000 < dt:
        sample_every = dt          # the default spacing, but never below what dt can resolve
    if times is None and sample_every is not None:
        every = _real(sample_every, "sample_every")
        if math.isfinite(every) and every > 0:
            n_est = (t_end - t0) / every + 1       # memory of the samples, before any allocation
            n_dev_est = 0 if deviations is None else np.size(deviations) // (2 * N)
            check_memory(8.0 * n_est * (2 * N + 3 + (2 * N * (1 + n_dev_est) if store_states
                                                     else 0)),
                         f"{n_est:.4g} samples of a lattice of N = {N}")
    ts = _sample_times(t0, t_end, sample_every, times)
    orbit = lattice.mode_state(1, 1.0) if y0 is None else as_float_array(y0, "y0", (2 * N,))
    if deviations is not None:
        dev = as_float_array(deviations, "deviations", last=2 * N).reshape(-1, 2 * N)
        state0 = np.concatenate([orbit[None, :], dev])
    else:
        state0 = orbit[None, :]
    check_memory(8.0 * ts.size * (N + 2 + (state0.size if store_states else 0)),
                 f"{ts.size} samples of a lattice of N = {N}")
    if fixed_step and ts.size > 1:
        # a fixed-step method only reaches multiples of dt: samples closer than dt would repeat
        # the same grid state under different times
        gaps = np.diff(np.concatenate([[t0], ts]))
        small = gaps[gaps > 0]
        if small.size and small.min() < dt * (1 - 1e-9):
            raise ValueError(f"dt = {dt:g} is larger than the sample spacing {small.min():g}: a "
                             "fixed-step method only reaches multiples of dt (use a smaller dt or "
                             "sample less often)")
    criteria_events(stop_on)       # bad criteria raise here, before anything runs
    chunk = _int(chunk, "chunk")
    if chunk < 1:
        raise ValueError(f"chunk must be >= 1 (got {chunk})")
    return _integrate(lattice, ts, state0, orbit, method, t0, dt, rtol, atol, store_states,
                      chunk, on_failure, progress, stop_on, compensated_sums)


def _integrate(lattice, ts, state0, orbit, method, t0, dt, rtol, atol, store_states, chunk,
               on_failure, progress=False, criteria=None, compensated_sums=False):
    N = lattice.N
    integ = Integrator(lattice, state0, method=method, t0=t0, dt=dt, rtol=rtol, atol=atol,
                       criteria=criteria, compensated_sums=compensated_sums)
    parts = {"t": [], "ek": [], "en": [], "st": []}
    message, completed, status = "", True, ll.ERR_NONFINITE
    bar = None
    if progress:
        from tqdm.auto import tqdm
        bar = tqdm(total=float(ts[-1] - t0), desc=f"integrate N={N}", unit="t", disable=None,
                   bar_format="{l_bar}{bar}| {n:.4g}/{total:.4g} [{elapsed}<{remaining}]")
    # Segments of ~0.2 s (C calls do not see Ctrl-C): blocks of samples, and for fixed-step
    # methods also pieces of a long gap before a sample (grid states do not depend on pauses).
    pacer = Pacer(first_span(dt, N, integ.n_dev))
    can_pause = not integ.adaptive
    event_hit, interrupted = False, False
    start = 0
    try:
        while start < ts.size:
            while can_pause and ts[start] - integ.t > pacer.span:
                t_before, clock = integ.t, time.perf_counter()
                integ.advance(integ.t + pacer.span)
                pacer.record(integ.t - t_before, time.perf_counter() - clock)
                if bar is not None:
                    bar.update(float(integ.t - t0) - bar.n)
                if integ.event:
                    event_hit = True
                    break
            if event_hit:
                break
            limit = min(ts.size, start + chunk)
            stop = start + 1 + int(np.searchsorted(ts[start + 1:limit], integ.t + pacer.span,
                                                   side="right"))
            block = ts[start:stop]
            t_before, clock = integ.t, time.perf_counter()
            try:
                k, st, ek, en = integ.sample(block, states=store_states)
            except FputlabError as err:
                if not hasattr(err, "partial"):
                    raise
                k, st, ek, en = err.partial
                completed, message, status = False, str(err), err.status
            pacer.record(integ.t - t_before, time.perf_counter() - clock)
            parts["t"].append(block[:k])
            parts["ek"].append(ek[:k])
            parts["en"].append(en[:k])
            if store_states:
                parts["st"].append(st[:k])
            if bar is not None and k:
                bar.update(float(block[k - 1] - t0) - bar.n)
            start = stop
            if not completed or integ.last_status == ll.EVENT:
                break
    except FputlabError as err:          # NaN/Inf or a back end giving up between samples
        completed, message, status = False, str(err), err.status
    except KeyboardInterrupt:
        interrupted, completed = True, False
        message = f"interrupted (Ctrl-C) at t = {integ.t:.10g}"
    finally:
        if bar is not None:
            bar.close()
    cat = lambda xs, shape: np.concatenate(xs) if xs else np.empty(shape)
    states = cat(parts["st"], (0, 1 + integ.n_dev, 2 * N)) if store_states else None
    if states is not None and integ.n_dev == 0:
        states = states[:, 0, :]
    run = Run(t=cat(parts["t"], (0,)), mode_energies=cat(parts["ek"], (0, N)),
              energy=cat(parts["en"], (0,)), states=states, lattice=lattice, method=method,
              dt=dt if dt is not None else float("nan"), completed=completed, message=message,
              y0=orbit.copy(), counters=integ.counters, event=integ.event,
              final_state=integ.state if integ.n_dev else integ.state[0])
    if interrupted:
        raise Interrupted(message, run)
    if not completed and on_failure == "raise":
        raise IntegrationError(message, status, run)
    return run


def _lattice_integrate(self: Lattice, t_end: float, *, method: str = "yoshida4",
                       dt: float | None = None, rtol: float = ll.RTOL, atol: float = ll.ATOL,
                       sample_every: float | None = None, times=None, y0=None, deviations=None,
                       t0: float = 0.0, store_states: bool = False, stop_on=None,
                       chunk: int = 4096, on_failure: str = "raise",
                       progress: bool = False, compensated_sums: bool = False) -> Run:
    """Integrate this lattice: ``fputlab.integrate(self, t_end, ...)``.

    Parameters
    ----------
    t_end : float
        Final time (finite, >= `t0`).
    method : str, optional
        Integrator name (`fputlab.methods()`); default "yoshida4", the paper's.
    dt : float, optional
        Step of the fixed-step methods (default 0.01); an initial step for adaptive ones.
    rtol, atol : float, optional
        Tolerances of the adaptive methods.
    sample_every : float, optional
        Sampling interval (default: (t_end - t0)/1000). Exclusive with `times`.
    times : array_like, optional
        Explicit increasing sample times.
    y0 : array_like, optional
        Initial state [x, p], length 2N (default: the paper's mode-1 state, Eq. initxi).
    deviations : array_like, optional
        Initial deviation vectors, shape (k, 2N).
    t0 : float, optional
        Initial time.
    store_states : bool, optional
        Keep the full state at every sample.
    stop_on : list of tuple, optional
        Stopping criteria, e.g. ``[("stretch", 4.0)]`` (see `fputlab.blowup`).
    chunk : int, optional
        Samples computed per call into the C library.
    on_failure : {"raise", "return"}, optional
        What a blow-up (NaN/Inf state) does: raise `IntegrationError` or return the finite
        samples with ``completed=False``.
    progress : bool, optional
        A progress bar with ETA (tqdm.auto).
    compensated_sums : bool, optional
        SPRKStep methods (``sprk-*``) only: compensated summation (ValueError otherwise).

    Returns
    -------
    Run

    See Also
    --------
    fputlab.integrate : the same, with the details of every parameter.
    """
    return integrate(self, t_end, method=method, dt=dt, rtol=rtol, atol=atol,
                     sample_every=sample_every, times=times, y0=y0, deviations=deviations,
                     t0=t0, store_states=store_states, stop_on=stop_on, chunk=chunk,
                     on_failure=on_failure, progress=progress,
                     compensated_sums=compensated_sums)


# The convenience method of the model layer's Lattice, defined here so that fputlab.lattice
# never imports this module (the layers import downwards only).
_lattice_integrate.__name__ = "integrate"
_lattice_integrate.__qualname__ = "Lattice.integrate"
Lattice.integrate = _lattice_integrate


def iter_samples(lattice: Lattice, times, *, y0=None, deviations=None, method: str = "yoshida4",
                 t0: float = 0.0, dt: float | None = None, rtol: float = ll.RTOL,
                 atol: float = ll.ATOL,
                 compensated_sums: bool = False) -> Iterator[tuple[float, np.ndarray]]:
    """Stream (t, state) pairs without keeping the trajectory.

    Parameters
    ----------
    lattice : Lattice
        The lattice.
    times : array_like
        Increasing sample times.
    y0 : array_like, optional
        Initial orbit state, length 2N (default: the paper's mode-1 state).
    deviations : array_like, optional
        Initial deviation vectors, shape (k, 2N).
    method : str, optional
        Integrator name (`fputlab.methods()`).
    t0 : float, optional
        Initial time.
    dt : float, optional
        Step of the fixed-step methods (default 0.01).
    rtol, atol : float, optional
        Tolerances of the adaptive methods.
    compensated_sums : bool, optional
        SPRKStep methods (``sprk-*``) only: compensated summation (see `Integrator`).

    Yields
    ------
    t : float
        The sample time.
    state : numpy.ndarray
        The state at `t`, shape (1 + k, 2N).
    """
    N = lattice.N
    orbit = lattice.mode_state() if y0 is None else as_float_array(y0, "y0", (2 * N,))
    state0 = orbit[None, :] if deviations is None else np.concatenate(
        [orbit[None, :], as_float_array(deviations, "deviations", last=2 * N).reshape(-1, 2 * N)])
    if dt is None and not method_info(method)["adaptive"]:
        dt = ll.DT
    integ = Integrator(lattice, state0, method=method, t0=t0, dt=dt, rtol=rtol, atol=atol,
                       compensated_sums=compensated_sums)
    for t in as_float_array(times, "times"):
        yield float(t), integ.advance(t)
