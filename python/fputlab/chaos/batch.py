"""Chaos indicators for many orbits at once: the batched C kernel (include/fputlab/chaos_batch.h).

R orbits of the same N, model, alpha and beta (each its own disorder realisation and/or initial
state) are advanced together with the orbits in the vector lanes, which makes small lattices
(N <= 16) several times cheaper per orbit than one `fputlab.chaos.lyapunov` call each. Every
orbit's lambda(t), SALI(t), GALI(t) are those `lyapunov` computes for it with the same method,
dt and initial deviation vectors (bit for bit in the default build)."""
from __future__ import annotations

import dataclasses

import numpy as np

from .. import _lowlevel as ll
from .._arrays import as_float_array
from .result import ChaosResult
from .._validate import _int, _real
from ..integrate import criteria_events
from ..lattice import Lattice

__all__ = ["lyapunov_batch", "BATCH_METHODS"]

#: methods the batch kernel runs (the splitting schemes with the kinetic drift; the list is C's,
#: fpl_chaos_batch_method_name)
BATCH_METHODS = tuple(ll.chaos_batch_method_names())

#: the C defaults of the chaos options (fpl_chaos_options_init, shared by the batch handle)
_C = ll.CHAOS_DEFAULTS

_BLOWUP_REASONS = {0: "", 1: "event", 2: "non-finite", 3: "stretch"}


def _states(values, name: str, R: int, shape: tuple, default):
    """None -> default(r) per orbit; one array of shape `shape` -> the same for every orbit;
    else an array of shape (R,) + shape."""
    if values is None:
        return np.stack([as_float_array(default(r), name, shape) for r in range(R)])
    arr = as_float_array(values, name)
    if arr.shape == shape:
        return np.broadcast_to(arr, (R,) + shape).copy()
    if arr.shape != (R,) + shape:
        raise ValueError(f"{name} has shape {arr.shape}, expected {shape} or {(R,) + shape}")
    return np.ascontiguousarray(arr)


def lyapunov_batch(lattices, t_end: float, *, method: str = "yoshida4", dt: float | None = None,
                   y0=None, w0=None, n_dev: int = _C["n_dev"],
                   renorm_interval: float = _C["renorm_interval"],
                   n_samples: int = _C["n_samples"], t_first_sample: float = _C["t_first_sample"],
                   sali_threshold: float = _C["sali_threshold"], stop_when_chaotic: bool = False,
                   seed: int = _C["seed"],
                   t0: float = 0.0, criteria=None, progress: bool = False,
                   blowup_stretch: float | None = None) -> list[ChaosResult]:
    """lambda(t), SALI(t), GALI(t) of several orbits computed together; one ChaosResult each.

    Parameters
    ----------
    lattices : sequence of Lattice
        One lattice per orbit (the same object may repeat), all with the same N, model, alpha,
        beta (and stopping criteria).
    t_end : float
        Final time.
    method : str
        A splitting scheme with the kinetic drift: "leapfrog", "yoshida4" (default), "aba864",
        "srkn14a6".
    dt : float, optional
        Step (default 0.01).
    y0 : array, optional
        Initial orbits, shape (R, 2N) or (2N,) for all; default each lattice's mode_state().
    w0 : array, optional
        Initial deviation vectors, shape (R, n_dev, 2N) or (n_dev, 2N) for all; default Gaussian
        random from `seed`, the same for every orbit (as `lyapunov` with that seed).
    n_dev, renorm_interval, n_samples, t_first_sample, sali_threshold, stop_when_chaotic, seed, t0
        As in `fputlab.chaos.lyapunov` (renorm_interval must be >= dt).
    criteria : list, optional
        Stopping criteria for blow-up, as in `fputlab.blowup.blowup_time` (e.g.
        ``[("stretch", 4.0)]``), for every orbit of this run (the lattices are not changed).
        Default: none. "mode_energy" is not supported here.
    progress : bool
        A progress bar with ETA (the same computation in 100 segments).
    blowup_stretch : float, optional
        As in `fputlab.chaos.lyapunov`: a bond stretch above this at a renormalisation ends the
        orbit as a blow-up, before SALI is looked at. Default: 1/alpha (the barrier) for
        alpha > 0; a negative value switches the check off.

    Returns
    -------
    list of ChaosResult
        In the order of `lattices`. An orbit that blew up has ``completed=False``, the reason in
        ``message`` and ``chaotic=False`` unless SALI fell below the threshold on the finite orbit
        at least one renormalisation interval before the blow-up; ``params`` carries
        ``blew_up``, ``t_blowup``, ``blowup_reason`` ("event", "stretch" or "non-finite"), ``sali_final``,
        ``gali_final`` and ``mle_final``.

    Notes
    -----
    A SALI collapse is confirmed at the next renormalisation (the orbit must still be finite and
    no criterion fired); with stop_when_chaotic an orbit therefore stops one renorm_interval
    after t_chaotic, exactly as `lyapunov` does. The lanes pay off from two orbits on; one orbit
    alone costs about what `lyapunov` costs (0.9-1.2x), which is why `chaotic_fraction`, chaos
    sweeps and `fputlab.chaos.study` give a group of one orbit to the single-orbit path.
    """
    lattices = list(lattices)
    if not lattices:
        raise ValueError("lattices must hold at least one Lattice (n_orbits >= 1)")
    for r, lat in enumerate(lattices):
        if not isinstance(lat, Lattice):
            raise TypeError(f"lattices[{r}] must be a fputlab.Lattice, got {type(lat).__name__}")
    if not isinstance(method, str):
        raise TypeError(f"method must be a string, got {type(method).__name__}")
    R, N = len(lattices), lattices[0].N
    for r, lat in enumerate(lattices):
        if lat.N != N:
            raise ValueError(f"lattices[{r}]: N = {lat.N} differs from lattices[0] (N = {N}): "
                             "a batch holds orbits of one N")
    n_dev = _int(n_dev, "n_dev")
    if n_dev < 1:
        raise ValueError(f"n_dev must be >= 1 (got {n_dev})")
    events = criteria_events(criteria)      # bad criteria raise here
    y = _states(y0, "y0", R, (2 * N,), lambda r: lattices[r].mode_state())
    w = None if w0 is None else _states(w0, "w0", R, (n_dev, 2 * N), None)
    io = ll.integrator_options(ll.DT if dt is None else _real(dt, "dt"))
    seed = _int(seed, "seed")
    if seed < 0:
        raise ValueError(f"seed must be >= 0 (got {seed})")
    co = {"renorm_interval": _real(renorm_interval, "renorm_interval"),
          "n_samples": _int(n_samples, "n_samples"),
          "t_first_sample": _real(t_first_sample, "t_first_sample"), "n_dev": n_dev,
          "sali_threshold": _real(sali_threshold, "sali_threshold"),
          "stop_when_chaotic": bool(stop_when_chaotic), "seed": seed}
    if blowup_stretch is not None:
        co["blowup_stretch"] = _real(blowup_stretch, "blowup_stretch")
    bo = ll.chaos_batch_options(_real(t_end, "t_end"), **co)
    t0 = _real(t0, "t0")
    batch = ll.ChaosBatchHandle([lat._h for lat in lattices], method, io, t0, y, w, bo, events)
    S = max(bo.chaos.n_samples, 1)
    t, mle, sali, gali, megno = (np.full((R, S), np.nan) for _ in range(5))
    span = bo.chaos.t_end - t0
    if progress:
        from tqdm.auto import tqdm
        with tqdm(total=span, desc=f"chaos batch R={R} N={N}", unit="t", disable=None,
                  bar_format="{l_bar}{bar}| {n:.4g}/{total:.4g} [{elapsed}<{remaining}]") as bar:
            for k in range(1, 101):
                batch.advance(t0 + span * k / 100, t, mle, sali, gali, megno)
                bar.update(batch.time() - t0 - bar.n)
                if batch.done():
                    break
    else:
        batch.advance(bo.chaos.t_end, t, mle, sali, gali, megno)
    results = []
    res = None
    for r, lat in enumerate(lattices):
        res = batch.get_result(r, res)
        k = res.n_samples
        blew_up = bool(res.blew_up)
        params = {"N": N, "model": lat.model, "tau": lat.tau, "seed": lat.seed, "t_end": t_end,
                  "dt": io.dt, "renorm_interval": renorm_interval, "batched": True,
                  "blew_up": blew_up, "t_blowup": res.t_blowup,
                  "blowup_reason": _BLOWUP_REASONS.get(res.blowup_reason, ""),
                  "event_index": res.event_index, "mle_final": res.mle,
                  "sali_final": res.sali, "gali_final": res.gali}
        fields = {"t": t[r, :k].copy(), "mle": mle[r, :k].copy(), "sali": sali[r, :k].copy(),
                  "gali": gali[r, :k].copy(), "chaotic": bool(res.chaotic),
                  "t_chaotic": res.t_chaotic, "t_final": res.t_final, "steps": res.steps,
                  "method": method, "completed": not blew_up,
                  "message": batch.message(r),
                  "params": params}
        # fields the single-orbit result may gain (blow-up bookkeeping) are filled if present
        names = {f.name for f in dataclasses.fields(ChaosResult)}
        for name, value in (("blew_up", blew_up), ("t_blowup", res.t_blowup),
                            ("megno", megno[r, :k].copy())):
            if name in names:
                fields[name] = value
        results.append(ChaosResult(**{k_: v for k_, v in fields.items() if k_ in names}))
    return results
