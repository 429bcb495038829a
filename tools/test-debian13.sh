#!/usr/bin/env bash
# Runs the README's two set-up commands, `make demo` and `make test`, on Debian 13 (trixie):
# Ipopt 3.14 with the MPI build of MUMPS, where the host has bookworm's 3.11. `make test` runs
# the Python package's pytest suite too (Debian 13's python3-venv, Python 3.13; maturin, numpy,
# pandas, matplotlib, pytest from PyPI into /src/.venv).
#
#   sudo bash tools/test-debian13.sh        (or: make test-debian13)
#
# What it does, all under one temporary directory that is removed at the end, also after a
# failure or Ctrl-C:
#   1. debootstrap a minimal trixie root with gcc, make and ca-certificates (what README's
#      "fresh machine" assumes besides Rust), and procps (`kill`, which the Ctrl-C test of
#      tests/cli runs; a standard Debian install has it, the minbase variant does not);
#   2. copy HEAD of this repository into it (`git archive`: committed files only);
#   3. in private mount and PID namespaces (every mount and process disappears with them),
#      mount /proc, /sys (read-only), a tmpfs on /dev/shm, the host's Rust toolchain read-only at /opt/rust, and the host's cargo registry
#      as the lower layer of an overlay (the chroot reuses the downloaded crates; whatever it
#      adds goes to the temporary directory, never to the host's ~/.cargo);
#   4. chroot and run `make demo && make test` there, as root with CI=true, from /src.
# Needs the network to PyPI as well (the Python package's set-up).
#
# Needs root, a Debian-like host with apt-get (debootstrap is installed when missing) and the
# network to Debian's archive (and crates.io for crates the host has not downloaded yet).
# Environment:
#   VITO_DEBIAN13_MIRROR   archive to bootstrap from (http://deb.debian.org/debian)
#   VITO_DEBIAN13_COMMAND  what to run in /src instead of `make demo && make test`
#   VITO_DEBIAN13_OUT      a host directory that receives /src/out from the chroot afterwards
#                          (e.g. summaries of a benchmark run through VITO_DEBIAN13_COMMAND)
# Exit status: that of the command in the chroot; 2 when a precondition is missing.
set -euo pipefail

say() { echo "test-debian13: $*" >&2; }

# ---- inside the private mount namespace: mount, chroot, run ---------------------------------
if [ "${1:-}" = "--inside" ]; then
    root="$2" sysroot="$3" registry="$4" work="$5"
    mount -t proc proc "$root/proc"
    # OpenMPI (initialised when libipopt loads, see src/ipopt/compat.rs) reads the CPU
    # topology from /sys through hwloc.
    mount -t sysfs -o ro sysfs "$root/sys"
    mount -t tmpfs -o mode=1777 tmpfs "$root/dev/shm"
    mkdir -p "$root/opt/rust"
    mount --bind "$sysroot" "$root/opt/rust"
    mount -o remount,bind,ro "$root/opt/rust"
    mkdir -p "$root/root/.cargo/registry" "$work/registry-upper" "$work/registry-work"
    if [ -d "$registry" ]; then
        mount -t overlay overlay \
            -o "lowerdir=$registry,upperdir=$work/registry-upper,workdir=$work/registry-work" \
            "$root/root/.cargo/registry"
    fi
    # pip reaches PyPI through the host's certificate authorities (a proxy's among them):
    # the chroot gets the host's bundle and pip, requests and OpenSSL are pointed at it.
    ca_env=()
    host_ca="${SSL_CERT_FILE:-/etc/ssl/certs/ca-certificates.crt}"
    if [ -r "$host_ca" ]; then
        cp "$host_ca" "$root/etc/vito-host-ca.crt"
        ca_env=(PIP_CERT=/etc/vito-host-ca.crt SSL_CERT_FILE=/etc/vito-host-ca.crt
            REQUESTS_CA_BUNDLE=/etc/vito-host-ca.crt)
    fi
    command="${VITO_DEBIAN13_COMMAND:-make demo && make test}"
    say "running in the trixie chroot: $command"
    set +e
    chroot "$root" /usr/bin/env -i \
        HOME=/root \
        PATH=/opt/rust/bin:/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
        CARGO_HOME=/root/.cargo \
        CARGO_TERM_COLOR=never \
        CI=true \
        LANG=C.UTF-8 \
        TERM=dumb \
        "${ca_env[@]}" \
        /bin/bash -c "cd /src && $command" </dev/null
    status=$?
    set -e
    # Unmount explicitly (the namespace would drop them anyway when this process ends).
    umount "$root/root/.cargo/registry" 2>/dev/null || true
    umount "$root/opt/rust" "$root/dev/shm" "$root/sys" "$root/proc"
    exit "$status"
fi

# ---- on the host ------------------------------------------------------------------------------
start=$SECONDS
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(git -C "$here" rev-parse --show-toplevel)"
mirror="${VITO_DEBIAN13_MIRROR:-http://deb.debian.org/debian}"

if [ "$(id -u)" -ne 0 ]; then
    say "needs root (debootstrap, chroot, mounts): run sudo make test-debian13"
    exit 2
fi
for tool in unshare chroot mount git; do
    command -v "$tool" >/dev/null 2>&1 || { say "needs $tool"; exit 2; }
done
if ! command -v debootstrap >/dev/null 2>&1; then
    command -v apt-get >/dev/null 2>&1 || { say "needs debootstrap (or apt-get to install it)"; exit 2; }
    say "installing debootstrap"
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends debootstrap >/dev/null
fi
if ! sysroot="$(rustc --print sysroot 2>/dev/null)" || [ ! -x "$sysroot/bin/cargo" ]; then
    say "needs the host's Rust toolchain (rustc --print sysroot with bin/cargo in it)"
    exit 2
fi
registry="${CARGO_HOME:-$HOME/.cargo}/registry"
if [ -n "$(git -C "$repo" status --porcelain --untracked-files=no)" ]; then
    say "note: uncommitted changes are not tested (the chroot gets HEAD)"
fi

work="$(mktemp -d /var/tmp/vito-debian13.XXXXXX)"
root="$work/root"
inner=""

cleanup() {
    local status=$?
    # Finish the clean-up even if another Ctrl-C or TERM comes.
    trap - EXIT
    trap '' INT TERM
    if [ -n "$inner" ] && kill -0 "$inner" 2>/dev/null; then
        # unshare ignores INT and TERM while its child runs: KILL it, and --kill-child takes
        # down the PID namespace, i.e. everything still running in the chroot.
        kill -KILL "$inner" 2>/dev/null || true
        wait "$inner" 2>/dev/null || true
    fi
    # The mounts live in the inner namespace only; should any be visible here (an unshare
    # that failed half-way), take them down before deleting, deepest first.
    local mounts
    mounts="$(awk -v w="$work" 'index($2, w) == 1 {print $2}' /proc/self/mounts | sort -r)"
    if [ -n "$mounts" ]; then
        while read -r mnt; do umount -l "$mnt" || true; done <<<"$mounts"
    fi
    if awk -v w="$work" 'index($2, w) == 1 {found=1} END {exit !found}' /proc/self/mounts; then
        say "something is still mounted under $work; not deleting it"
    else
        rm -rf --one-file-system "$work"
    fi
    say "finished in $((SECONDS - start)) s with status $status"
    exit "$status"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

say "bootstrapping trixie into $root from $mirror"
t=$SECONDS
if ! debootstrap --variant=minbase --include=ca-certificates,gcc,libc6-dev,make,procps \
    trixie "$root" "$mirror" >"$work/debootstrap.log" 2>&1; then
    tail -n 30 "$work/debootstrap.log" >&2
    say "debootstrap failed"
    exit 1
fi
say "bootstrap took $((SECONDS - t)) s"

mkdir -p "$root/src"
git -C "$repo" archive --format=tar HEAD | tar -x -C "$root/src"
say "copied HEAD $(git -C "$repo" rev-parse --short HEAD) into /src"

t=$SECONDS
# A private mount namespace (the mounts vanish with it) and a PID namespace whose first process
# is the inner script: when cleanup ends unshare, --kill-child kills that process, and with it
# every process left in the chroot.
unshare --mount --propagation private --pid --fork --kill-child \
    bash "$here/test-debian13.sh" --inside "$root" "$sysroot" "$registry" "$work" &
inner=$!
set +e
wait "$inner"
status=$?
set -e
inner=""
say "command in the chroot took $((SECONDS - t)) s, status $status"

if [ -n "${VITO_DEBIAN13_OUT:-}" ] && [ -d "$root/src/out" ]; then
    mkdir -p "$VITO_DEBIAN13_OUT"
    cp -r "$root/src/out/." "$VITO_DEBIAN13_OUT/"
    say "copied /src/out to $VITO_DEBIAN13_OUT"
fi
exit "$status"
