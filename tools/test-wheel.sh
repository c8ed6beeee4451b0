#!/usr/bin/env bash
# Test a built wheel where nothing else of fputlab's build is: a Debian 12 (bookworm) root made
# with debootstrap that holds only python3 and python3-venv (no compiler, no -dev packages, no
# SUNDIALS/GSL/HDF5), entered with chroot. There the wheel and the test dependencies are installed
# from PyPI into a fresh venv, and the Python test suite (tests/python, with the repository's
# tracked files) runs against the installed wheel.
#
#   tools/test-wheel.sh [WHEEL [PYTEST ARGS...]]   (default: the newest dist/fputlab-*manylinux*.whl;
#                                                   `./dev test-wheel` runs it)
#
# Needs root (debootstrap, mount, chroot), debootstrap (apt-get install debootstrap) and the
# network to this machine's Debian mirror and PyPI. The root is made once and kept in
# FPUTLAB_WHEEL_CACHE/bookworm-root (default build-wheel/; delete it to make it again); the venv
# in it is made anew on every run. /proc, /dev and a private /dev/shm are mounted into the root for
# the run and unmounted on exit.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
CACHE=${FPUTLAB_WHEEL_CACHE:-$ROOT/build-wheel}
CHROOT=$CACHE/bookworm-root
log() { printf '[test-wheel] %s\n' "$*" >&2; }

WHEEL=${1:-}
shift || true
if [[ -z $WHEEL ]]; then
  WHEEL=$(ls -t "$ROOT"/dist/fputlab-*manylinux*.whl 2>/dev/null | head -n 1 || true)
  [[ -n $WHEEL ]] || { log "no dist/fputlab-*manylinux*.whl: run ./dev wheel first"; exit 1; }
fi
[[ -f $WHEEL ]] || { log "no wheel $WHEEL"; exit 1; }
[[ $(id -u) -eq 0 ]] || { log "needs root (debootstrap, mount, chroot)"; exit 1; }
command -v debootstrap >/dev/null || { log "needs debootstrap: apt-get install debootstrap"; exit 1; }

# ---- the clean root -----------------------------------------------------------------------------
if [[ ! -f $CHROOT/.fputlab-clean-root ]]; then
  mirror=$("$ROOT/tools/debian-mirror.sh")
  log "making a Debian 12 root with python3 and python3-venv only ($mirror) in $CHROOT"
  rm -rf "$CHROOT" "$CHROOT.part"
  mkdir -p "$CACHE"
  debootstrap --variant=minbase --include=python3,python3-venv bookworm "$CHROOT.part" "$mirror" \
    >"$CACHE/debootstrap.log" 2>&1 ||
    { tail -n 30 "$CACHE/debootstrap.log" >&2; log "debootstrap failed (log: $CACHE/debootstrap.log)"; exit 1; }
  touch "$CHROOT.part/.fputlab-clean-root"
  mv "$CHROOT.part" "$CHROOT"
fi

mounted=()
cleanup() {
  local i
  for ((i = ${#mounted[@]} - 1; i >= 0; i--)); do umount "${mounted[i]}" || umount -l "${mounted[i]}"; done
}
trap cleanup EXIT
trap 'exit 130' INT TERM   # so that the EXIT trap unmounts
mount_in_root() {  # mount_in_root TARGET MOUNT-ARGS...
  mount "${@:2}" "$CHROOT$1"
  mounted+=("$CHROOT$1")
}
# left mounted by a run that was killed (SIGKILL skips the trap)
for m in /dev/shm /dev /proc; do
  if mountpoint -q "$CHROOT$m"; then umount "$CHROOT$m" || umount -l "$CHROOT$m"; fi
done
mount_in_root /proc -t proc proc
mount_in_root /dev --bind /dev
mount_in_root /dev/shm -t tmpfs -o mode=1777 shm   # multiprocessing's semaphores

# Name resolution and the CA bundle of this machine (PyPI may be reached through a proxy whose CA
# only the host trusts).
cp /etc/resolv.conf "$CHROOT/etc/resolv.conf"
mkdir -p "$CHROOT/etc/ssl/certs"
cp /etc/ssl/certs/ca-certificates.crt "$CHROOT/etc/ssl/certs/ca-certificates.crt"

in_root() {
  chroot "$CHROOT" /usr/bin/env -i HOME=/root LANG=C.UTF-8 PATH=/usr/sbin:/usr/bin:/sbin:/bin \
    PIP_CERT=/etc/ssl/certs/ca-certificates.crt PIP_DISABLE_PIP_VERSION_CHECK=1 \
    PIP_DEFAULT_TIMEOUT=180 MPLBACKEND=Agg "$@"
}

# The root must be what a user without a build environment has.
for tool in cc gcc meson pkg-config h5cc; do
  if in_root sh -c "command -v $tool" >/dev/null; then log "the root has $tool: not a clean root"; exit 1; fi
done
for pkg in libhdf5-dev libgsl-dev libsundials-dev libhdf5-103-1 libgsl27; do
  if in_root dpkg -s "$pkg" >/dev/null 2>&1; then log "the root has $pkg: not a clean root"; exit 1; fi
done

# ---- the wheel and the tests --------------------------------------------------------------------
work=$CHROOT/work
rm -rf "$work"
mkdir -p "$work/src"
cp "$WHEEL" "$work/"
wheel_name=$(basename "$WHEEL")
# the tests read the repository's files (README, docs, examples, headers, the package sources for
# test_layering): its tracked files as this work tree has them, no build tree; python/ is not on
# sys.path there (checked below: fputlab is imported from the venv)
git -C "$ROOT" ls-files -z --cached --others --exclude-standard |
  tar -C "$ROOT" --null -T - --ignore-failed-read -cf - 2>/dev/null | tar -xf - -C "$work/src"

log "installing $wheel_name and the test dependencies from PyPI into a fresh venv in the root"
in_root python3 -m venv /work/venv
in_root /work/venv/bin/python -m pip install -q "/work/$wheel_name[test,xarray,dask]"
in_root sh -c 'cd /work/src && exec /work/venv/bin/python -c "$0"' '
import sys, fputlab, fputlab._native as n
assert fputlab.__file__.startswith("/work/venv/"), fputlab.__file__
print("[test-wheel] fputlab", fputlab.__version__, "from", fputlab.__file__, "SUNDIALS",
      n.ffi.string(n.lib.fpl_sundials_version()).decode(), file=sys.stderr)'
log "Python tests (pytest) in the root, against the installed wheel"
in_root sh -c 'cd /work/src && exec /work/venv/bin/python -m pytest -p no:cacheprovider "$@"' \
  pytest "$@"
