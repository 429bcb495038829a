"""`import vito`: the Python package over the library the `vito` command runs."""

import math
import os
import signal
import subprocess
import threading

import numpy as np
import pytest

import vito
from conftest import ENDLESS, HOPPER, ROOT


def run_cli(*args):
    return subprocess.run(
        [vito.find_executable(), *args], capture_output=True, text=True, cwd=ROOT
    )


def test_solve_equals_the_command_bit_for_bit(tmp_path, hopper_solution):
    cli = run_cli("solve", str(HOPPER), "--quiet", "--out", str(tmp_path / "cli"))
    assert cli.returncode == 0, cli.stderr
    expected = (tmp_path / "cli" / "trajectory.csv").read_bytes()
    assert hopper_solution.trajectory_csv().encode() == expected
    hopper_solution.write(str(tmp_path / "py"))
    assert (tmp_path / "py" / "trajectory.csv").read_bytes() == expected
    # The arrays are the file's numbers, not re-rounded ones.
    frame = hopper_solution.to_pandas()
    assert np.array_equal(frame["x [m]"].to_numpy(), hopper_solution.q[:, 0])
    import json

    summary = json.loads((tmp_path / "cli" / "summary.json").read_text())
    assert hopper_solution.status == summary["status"] == "solve_succeeded"
    assert hopper_solution.objective == summary["objective"]
    assert hopper_solution.iterations == summary["iterations"]
    assert hopper_solution.summary["openblas_coretype"] == summary["openblas_coretype"]
    # The written folder's summary also names the problem copies it carries; the same keys
    # otherwise. Written from Python, the folder carries them too.
    assert summary["problem_copy"] == {"file": "problem/hopper_2d.toml",
                                       "urdf": "problem/hopper_2d.urdf"}
    assert sorted(hopper_solution.summary) == sorted(k for k in summary if k != "problem_copy")
    written = json.loads((tmp_path / "py" / "summary.json").read_text())
    assert written["problem_copy"] == summary["problem_copy"]
    assert (tmp_path / "py" / "problem" / "hopper_2d.urdf").is_file()


def test_solve_with_out_writes_what_the_command_writes(tmp_path, hopper):
    out = tmp_path / "run"
    solution = hopper.solve(out=str(out))
    for name in ["trajectory.csv", "summary.json", "coordinates.svg", "inputs.svg", "contact_modes.svg"]:
        assert (out / name).is_file(), name
    assert (out / "trajectory.csv").read_text() == solution.trajectory_csv()


def test_the_package_pins_the_commands_blas_kernels():
    assert os.environ.get("OPENBLAS_CORETYPE") == vito.pinned_coretype()


def test_a_bad_problem_raises_problem_error_with_line_and_field(tmp_path):
    text = HOPPER.read_text()
    text = text.replace('urdf = "robots/hopper_2d.urdf"', f'urdf = "{ROOT}/problems/robots/hopper_2d.urdf"')
    assert "friction = 0.8\n" in text
    text = text.replace("friction = 0.8\n", "friction = -0.8\n")
    bad = tmp_path / "bad.toml"
    bad.write_text(text)
    line = text.splitlines().index("friction = -0.8") + 1
    with pytest.raises(vito.ProblemError) as caught:
        vito.Problem(str(bad))
    e = caught.value
    assert e.file == str(bad)
    assert e.line == line
    assert e.field == "contacts.friction"
    # The message is the command's.
    cli = run_cli("check", str(bad))
    assert cli.returncode == 2
    assert cli.stderr.strip().splitlines()[0] == f"error: {e.message}"
    assert str(e) == e.message


def test_a_bad_override_raises_problem_error(hopper):
    with pytest.raises(vito.ProblemError) as caught:
        hopper.with_set({"contacts.frction": 0.5})
    assert caught.value.field == "contacts.frction"
    assert "friction" in caught.value.message


def test_to_pandas_columns_equal_the_csv_header(hopper_solution):
    header = hopper_solution.trajectory_csv().splitlines()[0].split(",")
    frame = hopper_solution.to_pandas()
    assert list(frame.columns) == header == hopper_solution.columns
    assert len(frame) == len(hopper_solution.time) == 21
    # Interval columns are blank (NaN) at the last knot, as in the file.
    assert math.isnan(frame["u_r [N]"].iloc[-1])


def test_arrays_have_named_axes_and_units(hopper_solution):
    s = hopper_solution
    n, m = len(s.coordinate_names), len(s.input_names)
    assert s.coordinate_names == ["x", "z", "theta", "r"]
    assert s.q.shape == s.v.shape == (21, n)
    assert s.u.shape == (20, m)
    assert s.normal_impulse.shape == (20, len(s.contact_names))
    # The distance at every knot (the impulse of interval k pairs with knot k + 1).
    assert s.signed_distance.shape == (21, len(s.contact_names))
    assert s.friction_impulse.shape == (20, 1, len(s.friction_directions))
    assert s.units["q"] == ["m", "m", "rad", "m"]
    assert s.units["time"] == "s"
    assert s.q[0].tolist() == [0.0, 0.5, 0.0, 0.5]
    assert sum(s.objective_terms.values()) == pytest.approx(s.objective, rel=1e-12)
    assert s.max_slack == s.summary["max_slack"]


def test_check_reports_the_sizes_the_solver_builds(hopper, hopper_solution):
    c = hopper.check()
    assert c["coordinates"] == hopper_solution.coordinate_names
    assert c["n_variables"] == hopper_solution.summary["n_variables"] == 288
    assert c["n_constraints"] == 220


def test_with_set_and_family_parameters():
    trot = vito.Problem(str(ROOT / "problems" / "hamr_trot.toml"))
    assert trot.parameters == {"c1": 20.0, "q11": 20.0, "stride_hz": 10.0}
    faster = trot.with_set({"stride_hz": 30})
    assert faster.parameters["stride_hz"] == 30.0
    assert trot.parameters["stride_hz"] == 10.0
    assert faster.sets == ["stride_hz=30"]


def test_warm_start_from_a_solution_takes_fewer_iterations(hopper, hopper_solution):
    heavier = hopper.with_set({"slack.weight": 1000})
    cold = heavier.solve()
    warm = heavier.solve(warm_start=hopper_solution)
    assert cold.solved and warm.solved
    assert warm.iterations < cold.iterations


def test_warm_start_from_a_file_is_the_solution_warm_start(tmp_path, hopper, hopper_solution):
    hopper_solution.write(str(tmp_path / "prev"))
    heavier = hopper.with_set({"slack.weight": 1000})
    from_file = heavier.solve(warm_start=str(tmp_path / "prev" / "trajectory.csv"))
    from_solution = heavier.solve(warm_start=hopper_solution)
    assert from_file.trajectory_csv() == from_solution.trajectory_csv()


def test_a_sweep_of_four_points_returns_four_rows(tmp_path, hopper):
    table = vito.sweep(
        hopper,
        grid={"contacts.friction": [0.5, 0.8], "slack.weight": [100, 1000]},
        out=tmp_path / "sweep",
        jobs=2,
    )
    assert len(table) == 4
    assert list(table["status"]) == ["finished"] * 4
    assert sorted(zip(table["contacts.friction"], table["slack.weight"])) == [
        (0.5, 100), (0.5, 1000), (0.8, 100), (0.8, 1000)
    ]
    assert (tmp_path / "sweep" / "sweep.csv").is_file()


@pytest.fixture
def python_ctrl_c():
    """Python's own Ctrl-C handler, as an interactive interpreter or a script started from a
    terminal has it. A process started in the background by a non-interactive shell (`cmd &`,
    as CI scripts do) inherits SIGINT ignored, and Python then leaves it ignored: such a
    process cannot be stopped with Ctrl-C at all, by vito or anything else."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


def interrupt_during_solve(problem, interrupt):
    """Solves `problem` in this (the main) thread; at iteration 3 another thread calls
    `interrupt()`. Returns the exception raised and the iterations seen."""
    at_three = threading.Event()
    seen = []

    def progress(p):
        seen.append(p["iteration"])
        if p["iteration"] == 3:
            at_three.set()
            # Let the other thread send the signal before the solve goes on.
            sent.wait(10)

    sent = threading.Event()

    def interrupter():
        at_three.wait(60)
        interrupt()
        sent.set()

    thread = threading.Thread(target=interrupter)
    thread.start()
    try:
        with pytest.raises(KeyboardInterrupt) as caught:
            problem.solve(progress=progress)
    finally:
        sent.set()
        thread.join()
    return caught.value, seen


@pytest.mark.parametrize("how", ["pthread_kill", "interrupt_main"])
def test_ctrl_c_from_another_thread_stops_the_solve_and_keeps_the_iterate(
    hopper, hopper_solution, how, python_ctrl_c
):
    assert threading.current_thread() is threading.main_thread()
    main = threading.main_thread().ident
    interrupt = {
        "pthread_kill": lambda: signal.pthread_kill(main, signal.SIGINT),
        "interrupt_main": __import__("_thread").interrupt_main,
    }[how]
    error, seen = interrupt_during_solve(hopper, interrupt)
    solution = error.solution
    assert isinstance(solution, vito.Solution)
    assert solution.status == "user_requested_stop"
    assert not solution.solved
    # Stopped after the iteration it was in, not at the end (the full solve takes 102 on
    # Debian 12's Ipopt 3.11, 91 on Debian 13's 3.14).
    assert solution.iterations <= 5
    assert max(seen) <= 5
    assert solution.q.shape == (21, 4) and np.isfinite(solution.q).all()
    # The interpreter is usable and the next solve is the whole, uninterrupted one, to the bit.
    again = hopper.solve()
    assert again.iterations == hopper_solution.iterations
    assert again.objective == hopper_solution.objective


def test_ctrl_c_stops_a_solve_without_a_progress_callable(hopper, python_ctrl_c):
    # No Python code runs during this solve but vito's signal check at each iteration: the
    # SIGINT sent from another thread must stop it there, whenever it arrives (the solve
    # cannot end by itself: ENDLESS).
    long = hopper.with_set({"horizon.knots": 81, "horizon.time_step": 0.0125, **ENDLESS})
    main = threading.main_thread().ident
    timer = threading.Timer(0.3, lambda: signal.pthread_kill(main, signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt) as caught:
            long.solve()
    finally:
        timer.cancel()
    solution = caught.value.solution
    assert solution.status == "user_requested_stop"
    assert solution.q.shape == (81, 4)


def test_a_finer_grid_is_solved_through_the_files_grid(hopper):
    # The hopper file (21 knots) at 41: through the 21-knot level, as `vito solve` does;
    # cold at 41 knots the same NLP ends relaxed_contact at 88.0.
    fine = hopper.with_set({"horizon.knots": 41, "horizon.time_step": 0.025}).solve()
    assert fine.status == "solve_succeeded"
    levels = fine.summary["levels"]
    assert [level["knots"] for level in levels] == [21, 41]
    assert all(level["status"] == "solve_succeeded" for level in levels)
    assert fine.iterations == sum(level["iterations"] for level in levels)
    assert fine.q.shape == (41, 4)
    assert fine.objective == levels[-1]["objective"]
    # The 41-knot level also solved the NLP with the 21-knot plan's contact modes fixed and
    # kept the lower plan; its objective is the problem's at the fine grid's own tolerance.
    carried = fine.summary["carried_modes"]
    assert carried["status"] == "solve_succeeded"
    assert levels[0]["carried_modes_kept"] is None
    assert levels[1]["carried_modes_kept"] == carried["kept"]
    assert fine.objective <= carried["objective"]
    assert fine.summary["slack_tolerance"] == pytest.approx(1e-4 / 2, rel=1e-12)


def test_an_exception_in_progress_stops_the_solve(hopper):
    def progress(p):
        if p["iteration"] == 2:
            raise ValueError("enough")

    with pytest.raises(ValueError, match="enough") as caught:
        hopper.solve(progress=progress)
    assert caught.value.solution.iterations <= 3


def test_two_threads_solving_give_two_correct_results(hopper, hopper_solution):
    other = hopper.with_set({"contacts.friction": 0.5})
    expected = {"a": hopper_solution.trajectory_csv(), "b": other.solve().trajectory_csv()}
    results = {}

    def solve(name, problem):
        results[name] = problem.solve().trajectory_csv()

    threads = [
        threading.Thread(target=solve, args=("a", hopper)),
        threading.Thread(target=solve, args=("b", other)),
    ]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert results == expected


def test_simulate_tracks_a_solution(tmp_path, hopper, hopper_solution):
    sim = vito.simulate(hopper, track=hopper_solution, gains={"all": (100.0, 10.0)}, out=str(tmp_path / "sim"))
    assert sim.q.shape[1] == 4
    assert sim.time[-1] == pytest.approx(1.0)
    assert sim.summary["feedback"] == "explicit"
    assert list(sim.to_pandas().columns) == sim.columns
    assert (tmp_path / "sim" / "trajectory.csv").read_text() == sim.trajectory_csv()
    # Each contact's world position on every row: the foot by hand from q = [x, z, theta, r].
    frame = sim.to_pandas()
    x, z, theta, r = sim.q.T
    assert np.allclose(frame["foot_contact_x [m]"], x + r * np.sin(theta), atol=1e-12)
    assert np.allclose(frame["foot_contact_y [m]"], 0.0, atol=1e-12)
    assert np.allclose(frame["foot_contact_z [m]"], z - r * np.cos(theta), atol=1e-12)
    # The command, tracking the same file, writes the same trajectory.
    hopper_solution.write(str(tmp_path / "plan"))
    cli = run_cli(
        "simulate", str(HOPPER), "--quiet", "--track", str(tmp_path / "plan" / "trajectory.csv"),
        "--gains", "all=100,10", "--out", str(tmp_path / "cli"),
    )
    assert cli.returncode == 0, cli.stderr
    assert (tmp_path / "cli" / "trajectory.csv").read_text() == sim.trajectory_csv()


def test_write_never_replaces_what_vito_did_not_write(tmp_path, hopper_solution):
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("keep me")
    with pytest.raises(vito.VitoError):
        hopper_solution.write(str(mine))
    assert (mine / "notes.txt").read_text() == "keep me"
    assert sorted(p.name for p in mine.iterdir()) == ["notes.txt"]


def test_the_friction_sweep_example_runs(tmp_path):
    import sys

    run = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "friction_sweep.py"), "--mu", "0.6", "0.8",
         "--out", str(tmp_path)],
        capture_output=True, text=True, cwd=ROOT,
    )
    assert run.returncode == 0, run.stderr
    lines = run.stdout.splitlines()
    assert lines[1].split()[:2] == ["0.6", "solve_succeeded"]
    assert lines[2].split()[:2] == ["0.8", "solve_succeeded"]
    assert (tmp_path / "objective_vs_friction.png").is_file()
