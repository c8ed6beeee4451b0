#!/usr/bin/env bash
# Build one SUNDIALS release from source into a private prefix, for building fputlab against a
# SUNDIALS that no Debian release ships (e.g. the newest 7.x):
#
#   tools/sundials-source-prefix.sh VERSION PREFIX [SOURCE]
#   meson setup BUILDDIR -Dsundials_dir=PREFIX/usr
#
# SOURCE is a SUNDIALS git repository (bare or not; tag vVERSION is used), an unpacked source tree,
# or a source tarball (.tar.gz, .tar.xz); without it the release tarball is downloaded from GitHub
# (https://github.com/LLNL/sundials/releases). Only what fputlab links is built: ARKODE and CVODE
# with the serial vector, dense/band matrices and linear solvers and the Newton/fixed-point
# nonlinear solvers, shared libraries only, Release, no MPI, Fortran, examples or tests. The
# libraries go to PREFIX/usr/lib, the headers to PREFIX/usr/include (the layout -Dsundials_dir and
# tools/sundials7-prefix.sh expect; with PREFIX build-sun7/prefix, `./dev test-sun7` uses it).
#
# Needs cmake, make and a C compiler. JOBS (default 1) sets the parallel build jobs; STATIC=1 builds
# static, position-independent libraries instead of shared ones (for linking into the wheel's
# extension, tools/build-wheel.sh). Idempotent: a PREFIX already holding SUNDIALS VERSION is kept.
# Not used by CI.
set -euo pipefail
log() { printf '[sundials-source-prefix] %s\n' "$*" >&2; }
[[ $# -ge 2 ]] || { sed -n '2,19p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
VERSION=$1
PREFIX=$2
SOURCE=${3:-}
JOBS=${JOBS:-1}
if [[ ${STATIC:-0} == 1 ]]; then
  library_kind=(-DBUILD_SHARED_LIBS=OFF -DBUILD_STATIC_LIBS=ON -DCMAKE_POSITION_INDEPENDENT_CODE=ON)
else
  library_kind=(-DBUILD_SHARED_LIBS=ON -DBUILD_STATIC_LIBS=OFF)
fi
[[ $VERSION =~ ^[0-9]+\.[0-9]+\.[0-9]+$ ]] || { log "VERSION must be X.Y.Z (got '$VERSION')"; exit 2; }
command -v cmake >/dev/null || { log "needs cmake"; exit 1; }
mkdir -p "$PREFIX"
PREFIX=$(cd "$PREFIX" && pwd)
config=$PREFIX/usr/include/sundials/sundials_config.h
if grep -qs "#define SUNDIALS_VERSION \"$VERSION\"" "$config"; then
  log "SUNDIALS $VERSION already in $PREFIX/usr"
  exit 0
elif [[ -e $config ]]; then
  log "$PREFIX/usr already holds $(sed -n 's/^#define SUNDIALS_VERSION "\(.*\)"/SUNDIALS \1/p' "$config"):" \
      "give an empty PREFIX (and remove the meson build directories that used this one)"
  exit 1
fi

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
src=$tmp/src
mkdir -p "$src"
if [[ -z $SOURCE ]]; then
  url=https://github.com/LLNL/sundials/releases/download/v$VERSION/sundials-$VERSION.tar.gz
  log "downloading $url"
  curl -fsSL "$url" -o "$tmp/sundials.tar.gz"
  tar -xzf "$tmp/sundials.tar.gz" -C "$src" --strip-components=1
elif [[ -f $SOURCE ]]; then
  tar -xaf "$SOURCE" -C "$src" --strip-components=1
elif git --git-dir="$SOURCE" rev-parse -q --verify "v$VERSION^{commit}" >/dev/null 2>&1 ||
     git -C "$SOURCE" rev-parse -q --verify "v$VERSION^{commit}" >/dev/null 2>&1; then
  gitdir=$(git -C "$SOURCE" rev-parse --absolute-git-dir 2>/dev/null || echo "$SOURCE")
  # only the parts the build reads (docs and examples are large and not needed)
  git --git-dir="$gitdir" archive "v$VERSION" CMakeLists.txt LICENSE NOTICE cmake include src |
    tar -x -C "$src"
elif [[ -f $SOURCE/CMakeLists.txt ]]; then
  src=$(cd "$SOURCE" && pwd)
else
  log "SOURCE '$SOURCE' is neither a tarball, a git repository with tag v$VERSION nor a source tree"
  exit 1
fi
found=$(for part in MAJOR MINOR PATCH; do
          sed -n "s/^set(PACKAGE_VERSION_$part \"\([0-9]*\)\")/\1/p" "$src/CMakeLists.txt"
        done | paste -sd.)
[[ -z $found || $found == "$VERSION" ]] || { log "SOURCE holds SUNDIALS $found, not $VERSION"; exit 1; }

log "configuring SUNDIALS $VERSION for $PREFIX/usr"
cmake -S "$src" -B "$tmp/build" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_INSTALL_PREFIX="$PREFIX/usr" -DCMAKE_INSTALL_LIBDIR=lib \
  "${library_kind[@]}" \
  -DBUILD_ARKODE=ON -DBUILD_CVODE=ON -DBUILD_CVODES=OFF -DBUILD_IDA=OFF -DBUILD_IDAS=OFF \
  -DBUILD_KINSOL=OFF -DBUILD_FORTRAN_MODULE_INTERFACE=OFF -DENABLE_MPI=OFF -DENABLE_OPENMP=OFF \
  -DENABLE_PTHREAD=OFF -DEXAMPLES_ENABLE_C=OFF -DEXAMPLES_ENABLE_CXX=OFF -DEXAMPLES_INSTALL=OFF \
  -DBUILD_BENCHMARKS=OFF -DSUNDIALS_TEST_ENABLE_UNIT_TESTS=OFF >"$tmp/cmake.log" 2>&1 ||
  { tail -n 30 "$tmp/cmake.log" >&2; log "cmake failed"; exit 1; }
log "building ($JOBS job(s))"
cmake --build "$tmp/build" -j "$JOBS" >"$tmp/build.log" 2>&1 ||
  { tail -n 30 "$tmp/build.log" >&2; log "build failed"; exit 1; }
cmake --install "$tmp/build" >"$tmp/install.log" 2>&1 ||
  { tail -n 30 "$tmp/install.log" >&2; log "install failed"; exit 1; }
grep -h 'define SUNDIALS_VERSION ' "$config" >&2
log "done: meson setup BUILDDIR -Dsundials_dir=$PREFIX/usr"
