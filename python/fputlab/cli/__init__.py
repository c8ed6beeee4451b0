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
try:
    from .main import SUBCOMMANDS, build_parser, main, parse_args
    from .parsers import python_defaults
except KeyboardInterrupt:          # Ctrl-C while the command starts: one line, 130
    import sys

    from .. import _command_line_start
    if not _command_line_start():
        raise
    print("fputlab: interrupted", file=sys.stderr)
    raise SystemExit(130) from None

__all__ = ["main", "build_parser", "parse_args", "python_defaults", "SUBCOMMANDS"]
