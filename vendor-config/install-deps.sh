#!/usr/bin/env bash
# Installs the Debian packages listed in vendor-config/debian-packages.txt that are missing.
#
# Idempotent: installed packages are left alone, and when nothing is missing it changes
# nothing (no apt-get update either). Runs as root, or through sudo otherwise.
# Usage: bash vendor-config/install-deps.sh   (from any directory)
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
list="$here/debian-packages.txt"

if ! command -v dpkg-query >/dev/null 2>&1 || ! command -v apt-get >/dev/null 2>&1; then
    echo "install-deps: this script needs Debian's dpkg-query and apt-get." >&2
    echo "install-deps: on another system install the equivalents of: $(sed -e 's/#.*//' "$list" | xargs)" >&2
    echo "install-deps: or point VITO_IPOPT_DIR at an Ipopt 3.11-3.13 prefix (see README.md)." >&2
    exit 1
fi

wanted=()
while read -r line; do
    pkg="${line%%#*}"
    pkg="$(echo "$pkg" | xargs)"
    [ -n "$pkg" ] && wanted+=("$pkg")
done <"$list"

missing=()
for pkg in "${wanted[@]}"; do
    status="$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)"
    if [ "$status" != "install ok installed" ]; then
        missing+=("$pkg")
    fi
done

if [ "${#missing[@]}" -eq 0 ]; then
    echo "install-deps: all ${#wanted[@]} packages present (${wanted[*]}); nothing to do."
    exit 0
fi

if [ "$(id -u)" -eq 0 ]; then
    as_root=()
elif command -v sudo >/dev/null 2>&1; then
    as_root=(sudo)
    echo "install-deps: not root, using sudo."
else
    echo "install-deps: missing ${missing[*]}, and this is not root and sudo is absent." >&2
    echo "install-deps: run as root: bash $here/install-deps.sh" >&2
    exit 1
fi

echo "install-deps: installing ${missing[*]}"
echo "install-deps: running apt-get update"
"${as_root[@]}" apt-get update
echo "install-deps: running apt-get install -y --no-install-recommends ${missing[*]}"
"${as_root[@]}" env DEBIAN_FRONTEND=noninteractive \
    apt-get install -y --no-install-recommends "${missing[@]}"
echo "install-deps: done."
