"""The `fputlab` command: the parser of every subcommand and the entry point."""
from __future__ import annotations

import argparse
import os
import sys

from .blowup import _parser_blowup
from .chaos import _parser_chaos
from .figures import _parser_figures
from .methods import _parser_demo, _parser_methods
from .reduction import _parser_bifurcation, _parser_coefficients, _parser_tauc
from .simulate import _parser_simulate
from .spectrum import _parser_spectrum
from .sweep import _parser_sweep
from .parsers import _DefaultsFormatter


def _parser_thermalization(sub, parents):
    from .thermalization import add_parser
    add_parser(sub, _DefaultsFormatter)


SUBCOMMANDS = (_parser_demo, _parser_simulate, _parser_blowup, _parser_chaos, _parser_spectrum,
               _parser_sweep, _parser_coefficients, _parser_tauc, _parser_bifurcation,
               _parser_figures, _parser_methods, _parser_thermalization)


def build_parser():
    p = argparse.ArgumentParser(prog="fputlab", description="Ordered and disordered FPUT lattices "
                                "(paper: Energy-recurrence breakdown and chaos in disordered FPUT lattices).")
    p.add_argument("--version", action="store_true", help="print the version and exit")
    sub = p.add_subparsers(dest="command")
    for make in SUBCOMMANDS:
        make(sub, None)
    return p


def _parse(parser, argv):
    """parse_args, except that an option the subcommand does not know is reported by the
    subcommand's parser (its usage, not the top-level one: `simulate --Ns 8`)."""
    a, extras = parser.parse_known_args(argv)
    if extras:
        sub = getattr(a, "command", None)
        subparsers = [act for act in parser._actions
                      if isinstance(act, argparse._SubParsersAction)]
        target = subparsers[0].choices.get(sub, parser) if sub and subparsers else parser
        target.error(f"unrecognized arguments: {' '.join(extras)}")
    return a


def parse_args(argv):
    """The arguments of a command line with every default resolved (as the subcommand runs)."""
    a = _parse(build_parser(), argv)
    if getattr(a, "resolve", None):
        a.resolve(a)
    return a


def _run(argv) -> int:
    if argv[:1] == ["demo"]:
        from ..demo import main as demo_main
        return demo_main(argv[1:])
    parser = build_parser()
    a = _parse(parser, argv)
    if a.version:
        from .. import __version__
        print(__version__)
        return 0
    if not getattr(a, "func", None):
        parser.print_help()
        return 2
    if getattr(a, "resolve", None):
        a.resolve(a)
    from ._common import _check_args
    _check_args(a)
    return a.func(a)


def _one_line(err: BaseException) -> str:
    msg = " ".join(str(err).split()) or type(err).__name__
    if isinstance(err, (ValueError, TypeError)):
        return msg
    if isinstance(err, OSError) and err.filename and str(err.filename) not in msg:
        msg = f"{msg}: {err.filename}"
    if isinstance(err, ImportError) and err.name:
        return f"{msg} (the Python package {err.name!r} is needed for this; pip install it)"
    return f"{type(err).__name__}: {msg}" if not isinstance(err, OSError) else msg


def main(argv=None) -> int:
    """The `fputlab` command. Every failure is one line on stderr and exit status 2 (130 on
    Ctrl-C / SIGINT); FPUTLAB_TRACEBACK=1 shows the traceback instead."""
    argv = sys.argv[1:] if argv is None else list(argv)
    try:
        return _run(argv)
    except KeyboardInterrupt:
        print("fputlab: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:                   # `fputlab ... | head`: not an error of ours
        try:
            sys.stdout = open(os.devnull, "w")
        except OSError:
            pass
        return 0
    except SystemExit:
        raise
    except Exception as err:                  # noqa: BLE001 - the CLI never shows a traceback
        if os.environ.get("FPUTLAB_TRACEBACK"):
            raise
        print(f"fputlab: error: {_one_line(err)}", file=sys.stderr)
        return 2
