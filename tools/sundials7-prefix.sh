#!/usr/bin/env bash
# Unpack Debian 13 ("trixie") SUNDIALS 7.x (libsundials-dev and the libraries fputlab links) into a
# private prefix, for building fputlab against SUNDIALS 7 on a Debian 12 machine:
#
#   tools/sundials7-prefix.sh [PREFIX [SUITE]]  (default: ./build-sun7/prefix, suite trixie)
#   meson setup build-sun7/build -Dsundials_dir=PREFIX/usr
#
# SUITE picks another Debian suite by the same mechanism (e.g. sid or experimental, for another
# SUNDIALS 7.x; experimental carries only what differs from sid, so sid is added under it).
#
# Trixie's SUNDIALS libraries only need glibc >= 2.14, so they run on Debian 12 from any directory.
# Nothing is installed and the system's apt configuration is left alone: apt-get runs with a
# temporary sources list (the system's own Debian mirror, suite trixie), its own package lists and
# cache in a temporary directory, and the packages are unpacked with `dpkg -x`. Idempotent: an
# existing prefix with a SUNDIALS 7 sundials_config.h is kept.
set -euo pipefail
PREFIX=${1:-build-sun7/prefix}
SUITE=${2:-trixie}
[[ $SUITE =~ ^[a-z]+$ ]] || { echo "[sundials7-prefix] SUITE must be a Debian suite name (got '$SUITE')" >&2; exit 2; }
mkdir -p "$PREFIX"
PREFIX=$(cd "$PREFIX" && pwd)
log() { printf '[sundials7-prefix] %s\n' "$*" >&2; }

if grep -qs '#define SUNDIALS_VERSION_MAJOR 7' "$PREFIX/usr/include/sundials/sundials_config.h"; then
  log "SUNDIALS 7 already in $PREFIX/usr"
  exit 0
fi
command -v apt-get >/dev/null && command -v dpkg >/dev/null ||
  { log "needs apt-get and dpkg (a Debian system)"; exit 1; }

mirror=$("$(dirname "$0")/debian-mirror.sh")
keyring=/usr/share/keyrings/debian-archive-keyring.gpg
log "mirror $mirror, suite $SUITE"

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/lists/partial" "$tmp/cache/archives/partial" "$tmp/parts" "$tmp/prefs" "$tmp/debs"
cat > "$tmp/sources.list" <<EOF
deb [signed-by=$keyring] $mirror $SUITE main
EOF
if [[ $SUITE == experimental ]]; then
  echo "deb [signed-by=$keyring] $mirror sid main" >> "$tmp/sources.list"
  printf 'Package: *\nPin: release a=experimental\nPin-Priority: 990\n' > "$tmp/prefs/experimental.pref"
fi
: > "$tmp/status"
APT=(apt-get -q -o Dir::Etc::SourceList="$tmp/sources.list" -o Dir::Etc::SourceParts="$tmp/parts"
     -o Dir::Etc::Preferences="$tmp/prefs/none" -o Dir::Etc::PreferencesParts="$tmp/prefs"
     -o Dir::State::Lists="$tmp/lists" -o Dir::State::status="$tmp/status"
     -o Dir::Cache="$tmp/cache" -o Debug::NoLocking=1 -o APT::Architecture="$(dpkg --print-architecture)")
[[ $(id -u) -eq 0 ]] && APT+=(-o APT::Sandbox::User=root)  # _apt cannot read $tmp
"${APT[@]}" update >/dev/null
CACHE=(apt-cache -o Dir::Etc::SourceList="$tmp/sources.list" -o Dir::Etc::SourceParts="$tmp/parts"
       -o Dir::State::Lists="$tmp/lists" -o Dir::State::status="$tmp/status" -o Dir::Cache="$tmp/cache")

# libsundials-dev and the libraries it depends on that fputlab (or a program calling CVODE/ARKODE
# with serial vectors, dense/band matrices and the direct/Newton/fixed-point solvers) links.
pkgs=(libsundials-dev)
while read -r dep; do
  case $dep in
    libsundials-core* | libsundials-arkode* | libsundials-cvode[0-9]* | libsundials-nvecserial* | \
    libsundials-sunmatrix* | libsundials-sunlinsol* | libsundials-sunnonlinsol*) pkgs+=("$dep") ;;
  esac
done < <("${CACHE[@]}" depends libsundials-dev | awk '/Depends:/ { print $2 }' | sed 's/:.*//' | sort -u)
log "downloading ${pkgs[*]}"
(cd "$tmp/debs" && "${APT[@]}" download "${pkgs[@]}" >/dev/null)
for deb in "$tmp"/debs/*.deb; do dpkg -x "$deb" "$PREFIX"; done

# Debian puts the libraries under lib/<multiarch>; meson's -Dsundials_dir looks in PREFIX/usr/lib.
multiarch=$(dpkg-architecture -qDEB_HOST_MULTIARCH 2>/dev/null || gcc -print-multiarch)
if [[ -d $PREFIX/usr/lib/$multiarch ]]; then
  for so in "$PREFIX/usr/lib/$multiarch"/libsundials_*; do
    ln -sf "$multiarch/$(basename "$so")" "$PREFIX/usr/lib/$(basename "$so")"
  done
fi
grep -h 'define SUNDIALS_VERSION ' "$PREFIX/usr/include/sundials/sundials_config.h" >&2
log "done: meson setup BUILDDIR -Dsundials_dir=$PREFIX/usr"
