#!/usr/bin/env python3
"""Generated Python values through the package's entry points: `vito.Problem(path, set=...)`
with real and invented keys, `set=` strings, problem paths, and `Problem.solve` and
`vito.simulate` options that must be refused before anything runs. Each call must return or
raise an ordinary exception (ValueError, TypeError, FileNotFoundError, vito.VitoError, ...),
and an option meant to be refused must raise; a PanicException, a SystemError, a crash, a
hang or an accepted option is a finding.

    tools/fuzz_python.py [--count N] [--seed S] [--first K]

Input i has its own generator (seeded with S and i), so a finding is repeated with
`--first i --count i+1`. Prints the inputs, the calls that returned, the exceptions by type
and the slowest input; exits 1 on a finding.
"""

import argparse
import math
import random
import sys
import time
from pathlib import Path

import vito

ROOT = Path(__file__).resolve().parent.parent
HOPPER = str(ROOT / "problems" / "hopper_2d.toml")

KEYS = [
    "contacts.friction", "robot.gravity", "horizon.knots", "horizon.time_step", "slack.weight",
    "slack.mode", "slack.homotopy", "slack.tied_tolerances", "slack.growth", "slack.rounds",
    "solver.integrator",
    "solver.ipopt.max_iter", "solver.ipopt.tol", "solver.ipopt.mu_strategy", "initial.q.x",
    "final.q.x", "name", "terrain.kind", "costs", "robot.units", "tracking.feedback",
]
STRINGS = [
    "", "midpoint", "euler", "per_contact", "penalty", "<!--<script>", "</script>", "a,b",
    '"a"', "\u2028", "\x00", "x" * 5000, "nan", "inf", "-0", "1e309", "true", "[1, 2]",
    "{a = 1}", "m kg s", "../../etc/passwd", "💥",
]
NUMBERS = [
    0, 1, -1, 2**31, 2**63, 2**64, -(2**63) - 1, 10**400, 0.0, -0.0, 1e-300, 1e308,
    math.inf, -math.inf, math.nan, 0.5, 21, 3, 1e9, 1e20,
]


# (option, value) pairs `Problem.solve` must refuse before solving.
INVALID_SOLVE = [
    (option, bad)
    for option, values in {
        "starts": [0, -1, -(2**70), 2**64, 10**30, math.nan, math.inf, "3", [1], 1.5],
        "seed": [-1, -(2**70), 2**64, math.nan, "3", [1], 1.5],
        "warm_start": [42, [1], "missing.csv", "", "/dev/null", str(ROOT)],
        "progress": [42, "print", [1]],
    }.items()
    for bad in values
]
# Durations `vito.simulate` must refuse before simulating.
INVALID_DURATIONS = [-1.0, -(2**70), math.nan, math.inf, -math.inf, 1e20, "1", [1]]


def value(rng, depth=0):
    """A random Python value: scalars, strings, containers, odd objects."""
    kind = rng.randrange(10 if depth < 4 else 5)
    if kind == 0:
        return rng.choice(NUMBERS)
    if kind == 1:
        return rng.uniform(-1e3, 1e3)
    if kind == 2:
        return rng.choice(STRINGS)
    if kind == 3:
        return rng.choice([None, True, False, b"bytes", object(), 1j, Ellipsis])
    if kind == 4:
        return rng.randrange(-100, 100)
    if kind in (5, 6):
        items = [value(rng, depth + 1) for _ in range(rng.randrange(6))]
        return tuple(items) if kind == 6 else items
    if kind == 7:
        return {rng.choice(STRINGS + ["a", "b"]): value(rng, depth + 1)
                for _ in range(rng.randrange(4))}
    if kind == 8:
        deep = []
        for _ in range(rng.choice([10, 1000, 30000])):
            deep = [deep]
        return deep
    me = []
    me.append(me)
    return me


def key(rng):
    k = rng.choice(KEYS)
    r = rng.random()
    if r < 0.1:
        return k + "." + rng.choice(STRINGS)
    if r < 0.15:
        return rng.choice(STRINGS)
    return k


def one(rng):
    """One call; returns its name."""
    what = rng.randrange(4)
    if what == 0:
        sets = {key(rng): value(rng) for _ in range(rng.randrange(1, 4))}
        vito.Problem(HOPPER, set=sets)
        return "Problem(set=dict)"
    if what == 1:
        sets = [f"{key(rng)}={rng.choice(STRINGS + [str(x) for x in NUMBERS])}"
                for _ in range(rng.randrange(1, 3))]
        vito.Problem(HOPPER, set=sets)
        return "Problem(set=list)"
    if what == 2:
        vito.Problem(rng.choice([HOPPER, value(rng), "/dev/null", str(ROOT), "missing.toml"]))
        return "Problem(path)"
    # Options validated before a solve or a simulation starts: only values each must
    # refuse, so that no call actually solves or writes.
    if rng.random() < 0.5:
        option, bad = rng.choice(INVALID_SOLVE)
        vito.Problem(HOPPER).solve(**{option: bad})
        raise Accepted(f"solve({option}={bad!r}) ran")
    duration = rng.choice(INVALID_DURATIONS)
    vito.simulate(vito.Problem(HOPPER), duration=duration)
    raise Accepted(f"simulate(duration={duration!r}) ran")


class Accepted(Exception):
    """A value meant to be refused before anything runs was accepted."""


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--count", type=int, default=100_000)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--first", type=int, default=0)
    args = p.parse_args()
    sys.setrecursionlimit(100_000)
    returned, raised, findings = 0, {}, []
    slowest = (0.0, None)
    start = time.monotonic()
    for i in range(args.first, args.count):
        rng = random.Random(f"{args.seed}:{i}")
        t0 = time.process_time()
        try:
            one(rng)
            returned += 1
        except BaseException as e:  # noqa: BLE001 - every exception is sorted below
            name = type(e).__name__
            if name in ("PanicException", "SystemError", "KeyboardInterrupt", "MemoryError",
                        "Accepted"):
                findings.append((i, name, str(e)[:300]))
            raised[name] = raised.get(name, 0) + 1
        dt = time.process_time() - t0
        if dt > slowest[0]:
            slowest = (dt, i)
        if dt > 10:
            findings.append((i, "hang", f"{dt:.1f} s of CPU time"))
        if (i + 1) % 10_000 == 0:
            print(f"next input {i + 1}", flush=True)
    inputs = args.count - args.first
    print(f"inputs {inputs} returned {returned} raised {sum(raised.values())} "
          f"findings {len(findings)} wall {time.monotonic() - start:.1f} s "
          f"slowest {1e3 * slowest[0]:.1f} ms CPU (input {slowest[1]})")
    for name, n in sorted(raised.items(), key=lambda kv: -kv[1]):
        print(f"  {name:<22} {n}")
    for f in findings[:20]:
        print("finding:", *f)
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
