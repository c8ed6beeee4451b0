"""The option groups every subcommand shares (parent parsers), the help formatter that
shows defaults, and the resolution of the form-dependent defaults.

Defaults. A single-lattice form (simulate, chaos of one orbit) is exactly fputlab.Lattice():
the homogeneous chain, no disorder. The ensemble forms take the defaults of the Python
function they call: blowup sweeps blowup.blowup_sweep's, chaos ensembles
chaos.chaotic_fraction's, `sweep` ensemble.run_sweep's (and per kind blowup_sweep's or
chaotic_fraction's sizes, realisations and final time). One blow-up realisation needs
disorder: blowup_sweep's model, with --tau given. The values are read from the signatures
(python_defaults), so the two cannot drift apart; tests/python/test_cli_options.py checks it."""
from __future__ import annotations

import argparse
import functools
import inspect
import math
import sys

from ._common import _g

MODELS = ["homogeneous", "hamiltonian", "nonlinear"]
#: the models of the single-lattice forms (simulate, chaos of one orbit): also the Toda chain
SINGLE_MODELS = MODELS + ["toda"]
BOUNDARIES = ["fixed", "periodic"]
DISORDERS = ["gaussian", "truncated", "uniform"]
#: the taus of `fputlab sweep --kind blowup` (blowup_sweep has no default taus)
SWEEP_BLOWUP_TAUS = [0.0, 5.0, 10.0, 15.0, 20.0]


def _signature_defaults(fn) -> dict:
    return {n: p.default for n, p in inspect.signature(fn).parameters.items()
            if p.default is not inspect.Parameter.empty}


@functools.lru_cache(maxsize=None)
def python_defaults() -> dict:
    """{Python function name: {parameter: default}} of the functions the subcommands call."""
    from ..blowup import blowup_sweep, blowup_time
    from ..chaos import chaotic_fraction, lyapunov, lyapunov_spectrum
    from ..ensemble import run_sweep
    from ..lattice import Lattice
    return {"Lattice": _signature_defaults(Lattice.__init__),
            "integrate": _signature_defaults(Lattice.integrate),
            "lyapunov": _signature_defaults(lyapunov),
            "lyapunov_spectrum": _signature_defaults(lyapunov_spectrum),
            "blowup_time": _signature_defaults(blowup_time),
            "blowup_sweep": _signature_defaults(blowup_sweep),
            "chaotic_fraction": _signature_defaults(chaotic_fraction),
            "run_sweep": _signature_defaults(run_sweep)}


class _Given(argparse._StoreAction):
    """Store, and note that the option was given (`<dest>_given`): a default and the same value
    typed by the user are not the same thing (the homogeneous model refuses a --seed)."""

    def __call__(self, parser, namespace, values, option_string=None):
        setattr(namespace, self.dest + "_given", True)
        super().__call__(parser, namespace, values, option_string)


class _Deprecated(argparse._StoreAction):
    """An old spelling of an option: hidden from --help, still works, says what replaced it
    (and, like the new spelling, that it was given, where that matters)."""

    def __init__(self, option_strings, dest, replacement="", **kw):
        super().__init__(option_strings, dest, **kw)
        self.replacement = replacement

    def __call__(self, parser, namespace, values, option_string=None):
        print(f"fputlab: warning: {option_string} is deprecated; use {self.replacement}",
              file=sys.stderr)
        if any(isinstance(act, _Given) and act.dest == self.dest for act in parser._actions):
            setattr(namespace, self.dest + "_given", True)
        super().__call__(parser, namespace, values, option_string)


def _alias(p, old: str, new: str, dest: str, **kw):
    """`old` as a hidden deprecated spelling of `new` (same dest, type and nargs)."""
    p.add_argument(old, dest=dest, action=_Deprecated, replacement=new, help=argparse.SUPPRESS,
                   default=argparse.SUPPRESS, **kw)


def _lattice_options(*, N: str, model: str, tau: str, several: tuple = (),
                     seed: str = "disorder seed (default 1)",
                     single: bool = False) -> argparse.ArgumentParser:
    """Parent parser: the lattice. N, model and tau are described by the subcommand (their
    defaults depend on its form); several: those of "N", "tau" that take several values
    (ensembles); single: the command has a single-lattice form (simulate, chaos), which also
    takes --model toda and --boundary."""
    L = python_defaults()["Lattice"]
    p = argparse.ArgumentParser(add_help=False)
    g = p.add_argument_group("lattice")
    g.add_argument("--N", type=int, nargs="+" if "N" in several else None, default=None, help=N)
    g.add_argument("--alpha", type=float, default=L["alpha"], help="quadratic (cubic-potential) "
                   f"coupling (default {_g(L['alpha'])})")
    g.add_argument("--beta", type=float, default=L["beta"],
                   help=f"quartic coupling (default {_g(L['beta'])})")
    g.add_argument("--model", default=None, choices=SINGLE_MODELS if single else MODELS,
                   help=model + ("; toda: the integrable Toda chain, homogeneous, with "
                                 "--beta 0" if single else ""))
    if single:
        # checked in _common._check_args (one line), not by argparse's choices (its usage too)
        g.add_argument("--boundary", default=L["boundary"], metavar="{fixed,periodic}",
                       help="fixed: walls at both ends (the paper); periodic: a ring of N "
                       f"particles (default {L['boundary']}, as fputlab.Lattice())")
    # default None: whether --tau was given matters (the homogeneous model refuses it)
    g.add_argument("--tau", type=float, nargs="+" if "tau" in several else None, default=None,
                   help=tau)
    g.add_argument("--seed", type=int, default=1, action=_Given, help=seed)
    g.add_argument("--disorder", default=L["disorder"], choices=DISORDERS,
                   help=f"distribution of the disorder draws (default {L['disorder']})")
    return p


def _integrator_options(*, method: str, dt: str) -> argparse.ArgumentParser:
    """Parent parser: the integrator. rtol/atol default to None = the Python default (not
    passed), so a sweep's task options, hence its work-directory key, stay as they were."""
    I = python_defaults()["integrate"]
    p = argparse.ArgumentParser(add_help=False)
    g = p.add_argument_group("integrator")
    g.add_argument("--method", default=None, help=method + "; see `fputlab methods`")
    g.add_argument("--dt", type=float, default=None, help=dt)
    g.add_argument("--rtol", type=float, default=None,
                   help=f"relative tolerance of the adaptive methods (default {_g(I['rtol'])})")
    g.add_argument("--atol", type=float, default=None,
                   help=f"absolute tolerance of the adaptive methods (default {_g(I['atol'])})")
    return p


def _time_options(default: float, what: str = "final time") -> argparse.ArgumentParser:
    """Parent parser: --t-end (the old spelling --t-max still works)."""
    p = argparse.ArgumentParser(add_help=False)
    p.add_argument("--t-end", dest="t_end", type=float, default=default, metavar="T",
                   help=f"{what} (default {_g(default)})")
    _alias(p, "--t-max", "--t-end", "t_end", type=float)
    return p


def _output_options(out: str, *, out_default=None, overwrite: bool = True):
    """Parent parser: the output file, --overwrite and --json."""
    p = argparse.ArgumentParser(add_help=False)
    g = p.add_argument_group("output")
    g.add_argument("--out", metavar="FILE", default=out_default, help=out)
    if overwrite:
        g.add_argument("--overwrite", action="store_true",
                       help="replace an existing --out file (default: refuse)")
    g.add_argument("--json", action="store_true",
                   help="print the summary as JSON, strict: NaN/Inf as null (default: text)")
    return p


def _ensemble_options(realisations: str) -> argparse.ArgumentParser:
    """Parent parser: realisations and where they run."""
    p = argparse.ArgumentParser(add_help=False)
    g = p.add_argument_group("ensemble")
    g.add_argument("--realisations", type=int, default=None, help=realisations)
    g.add_argument("--workers", type=int, default=None,
                   help="local worker processes (default: all cores)")
    g.add_argument("--scheduler", default=None, help="Dask scheduler address tcp://host:port "
                   "(default: local processes)")
    return p


def _checkpoint_options() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(add_help=False)
    g = p.add_argument_group("checkpoints (with --out)")
    g.add_argument("--checkpoint", metavar="FILE", help="checkpoint file: resume from it if it "
                   "exists (default: none, no restart possible)")
    g.add_argument("--checkpoint-every", type=float, default=600.0, metavar="SECONDS",
                   help="write a checkpoint every SECONDS of wall time (default 600)")
    g.add_argument("--checkpoint-steps", type=int, default=None, metavar="K",
                   help="also write one every K integrator steps (default: only by time)")
    g.add_argument("--restart", action="store_true",
                   help="ignore an existing checkpoint and start from t = 0 (default: resume)")
    return p


def _sub(sub, name, help, parents=(), **kw):
    return sub.add_parser(name, help=help, parents=list(parents),
                          formatter_class=_DefaultsFormatter, **kw)


class _DefaultsFormatter(argparse.HelpFormatter):
    """Every option's help ends with its default (unless the help already states it)."""

    def _get_help_string(self, action):
        text = action.help or ""
        default = action.default
        if "default" in text or not action.option_strings or default is argparse.SUPPRESS:
            return text
        if default is None:
            default = "none"
        elif default is False:
            default = "off"
        elif isinstance(default, (list, tuple)):
            default = " ".join(map(str, default))
        elif isinstance(default, float):
            default = f"{default:g}"
        return f"{text} (default {str(default).replace('%', '%%')})".strip()


def _fill(a, **defaults):
    """Set every attribute of a that is None to its default."""
    for k, v in defaults.items():
        if getattr(a, k, None) is None:
            setattr(a, k, v)


def _finite_positive(a, name: str):
    value = getattr(a, name)
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"--{name.replace('_', '-')} must be finite and > 0 (got {value:g})")


def _one(a, name: str, why: str):
    """A list option of a single-lattice form as its one value."""
    values = getattr(a, name)
    if isinstance(values, list):
        if len(values) != 1:
            raise ValueError(f"--{name}: {why}")
        setattr(a, name, values[0])


def _resolve_single_lattice(a):
    L = python_defaults()["Lattice"]
    a.tau_given = a.tau is not None
    _fill(a, N=L["N"], model=L["model"], tau=L["tau"])
