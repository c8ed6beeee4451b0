"""The `fputlab` command."""
from __future__ import annotations

import argparse
import sys


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    parser = argparse.ArgumentParser(prog="fputlab", description="Ordered and disordered FPUT lattices.")
    parser.add_argument("--version", action="store_true", help="print the version and exit")
    parser.add_argument("command", nargs="?", choices=["demo", "methods"],
                        help="demo: reproduce the paper's Fig. 1 (PNG); methods: list integrators")
    args, rest = parser.parse_known_args(argv)
    if args.version:
        from . import __version__
        print(__version__)
        return 0
    if args.command == "demo":
        from .demo import main as demo_main
        return demo_main(rest)
    if args.command == "methods":
        from .integrate import methods
        print("\n".join(methods()))
        return 0
    parser.print_help()
    return 2
