#!/usr/bin/env bash
# Issue 15 part 4: ns per particle and rhs evaluation of ERKStep DOP853 with/without fused vector
# operations, against each SUNDIALS build present (build/: 6.4; build-sun7/build: 7.x, made by
# ./dev test-sun7). Under a minute. Usage: benchmarks/sundials_fused.sh [T]
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
for b in "$ROOT/build" "$ROOT/build-sun7/build"; do
  [[ -f $b/libfputlab.so ]] || continue
  inc=(-I"$ROOT/include" -I"$b/include")
  libs=("$b/libfputlab.so" -lsundials_arkode -lsundials_nvecserial -lm)
  if [[ $b == "$ROOT/build-sun7/build" ]]; then
    p=$ROOT/build-sun7/prefix/usr
    inc+=(-I"$p/include" $(mpicc --showme:compile))
    libs=("$b/libfputlab.so" -L"$p/lib" -lsundials_arkode -lsundials_nvecserial -lsundials_core
          $(mpicc --showme:link) -lm -Wl,-rpath,"$p/lib")
  fi
  cc -O2 -std=c11 "${inc[@]}" "$ROOT/benchmarks/sundials_fused.c" -o "$b/sundials_fused" \
     "${libs[@]}" -Wl,-rpath,"$b"
  "$b/sundials_fused" "$@"
done
