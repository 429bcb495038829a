"""Problems, solutions and simulations cross process boundaries (pickle, multiprocessing)."""

import multiprocessing
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
