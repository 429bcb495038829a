#!/usr/bin/env bash
# Installs the Debian packages of vendor-config/debian-packages.txt that this release needs and
# that are missing.
#
# The release comes from /etc/os-release (VERSION_CODENAME, ID): Debian 12 (bookworm, Ipopt
# 3.11) and Debian 13 (trixie, Ipopt 3.14) are known. On any other release with apt-get (an
# Ubuntu, a Debian testing) it says so and installs only the packages every release names
# alike (the `*` lines); build.rs then accepts whatever Ipopt 3.11-3.14 pkg-config finds.
#
# Idempotent: installed packages are left alone, and when nothing is missing it changes
# nothing (no apt-get update either). Runs as root, or through sudo otherwise.
# Usage: bash vendor-config/install-deps.sh [--list]   (from any directory; --list prints the
#        packages this release needs, one a line, and installs nothing)
# Environment: VITO_OS_RELEASE names another os-release file (for tests).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
list="$here/debian-packages.txt"
os_release="${VITO_OS_RELEASE:-/etc/os-release}"

# The release: ID and VERSION_CODENAME from os-release (empty when the file is missing).
id="" codename=""
if [ -r "$os_release" ]; then
    id="$(. "$os_release" && echo "${ID:-}")"
    codename="$(. "$os_release" && echo "${VERSION_CODENAME:-}")"
fi

# The packages the list gives for `$1` (a codename; empty: only the `*` lines).
packages_for() {
    local release pkg rest
    while read -r release pkg rest; do
        case "$release" in '' | '#'*) continue ;; esac
        if [ "$release" = "*" ] || { [ -n "$1" ] && [[ ",$release," == *",$1,"* ]]; }; then
            echo "$pkg"
        fi
    done <"$list"
}

case "$id:$codename" in
debian:bookworm) release="$codename"; echo "install-deps: Debian 12 (bookworm): Ipopt 3.11 from Debian." >&2 ;;
debian:trixie) release="$codename"; echo "install-deps: Debian 13 (trixie): Ipopt 3.14 from Debian." >&2 ;;
*)
    release=""
    echo "install-deps: unknown release (ID=${id:-?}, VERSION_CODENAME=${codename:-?} in $os_release):" \
        "this script knows Debian 12 (bookworm) and 13 (trixie)." >&2
    ;;
esac

wanted=()
while read -r pkg; do wanted+=("$pkg"); done < <(packages_for "$release")
if [ "${1:-}" = "--list" ]; then
    printf '%s\n' "${wanted[@]}"
    exit 0
fi

if ! command -v dpkg-query >/dev/null 2>&1 || ! command -v apt-get >/dev/null 2>&1; then
    echo "install-deps: this script needs Debian's dpkg-query and apt-get; it installs nothing here." >&2
    echo "install-deps: install the equivalents of: ${wanted[*]}" >&2
    echo "install-deps: (Ipopt 3.11-3.14 with MUMPS and its C headers, libclang, pkg-config, a BLAS)," >&2
    echo "install-deps: or point VITO_IPOPT_DIR at an Ipopt 3.11-3.14 prefix (see docs/install.md)." >&2
    exit 1
fi
if [ -z "$release" ]; then
    echo "install-deps: installing only the packages Debian 12 and 13 name alike (${wanted[*]})" \
        "with apt-get; if one is missing from this release's archive, install Ipopt 3.11-3.14" \
        "with its C headers yourself or set VITO_IPOPT_DIR (see docs/install.md)." >&2
fi

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
