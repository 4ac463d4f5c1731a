#!/usr/bin/env bash
# Installs the Debian packages Quack needs for the given purposes (build, test, bench, ...),
# as listed in scripts/packages/<purpose>.txt. Run as root it installs what is missing;
# otherwise it prints the exact command to run and fails.
#   scripts/setup.sh build test bench
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
[ $# -gt 0 ] || set -- build
missing=()
for purpose in "$@"; do
  list="$here/packages/$purpose.txt"
  if [ ! -f "$list" ]; then
    echo "setup.sh: unknown purpose '$purpose' (no $list)" >&2
    exit 2
  fi
  while read -r pkg; do
    pkg=${pkg%%#*}
    pkg=$(echo "$pkg" | tr -d '[:space:]')
    [ -n "$pkg" ] || continue
    if ! dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q 'install ok installed'; then
      missing+=("$pkg")
    fi
  done <"$list"
done
[ ${#missing[@]} -eq 0 ] && exit 0
if [ "$(id -u)" -eq 0 ]; then
  echo "setup.sh: installing ${missing[*]}" >&2
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
else
  echo "setup.sh: missing Debian packages: ${missing[*]}" >&2
  echo "install them with:  sudo apt-get install ${missing[*]}" >&2
  exit 1
fi
