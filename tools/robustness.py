#!/usr/bin/env python3
"""How accidental is each optimum? Solves problems from K seeded starts under each solve
strategy and prints one Markdown table row per (problem, strategy): the objectives' min,
median and max over the starts that solved, how many solved, the iterations' median and the
wall time per answer.

    tools/robustness.py [--vito PATH] [--starts K] [--jobs J] [--seed S]
                        [--strategy NAME ...] [--out DIR] [FILE ...]

Every start is `vito solve FILE --starts K --seed S --jobs J` (the file's guess, then K−1
seeded perturbations of it), one BLAS thread per start; the strategies are `--set` overrides
(STRATEGIES below). Results stay in DIR/<problem>-<strategy>/ (summary.json lists every start
under `starts`). `make robustness` runs it on the nonconvex reference problems.
"""

import argparse
import json
import os
import statistics
from pathlib import Path

from vito_solve import solve_summary

ROOT = Path(__file__).resolve().parent.parent

DEFAULT_FILES = [
    "problems/spring_flamingo_walk.toml",
    "problems/littledog_step.toml",
    "problems/hamr_trot.toml",
    "problems/hamr_jump.toml",
]


# Each strategy as `--set` overrides on the file as shipped, all ending with the polish (the
# contact modes fixed) unless it says otherwise. `shipped`: the file as it is. Every other
# strategy names the continuation it uses, so that it means the same on every file (Spring
# Flamingo's and the HAMR jump's files ship with the tied homotopy). `relaxation`: the file's
# slack weight without a homotopy (one solve, or the continuation of a file's `slack.target`,
# as LittleDog's). `no-polish`: the file without the polish.
# `exact-bounds`: the relaxation with Ipopt's relaxation of the bounds by 1e-8 off, so that no
# factor of a product is negative and none can cancel another in the rows' sums. `homotopy`:
# the first solve's slack weight 1000 times below the file's, raised tenfold per solve from
# the last point and its multipliers until the largest slack is below the target (the file's,
# else a tenth of the tolerance), each solve at the file's Ipopt tolerances.
# `homotopy-slow`: that with the weight raised threefold per solve (up to ten solves), the
# slower shrinking NOSBENCH found better on contact problems. `slip-10`, `slip-100`,
# `slip-1000`: the relaxation with `contacts.max_slip_speed` (m/s) bounding ψ, and η with it,
# so that no product hidden by Ipopt's relaxation exceeds 1e-7, 1e-6 or 1e-5;
# `homotopy-slip-100`: the homotopy with that bound. `homotopy-tied`: the homotopy with
# `[slack] tied_tolerances`, each solve's Ipopt tolerance, initial and target barrier
# parameter a tenth of the relaxation its weight stands for, the polish the tight solve;
# `homotopy-tied-slip-100`: that with ψ bounded at 100 m/s.
RELAXATION = ["slack.homotopy=false", "slack.tied_tolerances=false"]
HOMOTOPY = ["slack.homotopy=true", "slack.tied_tolerances=false"]
TIED = ["slack.homotopy=true", "slack.tied_tolerances=true"]
STRATEGIES = {
    "shipped": [],
    "relaxation": RELAXATION,
    "no-polish": ["slack.polish=false"],
    "exact-bounds": RELAXATION + ["solver.ipopt.bound_relax_factor=0"],
    "homotopy": HOMOTOPY,
    "homotopy-slow": HOMOTOPY + ["slack.growth=3", "slack.rounds=10"],
    "slip-10": RELAXATION + ["contacts.max_slip_speed=10"],
    "slip-100": RELAXATION + ["contacts.max_slip_speed=100"],
    "slip-1000": RELAXATION + ["contacts.max_slip_speed=1000"],
    "homotopy-slip-100": HOMOTOPY + ["contacts.max_slip_speed=100"],
    "homotopy-tied": TIED,
    "homotopy-tied-slip-100": TIED + ["contacts.max_slip_speed=100"],
}


def median(values):
    return statistics.median(values) if values else float("nan")


def run(vito, file, strategy, args, out):
    sets = STRATEGIES[strategy]
    name = Path(file).stem
    target = out / f"{name}-{strategy}"
    cmd = [vito, "solve", str(file), "--quiet", "--starts", str(args.starts), "--seed",
           str(args.seed), "--jobs", str(args.jobs), "--out", str(target)]
    for s in sets:
        cmd += ["--set", s]
    summary, wall = solve_summary(cmd, target)
    if summary is None:
        return None
    starts = summary.get("starts") or [summary]
    solved = [s for s in starts if s["status"] in ("solve_succeeded", "solved_to_acceptable_level")]
    objectives = sorted(s["objective"] for s in solved)
    iterations = [s["iterations"] for s in starts]
    solve_s = sum(s["wall_time_s"] for s in starts)
    # The polish (on by default): the relaxed optimum each start reached before it, and
    # whether that one was solved by itself (its slack within the tolerance).
    tolerance = summary["slack_tolerance"]
    polished = [s["polish"] for s in starts if s.get("polish")]
    before_solved = [p["objective_before"] for p in polished
                     if p["max_slack_before"] is not None and p["max_slack_before"] <= tolerance]
    return {
        "problem": summary["problem"],
        "strategy": strategy,
        "solved": len(solved),
        "starts": len(starts),
        "min": objectives[0] if objectives else float("nan"),
        "median": median(objectives),
        "max": objectives[-1] if objectives else float("nan"),
        "iterations": median(iterations),
        "per_start_s": solve_s / len(starts),
        "wall_s": wall,
        "objectives": [s["objective"] if s in solved else None for s in starts],
        "polished": len(polished),
        "polish_kept": sum(1 for p in polished if p["kept"]),
        "solved_before_polish": len(before_solved),
        "objectives_before": [p["objective_before"] for p in polished],
    }


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("files", nargs="*", default=DEFAULT_FILES)
    p.add_argument("--vito", default=str(ROOT / "target/release/vito"))
    p.add_argument("--starts", type=int, default=10)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    p.add_argument("--strategy", action="append", choices=sorted(STRATEGIES))
    p.add_argument("--out", default="out/robustness")
    args = p.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    strategies = args.strategy or list(STRATEGIES)
    print("| problem | strategy | solved | min | median | max | max/min | iterations (median) "
          "| time per start [s] | polish kept / solved before it |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    rows = []
    for file in args.files:
        for strategy in strategies:
            row = run(args.vito, file, strategy, args, out)
            if row is None:
                continue
            rows.append(row)
            ratio = row["max"] / row["min"] if row["solved"] else float("nan")
            print(f"| {row['problem']} | {strategy} | {row['solved']}/{row['starts']} "
                  f"| {row['min']:.4g} | {row['median']:.4g} | {row['max']:.4g} | {ratio:.2f} "
                  f"| {row['iterations']:.0f} | {row['per_start_s']:.1f} "
                  f"| {row['polish_kept']}/{row['polished']} / {row['solved_before_polish']} |",
                  flush=True)
    (out / "robustness.json").write_text(json.dumps(rows, indent=1) + "\n")


if __name__ == "__main__":
    main()
