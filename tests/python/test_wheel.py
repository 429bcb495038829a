"""`pip wheel ./python` builds a wheel that installs into a clean virtual environment (numpy
from the package index, Debian's Ipopt on the system) and solves. Slow (a build and a fresh
environment): marked `wheel`, run by `make test-wheel`."""

import subprocess
import sys

import pytest

from conftest import HOPPER, ROOT


@pytest.mark.wheel
def test_a_wheel_installs_into_a_clean_venv_and_solves(tmp_path):
    wheels = tmp_path / "wheels"
    build = subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--no-deps", "--disable-pip-version-check",
         "-w", str(wheels), str(ROOT / "python")],
        capture_output=True, text=True, cwd=tmp_path,
    )
    assert build.returncode == 0, build.stdout[-3000:] + build.stderr[-3000:]
    [wheel] = list(wheels.glob("vito-*.whl"))
    assert "abi3" in wheel.name
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    python = venv / "bin" / "python"
    install = subprocess.run(
        [str(python), "-m", "pip", "install", "--disable-pip-version-check", str(wheel)],
        capture_output=True, text=True,
    )
    assert install.returncode == 0, install.stdout[-3000:] + install.stderr[-3000:]
    # Outside the repository, with no `vito` command anywhere: the wheel alone solves.
    script = f"""
import vito
s = vito.solve({str(HOPPER)!r})
print(s.status, s.iterations)
"""
    run = subprocess.run([str(python), "-c", script], capture_output=True, text=True,
                         cwd=tmp_path, env={"PATH": "/usr/bin:/bin"})
    assert run.returncode == 0, run.stderr
    status, iterations = run.stdout.split()
    assert status == "solve_succeeded"
    # The same solve as this environment's package.
    import vito

    assert int(iterations) == vito.solve(str(HOPPER)).iterations
