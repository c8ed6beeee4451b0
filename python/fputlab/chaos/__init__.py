"""Chaos indicators (paper Sec. 5, Figs. 11-14), in one subpackage:

* `single`   -- one orbit: `lyapunov` (lambda(t), SALI(t), GALI_k(t)), `sali`, `gali`;
* `batch`    -- many orbits of one N in the vector lanes of the batched kernel: `lyapunov_batch`;
* `result`   -- `ChaosResult`, `classify_orbit`, `CLASSES`;
* `ensemble` -- the chaotic fraction over disorder realisations: `chaotic_fraction`;
* `study`    -- the paper's full-length study behind Figs. 12-14, resumable: `ChaosStudy`.
"""
from .batch import BATCH_METHODS, lyapunov_batch
from .ensemble import (OrbitRecord, _batch_of_realisations, _one_realisation,  # noqa: F401
                       chaotic_fraction, ensemble_defaults)
from .result import CLASSES, ChaosResult, classify_orbit
from .single import ENSEMBLE_DT, ENSEMBLE_METHOD, gali, lyapunov, sali

__all__ = ["lyapunov", "lyapunov_batch", "chaotic_fraction", "ChaosResult", "classify_orbit",
           "CLASSES", "BATCH_METHODS", "ENSEMBLE_METHOD", "ENSEMBLE_DT", "OrbitRecord",
           "ensemble_defaults", "sali", "gali"]
