"""fputlab: ordered and disordered Fermi-Pasta-Ulam-Tsingou lattices, fast.

    >>> import fputlab
    >>> lat = fputlab.Lattice(N=64, alpha=0.25)              # homogeneous FPUT-alpha
    >>> run = lat.integrate(7e4, sample_every=10.0)           # Yoshida 4, dt = 0.01
    >>> run.mode_energies[:, :4]                              # E_1..E_4 (paper Fig. 1b)
"""
import os as _os
import sys as _sys


def _command_line_start() -> bool:
    """Whether this process is the `fputlab` command starting: the console script, or
    `python -m fputlab` (whose argv[0] is "-m" while the package is imported, then the path of
    fputlab/__main__.py)."""
    arg0 = _sys.argv[0] if _sys.argv else ""
    return (arg0 == "-m" or _os.path.basename(arg0).removesuffix(".exe") == "fputlab" or
            arg0.endswith(_os.path.join("fputlab", "__main__.py")))


try:
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
except KeyboardInterrupt:
    # Ctrl-C while the command is still importing (the first ~0.3 s) is the command's
    # Ctrl-C: one line and 130, as once it runs, not a traceback. A program importing
    # fputlab gets its KeyboardInterrupt as usual.
    if not _command_line_start():
        raise
    print("fputlab: interrupted", file=_sys.stderr)
    raise SystemExit(130) from None

__all__ = ["Lattice", "draw_disorder", "integrate", "iter_samples", "Integrator", "methods",
           "method_info", "Run", "omega", "mode_matrix", "mode_excitation", "random_phases",
           "thermal",
           "MODELS", "DISORDERS", "load", "FputlabError", "IntegrationError", "Interrupted",
           "__version__"]
