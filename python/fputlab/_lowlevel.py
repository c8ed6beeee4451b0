"""The low-level layer: 1:1 wrappers of the C library's handles and calls (as h5py's low-level
layer wraps libhdf5). Besides `_native`, `_errors` and `_arrays`, this is the only module that
touches `lib` and `ffi`; every other module calls it.

Conventions: a handle class owns one C handle (created in ``__init__``, freed by ``close()``,
by leaving a ``with`` block, or when garbage-collected); arrays go in as C-contiguous float64
numpy arrays (checked by the callers, see `fputlab._arrays.as_float_array`) and come out as
new numpy arrays or are written into arrays passed as ``out``; a negative status raises the
matching exception with the C message (`fputlab._errors.check`), a non-negative one is
returned when it carries information (``FPL_EVENT``, a located blow-up). Parameter checks that
name the user's argument stay in the modules above; this layer only converts and calls.

Defaults come from C once, at import: `DT`, `RTOL`, `ATOL`, `MAX_STEPS` from
``fpl_integrator_options_init`` and `CHAOS_DEFAULTS` from ``fpl_chaos_options_init``."""
from __future__ import annotations

import os

import numpy as np

from ._arrays import ptr
from ._errors import FputlabError, check, last_error
from ._native import ffi, lib

__all__ = [
    "VERSION", "DT", "RTOL", "ATOL", "MAX_STEPS", "CHAOS_DEFAULTS", "CHAOS_N_ACCUMULATORS",
    "MODEL_CODES", "BOUNDARY_CODES", "DISORDER_CODES", "EVENT_KINDS", "MAX_EVENTS", "EVENT",
    "ERR_NONFINITE", "ARG_ERRORS",
    "model_name", "method_names", "method_info", "chaos_batch_method_names", "orbit_class_name",
    "disorder_draw", "disorder_standard", "modes_omega",
    "integrator_options", "chaos_options", "chaos_result", "chaos_batch_options", "event_set",
    "LatticeHandle", "IntegratorHandle", "ChaosHandle", "ChaosBatchHandle", "GalerkinHandle",
    "RunInfo", "ResultsHandle", "results_verify", "checkpoint_write", "checkpoint_load",
    "checkpoint_peek", "chaos_classify", "chaos_sali", "chaos_gali", "splitting_lookup",
    "reduction_coefficients", "reduction_quadratic_forms", "reduction_moments",
    "reduction_two_mode_run", "last_error",
]


def _string(p) -> str:
    return ffi.string(p).decode() if p != ffi.NULL else ""


def _nul(arr):
    """double* of an array, NULL for None or an empty array."""
    return ptr(arr) if arr is not None and arr.size else ffi.NULL


# ---- constants and defaults (read from C once) -------------------------------------------------

#: version of the C library
VERSION = _string(lib.fpl_version())

_io = ffi.new("fpl_integrator_options *")
lib.fpl_integrator_options_init(_io)
#: defaults of fpl_integrator_options_init: step of the fixed-step methods, tolerances of the
#: adaptive ones, most steps per call (0: the back end's default)
DT, RTOL, ATOL, MAX_STEPS = float(_io.dt), float(_io.rtol), float(_io.atol), int(_io.max_steps)
_co = ffi.new("fpl_chaos_options *")
lib.fpl_chaos_options_init(_co)
#: defaults of fpl_chaos_options_init (t_end is NaN there: it has no default)
CHAOS_DEFAULTS = {name: getattr(_co, name) for name in (
    "renorm_interval", "n_samples", "t_first_sample", "n_dev", "sali_threshold",
    "stop_when_chaotic", "seed", "blowup_stretch")}
del _io, _co

#: length of the accumulator vector of fpl_chaos_save / fpl_chaos_restore
CHAOS_N_ACCUMULATORS = int(lib.FPL_CHAOS_N_ACCUMULATORS)
#: model names -> C codes (the paper's equations in fputlab.lattice.MODELS' comments)
MODEL_CODES = {"homogeneous": lib.FPL_MODEL_HOMOGENEOUS, "hamiltonian": lib.FPL_MODEL_HAMILTONIAN,
               "nonlinear": lib.FPL_MODEL_NONLINEAR, "toda": lib.FPL_MODEL_TODA}
#: boundary-condition names -> C codes
BOUNDARY_CODES = {"fixed": lib.FPL_BOUNDARY_FIXED, "periodic": lib.FPL_BOUNDARY_PERIODIC}
#: disorder names -> C codes
DISORDER_CODES = {"gaussian": lib.FPL_DISORDER_GAUSSIAN,
                  "truncated": lib.FPL_DISORDER_TRUNCATED_GAUSSIAN,
                  "uniform": lib.FPL_DISORDER_UNIFORM}
#: stopping-criterion names -> C kinds
EVENT_KINDS = {"energy": lib.FPL_EVENT_ENERGY, "displacement": lib.FPL_EVENT_MAX_DISPLACEMENT,
               "stretch": lib.FPL_EVENT_MAX_STRETCH, "mode_energy": lib.FPL_EVENT_MODE_ENERGY}
#: most stopping criteria in one set (fpl_event_set)
MAX_EVENTS = len(ffi.new("fpl_event_set *").kind)
#: informational status: a stopping criterion fired
EVENT = int(lib.FPL_EVENT)
#: error statuses of a bad argument (ValueError in Python)
ARG_ERRORS = (int(lib.FPL_ERR_ARG), int(lib.FPL_ERR_UNKNOWN))
#: error status: the state became NaN/Inf
ERR_NONFINITE = int(lib.FPL_ERR_NONFINITE)


def model_name(code: int) -> str:
    """fpl_model_name."""
    return _string(lib.fpl_model_name(code))


def method_names() -> list[str]:
    """fpl_method_name for every method (fpl_method_count)."""
    return [_string(lib.fpl_method_name(i)) for i in range(lib.fpl_method_count())]


def chaos_batch_method_names() -> list[str]:
    """fpl_chaos_batch_method_name for every batch method (fpl_chaos_batch_method_count)."""
    return [_string(lib.fpl_chaos_batch_method_name(i))
            for i in range(lib.fpl_chaos_batch_method_count())]


def method_info(method: str) -> tuple[int, bool]:
    """fpl_method_info: (order, adaptive)."""
    order, adaptive = ffi.new("int *"), ffi.new("int *")
    check(lib.fpl_method_info(method.encode(), order, adaptive))
    return order[0], bool(adaptive[0])


def orbit_class_name(code: int) -> str:
    """fpl_orbit_class_name."""
    return _string(lib.fpl_orbit_class_name(code))


def disorder_draw(kind: int, tau: float, seed: int, N: int) -> np.ndarray:
    """fpl_disorder_draw: v (length N)."""
    v = np.empty(max(N, 0))
    check(lib.fpl_disorder_draw(kind, tau, seed, N, _nul(v)))
    return v


def disorder_standard(kind: int, seed: int, N: int, out: np.ndarray) -> None:
    """fpl_disorder_standard: the standardised draws z into `out` (length N)."""
    check(lib.fpl_disorder_standard(kind, seed, N, ptr(out)))


def modes_omega(N: int) -> np.ndarray:
    """fpl_modes_omega: omega_k, k = 1..N."""
    out = np.empty(max(N, 1))
    check(lib.fpl_modes_omega(N, ptr(out)))
    return out


# ---- option structs ------------------------------------------------------------------------

def integrator_options(dt: float = DT, rtol: float = RTOL, atol: float = ATOL,
                       max_steps: int = MAX_STEPS, compensated_sums: int = 0):
    """An fpl_integrator_options (fpl_integrator_options_init, then the given values). Stopping
    criteria (its `events` field) are given to the handle that creates the run: C copies them
    at create, so they need to live only that long."""
    opt = ffi.new("fpl_integrator_options *")
    lib.fpl_integrator_options_init(opt)
    opt.dt, opt.rtol, opt.atol, opt.max_steps = dt, rtol, atol, max_steps
    opt.compensated_sums = compensated_sums
    return opt


def _with_events(options, events, create):
    """Run create() with `events` (an `event_set` or None) in options.events, which points
    at it only while C copies it."""
    options.events = ffi.NULL if events is None else events
    try:
        return create()
    finally:
        options.events = ffi.NULL


def chaos_options(t_end: float, **values):
    """An fpl_chaos_options (fpl_chaos_options_init, then t_end and the given fields)."""
    co = ffi.new("fpl_chaos_options *")
    lib.fpl_chaos_options_init(co)
    co.t_end = t_end
    for name, value in values.items():
        setattr(co, name, value)
    return co


def chaos_result():
    """An empty fpl_chaos_result (filled by `ChaosHandle.get_result`)."""
    return ffi.new("fpl_chaos_result *")


def chaos_batch_options(t_end: float, **values):
    """An fpl_chaos_batch_options (fpl_chaos_batch_options_init, then t_end and the given
    fields)."""
    bo = ffi.new("fpl_chaos_batch_options *")
    lib.fpl_chaos_batch_options_init(bo)
    bo.chaos.t_end = t_end
    for name, value in values.items():      # the chaos options are a member (bo.chaos)
        setattr(bo if name == "compact" else bo.chaos, name, value)
    return bo


def event_set(criteria) -> object:
    """An fpl_event_set from [(kind code, threshold, mode k)] (at most MAX_EVENTS)."""
    ev = ffi.new("fpl_event_set *")
    for i, (kind, threshold, mode) in enumerate(criteria):
        ev.kind[i], ev.threshold[i], ev.mode[i] = kind, threshold, mode
    ev.n = len(criteria)
    return ev


# ---- handles ---------------------------------------------------------------------------------

class _Handle:
    """One owned C handle: `ptr` is the cdata, freed by close(), a with block or the GC."""
    _free = None          # the fpl_x_free function
    _ctype = ""           # "fpl_x"

    def _own(self, cdata) -> None:
        free, ctype = type(self)._free, type(self)._ctype
        self.ptr = ffi.gc(cdata, lambda h: free(ffi.new(f"{ctype} **", h)))

    def close(self) -> None:
        """Free the C handle now (the object must not be used afterwards)."""
        if getattr(self, "ptr", None) is not None:
            ffi.release(self.ptr)
            self.ptr = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


class LatticeHandle(_Handle):
    """fpl_lattice: create from (N, alpha, beta, model code, v, boundary code)."""
    _free, _ctype = lib.fpl_lattice_free, "fpl_lattice"

    def __init__(self, N: int, alpha: float, beta: float, model: int, v: np.ndarray,
                 boundary: int = lib.FPL_BOUNDARY_FIXED):
        out = ffi.new("fpl_lattice **")
        check(lib.fpl_lattice_create_ex(N, alpha, beta, model, ptr(v), boundary, out))
        self._own(out[0])
        self.N = N
        self.boundary = int(lib.fpl_lattice_boundary(self.ptr))

    def errmsg(self) -> str:
        return _string(lib.fpl_lattice_errmsg(self.ptr))

    def barrier(self) -> tuple[float, float]:
        """fpl_lattice_barrier: (lower, upper), -inf / inf where there is none."""
        lo, up = ffi.new("double *"), ffi.new("double *")
        self.check(lib.fpl_lattice_barrier(self.ptr, lo, up))
        return float(lo[0]), float(up[0])

    def check(self, status: int) -> int:
        """`fputlab._errors.check` with this handle's message."""
        return check(status, self.errmsg)

    def get_v(self) -> np.ndarray:
        v = np.empty(self.N)
        self.check(lib.fpl_lattice_get_v(self.ptr, ptr(v), self.N))
        return v

    def force(self, x: np.ndarray) -> np.ndarray:
        f = np.empty(self.N)
        self.check(lib.fpl_lattice_force(self.ptr, ptr(x), ptr(f)))
        return f

    def force_jacobian(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(lower, diag, upper), each of length N (the last entries of lower/upper unused)."""
        lo, di, up = np.zeros(self.N), np.empty(self.N), np.zeros(self.N)
        self.check(lib.fpl_lattice_force_jacobian(self.ptr, ptr(x), ptr(lo), ptr(di), ptr(up)))
        return lo, di, up

    def tangent_force(self, x: np.ndarray, k: int, dx: np.ndarray, out: np.ndarray) -> None:
        self.check(lib.fpl_lattice_tangent_force(self.ptr, ptr(x), k, ptr(dx), ptr(out)))

    def rhs(self, y: np.ndarray, n_dev: int) -> np.ndarray:
        out = np.empty_like(y)
        self.check(lib.fpl_lattice_rhs(self.ptr, ptr(y), n_dev, ptr(out)))
        return out

    def jacobian_dense(self, y: np.ndarray, n_dev: int) -> np.ndarray:
        jac = np.empty((y.size, y.size))
        self.check(lib.fpl_lattice_jacobian_dense(self.ptr, ptr(y), n_dev, ptr(jac)))
        return jac

    def energy(self, y: np.ndarray) -> float:
        e = ffi.new("double *")
        self.check(lib.fpl_lattice_energy(self.ptr, ptr(y), e))
        return e[0]

    def velocity(self, y: np.ndarray) -> np.ndarray:
        out = np.empty(self.N)
        self.check(lib.fpl_lattice_velocity(self.ptr, ptr(y), ptr(out)))
        return out

    def modes_frequencies(self) -> np.ndarray:
        """fpl_modes_frequencies: omega in the order of the mode energies."""
        out = np.empty(self.N)
        self.check(lib.fpl_modes_frequencies(self.ptr, ptr(out)))
        return out

    def modes_transform(self, x: np.ndarray, out: np.ndarray) -> None:
        self.check(lib.fpl_modes_transform(self.ptr, ptr(x), ptr(out)))

    def modes_energies(self, y: np.ndarray, out: np.ndarray) -> None:
        self.check(lib.fpl_modes_energies(self.ptr, ptr(y), ptr(out)))

    def initial_state(self, k: int, amplitude: float, coupled: bool = False) -> np.ndarray:
        """fpl_modes_initial_state (or _coupled): a single-mode state (2N,)."""
        y = np.empty(2 * self.N)
        fn = lib.fpl_modes_initial_state_coupled if coupled else lib.fpl_modes_initial_state
        self.check(fn(self.ptr, k, amplitude, ptr(y)))
        return y


class IntegratorHandle(_Handle):
    """fpl_integrator on a lattice: create(lattice, method, n_dev, options, t0, y0 (1+n_dev, 2N),
    events = an `event_set` or None); or a view of the integrator inside a chaos handle
    (`ChaosHandle.integrator`, not owned)."""
    _free, _ctype = lib.fpl_integrator_free, "fpl_integrator"

    def __init__(self, lattice: LatticeHandle, method: str, n_dev: int, options, t0: float,
                 y0: np.ndarray, events=None):
        out = ffi.new("fpl_integrator **")
        _with_events(options, events, lambda: check(lib.fpl_integrator_create(
            lattice.ptr, method.encode(), n_dev, options, t0, ptr(y0), out)))
        self._own(out[0])
        self.lattice, self.shape = lattice, (1 + n_dev, 2 * lattice.N)
        self._state_buffer()

    @classmethod
    def _view(cls, cdata, lattice: LatticeHandle, n_dev: int, owner) -> "IntegratorHandle":
        self = cls.__new__(cls)
        self.ptr, self.lattice, self.shape = cdata, lattice, (1 + n_dev, 2 * lattice.N)
        self._owner = owner               # keeps the handle that owns the integrator alive
        self._state_buffer()
        return self

    def _state_buffer(self) -> None:
        # advance_copy's output buffer and its double*, made once: a pointer from a numpy array
        # (ffi.from_buffer + cast) costs ~2 us, more than the rest of a short advance
        self._out = np.empty(self.shape)
        self._out_ptr = ptr(self._out)

    def close(self) -> None:
        if getattr(self, "_owner", None) is None:
            super().close()

    def errmsg(self) -> str:
        return _string(lib.fpl_integrator_errmsg(self.ptr))

    def check(self, status: int) -> int:
        return check(status, self.errmsg)

    def time(self) -> float:
        return lib.fpl_integrator_time(self.ptr)

    def steps(self) -> int:
        return int(lib.fpl_integrator_steps(self.ptr))

    def counters(self) -> tuple[int, int]:
        """(steps, force evaluations)."""
        s, f = ffi.new("long *"), ffi.new("long *")
        lib.fpl_integrator_counters(self.ptr, s, f)
        return s[0], f[0]

    def get_state(self) -> np.ndarray:
        y = np.empty(self.shape)
        self.check(lib.fpl_integrator_get_state(self.ptr, ptr(y)))
        return y

    def restore(self, steps: int, t: float, state: np.ndarray) -> None:
        self.check(lib.fpl_integrator_restore(self.ptr, steps, t, ptr(state)))

    def get_compensation(self) -> np.ndarray:
        """fpl_integrator_get_compensation: the compensated sums' carry, shape of the state."""
        c = np.empty(self.shape)
        self.check(lib.fpl_integrator_get_compensation(self.ptr, ptr(c)))
        return c

    def set_compensation(self, c: np.ndarray) -> None:
        """fpl_integrator_set_compensation."""
        self.check(lib.fpl_integrator_set_compensation(self.ptr, ptr(c)))

    def advance(self, t: float, out: np.ndarray | None = None) -> int:
        """fpl_integrator_advance to t, the state there into `out` (None: not copied); returns
        the status (FPL_EVENT if a criterion fired)."""
        return self.check(lib.fpl_integrator_advance(self.ptr, t, _nul(out)))

    def advance_copy(self, t: float) -> np.ndarray:
        """fpl_integrator_advance to t; returns the state there as a new array of shape
        `shape` (through the handle's own output buffer: per call the C call and one copy)."""
        status = lib.fpl_integrator_advance(self.ptr, t, self._out_ptr)
        if status < 0:
            self.check(status)
        return self._out.copy()

    def transform_deviations(self, m: np.ndarray) -> None:
        self.check(lib.fpl_integrator_transform_deviations(self.ptr, ptr(m)))

    def sample(self, times: np.ndarray, states: np.ndarray | None, mode_energies: np.ndarray | None,
               energies: np.ndarray | None) -> tuple[int, int]:
        """fpl_integrator_sample into the given arrays (None: not wanted); returns (status,
        samples taken). A negative status raises with ``.done`` = the samples taken."""
        done = ffi.new("int *")
        status = lib.fpl_integrator_sample(self.ptr, _nul(times), times.size, _nul(states),
                                           _nul(mode_energies), _nul(energies), done)
        try:
            self.check(status)
        except FputlabError as err:
            err.done = done[0]
            raise
        return status, done[0]

    def event(self) -> tuple[int, float] | None:
        """(criterion index, time) if a stopping criterion stopped the integrator."""
        index, t = ffi.new("int *"), ffi.new("double *")
        if not lib.fpl_integrator_event(self.ptr, index, t):
            return None
        return index[0], t[0]

    def event_describe(self, index: int) -> str:
        """fpl_integrator_event_describe: criterion `index` in words."""
        return _string(lib.fpl_integrator_event_describe(self.ptr, index))


class ChaosHandle(_Handle):
    """fpl_chaos: create(lattice, method, integrator options, t0, y0 (2N,), w0 (n_dev, 2N) or
    None, chaos options). The status of a create that fails is raised."""
    _free, _ctype = lib.fpl_chaos_free, "fpl_chaos"

    def __init__(self, lattice: LatticeHandle, method: str, options, t0: float, y0: np.ndarray,
                 w0: np.ndarray | None, chaos_opts, events=None):
        out = ffi.new("fpl_chaos **")
        _with_events(options, events, lambda: check(lib.fpl_chaos_create(
            lattice.ptr, method.encode(), options, t0, ptr(y0), _nul(w0), chaos_opts, out)))
        self._own(out[0])
        self.lattice, self.n_dev = lattice, int(chaos_opts.n_dev)

    def integrator(self) -> IntegratorHandle:
        """fpl_chaos_integrator: the integrator inside (owned by this handle)."""
        return IntegratorHandle._view(lib.fpl_chaos_integrator(self.ptr), self.lattice,
                                      self.n_dev, self)

    def advance(self, t: float, t_out: np.ndarray, mle: np.ndarray, sali: np.ndarray,
                gali: np.ndarray) -> int:
        """fpl_chaos_advance to t, samples into the arrays; returns the status (> 0: the orbit
        blew up, `last_error()` says when and why)."""
        return check(lib.fpl_chaos_advance(self.ptr, t, ptr(t_out), ptr(mle), ptr(sali),
                                           ptr(gali)))

    def get_result(self, res=None):
        """fpl_chaos_get_result into `res` (a new fpl_chaos_result if None); returns it."""
        res = ffi.new("fpl_chaos_result *") if res is None else res
        check(lib.fpl_chaos_get_result(self.ptr, res))
        return res

    def done(self) -> bool:
        return bool(lib.fpl_chaos_done(self.ptr))

    def save(self) -> np.ndarray:
        acc = np.empty(CHAOS_N_ACCUMULATORS)
        check(lib.fpl_chaos_save(self.ptr, ptr(acc)))
        return acc

    def restore(self, acc: np.ndarray) -> None:
        check(lib.fpl_chaos_restore(self.ptr, ptr(acc)))


class ChaosBatchHandle(_Handle):
    """fpl_chaos_batch: create(lattices, method, integrator options, t0, y0 (R, 2N), w0 or None,
    batch options)."""
    _free, _ctype = lib.fpl_chaos_batch_free, "fpl_chaos_batch"

    def __init__(self, lattices, method: str, options, t0: float, y0: np.ndarray,
                 w0: np.ndarray | None, batch_opts, events=None):
        self._lattices = list(lattices)
        handles = ffi.new("fpl_lattice *[]", [lat.ptr for lat in self._lattices])
        out = ffi.new("fpl_chaos_batch **")
        _with_events(options, events, lambda: check(lib.fpl_chaos_batch_create(
            handles, len(self._lattices), method.encode(), options, t0, ptr(y0), _nul(w0),
            batch_opts, out)))
        self._own(out[0])

    def advance(self, t: float, t_out: np.ndarray, mle: np.ndarray, sali: np.ndarray,
                gali: np.ndarray) -> int:
        return check(lib.fpl_chaos_batch_advance(self.ptr, t, ptr(t_out), ptr(mle), ptr(sali),
                                                 ptr(gali)))

    def time(self) -> float:
        return lib.fpl_chaos_batch_time(self.ptr)

    def done(self) -> bool:
        return bool(lib.fpl_chaos_batch_done(self.ptr))

    def get_result(self, orbit: int, res=None):
        res = ffi.new("fpl_chaos_batch_result *") if res is None else res
        check(lib.fpl_chaos_batch_get_result(self.ptr, orbit, res))
        return res

    def message(self, orbit: int) -> str:
        return _string(lib.fpl_chaos_batch_message(self.ptr, orbit))

    def save_size(self) -> int:
        return int(lib.fpl_chaos_batch_save_size(self.ptr))

    def save(self) -> np.ndarray:
        buf = np.empty(self.save_size())
        check(lib.fpl_chaos_batch_save(self.ptr, ptr(buf)))
        return buf

    def restore(self, buf: np.ndarray) -> None:
        check(lib.fpl_chaos_batch_restore(self.ptr, ptr(buf), buf.size))


class GalerkinHandle(_Handle):
    """fpl_galerkin: the lattice truncated to its first M normal modes."""
    _free, _ctype = lib.fpl_galerkin_free, "fpl_galerkin"

    def __init__(self, lattice: LatticeHandle, M: int):
        out = ffi.new("fpl_galerkin **")
        check(lib.fpl_galerkin_create(lattice.ptr, M, out))
        self._own(out[0])
        self.lattice, self.M = lattice, M

    def errmsg(self) -> str:
        return _string(lib.fpl_galerkin_errmsg(self.ptr))

    def acceleration(self, Q: np.ndarray) -> np.ndarray:
        out = np.empty(self.M)
        check(lib.fpl_galerkin_acceleration(self.ptr, ptr(Q), ptr(out)), self.errmsg)
        return out

    def run(self, scheme, z0: np.ndarray, t0: float, dt: float, times: np.ndarray,
            states: np.ndarray) -> tuple[int, int]:
        """fpl_galerkin_run: samples (Q, P) into `states`; returns (status, samples taken)
        unchecked (a blow-up keeps the finite samples: the caller decides)."""
        done = ffi.new("int *")
        status = lib.fpl_galerkin_run(scheme, self.ptr, ptr(z0), t0, dt, _nul(times), times.size,
                                      ffi.NULL, ptr(states), done)
        return status, done[0]


# ---- results files and checkpoints -----------------------------------------------------------

class RunInfo:
    """fpl_run_info (fpl_run_info_init, then the given fields) with the C strings it points to
    kept alive: `c` is the struct."""

    def __init__(self, **fields):
        self._keep = []
        self.c = ffi.new("fpl_run_info *")
        lib.fpl_run_info_init(self.c)
        for name, value in fields.items():
            if isinstance(value, str):
                value = ffi.new("char[]", value.encode())
                self._keep.append(value)
            setattr(self.c, name, value)


class ResultsHandle:
    """fpl_results: a results file being written (create, or resume cut back to a checkpoint);
    closed by close() or a with block."""

    def __init__(self, path, lattice: LatticeHandle, info: RunInfo, resume_from=None):
        out = ffi.new("fpl_results **")
        if resume_from is None:
            check(lib.fpl_results_create(os.fspath(path).encode(), lattice.ptr, info.c, out))
        else:
            check(lib.fpl_results_resume(os.fspath(path).encode(), lattice.ptr, info.c,
                                         os.fspath(resume_from).encode(), out))
        self.ptr = out[0]

    def count(self) -> int:
        return int(lib.fpl_results_count(self.ptr))

    def append(self, t: float, y: np.ndarray) -> None:
        check(lib.fpl_results_append(self.ptr, t, ptr(y)))

    def append_chaos(self, t: float, mle: float, sali: float, gali: float) -> None:
        check(lib.fpl_results_append_chaos(self.ptr, t, mle, sali, gali))

    def set_status(self, status: str, message: str) -> None:
        check(lib.fpl_results_set_status(self.ptr, status.encode(), message.encode()))

    def set_event(self, t: float, criterion: str) -> None:
        check(lib.fpl_results_set_event(self.ptr, t, criterion.encode()))

    def flush(self) -> None:
        check(lib.fpl_results_flush(self.ptr))

    def close(self) -> None:
        if self.ptr is not None:
            h = ffi.new("fpl_results **", self.ptr)
            self.ptr = None
            check(lib.fpl_results_close(h))

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def results_verify(path, lattice: LatticeHandle, info: RunInfo, checkpoint) -> int:
    """fpl_results_verify: the status, unchecked (it may run in a forked child, which reports
    the status and `last_error()` to its parent)."""
    return lib.fpl_results_verify(os.fspath(path).encode(), lattice.ptr, info.c,
                                  os.fspath(checkpoint).encode())


def checkpoint_write(path, integrator: IntegratorHandle, info: RunInfo, extra: np.ndarray,
                     results: ResultsHandle | None = None) -> None:
    """fpl_checkpoint_write (atomic), with the accumulators `extra` and where `results` stands."""
    check(lib.fpl_checkpoint_write(os.fspath(path).encode(), integrator.ptr, info.c, _nul(extra),
                                   extra.size, results.ptr if results is not None else ffi.NULL))


def checkpoint_load(path, integrator: IntegratorHandle, info: RunInfo,
                    max_extra: int) -> np.ndarray:
    """fpl_checkpoint_load: restores the integrator, returns the accumulators."""
    ex = np.empty(max(max_extra, 1))
    n = ffi.new("int *")
    check(lib.fpl_checkpoint_load(os.fspath(path).encode(), integrator.ptr, info.c, ptr(ex),
                                  max_extra, n))
    return ex[:n[0]].copy()


def checkpoint_peek(path) -> tuple[float, int]:
    """fpl_checkpoint_peek: (t, step count)."""
    t, n = ffi.new("double *"), ffi.new("long *")
    check(lib.fpl_checkpoint_peek(os.fspath(path).encode(), t, n))
    return t[0], int(n[0])


# ---- chaos indicators of given vectors and classification ------------------------------------

def chaos_classify(chaotic: bool, t_chaotic: float, blew_up: bool, t_blowup: float,
                   t_final: float, t: np.ndarray, mle: np.ndarray, t_eval: float) -> str:
    """fpl_chaos_classify: the orbit's class name at t_eval (NaN: the end of the run)."""
    r = ffi.new("fpl_chaos_result *")
    r.chaotic, r.t_chaotic = chaotic, t_chaotic
    r.blew_up, r.t_blowup, r.t_final = blew_up, t_blowup, t_final
    out = ffi.new("int *")
    check(lib.fpl_chaos_classify(r, _nul(t), _nul(mle), t.size, t_eval, out))
    return orbit_class_name(out[0])


def chaos_sali(w1: np.ndarray, w2: np.ndarray) -> float:
    out = ffi.new("double *")
    check(lib.fpl_chaos_sali(ptr(w1), ptr(w2), w1.size, out))
    return out[0]


def chaos_gali(w: np.ndarray) -> float:
    out = ffi.new("double *")
    check(lib.fpl_chaos_gali(ptr(w), w.shape[0], w.shape[1], out))
    return out[0]


# ---- reduction -------------------------------------------------------------------------------

def splitting_lookup(method: str):
    """fpl_splitting_lookup: the constant scheme table of a splitting method."""
    out = ffi.new("const fpl_splitting **")
    check(lib.fpl_splitting_lookup(method.encode(), out))
    return out[0]


def reduction_coefficients(N: int, alpha: float, model: int, v: np.ndarray | None,
                           a: np.ndarray, b: np.ndarray) -> None:
    """fpl_reduction_coefficients into a (3,), b (3,); v None means v_j = 1."""
    check(lib.fpl_reduction_coefficients(N, alpha, model, _nul(v), ptr(a), ptr(b)))


def reduction_quadratic_forms(N: int, alpha: float) -> tuple[np.ndarray, np.ndarray]:
    """fpl_reduction_quadratic_forms: (diag (6, N), off (6, N-1))."""
    diag, off = np.empty((6, N)), np.empty((6, N - 1))
    check(lib.fpl_reduction_quadratic_forms(N, alpha, ptr(diag), ptr(off)))
    return diag, off


def reduction_moments(N: int, alpha: float, model: int, kind: int, tau: float,
                      mean: np.ndarray, cov: np.ndarray) -> None:
    """fpl_reduction_moments into mean (6,), cov (6, 6)."""
    check(lib.fpl_reduction_moments(N, alpha, model, kind, tau, ptr(mean), ptr(cov)))


def reduction_two_mode_run(scheme, omega: np.ndarray, a: np.ndarray, b: np.ndarray,
                           z0: np.ndarray, t0: float, dt: float, times: np.ndarray,
                           states: np.ndarray) -> tuple[int, int]:
    """fpl_reduction_two_mode_run: (Q1, Q2, P1, P2) samples into `states`; returns (status,
    samples taken) unchecked (a blow-up keeps the finite samples: the caller decides)."""
    done = ffi.new("int *")
    status = lib.fpl_reduction_two_mode_run(scheme, ptr(omega), ptr(a), ptr(b), ptr(z0), t0, dt,
                                            _nul(times), times.size, ptr(states), done)
    return status, done[0]


