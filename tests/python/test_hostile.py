"""Hostile input to the package: no crash, no deadlock, no panic. Each case that could crash
or hang the interpreter runs in a subprocess with a timeout, so that it fails the test rather
than the suite."""

import os
import signal
import subprocess
import sys
import textwrap
import time

import pytest

from conftest import ENDLESS, HOPPER, ROOT


def run_python(code, timeout=120):
    """Runs `code` in a fresh interpreter; returns (returncode, stdout, stderr); a hang is a
    test failure naming the case."""
    try:
        r = subprocess.run(
            [sys.executable, "-c", textwrap.dedent(code)],
            capture_output=True, text=True, timeout=timeout, cwd=ROOT,
        )
    except subprocess.TimeoutExpired as e:
        pytest.fail(f"the interpreter hung for {timeout} s:\n{e.stdout}\n{e.stderr}")
    return r.returncode, r.stdout, r.stderr


@pytest.mark.parametrize("value, what", [
    ("deep(20000)", "nests more than 64 deep"),
    ("itself()", "nests more than 64 deep"),
    ("[0.0] * 10**7", "larger than"),
    ("'x' * (1 << 20)", "larger than"),
])
def test_huge_or_deep_set_values_are_value_errors(value, what):
    code, out, err = run_python(f"""
        import vito
        def deep(n):
            v = 0.5
            for _ in range(n):
                v = [v]
            return v
        def itself():
            v = []
            v.append(v)
            return v
        try:
            vito.Problem({str(HOPPER)!r}, set={{"robot.gravity": {value}}})
        except ValueError as e:
            print("ValueError:", e)
    """)
    assert code == 0, err
    assert out.startswith("ValueError:") and what in out, out


def test_a_problem_loaded_during_another_threads_solve_does_not_deadlock():
    # Thread A solves; thread B loads a problem (which asks Ipopt about its options, under
    # the same lock) at A's first iteration. Both finish.
    code, out, err = run_python(f"""
        import threading, vito
        p = vito.Problem({str(HOPPER)!r})
        started = threading.Event()
        loaded = []
        def progress(info):
            started.set()
        def load():
            started.wait(60)
            loaded.append(vito.Problem({str(HOPPER)!r}, set={{"contacts.friction": 0.5}}).name)
        b = threading.Thread(target=load)
        b.start()
        s = p.solve(progress=progress)
        b.join(60)
        print(s.status, loaded)
    """, timeout=180)
    assert code == 0, err
    assert out.split()[0] == "solve_succeeded" and "hopper-2d" in out


def test_a_progress_callback_waiting_on_another_solve_does_not_deadlock():
    # A's progress callback waits for thread B's whole solve, which needs the Ipopt lock A
    # holds: A's solve goes on (its callbacks delivered late) and both finish.
    code, out, err = run_python(f"""
        import threading, vito
        p = vito.Problem({str(HOPPER)!r})
        other = p.with_set({{"contacts.friction": 0.5}})
        results = {{}}
        def solve_other():
            results["b"] = other.solve().status
        b = threading.Thread(target=solve_other)
        def progress(info):
            if info["iteration"] == 2 and not b.is_alive() and "b" not in results:
                b.start()
                b.join()
        results["a"] = p.solve(progress=progress).status
        b.join(120)
        print(results["a"], results.get("b"))
    """, timeout=240)
    assert code == 0, err
    assert out.split() == ["solve_succeeded", "solve_succeeded"]


def test_a_time_limit_over_a_billion_seconds_is_a_value_error(tmp_path, hopper):
    import vito

    with pytest.raises(ValueError, match="time_limit="):
        vito.sweep(hopper, grid={"contacts.friction": [0.5]}, out=tmp_path / "s", time_limit=1e20)
    with pytest.raises(ValueError, match="time_limit="):
        vito.sweep(hopper, grid={"contacts.friction": [0.5]}, out=tmp_path / "s",
                   time_limit=1e20, executor=object())
    assert not (tmp_path / "s").exists()


def test_a_comma_inside_a_grid_value_is_one_point(tmp_path, hopper):
    import vito

    table = vito.sweep(hopper, grid={"name": ['"a,b"']}, out=tmp_path / "s", jobs=1,
                       progress=False)
    assert len(table) == 1
    assert table["name"].tolist() == ['"a,b"']
    assert table["status"].tolist() == ["finished"]


def interrupt_after(code_before, seconds, timeout=120):
    """Starts a script, sends SIGINT `seconds` after it prints READY, returns (returncode,
    stdout, stderr, seconds from the signal to the exit). A script still running 20 s before
    the timeout prints every thread's Python stack to stderr and exits (the failure's
    message shows where it hung)."""
    watchdog = f"import faulthandler\nfaulthandler.dump_traceback_later({timeout - 20}, exit=True)\n"
    p = subprocess.Popen(
        [sys.executable, "-c", watchdog + textwrap.dedent(code_before)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT,
    )
    try:
        line = p.stdout.readline()
        assert line.strip() == "READY", (line, p.stderr.read())
        time.sleep(seconds)
        sent = time.monotonic()
        p.send_signal(signal.SIGINT)
        out, err = p.communicate(timeout=timeout)
        return p.returncode, line + out, err, time.monotonic() - sent
    except subprocess.TimeoutExpired:
        p.kill()
        out, err = p.communicate()
        pytest.fail(f"the script did not stop after SIGINT:\n{out}\n{err}")


def test_ctrl_c_stops_a_simulation():
    # 2x10^6 steps of the hopper (h = 0.1 ms) take minutes (84 us a step here; their record
    # fits in 4 GiB); SIGINT a second in stops it after a step, however fast the machine.
    code, out, err, _ = interrupt_after(f"""
        import signal, vito
        signal.signal(signal.SIGINT, signal.default_int_handler)
        p = vito.Problem({str(HOPPER)!r})
        print("READY", flush=True)
        try:
            vito.simulate(p, duration=200.0, rate=10000.0)
            print("FINISHED")
        except KeyboardInterrupt:
            print("INTERRUPTED")
    """, 1.0)
    assert code == 0, err
    assert out.split() == ["READY", "INTERRUPTED"]


@pytest.mark.parametrize("how", ["processes", "executor"])
def test_ctrl_c_stops_a_sweep_and_it_resumes(tmp_path, how):
    # Six points of a solve that never ends by itself, one at a time: SIGINT once the first
    # runs stops the sweep (no new point starts) and the first point's solve at its next
    # iteration, also on a thread of this process (an executor's task the interpreter would
    # wait for at exit), and the table marks the rest not run. No point can finish first,
    # whatever the machine's speed.
    sweep_dir = tmp_path / "sweep"
    executor = "executor=ThreadPoolExecutor(1)," if how == "executor" else ""
    script = f"""
        import signal, sys, vito
        from concurrent.futures import ThreadPoolExecutor
        signal.signal(signal.SIGINT, signal.default_int_handler)
        p = vito.Problem({str(HOPPER)!r}, set={ENDLESS!r})
        ready = []
        def progress(counts):
            if counts["running"] and not ready:
                ready.append(True)
                print("READY", flush=True)
        try:
            vito.sweep(p, grid={{"contacts.friction": [0.3, 0.4, 0.5, 0.6, 0.7, 0.8]}},
                       out={str(sweep_dir)!r}, jobs=1, {executor} progress=progress)
            print("FINISHED")
        except KeyboardInterrupt:
            print("INTERRUPTED")
    """
    code, out, err, _ = interrupt_after(script, 1.0)
    assert code == 0, err
    assert out.split() == ["READY", "INTERRUPTED"]
    import pandas

    table = pandas.read_csv(sweep_dir / "sweep.csv", keep_default_na=False)
    statuses = table["status"].tolist()
    assert "finished" not in statuses[1:], statuses
    assert statuses[1:] == ["pending"] * 5
    assert statuses[0] in ("interrupted", "pending")
    assert all(n for n in table["note"].tolist()[1:])
    # The first point's solve stopped (its iterate kept), not finished after the exception.
    import json

    summaries = [json.loads(f.read_text()) for f in sweep_dir.rglob("summary.json")]
    assert [s["status"] for s in summaries] in ([], ["user_requested_stop"]), summaries


def test_generated_python_values_raise_ordinary_exceptions():
    """3,000 inputs of tools/fuzz_python.py (`make fuzz-python` runs 100,000): every call
    returns or raises an ordinary exception; no panic, crash or hang."""
    r = subprocess.run(
        [sys.executable, str(ROOT / "tools" / "fuzz_python.py"), "--count", "3000"],
        capture_output=True, text=True, timeout=600, cwd=ROOT,
    )
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    assert "findings 0" in r.stdout, r.stdout[-3000:]
    assert "ProblemError" in r.stdout and "TypeError" in r.stdout, r.stdout[-3000:]


def test_a_pickled_solution_claiming_a_trillion_friction_directions_is_refused():
    # Its names of friction directions were built before anything was checked: 10^12 of
    # them aborted the interpreter.
    code, out, err = run_python(f"""
        import pickle, vito
        s = vito.Problem({str(HOPPER)!r}, set={{"solver.ipopt.max_iter": 2}}).solve()
        restore, (path, sets, text, sha) = s.__reduce__()
        text = text.replace("friction_directions = 2", "friction_directions = 1000000000000")
        try:
            restore(path, sets, text, sha)
        except vito.VitoError as e:
            print("VitoError:", e)
    """)
    assert code == 0, err
    assert out.startswith("VitoError: cannot unpickle this vito.Solution: it has "
                          "1000000000000 friction directions per contact, its problem 2"), out


class NoTasks:
    """An executor given no task: the test stops its sweep at the first progress."""

    def submit(self, fn, *args, **kwargs):
        raise AssertionError("no task was to be submitted")


@pytest.mark.parametrize("how", ["processes", "executor"])
def test_a_100000_value_axis_is_checked_with_a_few_loads(tmp_path, hopper, how):
    # Before the first run, a sweep checks its grid against the problem: a few loads of the
    # problem file per axis (its first, smallest and largest numbers), not one per value.
    import vito

    values = [0.3 + i * 1e-6 for i in range(100_000)]
    seen = []

    class Stop(Exception):
        pass

    def progress(counts):
        seen.append((vito._vito._problem_loads() - before, counts["total"]))
        raise Stop

    before = vito._vito._problem_loads()
    options = {"executor": NoTasks()} if how == "executor" else {"jobs": 1, "exe": "/bin/true"}
    with pytest.raises(Stop):
        vito.sweep(hopper, grid={"contacts.friction": values}, out=tmp_path / "s",
                   progress=progress, **options)
    assert seen[0][1] == 100_000
    assert seen[0][0] <= 3, seen[0]
    # The smallest value is among those loaded: a negative friction is still found up front.
    with pytest.raises(ValueError, match=r"the value `-0.5` is not valid here"):
        vito.sweep(hopper, grid={"contacts.friction": values[1:] + [-0.5]},
                   out=tmp_path / "t", progress=False, **options)
    assert not (tmp_path / "t").exists()
