#!/usr/bin/env bash
# Build and run benchmarks/roofline.c (fputlab's Yoshida 4 kernel against a hand-written plain-C
# step and the drift loop's memory bandwidth) against build/libfputlab.so, twice: the plain loop
# compiled with fputlab's own flags for its AVX2 clone (-O3 -march=x86-64-v3 -fno-math-errno
# -fno-trapping-math) and with -march=native. About a minute. Usage: benchmarks/roofline.sh [repeats]
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
B=${FPUTLAB_BUILD:-$ROOT/build}
[[ -f $B/libfputlab.so ]] || { echo "no $B/libfputlab.so: run ./dev test (or meson compile -C build) first" >&2; exit 1; }
for arch in x86-64-v3 native; do
  cc -O3 -std=c11 -march=$arch -fno-math-errno -fno-trapping-math -I"$ROOT/include" -I"$B/include" \
     "$ROOT/benchmarks/roofline.c" -o "$B/roofline-$arch" "$B/libfputlab.so" -lm -Wl,-rpath,"$B"
  echo "== plain C compiled with -march=$arch; load average $(cut -d' ' -f1-3 /proc/loadavg)"
  "$B/roofline-$arch" "$@"
done
