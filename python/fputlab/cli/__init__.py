"""The `fputlab` command: the paper's workflows with defaults that reproduce it.

One module per command or group of commands: `simulate`, `blowup`, `chaos`, `sweep`,
`reduction` (coefficients, tauc, bifurcation), `figures`, `methods` (and `demo`). The option
groups they share (parent parsers), the help formatter and the form-dependent defaults are in
`parsers`; the summary output and the checks of output paths in `_common`; `main` assembles the
parser (`build_parser()`, also what sphinx-argparse documents) and runs a command line (`main()`,
the console script).

A new command: a module with ``_parser_<name>(sub, parents)`` that adds its subparser (with
``parsers._sub`` and the parent parsers it needs) and sets ``func=`` (and ``resolve=`` when
defaults depend on the form), listed in `main.SUBCOMMANDS`.
"""
from .main import SUBCOMMANDS, build_parser, main, parse_args
from .parsers import python_defaults

__all__ = ["main", "build_parser", "parse_args", "python_defaults", "SUBCOMMANDS"]
