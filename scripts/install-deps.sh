#!/usr/bin/env bash
# install-deps.sh — installs the Debian packages listed in
# scripts/debian-packages.txt (or the packages given as arguments, e.g.
# `install-deps.sh afl++` for make fuzz) that are missing. As root it runs
# apt-get; otherwise it prints the exact command and fails, so nothing
# half-works later with an obscure compiler error.
#   scripts/install-deps.sh [PACKAGE...]
# Arguments:
#   PACKAGE...  Debian packages to install when missing (default: the list)
#   -h, --help  this text
set -euo pipefail
case ${1:-} in -h|--help) awk 'NR > 1 && !/^#/ { exit } NR > 1 { sub(/^# ?/, ""); print }' "$0"; exit 0 ;; esac
here=$(cd "$(dirname "$0")" && pwd)
if [ $# -gt 0 ]; then
  pkgs=("$@")
else
  mapfile -t pkgs < <(sed -e 's/#.*//' -e '/^[[:space:]]*$/d' "$here/debian-packages.txt" | awk '{print $1}')
fi
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
if [ "$(id -u)" -ne 0 ]; then
  echo "rtsim: missing Debian packages: ${missing[*]}" >&2
  echo "rtsim: install them with:  sudo apt-get install -y ${missing[*]}" >&2
  exit 1
fi
echo "rtsim: installing missing Debian packages: ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq >&2
apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
