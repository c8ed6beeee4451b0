#!/usr/bin/env bash
# Build and run benchmarks/roofline.c (every model's Yoshida 4 kernel with 0, 1, 2, 6 and 2N
# deviation vectors against a hand-fused plain-C step of the same model and against the bandwidth
# of a STREAM-like triad measured in the same run) against build/libfputlab.so. The plain loop is
# compiled with fputlab's own flags for its AVX2 clone (-O3 -march=x86-64-v3 -fno-math-errno
# -fno-trapping-math); ROOFLINE_ARCHES="x86-64-v3 native" also runs it with -march=native. About
# three minutes per arch on a quiet machine. Usage: benchmarks/roofline.sh [repeats] [max_N] [min_N]
# [fixed|ring] (ring: the periodic chains against their plain-C ring step and the fixed chains)
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
B=${FPUTLAB_BUILD:-$ROOT/build}
[[ -f $B/libfputlab.so ]] || { echo "no $B/libfputlab.so: run ./dev test (or meson compile -C build) first" >&2; exit 1; }
for arch in ${ROOFLINE_ARCHES:-x86-64-v3}; do
  cc -O3 -std=c11 -march=$arch -fno-math-errno -fno-trapping-math -I"$ROOT/include" -I"$B/include" \
     "$ROOT/benchmarks/roofline.c" -o "$B/roofline-$arch" "$B/libfputlab.so" -lm -Wl,-rpath,"$B"
  echo "== plain C compiled with -march=$arch; $(date -u '+%F %T') UTC; load average $(cut -d' ' -f1-3 /proc/loadavg)"
  "$B/roofline-$arch" "$@"
  echo "== done $(date -u '+%T') UTC; load average $(cut -d' ' -f1-3 /proc/loadavg)"
done
