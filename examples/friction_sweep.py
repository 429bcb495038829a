"""Sweep the hopper's friction coefficient from Python, each point warm-started from the last.

    .venv/bin/python examples/friction_sweep.py [--out out/friction_sweep]

Prints objective, iterations and max slack per friction coefficient mu, and, when matplotlib is
installed, plots the objective against mu (objective_vs_friction.png in --out). Each solve
starts from the previous point's solution (`warm_start=`), the way a continuation would; the
table is the Python counterpart of `vito sweep --warm-start neighbour` in one process.

What one warm-started chain can show: a plan for every mu that stays close to the previous
one, so the motion changes smoothly along the chain. What it cannot show: how the *optimal*
cost depends on friction. The problem is nonconvex, each number is the optimum nearest to the
previous point's plan, and a chain carries one early choice along: from the hopper's linear
guess the chain's cost rises with mu (6.75 at 0.2 to 8.07 at 1.0) while a cold solve at 0.8
alone gives 6.95. To compare costs across mu, use `vito.sweep(...)` (or `vito sweep`), whose
neighbour pass solves every point again from each neighbour's plan until none improves it by
more than 1 %, and `starts=K` for several seeded starts per point.
"""

import argparse
import pathlib

import vito

ROOT = pathlib.Path(__file__).resolve().parents[1]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--problem", default=str(ROOT / "problems" / "hopper_2d.toml"))
    parser.add_argument("--mu", type=float, nargs="+", default=[0.2, 0.3, 0.4, 0.5, 0.6, 0.8, 1.0])
    parser.add_argument("--out", default="out/friction_sweep")
    args = parser.parse_args()

    problem = vito.Problem(args.problem)
    previous = None
    rows = []
    print(f"{'mu':>5}  {'status':<28} {'objective':>12}  {'iterations':>10}  {'max slack':>9}")
    for mu in args.mu:
        solution = problem.with_set({"contacts.friction": mu}).solve(warm_start=previous)
        print(f"{mu:>5}  {solution.status:<28} {solution.objective:>12.6f}  "
              f"{solution.iterations:>10}  {solution.max_slack:>9.2e}")
        rows.append((mu, solution))
        if solution.solved:
            previous = solution

    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed: no plot")
        return
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    solved = [(mu, s.objective) for mu, s in rows if s.solved]
    fig, ax = plt.subplots(figsize=(5, 3.5))
    ax.plot([m for m, _ in solved], [o for _, o in solved], "o-")
    ax.set_xlabel("friction coefficient μ")
    ax.set_ylabel("objective")
    ax.set_title(problem.name)
    fig.tight_layout()
    path = out / "objective_vs_friction.png"
    fig.savefig(path, dpi=120)
    print(f"plot: {path}")


if __name__ == "__main__":
    main()
