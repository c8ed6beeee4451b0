"""The chaotic fraction over disorder realisations (paper Sec. 5, Figs. 12-14): many orbits of
`fputlab.chaos.lyapunov` (or of the batched kernel) on the ensemble engine."""
from __future__ import annotations

import inspect
import os
from typing import NamedTuple

from .._engine import check_ensemble, run_calls
from ..lattice import Lattice
from .batch import BATCH_METHODS, lyapunov_batch
from .result import CLASSES, ChaosResult
from .single import ENSEMBLE_DT, ENSEMBLE_METHOD, lyapunov


class OrbitRecord(NamedTuple):
    """One orbit of a chaos ensemble: its lattice size, disorder seed and result, read by name."""
    N: int
    seed: int
    result: ChaosResult


def _one_realisation(args) -> OrbitRecord:
    N, tau, seed, model, alpha, t_end, method, kwargs = args
    lat = Lattice(N, alpha, model, tau=tau, seed=seed)
    res = lyapunov(lat, t_end, method=method, **kwargs)
    return OrbitRecord(N, seed, res)


def _batch_of_realisations(args) -> list[OrbitRecord]:
    """Several realisations of one N in one batched run (fputlab.chaos.batch): the same numbers
    as `_one_realisation` for each, several times cheaper per orbit for small N."""
    N, tau, seeds, model, alpha, t_end, method, kwargs = args
    if len(seeds) == 1:      # one lane gains nothing over the single-orbit path (same numbers)
        return [_one_realisation((N, tau, seeds[0], model, alpha, t_end, method, kwargs))]
    lats = [Lattice(N, alpha, model, tau=tau, seed=s) for s in seeds]
    res = lyapunov_batch(lats, t_end, method=method, **kwargs)
    return [OrbitRecord(N, s, r) for s, r in zip(seeds, res)]


def ensemble_defaults(method: str | None, kwargs: dict) -> tuple[str, dict]:
    """(method, options) of a chaos ensemble: ENSEMBLE_METHOD at ENSEMBLE_DT unless a method is
    given, and early stop of chaotic orbits unless stop_when_chaotic is given."""
    kwargs = dict(kwargs)
    if method is None:
        method = ENSEMBLE_METHOD
        kwargs.setdefault("dt", ENSEMBLE_DT)
    kwargs.setdefault("stop_when_chaotic", True)
    return method, kwargs


def chaotic_fraction(Ns=(4, 8, 16, 32, 64), realisations: int = 30, tau: float = 10.0, *,
                     t_end: float = 1e4, model: str = "nonlinear", alpha: float = 0.25,
                     method: str | None = None, first_seed: int = 1, workers: int | None = None,
                     scheduler=None, progress: bool = False, **kwargs) -> dict:
    """Percentage of chaotic orbits over disorder realisations for each lattice size (paper
    Fig. 14: tau = 10 %, model 3, t = 1e8), and how many blew up.

    An orbit counts as chaotic when SALI falls below its threshold on the finite orbit
    (`ChaosResult.classify`); a blow-up is never counted as chaotic. The realisations run on
    the ensemble engine (`fputlab.ensemble.run_calls`: local processes, or a Dask cluster with
    `scheduler`). The splitting schemes run the orbits of one N in the vector lanes of the
    batched kernel (`fputlab.chaos.batch.lyapunov_batch`: the same numbers, several times
    cheaper for N <= 16). For t = 1e8 use the resumable `fputlab.chaos.study`.

    Parameters
    ----------
    Ns : sequence of int, optional
        Lattice sizes (each >= 2).
    realisations : int, optional
        Disorder realisations per N (>= 1), seeds ``first_seed, first_seed + 1, ...``.
    tau : float, optional
        Variability in percent (the paper's 10 %).
    t_end : float, optional
        Final time of every orbit.
    model : str, optional
        Lattice model (default "nonlinear", the paper's model 3).
    alpha : float, optional
        Cubic coupling.
    method : str, optional
        Integrator name (default: `ENSEMBLE_METHOD` at ``dt = ENSEMBLE_DT``, validated to
        classify orbits as the paper's methods do).
    first_seed : int, optional
        Disorder seed of the first realisation.
    workers : int, optional
        Local worker processes (default: all cores).
    scheduler : str or dask.distributed.Client, optional
        Run on a Dask cluster instead (an address "tcp://host:port", a Client or a cluster).
    progress : bool, optional
        A progress bar over the orbits (tqdm.auto).
    **kwargs
        Passed to `lyapunov` (dt, n_samples, sali_threshold, ...); chaotic orbits stop early
        unless ``stop_when_chaotic=False`` is given.

    Returns
    -------
    dict
        ``N`` (the sizes), ``percent`` (chaotic orbits per N, in percent), ``blowups`` (blown-up
        orbits per N), ``classes`` ({N: {class: count}} over `CLASSES`) and ``results``
        ({N: [ChaosResult, ...]} in seed order).

    Raises
    ------
    ValueError
        Empty `Ns`, a size below 2, `realisations` < 1, or an invalid option of `lyapunov`.

    Examples
    --------
    >>> from fputlab.chaos import chaotic_fraction
    >>> out = chaotic_fraction(Ns=(4, 8), realisations=4, t_end=1e3)    # doctest: +SKIP
    >>> out["percent"], out["classes"][8]                                 # doctest: +SKIP
    """
    method, kwargs = ensemble_defaults(method, kwargs)
    _, Ns, realisations = check_ensemble([tau], Ns, realisations)
    Ns = [int(N) for N in Ns]
    seeds = [first_seed + r for r in range(realisations)]
    batched = method in BATCH_METHODS and set(kwargs) <= set(
        inspect.signature(lyapunov_batch).parameters)
    if batched:    # orbits of one N in the vector lanes: chunks of >= 4 orbits, one per core
        cores = workers or os.cpu_count() or 1
        per = max(4, -(-realisations // cores))
        calls = [((N, tau, seeds[i:i + per], model, alpha, t_end, method, kwargs),)
                 for N in Ns for i in range(0, realisations, per)]
        fn = _batch_of_realisations
    else:
        calls = [((N, tau, s, model, alpha, t_end, method, kwargs),) for N in Ns for s in seeds]
        fn = _one_realisation
    got: dict = {}
    from tqdm.auto import tqdm
    with tqdm(total=len(Ns) * realisations, desc="chaos", unit="orbit",
              disable=None if progress else True) as bar:
        for _, out, err in run_calls(fn, calls, workers=workers, scheduler=scheduler):
            if err is not None:
                raise err
            for orbit in (out if batched else [out]):
                got[orbit.N, orbit.seed] = orbit.result
                bar.update(1)
    results = {N: [got[N, first_seed + r] for r in range(realisations)] for N in Ns}
    classes = {N: {c: sum(r.classify() == c for r in results[N]) for c in CLASSES} for N in Ns}
    percent = [100.0 * classes[N]["chaotic"] / realisations for N in Ns]
    blowups = [classes[N]["blow-up"] for N in Ns]
    return {"N": Ns, "percent": percent, "blowups": blowups, "classes": classes,
            "results": results}
