"""fputlab: ordered and disordered Fermi-Pasta-Ulam-Tsingou lattices, fast.

    >>> import fputlab
    >>> lat = fputlab.Lattice(N=64, alpha=0.25)              # homogeneous FPUT-alpha
    >>> run = lat.integrate(7e4, sample_every=10.0)           # Yoshida 4, dt = 0.01
    >>> run.mode_energies[:, :4]                              # E_1..E_4 (paper Fig. 1b)
"""
from ._errors import FputlabError, IntegrationError, Interrupted
from ._lowlevel import VERSION as __version__
from .integrate import Integrator, Run, integrate, iter_samples, method_info, methods
from . import analysis, blowup, chaos
from .lattice import DISORDERS, MODELS, Lattice, draw_disorder
from .modes import mode_matrix, omega
from .initial_states import mode_excitation, random_phases, thermal
from . import reduction, thermalization
from . import io
from .io import load

__all__ = ["Lattice", "draw_disorder", "integrate", "iter_samples", "Integrator", "methods",
           "method_info", "Run", "omega", "mode_matrix", "mode_excitation", "random_phases",
           "thermal",
           "MODELS", "DISORDERS", "load", "FputlabError", "IntegrationError", "Interrupted",
           "__version__"]
