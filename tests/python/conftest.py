"""Shared fixtures of the Python package's tests (run from the repository root by `make test`)."""

import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
HOPPER = ROOT / "problems" / "hopper_2d.toml"


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
