"""Robot files from elsewhere and to elsewhere: every URDF of the PyPI package
`example-robot-data` through `vito inspect`, `vito init` and `vito check` (the table in
docs/robots.md is made the same way, by tools/robots_table.py), and every robot file under
problems/robots/ read by urdfdom through Pinocchio (`pin`)."""

import pathlib
import re
import sys

import pytest

import vito
from conftest import ROOT

sys.path.insert(0, str(ROOT / "tools"))
import robots_table  # noqa: E402

# The three example-robot-data URDFs vito refuses, each for a reason it states.
REFUSED = {
    "ur3.urdf": "the URDF has no links",
    "tiago_dual.urdf": "it has 101 coordinates",
    "alex_psyonic_hands.urdf": "follows joint 'index_q1', which is not defined",
}


def example_robot_data():
    robots = robots_table.robots_dir()
    if robots is None:
        pytest.skip(
            "the PyPI package example-robot-data is not installed "
            "(vendor-config/install-python.sh installs it; was PyPI unreachable?)"
        )
    return robots


def test_every_example_robot_data_urdf_loads_and_its_starter_checks(tmp_path):
    robots = example_robot_data()
    urdfs = sorted(robots.rglob("*.urdf"))
    assert len(urdfs) >= 69, urdfs
    refused, failed, loaded = {}, {}, 0
    for urdf in urdfs:
        row = robots_table.survey(vito.find_executable(), urdf, tmp_path)
        if "error" in row:
            refused[urdf.name] = row["message"]
        elif row["init"] != "ok":
            failed[urdf.name] = row["init"]
        else:
            loaded += 1
    assert failed == {}
    assert sorted(refused) == sorted(REFUSED), refused
    for name, says in REFUSED.items():
        assert says in refused[name], refused[name]
    assert loaded == len(urdfs) - len(REFUSED)
    # The limit's message names what to make fixed.
    assert "e.g. the 36 below link `hand_left_palm_link`" in refused["tiago_dual.urdf"]


def verbatim_originals():
    """The authors' files kept byte for byte (problems/robots/SOURCES.md: `verbatim`), which
    vito reads with its repairs and urdfdom does not; their normalised copies are the
    portable ones."""
    text = (ROOT / "problems" / "robots" / "SOURCES.md").read_text()
    return {
        m.group(1)
        for m in re.finditer(r"^\| `([^`*]+\.urdf)` \|[^\n]*\| verbatim", text, re.M)
    }


def test_every_robot_file_parses_in_urdfdom():
    pinocchio = pytest.importorskip(
        "pinocchio", reason="Pinocchio (pip install pin) is not installed"
    )
    robots = ROOT / "problems" / "robots"
    originals = verbatim_originals()
    assert len(originals) == 7, originals
    portable = [
        p for p in sorted(robots.rglob("*.urdf")) if str(p.relative_to(robots)) not in originals
    ]
    assert len(portable) == 9, portable
    for urdf in portable:
        model = pinocchio.buildModelFromUrdf(str(urdf))
        assert model.nq >= 0, urdf
    # Each original has its portable copy beside it.
    for original in originals:
        assert (robots / original.replace(".urdf", ".normalized.urdf")).is_file(), original
