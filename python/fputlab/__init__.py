"""fputlab: ordered and disordered Fermi-Pasta-Ulam-Tsingou lattices, fast.

    >>> import fputlab
    >>> lat = fputlab.Lattice(N=64, alpha=0.25)              # homogeneous FPUT-alpha
    >>> run = lat.integrate(7e4, sample_every=10.0)           # Yoshida 4, dt = 0.01
    >>> run.mode_energies[:, :4]                              # E_1..E_4 (paper Fig. 1b)

The lattice, integration and modes are imported with the package; the other submodules
(``fputlab.chaos``, ``fputlab.plotting``, ...) load on first use (PEP 562, as in scipy), so
``import fputlab`` stays quick and needs neither matplotlib nor h5py.
"""
import importlib
import os as _os
import sys as _sys


def _command_line_start() -> bool:
    """Whether this process is the `fputlab` command starting: the console script, or
    `python -m fputlab` (whose argv[0] is "-m" while the package is imported, then the path of
    fputlab/__main__.py)."""
    arg0 = _sys.argv[0] if _sys.argv else ""
    return (arg0 == "-m" or _os.path.basename(arg0).removesuffix(".exe") == "fputlab" or
            arg0.endswith(_os.path.join("fputlab", "__main__.py")))


def _interrupted_while_starting(signum, frame):
    # exit at once: a KeyboardInterrupt raised inside numpy's own import comes out as an
    # ImportError with a traceback, whatever catches it here
    _sys.stderr.write("fputlab: interrupted\n")
    _sys.stderr.flush()
    _os._exit(130)


_previous_sigint = None
if _command_line_start():
    import signal as _signal
    try:
        _previous_sigint = _signal.signal(_signal.SIGINT, _interrupted_while_starting)
    except ValueError:              # not the main thread: leave signals alone
        _previous_sigint = None

try:
    from ._errors import FputlabError, IntegrationError, Interrupted
    from ._lowlevel import VERSION as __version__
    from .integrate import Integrator, Run, integrate, iter_samples, method_info, methods
    from .lattice import DISORDERS, MODELS, Lattice, draw_disorder
    from .modes import mode_matrix, omega
    from .initial_states import mode_excitation, random_phases, thermal
except KeyboardInterrupt:
    # Ctrl-C while the command is still importing (the first ~0.3 s) is the command's
    # Ctrl-C: one line and 130, as once it runs, not a traceback. A program importing
    # fputlab gets its KeyboardInterrupt as usual.
    if not _command_line_start():
        raise
    print("fputlab: interrupted", file=_sys.stderr)
    raise SystemExit(130) from None
finally:
    if _previous_sigint is not None:    # the command's own Ctrl-C handling from here on
        _signal.signal(_signal.SIGINT, _previous_sigint)

#: the public submodules, imported on first attribute access
_SUBMODULES = ("analysis", "blowup", "chaos", "cli", "engine", "ensemble", "figures",
               "figures_open", "figures_reduction", "figures_thermalization", "initial_states",
               "io", "lattice", "modes", "plotting", "recurrence", "reduction",
               "thermalization", "thermalization_study")
#: deprecated aliases (fputlab.chaos.batch, fputlab.chaos.study): still reachable, not listed
_DEPRECATED = ("chaos_batch", "study")

__all__ = ["Lattice", "draw_disorder", "integrate", "iter_samples", "Integrator", "methods",
           "method_info", "Run", "omega", "mode_matrix", "mode_excitation", "random_phases",
           "thermal",
           "MODELS", "DISORDERS", "load", "FputlabError", "IntegrationError", "Interrupted",
           "__version__"]


def __getattr__(name: str):
    if name in _SUBMODULES or name in _DEPRECATED:
        return importlib.import_module(f".{name}", __name__)
    if name == "load":          # lives in fputlab.io, which needs h5py: loaded when asked for
        from .io import load
        return load
    raise AttributeError(f"module 'fputlab' has no attribute {name!r}")


def __dir__():
    return sorted(set(__all__) | set(_SUBMODULES))
