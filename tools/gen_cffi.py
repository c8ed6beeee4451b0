#!/usr/bin/env python3
"""Generate the cffi API-mode C source of fputlab._native from the public headers.

The cdef is the headers themselves with preprocessor lines, C++ guards and the FPL_API export
macro removed, so the Python binding can never drift from the C declarations.
Usage: gen_cffi.py SELF HEADER... --output OUT.c   (SELF is this script, as Meson passes it)
"""
import argparse
import pathlib
import re
import sys

import cffi


def header_to_cdef(text: str) -> str:
    out, skip_cplusplus = [], False
    for line in text.splitlines():
        stripped = line.strip()
        if stripped.startswith("#"):
            if stripped.startswith("#ifdef __cplusplus"):
                skip_cplusplus = True
            elif stripped.startswith("#endif") and skip_cplusplus:
                skip_cplusplus = False
            continue
        if skip_cplusplus:
            continue
        out.append(line)
    cdef = "\n".join(out)
    cdef = re.sub(r"\bFPL_API\s+", "", cdef)
    cdef = re.sub(r"__attribute__\s*\(\(.*?\)\)", "", cdef)
    return cdef


def main(argv):
    parser = argparse.ArgumentParser()
    parser.add_argument("inputs", nargs="+", type=pathlib.Path)
    parser.add_argument("--output", required=True, type=pathlib.Path)
    args = parser.parse_args(argv)
    headers = [p for p in args.inputs if p.suffix == ".h"]
    ffi = cffi.FFI()
    ffi.cdef("\n".join(header_to_cdef(h.read_text()) for h in headers))
    ffi.set_source("fputlab._native", '#include "fputlab.h"')
    ffi.emit_c_code(str(args.output))


if __name__ == "__main__":
    main(sys.argv[1:])
