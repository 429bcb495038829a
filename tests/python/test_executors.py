"""Sweeps on executors: the same table as `vito solve` processes, on a process pool and on a
Dask LocalCluster; progress; resuming."""

import concurrent.futures
import multiprocessing
import os
import pathlib

import pytest

import vito
from conftest import ENDLESS, HOPPER

GRID = {"contacts.friction": [0.5, 0.8], "slack.weight": [100, 1000]}
# What must agree between two runs of the same point (wall time and notes may differ).
SAME = ["index", "contacts.friction", "slack.weight", "status", "solver_status", "objective",
        "iterations", "max_slack", "start", "settled", "dir"]


@pytest.fixture(scope="module")
def reference(tmp_path_factory, hopper):
    out = tmp_path_factory.mktemp("reference") / "sweep"
    # `vito solve` processes, first pass and neighbour pass: an executor sweep gives the same
    # table, answers taken from the same attempts.
    table = vito.sweep(hopper, grid=GRID, out=out, jobs=1, progress=False)
    assert table["status"].tolist() == ["finished"] * 4
    return table


def test_a_process_pool_gives_the_table_of_vito_solve_processes(tmp_path, hopper, reference):
    seen = []
    ctx = multiprocessing.get_context("spawn")
    with concurrent.futures.ProcessPoolExecutor(2, mp_context=ctx) as pool:
        table = vito.sweep(hopper, grid=GRID, out=tmp_path / "s", executor=pool,
                           progress=seen.append)
    assert table[SAME].equals(reference[SAME])
    # Each point's run directory is the command's.
    for d in table["dir"]:
        assert (tmp_path / "s" / d / "trajectory.csv").is_file()
    assert seen[-1]["done"] == 4 and seen[-1]["running"] == 0 and seen[-1]["total"] == 4
    # The neighbour pass ran as tasks of their own, every one back.
    assert seen[-1]["attempts_total"] > 0
    assert seen[-1]["attempts_done"] == seen[-1]["attempts_total"]
    assert (tmp_path / "s" / "attempts").is_dir()
    # A rerun resumes: nothing left to solve, the same table.
    with concurrent.futures.ProcessPoolExecutor(1, mp_context=ctx) as pool:
        again = vito.sweep(hopper, grid=GRID, out=tmp_path / "s", executor=pool,
                           progress=seen.append)
    assert again[SAME].equals(reference[SAME])
    assert seen[-1]["skipped"] == 4


def test_neighbour_warm_starts_on_an_executor_match_the_processes(tmp_path, hopper):
    grid = {"contacts.friction": [0.5, 0.6, 0.7]}
    by_processes = vito.sweep(hopper, grid=grid, out=tmp_path / "p", jobs=1,
                              warm_start="neighbour", progress=False, neighbour_rounds=0)
    with concurrent.futures.ThreadPoolExecutor(1) as pool:
        by_executor = vito.sweep(hopper, grid=grid, out=tmp_path / "e", executor=pool,
                                 warm_start="neighbour", progress=False, neighbour_rounds=0)
    cols = ["index", "contacts.friction", "status", "objective", "iterations", "note", "start"]
    assert by_executor[cols].equals(by_processes[cols])
    notes = by_executor["note"].tolist()
    assert notes[0] != notes[0]  # blank: NaN in the DataFrame
    assert all(n.startswith("warm start from") for n in notes[1:])


def test_a_point_stopped_at_the_time_limit_is_a_timeout_row(tmp_path, hopper):
    # A solve that never ends by itself: only the time limit stops it.
    endless = hopper.with_set(ENDLESS)
    with concurrent.futures.ThreadPoolExecutor(1) as pool:
        table = vito.sweep(endless, grid={"contacts.friction": [0.5]}, out=tmp_path / "s",
                           executor=pool, time_limit=0.5, progress=False)
    assert table["status"].tolist() == ["timeout"]
    assert "time limit" in table["note"][0]


def test_a_dask_local_cluster_gives_the_same_table(tmp_path, hopper, reference):
    distributed = pytest.importorskip(
        "dask.distributed", reason="dask[distributed] is not installed (no network at set-up)"
    )
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        table = vito.sweep(hopper, grid=GRID, out=tmp_path / "s",
                           executor=client.get_executor(), progress=False)
    assert table[SAME].equals(reference[SAME])


def test_the_tqdm_bar_shows_when_tqdm_is_installed(tmp_path, hopper, capsys):
    pytest.importorskip("tqdm", reason="tqdm is not installed")
    vito.sweep(hopper, grid={"contacts.friction": [0.8]}, out=tmp_path / "s", jobs=1)
    err = capsys.readouterr().err
    assert "vito sweep" in err and "1/1" in err


def test_a_job_runs_without_the_vito_command(tmp_path, hopper, monkeypatch):
    # The executor path solves in-process: no `vito` command is looked up.
    monkeypatch.setenv("PATH", "/nonexistent")
    monkeypatch.setenv("VITO_EXE", "/nonexistent/vito")
    monkeypatch.setattr(vito, "find_executable", lambda: pytest.fail("looked for the command"))
    job = vito.SweepJob(index=0, problem=str(HOPPER), sets=("contacts.friction=0.8",),
                        run_dir=str(tmp_path / "run"))
    assert vito.run_job(job) is None
    summary = (tmp_path / "run" / "summary.json").read_text()
    assert '"solve_succeeded"' in summary


def test_the_executor_sweep_example_runs(tmp_path, reference):
    import subprocess
    import sys

    from conftest import ROOT

    run = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "executor_sweep.py"), "--out", str(tmp_path / "s")],
        capture_output=True, text=True, cwd=ROOT,
    )
    assert run.returncode == 0, run.stderr
    lines = run.stdout.splitlines()
    assert lines[0].split()[:3] == ["contacts.friction", "slack.weight", "status"]
    rows = [line.split() for line in lines[1:]]
    assert [r[2] for r in rows] == ["finished"] * 4
    # The example's grid is the reference's: the same objectives, as printed.
    assert [float(r[4]) for r in rows] == pytest.approx(reference["objective"].tolist(), rel=1e-5)
