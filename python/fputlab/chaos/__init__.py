"""Chaos indicators (paper Sec. 5, Figs. 11-14), in one subpackage:

* `single`   -- one orbit: `lyapunov` (lambda(t), SALI(t), GALI_k(t)), `sali`, `gali`;
* `batch`    -- many orbits of one N in the vector lanes of the batched kernel: `lyapunov_batch`;
* `result`   -- `ChaosResult`, `classify_orbit`, `CLASSES`;
* `ensemble` -- the chaotic fraction over disorder realisations: `chaotic_fraction`;
* `study`    -- the paper's full-length study behind Figs. 12-14, resumable: `ChaosStudy`;
* `spectrum` -- the Lyapunov spectrum (`lyapunov_spectrum`) and covariant Lyapunov vectors
  (`covariant_lyapunov_vectors`, Ginelli et al. 2007).
"""
from .batch import BATCH_METHODS, lyapunov_batch
from .ensemble import (OrbitRecord, _batch_of_realisations, _one_realisation,  # noqa: F401
                       chaotic_fraction, ensemble_defaults)
from .result import CLASSES, ChaosResult, classify_orbit
from .single import ENSEMBLE_DT, ENSEMBLE_METHOD, gali, lyapunov, sali
from .spectrum import (CLVResult, SpectrumResult, covariant_lyapunov_vectors,
                       covariant_vectors_from_qr, inverse_participation_ratio,
                       kaplan_yorke_dimension, ks_entropy, lyapunov_spectra,
                       lyapunov_spectrum)

__all__ = ["lyapunov", "lyapunov_batch", "chaotic_fraction", "ChaosResult", "classify_orbit",
           "CLASSES", "BATCH_METHODS", "ENSEMBLE_METHOD", "ENSEMBLE_DT", "OrbitRecord",
           "ensemble_defaults", "sali", "gali", "lyapunov_spectrum", "SpectrumResult",
           "covariant_lyapunov_vectors", "CLVResult", "covariant_vectors_from_qr",
           "inverse_participation_ratio", "kaplan_yorke_dimension", "ks_entropy",
           "lyapunov_spectra"]

#: submodules not imported with the package, loaded on first attribute access (PEP 562)
_LAZY_SUBMODULES = ("study", "outcomes")


def __getattr__(name: str):
    if name in _LAZY_SUBMODULES:
        import importlib
        return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
