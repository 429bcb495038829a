"""Sweeps from Python: the library's sweep (directories, resumable table, neighbour warm
starts) with the points run either as ``vito solve`` processes on this machine or as tasks
on any ``concurrent.futures.Executor``."""

import dataclasses as _dataclasses
import os as _os
import time as _time

from . import _vito


@_dataclasses.dataclass(frozen=True)
class SweepJob:
    """One grid point as a task: what a worker needs to solve it and write its run directory.

    ``problem``: the problem file (absolute; the worker must reach it at that path);
    ``sets``: the overrides to load it with (the sweep's fixed ones, the point's, and the
    warm start's ``initial_guess.warm_start`` when it starts from a finished neighbour);
    ``run_dir``: the point's run directory (absolute); ``warm_start``: that neighbour's
    trajectory, or None; ``time_limit``: seconds, or None; ``starts``/``seed``: as for
    :meth:`Problem.solve`; ``attempt``: for a re-solve of the neighbour pass, its directory
    in the sweep (None for the point's own run); ``problem_sha256``: the problem file's
    SHA-256 when the sweep opened (the worker refuses a file that has changed since; None:
    not checked).
    """

    index: int
    problem: str
    sets: tuple
    run_dir: str
    warm_start: str = None
    time_limit: float = None
    starts: int = 1
    seed: int = 0
    attempt: str = None
    problem_sha256: str = None


def run_job(job):
    """Solves one :class:`SweepJob` in this process (what an executor's worker runs): loads
    the problem with the job's overrides, solves, writes the run directory. Returns the time
    limit when it stopped the solve, else None. Needs no ``vito`` command."""
    return _vito._solve_point(
        job.problem, list(job.sets), job.run_dir, job.time_limit, job.starts, job.seed,
        job.problem_sha256,
    )


def _counts_text(c):
    text = f"{c['done']} done, {c['failed']} failed, {c['running']} running of {c['total']}"
    if c.get("attempts_total"):
        text += f"; neighbour re-solves {c['attempts_done']} of {c['attempts_total']}"
    return text


class _Progress:
    """The user's ``progress`` callable, or a tqdm bar (when tqdm is installed and progress
    is None), or nothing (progress=False)."""

    def __init__(self, progress):
        self.callable = progress if callable(progress) else None
        self.bar = None
        if progress is None:
            try:
                import tqdm
            except ImportError:
                tqdm = None
            if tqdm is not None:
                self.bar = tqdm.tqdm(total=0, unit="point", desc="vito sweep", leave=True)

    def __call__(self, counts):
        if self.callable is not None:
            self.callable(dict(counts))
        if self.bar is not None:
            finished = counts["done"] + counts["failed"] + counts["interrupted"]
            self.bar.total = counts["total"]
            self.bar.n = finished
            self.bar.set_postfix_str(f"{counts['failed']} failed, {counts['running']} running")
            self.bar.refresh()

    def close(self):
        if self.bar is not None:
            self.bar.close()


def _executor_width(executor):
    for attr in ("_max_workers", "max_workers"):
        width = getattr(executor, attr, None)
        if isinstance(width, int) and width > 0:
            return width
    return _os.cpu_count() or 1


def run_on_executor(problem, grid, out, executor, jobs, time_limit, neighbour, progress,
                    starts=1, seed=0, neighbour_rounds=0):
    """Runs the sweep's points as tasks on ``executor``, at most ``jobs`` at a time, then
    the rounds of the neighbour pass the same way (no new task starts once a Ctrl-C
    arrives: the points not finished stay not run, and a rerun resumes). Returns the path
    of the table."""
    sweep = _vito.SweepJobs(problem, grid, _os.fspath(out), neighbour, time_limit,
                            neighbour_rounds)
    time_limit = sweep.time_limit
    width = jobs if jobs is not None else _executor_width(executor)
    if width < 1:
        raise ValueError(f"jobs={jobs}: give at least 1")
    show = _Progress(progress)
    pending = {}
    try:
        show(sweep.counts)
        while True:
            while len(pending) < width:
                job = sweep.next_job()
                if job is None:
                    break
                task = SweepJob(
                    index=job["index"], problem=_os.fspath(job["problem"]),
                    sets=tuple(job["sets"]), run_dir=_os.fspath(job["run_dir"]),
                    warm_start=None if job["warm_start"] is None else _os.fspath(job["warm_start"]),
                    time_limit=time_limit, starts=starts, seed=seed, attempt=job["attempt"],
                    problem_sha256=job["problem_sha256"],
                )
                pending[executor.submit(run_job, task)] = task
                show(sweep.counts)
            if not pending:
                break
            # Polled, so that any future-like job works (concurrent.futures, Dask, Ray,
            # submitit), and this thread stays where Python checks for signals.
            done = [f for f in pending if f.done()]
            if not done:
                _time.sleep(0.05)
            for future in done:
                task = pending.pop(future)
                try:
                    limit = future.result()
                    sweep.record(task.index, attempt=task.attempt, timed_out=limit)
                except Exception as e:  # the job's own error, recorded in its row
                    sweep.record(task.index, attempt=task.attempt,
                                 error=f"{type(e).__name__}: {e}")
                show(sweep.counts)
    except BaseException:
        for future in pending:
            future.cancel()
        sweep.stop()
        raise
    finally:
        show.close()
    return sweep.table_csv
