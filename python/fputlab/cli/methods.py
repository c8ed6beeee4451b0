"""`fputlab methods` (the integrators) and `fputlab demo` (Fig. 1; its options are
`fputlab.demo.main`'s)."""
from __future__ import annotations

from .parsers import _sub

def cmd_methods(a):
    from ..integrate import method_info, methods
    names = methods()
    width = max(len(m) for m in names)
    print(f"{'method':{width}s}  order  kind")
    for m in names:
        info = method_info(m)
        print(f"{m:{width}s}  {info['order']:>5d}  {'adaptive' if info['adaptive'] else 'fixed step'}")
    return 0


def _parser_methods(sub, parents):
    s = _sub(sub, "methods", "list the integrators")
    s.set_defaults(func=cmd_methods)


def _parser_demo(sub, parents):
    # its options are demo.main's own (`fputlab demo --help`)
    sub.add_parser("demo", help="reproduce Fig. 1 (FPUT recurrence, N = 64) as a PNG",
                   add_help=False)
