"""vito from Python: variational contact-implicit trajectory optimisation for legged robots.

The functions and classes here call the same Rust library the ``vito`` command runs (problem
loading and checking, the solve, the output writer, the simulator, the sweep runner), so a
result from Python is the command's result::

    import vito
    problem = vito.Problem("problems/hopper_2d.toml", set={"contacts.friction": 0.6})
    solution = problem.solve()
    solution.status, solution.objective, solution.q.shape
    frame = solution.to_pandas()            # the columns of trajectory.csv (needs pandas)
    warm = problem.with_set({"contacts.friction": 0.7}).solve(warm_start=solution)
    table = vito.sweep(problem, grid={"contacts.friction": [0.4, 0.6]}, out="out/sweep")

See docs/python.md.
"""

import os as _os
import shutil as _shutil
import sys as _sys
import sysconfig as _sysconfig

# OpenBLAS reads its core type and thread count once, when the library loads (the native
# module links Ipopt, MUMPS and OpenBLAS), so they are set here, before it loads. The `vito`
# command pins the core type (re-executing itself with it) so that results do not depend on
# the CPU's kernels; `vito._vito.pinned_coretype()` is that rule, and the test suite checks
# that the value set here is the same. One BLAS thread: parallel work uses processes.
def _pinned_coretype():
    import platform

    if _sys.platform != "linux" or platform.machine() != "x86_64":
        return None
    try:
        with open("/proc/cpuinfo", encoding="ascii", errors="replace") as f:
            for line in f:
                if line.startswith("flags"):
                    flags = set(line.split(":", 1)[1].split())
                    return "Haswell" if {"avx2", "fma"} <= flags else "Prescott"
    except OSError:
        pass
    return None


_coretype = _pinned_coretype()
if _coretype is not None:
    _os.environ["OPENBLAS_CORETYPE"] = _coretype
_os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
_os.environ.setdefault("OMP_NUM_THREADS", "1")

from ._vito import (  # noqa: E402
    IPOPT_VERSION,
    Dynamics,
    Kinematics,
    Problem,
    ProblemError,
    ProblemFileNotFoundError,
    Simulation,
    Solution,
    Trajectory,
    VitoError,
    __version__,
    pinned_coretype,
    simulate,
)
from . import _vito  # noqa: E402
from ._sweep import SweepJob, run_job  # noqa: E402

__all__ = [
    "IPOPT_VERSION",
    "Dynamics",
    "Kinematics",
    "Problem",
    "ProblemError",
    "ProblemFileNotFoundError",
    "Simulation",
    "Solution",
    "SweepJob",
    "Trajectory",
    "VitoError",
    "__version__",
    "find_executable",
    "run_job",
    "simulate",
    "solve",
    "sweep",
]

if _coretype != pinned_coretype():
    import warnings

    warnings.warn(
        f"vito: OPENBLAS_CORETYPE was set to {_coretype!r}, the command pins "
        f"{pinned_coretype()!r}: results may differ from the `vito` command's",
        RuntimeWarning,
        stacklevel=2,
    )


def find_executable():
    """The `vito` command that sweeps run (one `vito solve` process per grid point).

    In order: the environment variable ``VITO_EXE``; ``vito`` beside this Python interpreter
    (the project's set-up links ``.venv/bin/vito`` to ``target/release/vito``); ``vito`` on
    ``PATH``. Raises ``VitoError`` naming these when none is found.
    """
    candidates = [
        _os.environ.get("VITO_EXE"),
        _os.path.join(_sysconfig.get_path("scripts"), "vito"),
        _shutil.which("vito"),
    ]
    for path in candidates:
        if path and _os.path.isfile(path) and _os.access(path, _os.X_OK):
            return path
    raise VitoError(
        "cannot find the `vito` command that runs a sweep's solves: set VITO_EXE, or build it "
        "(`cargo build --release`) and link it into this environment's bin directory "
        "(the project's `make python` does), or put it on PATH"
    )


def solve(path, set=None, **options):
    """Loads the problem file ``path`` with ``set`` (as :class:`Problem`) and solves it:
    ``vito.solve("problems/hopper_2d.toml", set={"contacts.friction": 0.6}, out="out/h")``.
    ``options`` are those of :meth:`Problem.solve` (out, starts, seed, warm_start, progress).
    Returns the :class:`Solution`."""
    return Problem(path, set=set).solve(**options)


def sweep(problem, grid, out, jobs=None, time_limit=None, warm_start=None, exe=None,
          executor=None, progress=None, starts=1, seed=0, neighbour_rounds=5):
    """Solve ``problem`` over a grid of values, like ``vito sweep``; returns the table.

    ``problem``: a :class:`Problem` (its overrides apply to every run) or a problem file.
    ``grid``: a dict ``{key: [values]}`` of swept keys (any ``set`` key or family parameter;
    values as for ``set``, a str as given, so ``'"a,b"'`` is one value; the grid is the
    product, the last key varying fastest). ``out``: the sweep directory (created, or a
    sweep's, which resumes: finished points are not solved again). ``time_limit``: seconds
    per run (at most 1e9). ``warm_start``: None, or ``"neighbour"`` to start each run from
    its nearest finished point.

    Where the points run: without ``executor``, each in its own ``vito solve`` process on
    this machine, ``jobs`` at a time (default: the number of cores; ``exe``: the ``vito``
    command, default :func:`find_executable`). With ``executor`` (any
    ``concurrent.futures.Executor``: a ``ProcessPoolExecutor``, Dask's
    ``Client.get_executor()``, Ray's or submitit's), each point is a task running
    :func:`run_job` in a worker, which solves through the library (no ``vito`` command
    needed) into the point's run directory; ``jobs`` tasks at a time (default: the
    executor's worker count). The workers must reach the problem file and ``out`` at the
    same paths (a shared file system on a cluster).

    ``starts``, ``seed``: each point solved from that many seeded starts, the best kept (as
    ``vito solve --starts``). ``neighbour_rounds``: rounds of the neighbour pass (each point
    solved again from its grid neighbours' plans while that lowers its objective by more
    than 1 %; 0: none), as ``vito sweep --neighbour-rounds``. With an ``executor`` every
    start runs inside the point's task, and each re-solve of the neighbour pass is a task
    of its own (:class:`SweepJob` with ``attempt`` set), the rounds folded in as the
    command folds them: the table is the one ``vito sweep`` writes.

    ``progress``: called with a dict (done, failed, interrupted, running, total, skipped,
    attempts_done, attempts_total: the neighbour pass's re-solves) whenever the counts
    change; when None, a tqdm bar if tqdm is installed; False: nothing.

    Ctrl-C stops the sweep at once: no new point starts, the points running are asked to
    stop (``vito solve`` processes, and executor tasks in this process, such as a
    ``ThreadPoolExecutor``'s, at their next iteration) or left to finish (executor tasks in
    other processes), the table marks the points not finished as not run, and
    ``KeyboardInterrupt`` is raised; the same call again resumes.

    Returns the sweep table (``sweep.csv``, one row per point) as a pandas DataFrame.
    """
    import pandas

    if not isinstance(problem, Problem):
        problem = Problem(problem)
    if warm_start not in (None, "none", "neighbour"):
        raise ValueError(f"warm_start={warm_start!r}: give None or 'neighbour'")
    neighbour = warm_start == "neighbour"
    if executor is not None:
        from ._sweep import run_on_executor

        table = run_on_executor(problem, grid, out, executor, jobs, time_limit, neighbour,
                                progress, starts=starts, seed=seed,
                                neighbour_rounds=neighbour_rounds)
    else:
        from ._sweep import _Progress

        show = _Progress(progress)
        try:
            table = _vito._sweep(
                problem,
                grid,
                exe,
                _os.fspath(out),
                jobs if jobs is not None else (_os.cpu_count() or 1),
                time_limit,
                neighbour,
                show,
                starts,
                seed,
                neighbour_rounds,
            )
        finally:
            show.close()
    return pandas.read_csv(table, keep_default_na=False, na_values=[""])
