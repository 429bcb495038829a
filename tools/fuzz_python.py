#!/usr/bin/env python3
"""Generated Python values through the package's entry points: `vito.Problem(path, set=...)`
with real and invented keys, `set=` strings, problem paths (str, bytes, os.PathLike, names
that are not UTF-8), `Problem.solve` and `vito.simulate` options that must be refused before
anything runs, and pickles: `Solution`s, `Simulation`s and `Problem`s restored against
another problem file, a changed one or a missing one, with their arrays truncated or
perturbed, their state malformed. Each call must return or raise an ordinary exception
(ValueError, TypeError, FileNotFoundError, vito.VitoError, ...); an option meant to be
refused must raise, a pickle restored against another problem or a changed file must raise,
a path that names a problem file must load, and a restored result must display, convert and
write without a panic. A PanicException, a SystemError, a crash, a hang, an accepted option
or pickle or a refused path is a finding.

    tools/fuzz_python.py [--count N] [--seed S] [--first K]

Input i has its own generator (seeded with S and i), so a finding is repeated with
`--first i --count i+1`. Prints the inputs, the calls that returned, the exceptions by type,
the outcomes by kind of input and the slowest input; exits 1 on a finding.
"""

import argparse
import atexit
import hashlib
import math
import os
import pickle
import random
import re
import shutil
import sys
import tempfile
import time
from pathlib import Path

import vito

ROOT = Path(__file__).resolve().parent.parent
HOPPER = str(ROOT / "problems" / "hopper_2d.toml")
BRICK = str(ROOT / "problems" / "brick_3d.toml")

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


class Accepted(Exception):
    """A value meant to be refused before anything runs was accepted."""


class Refused(Exception):
    """A path that names a problem file was refused."""


class PathLike:
    """An os.PathLike of any value (os.fspath gives it back)."""

    def __init__(self, value):
        self.value = value

    def __fspath__(self):
        return self.value


class Crafted:
    """A pickle of `restore(*args)`: what `pickle.loads` calls, with any arguments."""

    def __init__(self, restore, args):
        self.restore, self.args = restore, args

    def __reduce__(self):
        return self.restore, self.args


class Fixtures:
    """What the pickle and path inputs need, made once on first use: pickled states of
    solutions (a few iterations) and simulations of the hopper (planar) and the brick
    (spatial), and a scratch directory with a changed copy of the hopper's file and a copy
    under a name that is not UTF-8."""

    _made = None

    @classmethod
    def get(cls):
        if cls._made is None:
            cls._made = cls()
        return cls._made

    def __init__(self):
        self.dir = Path(tempfile.mkdtemp(prefix="vito-fuzz-"))
        atexit.register(shutil.rmtree, self.dir, ignore_errors=True)
        shutil.copytree(ROOT / "problems" / "robots", self.dir / "robots")
        text = Path(HOPPER).read_bytes()
        self.changed = self.dir / "hopper_2d.toml"
        self.changed.write_bytes(text + b"\n# changed\n")
        self.not_utf8 = os.path.join(os.fsencode(self.dir), b"hopper-\xff\xfe.toml")
        with open(self.not_utf8, "wb") as f:
            f.write(text)
        self.files = [HOPPER, BRICK, str(ROOT / "problems" / "littledog_step.toml"),
                      str(self.changed), self.not_utf8, str(self.dir / "missing.toml")]
        self.states = []
        for path in (HOPPER, BRICK):
            problem = vito.Problem(path, set={"solver.ipopt.max_iter": 3})
            self.states.append(problem.solve().__reduce__())
            self.states.append(vito.simulate(problem, duration=0.2).__reduce__())
        self.problem_state = vito.Problem(HOPPER, set={"contacts.friction": 0.5}).__reduce__()
        self.solution = vito.Problem(HOPPER, set={"solver.ipopt.max_iter": 1}).solve()
        self.outputs = 0
        self.structures = {}

    def structure(self, path):
        """The names of the problem of `path` (None when it does not load)."""
        key = os.fsencode(path)
        if key not in self.structures:
            try:
                c = vito.Problem(path).check()
                self.structures[key] = (c["coordinates"], c["inputs"], c["contacts"])
            except (vito.VitoError, OSError):
                self.structures[key] = None
        return self.structures[key]

    def inside(self, path):
        """A relative str, bytes or Path taken inside the scratch directory (so that writing
        to a hostile name leaves the working directory alone); anything else as it is."""
        try:
            if isinstance(path, (str, bytes, Path)) and not os.path.isabs(path):
                return os.path.join(os.fsencode(self.dir), os.fsencode(path))
        except UnicodeEncodeError:
            pass  # no name at all: refused as it is
        return path

    def out(self):
        """A new output directory, sometimes under a name that is not UTF-8."""
        self.outputs += 1
        name = f"out{self.outputs}".encode() + (b"-\xff" if self.outputs % 3 == 0 else b"")
        return os.path.join(os.fsencode(self.dir), name)


def sha256_of(path):
    try:
        with open(path, "rb") as f:
            return hashlib.sha256(f.read()).hexdigest()
    except OSError:
        return None


NUMBER = re.compile(r"(?<![\w.\"])-?(?:\d+(?:\.\d+)?(?:e[-+]?\d+)?|nan|inf)(?![\w.\"])")
HOSTILE_NUMBERS = ["nan", "inf", "-inf", "1e308", "-1e308", "0", "-0.0", "5e-324", "-1",
                   "9223372036854775807", "-9223372036854775808", "3", "0.5", '"x"', "[]",
                   "[1.0]", "true"]


def perturbed(rng, text):
    """The TOML text of a pickled result, changed: a number replaced by a hostile value, an
    array element or row dropped or doubled, a line (a key) dropped, a name changed, the
    text cut short."""
    kind = rng.randrange(7)
    if kind == 0:
        spots = list(NUMBER.finditer(text))
        if not spots:
            return text
        m = rng.choice(spots)
        return text[:m.start()] + rng.choice(HOSTILE_NUMBERS) + text[m.end():]
    if kind in (1, 2):
        # An element of a flat array, or a row of a nested one: dropped or doubled.
        pattern = r", [^,\[\]\n]+(?=[,\]])" if kind == 1 else r", \[[^\[\]]*\]"
        spots = list(re.finditer(pattern, text))
        if not spots:
            return text
        m = rng.choice(spots)
        middle = "" if rng.random() < 0.6 else m.group(0) * 2
        return text[:m.start()] + middle + text[m.end():]
    if kind == 3:
        lines = text.splitlines()
        if lines:
            del lines[rng.randrange(len(lines))]
        return "\n".join(lines)
    if kind == 4:
        names = list(re.finditer(r'"[^"\n]*"', text))
        if not names:
            return text
        m = rng.choice(names)
        return text[:m.start()] + rng.choice(['"x"', '""', '"r"', '"theta"', '"\\u0000"',
                                              '"<b>"']) + text[m.end():]
    if kind == 5:
        return text[:rng.randrange(len(text) + 1)]
    return text.replace("\n", "\n\n", rng.randrange(3))


def exercise(rng, restored, fixtures):
    """What a user does with a restored result: every attribute, the display, the CSV, the
    DataFrame, writing it, and (a solution) a simulation replaying its inputs."""
    repr(restored)
    restored._repr_html_()
    restored.trajectory_csv()
    for name in ("columns", "time", "q", "v", "u", "normal_impulse", "friction_impulse",
                 "signed_distance", "slack", "summary", "units", "status", "objective",
                 "coordinate_names", "input_names", "contact_names", "friction_directions"):
        try:
            getattr(restored, name)
        except AttributeError:
            pass
    if rng.random() < 0.2:
        try:
            restored.to_pandas()
        except vito.VitoError:
            pass  # a NaN the CSV reader refuses: an ordinary error
    if rng.random() < 0.3:
        restored.write(fixtures.out())
    if isinstance(restored, vito.Solution) and rng.random() < 0.1:
        vito.simulate(HOPPER, inputs=restored, duration=0.1)


def unpickled(restore, args, through_pickle):
    """`restore(*args)` as `pickle.loads` calls it, through a pickle of them when asked (not
    for generated values: pickle itself recurses into a 30,000-deep list)."""
    if through_pickle:
        return pickle.loads(pickle.dumps(Crafted(restore, tuple(args))))
    return restore(*args)


def pickle_input(rng):
    """A pickle restored: a result's state against another problem file (or a changed, a
    missing one), its TOML perturbed, its arguments malformed; or a `Problem`'s."""
    f = Fixtures.get()
    if rng.random() < 0.15:
        restore, (path, sets, sha) = f.problem_state
        args = [path, sets, sha]
        mode = rng.randrange(3)
        if mode == 0:
            args[0] = rng.choice(f.files)
        elif mode == 1:
            args[2] = rng.choice([None, "", "x" * 64, 5, sha.upper(), sha256_of(f.changed)])
        else:
            args[rng.randrange(3)] = value(rng)
        restored = unpickled(restore, args, through_pickle=mode != 2)
        restored.check()
        if not isinstance(args[2], str) or sha256_of(args[0]) != args[2]:
            raise Accepted(f"a Problem restored from {args[0]!r} with the fingerprint {args[2]!r}")
        return "pickle(Problem)"
    restore, (path, sets, text, sha) = rng.choice(f.states)
    args = [path, sets, text, sha]
    mode = rng.randrange(4)
    if mode == 0:
        # Another problem file, with its own fingerprint or the pickle's.
        args[0] = rng.choice(f.files)
        args[3] = rng.choice([sha, sha256_of(args[0])])
    elif mode == 1:
        for _ in range(rng.randrange(1, 4)):
            args[2] = perturbed(rng, args[2])
    elif mode == 2:
        args[0] = rng.choice(f.files)
        args[3] = sha256_of(args[0])
        args[2] = perturbed(rng, args[2])
    else:
        i = rng.randrange(5)
        if i == 4:
            args = args[:rng.randrange(4)] + ([value(rng)] if rng.random() < 0.3 else [])
        else:
            args[i] = value(rng)
    restored = unpickled(restore, args, through_pickle=mode != 3)
    exercise(rng, restored, f)
    # Restored against another file: only that file's own fingerprint, and a problem of the
    # same names (a copy of the file, changed), may be accepted.
    if mode in (0, 2) and (args[3] != sha256_of(args[0])
                           or f.structure(args[0]) != f.structure(path)):
        raise Accepted(f"a result of {path} restored against {args[0]!r} ({args[3]!r})")
    return f"pickle({type(restored).__name__})"


def path_input(rng):
    """A problem path as Python gives one: bytes, os.PathLike (of str or bytes), a name that
    is not UTF-8 (which must load), or a value that is no path; through `Problem`,
    `Kinematics`, `simulate`, `solve(out=...)` and `Solution.write`."""
    f = Fixtures.get()
    good = [HOPPER.encode(), Path(HOPPER), PathLike(HOPPER), PathLike(HOPPER.encode()),
            f.not_utf8, os.fsdecode(f.not_utf8), PathLike(f.not_utf8)]
    bad = [b"", b"\x00", "a\x00b", b"\xff\xfe.toml", "\ud800.toml", "\udcff.toml",
           bytearray(HOPPER.encode()), memoryview(b"x"), PathLike(3), PathLike(None), 3,
           None, [HOPPER], Path("missing.toml"), os.fsencode(f.dir)]
    is_good = rng.random() < 0.5
    path = rng.choice(good if is_good else bad)
    how = rng.randrange(6)
    try:
        if how == 0:
            p = vito.Problem(path)
            again = eval(repr(p), {"vito": vito})
            assert again.path == p.path, (again.path, p.path)
            assert pickle.loads(pickle.dumps(p)).path == vito.Problem(p.path).path
        elif how == 1:
            vito.Kinematics(path)
        elif how == 2:
            vito.simulate(path, duration=rng.choice(INVALID_DURATIONS))
            raise Accepted(f"simulate({path!r}) ran")
        elif how == 3:
            vito.solve(path, starts=0)
            raise Accepted(f"solve({path!r}, starts=0) ran")
        elif how == 4:
            vito.Problem(HOPPER).solve(out=path, starts=0)
            raise Accepted(f"solve(out={path!r}, starts=0) ran")
        else:
            f.solution.write(f.out() if is_good else f.inside(path))
    except (TypeError, ValueError, FileNotFoundError, vito.ProblemError) as e:
        if is_good and how in (0, 1, 5):
            raise Refused(f"{path!r}: {type(e).__name__}: {e}") from e
        raise
    return ["Problem", "Kinematics", "simulate", "solve", "solve(out=)", "write"][how]


KINDS = ["set=dict", "set=str", "path", "options", "pickle", "path type"]


def one(rng, kind):
    """One call of the kind `KINDS[kind]`; returns its name."""
    what = kind
    if what == 4:
        return pickle_input(rng)
    if what == 5:
        return path_input(rng)
    if what == 0:
        sets = {key(rng): value(rng) for _ in range(rng.randrange(1, 4))}
        vito.Problem(HOPPER, set=sets)
        return "Problem(set=dict)"
    if what == 1:
        # str values, which `set=` reads as the command line reads a `--set` value.
        sets = {key(rng): rng.choice(STRINGS + [str(x) for x in NUMBERS])
                for _ in range(rng.randrange(1, 3))}
        vito.Problem(HOPPER, set=sets)
        return "Problem(set=str)"
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


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--count", type=int, default=100_000)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--first", type=int, default=0)
    args = p.parse_args()
    sys.setrecursionlimit(100_000)
    returned, raised, findings = 0, {}, []
    by_kind = {}
    slowest = (0.0, None)
    start = time.monotonic()
    for i in range(args.first, args.count):
        rng = random.Random(f"{args.seed}:{i}")
        kind = rng.randrange(len(KINDS))
        t0 = time.process_time()
        try:
            outcome = one(rng, kind)
            returned += 1
        except BaseException as e:  # noqa: BLE001 - every exception is sorted below
            name = type(e).__name__
            if name in ("PanicException", "SystemError", "KeyboardInterrupt", "MemoryError",
                        "Accepted", "Refused", "AssertionError"):
                findings.append((i, name, str(e)[:300]))
            raised[name] = raised.get(name, 0) + 1
            outcome = name
        tally = by_kind.setdefault(KINDS[kind], {})
        tally[outcome] = tally.get(outcome, 0) + 1
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
    print("by kind of input (returned: the call's name):")
    for kind in KINDS:
        tally = sorted(by_kind.get(kind, {}).items(), key=lambda kv: -kv[1])
        print(f"  {kind:<10}", ", ".join(f"{name} {n}" for name, n in tally))
    for f in findings[:20]:
        print("finding:", *f)
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
