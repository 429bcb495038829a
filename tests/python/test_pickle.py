"""Problems, solutions and simulations cross process boundaries (pickle, multiprocessing)."""

import multiprocessing
import pathlib
import pickle
import shutil

import numpy as np
import pytest

import vito
from conftest import HOPPER, ROOT


def test_a_problem_pickles_as_its_file_and_overrides(hopper):
    p = hopper.with_set({"contacts.friction": 0.6, "slack.weight": 1000})
    q = pickle.loads(pickle.dumps(p))
    assert isinstance(q, vito.Problem)
    assert q.sets == ["contacts.friction=0.6", "slack.weight=1000"]
    assert str(q.path) == str(HOPPER)  # absolute in the pickle; the fixture's path is absolute
    assert q.check()["n_variables"] == p.check()["n_variables"] == 288
    assert q.name == p.name


def test_a_moved_problem_file_is_a_clear_error_on_unpickling(tmp_path):
    shutil.copytree(ROOT / "problems", tmp_path / "problems")
    p = vito.Problem(str(tmp_path / "problems" / "hopper_2d.toml"))
    data = pickle.dumps(p)
    (tmp_path / "problems").rename(tmp_path / "moved")
    with pytest.raises(FileNotFoundError) as caught:
        pickle.loads(data)
    assert isinstance(caught.value, vito.ProblemError)
    assert caught.value.filename == str(tmp_path / "problems" / "hopper_2d.toml")
    assert any("unpickling" in note for note in caught.value.__notes__)


def test_a_solution_round_trips_through_pickle(tmp_path, hopper_solution):
    s = pickle.loads(pickle.dumps(hopper_solution))
    assert isinstance(s, vito.Solution)
    assert s.trajectory_csv() == hopper_solution.trajectory_csv()
    assert s.status == hopper_solution.status == "solve_succeeded"
    assert s.objective == hopper_solution.objective
    assert s.iterations == hopper_solution.iterations
    assert s.summary == hopper_solution.summary
    assert s.units == hopper_solution.units
    assert s.contact_names == hopper_solution.contact_names
    for name in ["time", "q", "v", "u", "normal_impulse", "friction_impulse", "signed_distance", "slack"]:
        assert np.array_equal(getattr(s, name), getattr(hopper_solution, name)), name
    # What it writes is the original's, file for file.
    s.write(str(tmp_path / "a"))
    hopper_solution.write(str(tmp_path / "b"))
    for name in ["trajectory.csv", "summary.json"]:
        assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes()


def test_a_simulation_round_trips_through_pickle(hopper, hopper_solution):
    sim = vito.simulate(hopper, track=hopper_solution, gains={"all": (100.0, 10.0)})
    again = pickle.loads(pickle.dumps(sim))
    assert isinstance(again, vito.Simulation)
    assert again.trajectory_csv() == sim.trajectory_csv()
    assert again.summary == sim.summary
    assert np.array_equal(again.q, sim.q) and np.array_equal(again.u, sim.u)


def solve_friction(mu):
    """A module-level function a pool can pickle by reference."""
    return vito.Problem(str(HOPPER), set={"contacts.friction": mu}).solve()


def test_a_pool_returns_solutions(hopper_solution):
    # The pool's workers solve and send Solutions back (pickled); the 0.8 point is the
    # fixture's problem, solved here in the parent: the worker's result is the same.
    ctx = multiprocessing.get_context("spawn")
    with ctx.Pool(2) as pool:
        results = pool.map(solve_friction, [0.8, 0.5])
    assert [type(r) for r in results] == [vito.Solution, vito.Solution]
    assert results[0].trajectory_csv() == hopper_solution.trajectory_csv()
    assert results[1].summary["parameters"] == {"contacts.friction": 0.5}
    assert results[1].solved


def test_a_pool_takes_problems(hopper):
    ctx = multiprocessing.get_context("spawn")
    problems = [hopper.with_set({"horizon.knots": k}) for k in (11, 21)]
    with ctx.Pool(2) as pool:
        names = pool.map(repr, problems)
    assert names == [repr(p) for p in problems]


BRICK = ROOT / "problems" / "brick_3d.toml"


def sha256(path):
    import hashlib

    return hashlib.sha256(pathlib.Path(path).read_bytes()).hexdigest()


@pytest.fixture(scope="module")
def short_hopper_solution():
    return vito.Problem(str(HOPPER), set={"solver.ipopt.max_iter": 3}).solve()


@pytest.fixture(scope="module")
def hopper_simulation():
    return vito.simulate(str(HOPPER), duration=0.2)


def restored(obj, path=None, text=None, sha=None, drop_sha=False):
    """`obj` pickled, its state changed (another problem file, another TOML text, another
    fingerprint), and unpickled."""
    restore, (p, sets, t, s) = obj.__reduce__()
    args = (path or p, sets, text or t) + (() if drop_sha else (sha or s,))

    class Changed:
        def __reduce__(self):
            return restore, args

    return pickle.loads(pickle.dumps(Changed()))


@pytest.mark.parametrize("which", ["solution", "simulation"])
def test_a_result_restored_against_another_problem_is_refused(
        which, short_hopper_solution, hopper_simulation):
    # The hopper's numbers (4 coordinates, 2 friction directions) with the brick's file
    # (6 coordinates, 4 directions), under the brick file's own fingerprint: refused on
    # restoring, not a panic when displayed or written.
    result = short_hopper_solution if which == "solution" else hopper_simulation
    with pytest.raises(vito.VitoError, match="cannot unpickle this vito.S") as caught:
        restored(result, path=BRICK, sha=sha256(BRICK))
    assert "its problem" in str(caught.value)


def without_last_row(text, key):
    """The TOML text with the last row of the 2-D array `key` dropped."""
    import re

    lines = text.splitlines()
    i = next(k for k, line in enumerate(lines) if line.startswith(f"{key} = "))
    lines[i] = re.sub(r", \[[^\[\]]*\]\]$", "]", lines[i])
    return "\n".join(lines)


def replaced(text, key, value):
    """The TOML text with the value of the top-level `key` replaced."""
    lines = text.splitlines()
    i = next(k for k, line in enumerate(lines) if line.startswith(f"{key} = "))
    lines[i] = f"{key} = {value}"
    return "\n".join(lines)


def text_of(result):
    return result.__reduce__()[1][2]


@pytest.mark.parametrize("change, message", [
    (lambda t: without_last_row(t, "q"), "`q` has 20 rows, not 21"),
    (lambda t: without_last_row(t, "u"), "`u` has 19 rows, not 20"),
    (lambda t: t.replace('coordinate_names = ["x", "z", "theta", "r"]',
                         'coordinate_names = ["x", "z", "theta"]'), "its coordinates"),
    (lambda t: t.replace("friction_directions = 2", "friction_directions = 4"),
     "4 friction directions"),
    (lambda t: replaced(t, "times", "[0.0, nan]"), "finite, increasing"),
    (lambda t: replaced(t, "times", "[]"), "finite, increasing"),
    (lambda t: replaced(t, "time_steps", "[-0.05]"), "time_steps"),
    (lambda t: "\n".join(l for l in t.splitlines() if not l.startswith("u = ")),
     "missing field `u`"),
    (lambda t: t.replace("iterations = 3", 'iterations = "three"'), "not a pickled vito result"),
    (lambda t: t[: len(t) // 2], "not a pickled vito result"),
])
def test_a_malformed_solution_state_is_refused(change, message, short_hopper_solution):
    text = change(text_of(short_hopper_solution))
    assert text != text_of(short_hopper_solution)
    with pytest.raises(vito.VitoError, match="cannot unpickle this vito.Solution") as caught:
        restored(short_hopper_solution, text=text)
    assert message in str(caught.value)


@pytest.mark.parametrize("change, message", [
    (lambda t: without_last_row(t, "q"), "`q` has"),
    (lambda t: replaced(t, "nd", 4), "4 friction directions"),
    (lambda t: replaced(t, "iterations", "[1]"), "`iterations` has 1 records"),
    (lambda t: replaced(t, "relaxed_steps", "[99]"), "`relaxed_steps` names step 99"),
    (lambda t: replaced(t, "summary", "'[1, 2'"), "its summary is not JSON"),
    (lambda t: replaced(t, "summary", "'[]'"), "its summary is not a JSON object"),
])
def test_a_malformed_simulation_state_is_refused(change, message, hopper_simulation):
    text = change(text_of(hopper_simulation))
    with pytest.raises(vito.VitoError, match="cannot unpickle this vito.Simulation") as caught:
        restored(hopper_simulation, text=text)
    assert message in str(caught.value)


def test_pickle_arguments_of_the_wrong_type_are_type_errors(short_hopper_solution):
    restore, (path, sets, text, sha) = short_hopper_solution.__reduce__()
    for args in [(42, sets, text, sha), (path, [1], text, sha), (path, sets, b"x", sha),
                 (path, sets, text, 5), (path,)]:
        with pytest.raises(TypeError):
            restore(*args)
    with pytest.raises(vito.VitoError, match="carries no fingerprint"):
        restored(short_hopper_solution, drop_sha=True)


def test_a_changed_problem_file_is_refused_on_unpickling(tmp_path):
    # A Problem, a Solution and a Simulation pickled, then their file edited (a comment
    # added): each refuses to come back as what it no longer is.
    shutil.copytree(ROOT / "problems", tmp_path / "problems")
    file = tmp_path / "problems" / "hopper_2d.toml"
    problem = vito.Problem(file, set={"solver.ipopt.max_iter": 2})
    pickles = {
        "Problem": pickle.dumps(problem),
        "Solution": pickle.dumps(problem.solve()),
        "Simulation": pickle.dumps(vito.simulate(problem, duration=0.1)),
    }
    for data in pickles.values():
        pickle.loads(data)  # unchanged: restored
    file.write_text(file.read_text() + "\n# edited\n")
    for name, data in pickles.items():
        with pytest.raises(vito.VitoError, match=f"cannot unpickle this vito.{name}: its "
                           "problem file .* has changed since it was pickled"):
            pickle.loads(data)


def test_a_sweep_job_refuses_a_problem_file_changed_since_its_sweep_opened(tmp_path):
    # A job carries the file's fingerprint to its worker, which refuses a changed file
    # before solving or writing anything.
    shutil.copytree(ROOT / "problems", tmp_path / "problems")
    file = tmp_path / "problems" / "hopper_2d.toml"
    job = vito.SweepJob(index=0, problem=str(file), sets=(), run_dir=str(tmp_path / "run"),
                        problem_sha256=sha256(file))
    job = pickle.loads(pickle.dumps(job))
    file.write_text(file.read_text() + "\n# edited\n")
    with pytest.raises(vito.VitoError, match="has changed since its sweep opened"):
        vito.run_job(job)
    assert not (tmp_path / "run").exists()
