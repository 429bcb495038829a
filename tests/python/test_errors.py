"""Errors in Python's terms; repr that round-trips; the module-level functions; notebooks."""

import html
import os
import re
import shutil

import pytest

import vito
from conftest import HOPPER, ROOT

TROT = ROOT / "problems" / "hamr_trot.toml"


def test_a_missing_file_is_file_not_found(tmp_path):
    missing = tmp_path / "nope.toml"
    with pytest.raises(FileNotFoundError) as caught:
        vito.Problem(str(missing))
    e = caught.value
    assert isinstance(e, vito.ProblemError) and isinstance(e, vito.ProblemFileNotFoundError)
    assert e.filename == e.file == str(missing)
    assert e.errno == 2
    assert str(missing) in e.message


def test_a_set_key_error_speaks_of_set_and_lists_the_family_parameters():
    with pytest.raises(vito.ProblemError) as caught:
        vito.Problem(str(TROT), set={"muu": 0.5})
    m = caught.value.message
    assert "--set" not in m
    assert "(from set=)" in m
    assert "`stride_hz`" in m and "`c1`" in m and "`q11`" in m


def test_a_value_of_the_wrong_type_is_named_in_python_words(hopper):
    with pytest.raises(vito.ProblemError) as caught:
        hopper.with_set({"horizon.knots": 2.5})
    m = caught.value.message
    assert "(from set=)" in m
    assert "i64" not in m and "usize" not in m
    assert "int" in m and "float" in m


def test_a_set_value_of_an_unknown_type_is_a_type_error(hopper):
    with pytest.raises(TypeError, match="str, bool, int, float"):
        hopper.with_set({"contacts.friction": {"a": 1}})
    with pytest.raises(TypeError, match="set= keys are str"):
        hopper.with_set({1: 0.5})


@pytest.mark.parametrize("set_", [
    {"contacts.friction": 0.6},
    {"contacts.friction": 0.6, "slack.weight": 1000},
    {"name": "it's a \"hop\""},
    {"name": '"41"'},
    {"horizon.knots": 31, "robot.joint_limits": False, "robot.gravity": [0.0, 0.0, -9.0]},
])
def test_repr_round_trips(set_):
    p = vito.Problem(str(HOPPER), set=set_)
    again = eval(repr(p), {"vito": vito})
    assert again.sets == p.sets
    assert repr(again) == repr(p)
    assert again.name == p.name


def test_repr_of_a_plain_problem():
    p = vito.Problem(str(HOPPER))
    assert repr(p) == f"vito.Problem({str(HOPPER)!r})"


def test_module_level_solve_is_the_methods(hopper_solution):
    s = vito.solve(str(HOPPER))
    assert s.trajectory_csv() == hopper_solution.trajectory_csv()
    warm = vito.solve(str(HOPPER), set={"slack.weight": 1000}, warm_start=hopper_solution)
    assert warm.summary["parameters"] == {"slack.weight": 1000}


def test_module_level_simulate_takes_a_path(hopper, hopper_solution):
    by_path = vito.simulate(str(HOPPER), inputs=hopper_solution, duration=0.5)
    by_problem = vito.simulate(hopper, inputs=hopper_solution, duration=0.5)
    assert by_path.trajectory_csv() == by_problem.trajectory_csv()
    assert by_path.time[-1] == pytest.approx(0.5)


def test_out_of_range_options_are_value_errors(hopper):
    with pytest.raises(ValueError, match="duration="):
        vito.simulate(hopper, duration=1e20)
    with pytest.raises(ValueError, match='feedback=.*"explicit" or "implicit"'):
        vito.simulate(hopper, feedback="sideways")
    with pytest.raises(ValueError, match="starts=0"):
        hopper.solve(starts=0)
    # Refused before the solve starts (not at its first iteration).
    with pytest.raises(TypeError, match="progress=42: give a callable"):
        hopper.solve(progress=42)


def test_notebook_display_shows_the_summary_and_the_motion_page(hopper, hopper_solution):
    page = hopper_solution._repr_html_()
    assert "<table>" in page and "solve_succeeded" in page
    assert f"{hopper_solution.objective:.6e}".split("e")[0] in page
    frame = re.search(r'<iframe srcdoc="([^"]*)"', page)
    assert frame is not None
    inner = html.unescape(frame.group(1))
    assert inner.lstrip().lower().startswith("<!doctype html>")
    # The page holds the motion: every knot time of the solution is in its data.
    assert hopper.name in inner and "<script" in inner
    sim = vito.simulate(hopper, inputs=hopper_solution, duration=0.2)
    sim_page = sim._repr_html_()
    assert "simulation" in sim_page and "<iframe srcdoc=" in sim_page
    assert "midpoint" in sim_page


class PathLike:
    def __init__(self, path):
        self.path = path

    def __fspath__(self):
        return self.path


@pytest.mark.parametrize("path", [
    bytes(HOPPER), PathLike(str(HOPPER)), PathLike(bytes(HOPPER)), HOPPER,
])
def test_bytes_and_path_like_paths_are_paths(path, tmp_path):
    # As open() takes them: str, bytes and os.PathLike, everywhere a path goes.
    p = vito.Problem(path)
    assert p.name == "hopper-2d" and str(p.path) == str(HOPPER)
    assert vito.Kinematics(path).contact_names == ["foot_contact"]
    sim = vito.simulate(path, duration=0.1)
    out = os.path.join(os.fsencode(tmp_path), b"sim")
    assert sim.write(out) and (tmp_path / "sim" / "trajectory.csv").is_file()
    s = vito.solve(path, set={"solver.ipopt.max_iter": 1}, out=PathLike(bytes(tmp_path / "s")))
    assert (tmp_path / "s" / "summary.json").is_file()
    s.write(bytes(tmp_path / "again"))
    csv = bytes(tmp_path / "s" / "trajectory.csv")
    warm = p.with_set({"solver.ipopt.max_iter": 1}).solve(warm_start=csv)
    assert warm.summary["iterations"] == 1
    assert vito.simulate(p, inputs=csv, duration=0.1).time[-1] == pytest.approx(0.1)
    for bad in [3, None, bytearray(bytes(HOPPER)), PathLike(3)]:
        with pytest.raises(TypeError, match="str, bytes or os.PathLike|str or bytes"):
            vito.Problem(bad)


def test_a_path_that_is_not_utf8_works(tmp_path):
    # A name of bytes that are not UTF-8 (as Linux allows), given as bytes or as the str
    # Python reads it as (os.fsdecode): the file loads, its repr and pickle give it back,
    # results are written under such names; a missing one is FileNotFoundError naming it.
    import pickle

    shutil.copytree(ROOT / "problems" / "robots", tmp_path / "robots")
    name = os.path.join(os.fsencode(tmp_path), b"hop\xffper.toml")
    with open(name, "wb") as f:
        f.write(HOPPER.read_bytes())
    for given in (name, os.fsdecode(name)):
        p = vito.Problem(given, set={"solver.ipopt.max_iter": 1})
        assert os.fsencode(p.path) == name
        assert os.fsencode(eval(repr(p), {"vito": vito}).path) == name
        assert os.fsencode(pickle.loads(pickle.dumps(p)).path) == name
    assert "b'" in repr(vito.Problem(name))
    out = os.path.join(os.fsencode(tmp_path), b"out-\xfe")
    s = p.solve(out=out)
    assert os.path.isfile(os.path.join(out, b"summary.json"))
    assert pickle.loads(pickle.dumps(s)).trajectory_csv() == s.trajectory_csv()
    # A warm start is named in the problem's TOML, which holds UTF-8 only: a clear error.
    with pytest.raises(ValueError, match="warm_start=b'.*': the path is not UTF-8"):
        p.solve(warm_start=os.path.join(out, b"trajectory.csv"))
    # A sweep writes under such a name; its warm starts would need to name it in TOML.
    from concurrent.futures import ThreadPoolExecutor

    sweep = os.path.join(os.fsencode(tmp_path), b"sweep-\xfe")
    with pytest.raises(ValueError, match="out=b'.*': the directory's name is not UTF-8"):
        vito.sweep(p, grid={"contacts.friction": [0.5]}, out=sweep, progress=False)
    with ThreadPoolExecutor(1) as pool:
        table = vito.sweep(p, grid={"contacts.friction": [0.5]}, out=sweep, executor=pool,
                           neighbour_rounds=0, progress=False)
    assert table["status"].tolist() == ["finished"]
    missing = os.path.join(os.fsencode(tmp_path), b"no\xff.toml")
    with pytest.raises(FileNotFoundError) as caught:
        vito.Problem(missing)
    assert os.fsencode(caught.value.filename) == missing
    assert os.fsencode(caught.value.file) == missing
