#!/bin/sh
# The README's "Quick start (C, with SUNDIALS)" code block must be examples/c/quickstart_cvode.c,
# verbatim (so the README's C example is a program that compiles, runs and is checked).
set -eu
readme="$1"; example="$2"
block=$(awk '/^## Quick start \(C, with SUNDIALS\)/ { sec = 1; next }
             sec && /^```c$/ { inblk = 1; next }
             inblk && /^```$/ { exit }
             inblk { print }' "$readme")
if [ "$block" != "$(cat "$example")" ]; then
  echo "README.md's C quick start differs from $example:"
  printf '%s\n' "$block" | diff - "$example" || true
  exit 1
fi
echo "README C quick start == $example"
