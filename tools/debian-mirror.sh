#!/usr/bin/env bash
# Print the Debian mirror this machine's apt uses (the first non-security URI of its deb822
# .sources files, else of its one-line sources.list), e.g. http://deb.debian.org/debian. The tools
# that fetch Debian packages or sources without touching the system's apt configuration
# (sundials7-prefix.sh, build-wheel.sh, test-wheel.sh) all take their mirror from here.
set -euo pipefail
mirror=""
for f in /etc/apt/sources.list.d/debian.sources /etc/apt/sources.list.d/*.sources; do
  [[ -r $f ]] || continue
  mirror=$(awk '/^URIs:/ { for (i = 2; i <= NF; i++) if ($i !~ /security/) { print $i; exit } }' "$f")
  [[ -n $mirror ]] && break
done
if [[ -z $mirror ]]; then
  for f in /etc/apt/sources.list /etc/apt/sources.list.d/*.list; do
    [[ -r $f ]] || continue
    mirror=$(awk '$1 == "deb" { for (i = 2; i <= NF; i++) if ($i ~ /^[a-z]+:\/\//) {
                 if ($i !~ /security/) { print $i; exit } ; break } }' "$f")
    [[ -n $mirror ]] && break
  done
fi
[[ -n $mirror ]] || { echo "[debian-mirror] no Debian mirror found in /etc/apt/sources.list{,.d}" >&2; exit 1; }
echo "${mirror%/}"
