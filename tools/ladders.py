#!/usr/bin/env python3
"""Refinement ladders: each reference problem asked for at its file's grid and at finer ones,
one `vito solve` per grid with only the grid changed, printed as one Markdown table
(BENCHMARKS.md, "Grid ladders").

    tools/ladders.py [--vito PATH] [--out DIR] [--cold] [NAME ...]

A grid finer than the file's is solved through the grid continuation (the file's grid, then
doublings; docs/solve.md), so each row gives the whole command's iterations and wall time
and, after them, its levels. `--cold` adds a `--no-refine` solve of every refined grid (one
solve on that grid alone, from the file's guess). Wall times are the commands' own
(`OPENBLAS_NUM_THREADS=1`, one solve at a time). Results stay in DIR/<problem>-<knots>/.
`make ladders` runs it on every ladder below.
"""

import argparse
import json
from pathlib import Path

from vito_solve import solve_summary

ROOT = Path(__file__).resolve().parent.parent

# name: (file, knots of each rung, the horizon T where the file fixes the step, else None).
LADDERS = {
    "hopper": ("problems/hopper_2d.toml", [21, 41, 81, 161], 1.0),
    "brick": ("problems/brick_3d.toml", [41, 81, 161], 1.0),
    "spring_flamingo": ("problems/spring_flamingo_walk.toml", [25, 49, 97], None),
    "littledog_step": ("problems/littledog_step.toml", [30, 59], None),
}


def solve(vito, file, knots, horizon, out, extra):
    cmd = [vito, "solve", str(ROOT / file), "--quiet", "--out", str(out),
           "--set", f"horizon.knots={knots}"]
    if horizon is not None:
        cmd += ["--set", f"horizon.time_step={horizon / (knots - 1)!r}"]
    cmd += extra
    return solve_summary(cmd, out)[0]


def levels_text(summary):
    levels = summary.get("levels") or []
    if not levels:
        start = summary.get("simulation_start")
        return "from its simulation" if start and start.get("kept") else "its grid alone"
    return " → ".join(f"{l['knots']}: {l['objective']:.4f} ({l['iterations']} it, "
                      f"{l['wall_time_s']:.1f} s)" for l in levels)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    # No `choices`: argparse checks a `nargs="*"` default list against them as one value.
    p.add_argument("names", nargs="*", metavar="NAME",
                   help=f"ladders to run (default: all of {', '.join(LADDERS)})")
    p.add_argument("--vito", default=str(ROOT / "target/release/vito"))
    p.add_argument("--out", default="out/ladders")
    p.add_argument("--cold", action="store_true")
    args = p.parse_args()
    unknown = [n for n in args.names if n not in LADDERS]
    if unknown:
        p.error(f"unknown ladder {unknown[0]!r}: choose from {', '.join(LADDERS)}")
    args.names = args.names or list(LADDERS)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    print("| problem | knots | status | objective | max slack | iterations | time [s] "
          "| levels: objective (iterations, s) |" + (" cold: status, objective (it, s) |"
                                                   if args.cold else ""))
    print("| --- | --- | --- | --- | --- | --- | --- | --- |" + (" --- |" if args.cold else ""))
    rows = []
    for name in args.names:
        file, rungs, horizon = LADDERS[name]
        for knots in rungs:
            s = solve(args.vito, file, knots, horizon, out / f"{name}-{knots}", [])
            if s is None:
                continue
            row = {"problem": name, "knots": knots, "status": s["status"],
                   "objective": s["objective"], "max_slack": s["max_slack"],
                   "iterations": s["iterations"], "wall_s": s["wall_time_s"],
                   "levels": s.get("levels") or []}
            line = (f"| {name} | {knots} | {s['status']} | {s['objective']:.4f} "
                    f"| {s['max_slack']:.1e} | {s['iterations']} | {s['wall_time_s']:.1f} "
                    f"| {levels_text(s)} |")
            if args.cold:
                cold = None
                if knots != rungs[0]:
                    cold = solve(args.vito, file, knots, horizon,
                                 out / f"{name}-{knots}-cold", ["--no-refine"])
                row["cold"] = cold and {k: cold[k] for k in
                                        ("status", "objective", "max_slack", "iterations",
                                         "wall_time_s")}
                line += (f" {cold['status']}, {cold['objective']:.4f} ({cold['iterations']} it, "
                         f"{cold['wall_time_s']:.1f} s) |" if cold else " |")
            rows.append(row)
            print(line, flush=True)
    (out / "ladders.json").write_text(json.dumps(rows, indent=1) + "\n")


if __name__ == "__main__":
    main()
