#!/usr/bin/env bash
# The Python package (python/, `import vito`) in the project's virtual environment .venv:
# creates .venv with Debian's python3 (python3-venv comes from vendor-config/install-deps.sh),
# installs maturin, numpy, pandas, matplotlib and pytest (and, for the tests, dask[distributed],
# tqdm, Pinocchio (`pin`), example-robot-data and MuJoCo) from PyPI when missing, builds the
# extension module with maturin (release profile, into the workspace's target/) and installs
# it into .venv; links .venv/bin/vito to target/release/vito (the command `vito.sweep` runs).
#
# Idempotent: an existing .venv and installed packages are kept; the build is cargo's
# (incremental). Usage: bash vendor-config/install-python.sh (from any directory).
# Environment: VITO_VENV (default: .venv at the repository root), PYTHON (default: python3).
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
venv="${VITO_VENV:-$root/.venv}"
python="${PYTHON:-python3}"

if [ ! -x "$venv/bin/python" ]; then
    echo "install-python: creating $venv with $($python --version 2>&1)"
    "$python" -m venv "$venv"
fi
if ! "$venv/bin/python" -c 'import maturin, numpy, pandas, pytest, matplotlib' 2>/dev/null \
    || [ ! -x "$venv/bin/maturin" ]; then
    echo "install-python: installing maturin, numpy, pandas, matplotlib, pytest into $venv"
    "$venv/bin/python" -m pip install --quiet --disable-pip-version-check \
        'maturin>=1.5,<2' numpy pandas matplotlib pytest
fi
# The executor tests' Dask (a LocalCluster) and the progress bar's tqdm; the tests that need
# Dask skip with a message where it cannot be installed (no network).
if ! "$venv/bin/python" -c 'import dask.distributed, tqdm' 2>/dev/null; then
    echo "install-python: installing dask[distributed] and tqdm into $venv"
    "$venv/bin/python" -m pip install --quiet --disable-pip-version-check \
        'dask[distributed]' tqdm \
        || echo "install-python: dask[distributed] or tqdm could not be installed; their tests skip" >&2
fi
# The independent libraries the tests check vito against: Pinocchio (PyPI `pin`) and the
# robots of example-robot-data (tests/python/test_pinocchio.py, test_robot_files.py and
# `make robots-table`), MuJoCo (vito.mujoco, the
# optional extra `vito[mujoco]`, tests/python/test_mujoco.py); their tests skip with a message
# where they cannot be installed.
if ! "$venv/bin/python" -c 'import pinocchio, mujoco, importlib.metadata as m; m.distribution("example-robot-data")' 2>/dev/null; then
    echo "install-python: installing pin, example-robot-data and mujoco into $venv"
    "$venv/bin/python" -m pip install --quiet --disable-pip-version-check \
        pin example-robot-data mujoco \
        || echo "install-python: pin, example-robot-data or mujoco could not be installed; their tests skip" >&2
fi
echo "install-python: building the extension module (maturin develop --release)"
(cd "$root/python" && VIRTUAL_ENV="$venv" PATH="$venv/bin:$PATH" \
    "$venv/bin/maturin" develop --release --quiet)
# The `vito` command `vito.sweep` runs by default (vito.find_executable).
cargo build --release --manifest-path "$root/Cargo.toml" --quiet
ln -sfn "$root/target/release/vito" "$venv/bin/vito"
echo "install-python: done ($("$venv/bin/python" -c 'import vito; print("vito", vito.__version__, "with Ipopt", vito.IPOPT_VERSION)'))"
