"""Sweep the hopper's friction and slack weight on a process pool (any concurrent.futures
executor works the same: Dask's Client.get_executor(), submitit, Ray).

    .venv/bin/python examples/executor_sweep.py [--out out/executor_sweep] [--workers 2]

The sweep directory, its run directories and its resumable table are vito's; each point runs
as a task (vito.run_job) in a worker process. Prints the table; a second run resumes (nothing
left to solve).
"""

import argparse
import concurrent.futures
import multiprocessing
import pathlib

import vito

ROOT = pathlib.Path(__file__).resolve().parents[1]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--problem", default=str(ROOT / "problems" / "hopper_2d.toml"))
    parser.add_argument("--mu", type=float, nargs="+", default=[0.5, 0.8])
    parser.add_argument("--weight", type=float, nargs="+", default=[100.0, 1000.0])
    parser.add_argument("--out", default="out/executor_sweep")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()

    problem = vito.Problem(args.problem)
    grid = {"contacts.friction": args.mu, "slack.weight": args.weight}
    context = multiprocessing.get_context("spawn")
    with concurrent.futures.ProcessPoolExecutor(args.workers, mp_context=context) as pool:
        table = vito.sweep(problem, grid=grid, out=args.out, executor=pool, progress=False)
    columns = ["contacts.friction", "slack.weight", "status", "solver_status", "objective",
               "iterations"]
    print(table[columns].to_string(index=False))


if __name__ == "__main__":
    main()
