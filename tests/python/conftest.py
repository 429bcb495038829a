"""Shared fixtures of the Python package's tests (run from the repository root by `make test`)."""

import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
HOPPER = ROOT / "problems" / "hopper_2d.toml"

# Ipopt options under which a solve never ends by itself: tolerances no iterate reaches, the
# acceptable-point and tiny-step exits off (a failed line search at an acceptable point
# included), an iteration limit no test reaches. A test that stops such a solve (a signal, a
# time limit) decides its outcome by that stop alone, whatever the machine's speed.
ENDLESS = {
    "solver.ipopt.max_iter": 100000000,
    "solver.ipopt.tol": 1e-300,
    "solver.ipopt.dual_inf_tol": 1e-300,
    "solver.ipopt.constr_viol_tol": 1e-300,
    "solver.ipopt.compl_inf_tol": 1e-300,
    "solver.ipopt.acceptable_iter": 0,
    "solver.ipopt.acceptable_tol": 1e-300,
    "solver.ipopt.tiny_step_tol": 0,
}


def pytest_configure(config):
    config.addinivalue_line(
        "markers", "wheel: builds the wheel and installs it into a fresh venv (make test-wheel)"
    )


@pytest.fixture(scope="session")
def hopper():
    import vito

    return vito.Problem(str(HOPPER))


@pytest.fixture(scope="session")
def hopper_solution(hopper):
    return hopper.solve()
