#!/bin/sh
# Fails if the shared library exports any defined symbol not starting with fpl_.
set -eu
lib="$1"
leaks=$(nm -D --defined-only "$lib" | awk '{print $NF}' | grep -v -e '^fpl_' -e '^_init$' -e '^_fini$' || true)
count=$(nm -D --defined-only "$lib" | awk '{print $NF}' | grep -c '^fpl_' || true)
if [ -n "$leaks" ]; then
  echo "symbols leaking from $lib:"; echo "$leaks"; exit 1
fi
echo "exports: $count fpl_ symbols, nothing else"
