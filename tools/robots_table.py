#!/usr/bin/env python3
"""The example-robot-data table (docs/robots.md): every URDF of the installed PyPI package
`example-robot-data` through `vito inspect`, `vito init` and `vito check`, with Pinocchio's
verdict beside vito's when `pin` is installed.

Usage: python3 tools/robots_table.py [--vito target/release/vito] [--out docs/robots.md]
(`make robots-table` runs it in .venv). Without --out the table is printed. Exit 1 when the
package is not installed.
"""

import argparse
import importlib.metadata
import json
import pathlib
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parents[1]
# Where the PyPI package (a cmeel wheel) puts the robots.
ROBOTS_IN_PACKAGE = "cmeel.prefix/share/example-robot-data/robots"


def robots_dir():
    """The installed package's robots directory, or None when it is not installed."""
    try:
        dist = importlib.metadata.distribution("example-robot-data")
    except importlib.metadata.PackageNotFoundError:
        return None
    path = pathlib.Path(dist.locate_file(ROBOTS_IN_PACKAGE))
    return path if path.is_dir() else None


def package_version():
    return importlib.metadata.version("example-robot-data")


def first_line(text):
    """The first line of a message that says something (vito's errors start with `error:`),
    with the first item of a list it introduces (`N problems to fix:`)."""
    lines = [line.strip() for line in text.splitlines() if line.strip()]
    if not lines:
        return ""
    first = lines[0].removeprefix("error: ")
    if first.endswith(":") and len(lines) > 1:
        first += " " + lines[1].removeprefix("- ") + (" …" if len(lines) > 2 else "")
    return first


def pinocchio_loads(urdf):
    """True/False when Pinocchio is installed, None when it is not."""
    try:
        import pinocchio
    except ImportError:
        return None
    try:
        pinocchio.buildModelFromUrdf(str(urdf))
        return True
    except Exception:  # noqa: BLE001 (urdfdom's errors are plain ValueErrors and RuntimeErrors)
        return False


def survey(vito, urdf, scratch):
    """One URDF through inspect, init and check: a dict of what happened."""
    row = {"urdf": urdf}
    run = lambda *args: subprocess.run(  # noqa: E731
        [str(vito), *map(str, args)], capture_output=True, text=True, timeout=600
    )
    inspected = run("inspect", urdf, "--json")
    if inspected.returncode != 0:
        # Named by the file's name, not the package's path.
        row["error"] = first_line(inspected.stderr).replace(str(urdf), urdf.name)
        row["message"] = inspected.stderr
        return row
    info = json.loads(inspected.stdout)
    row["base"] = info["base"]
    row["base_reason"] = info.get("base_reason", "")
    row["coordinates"] = len(info["coordinates"])
    row["inputs"] = len(info["inputs"])
    row["contacts"] = len(info["contacts"])
    row["warnings"] = len(info["warnings"])
    problem = scratch / f"{len(list(scratch.iterdir()))}_{urdf.stem}.toml"
    made = run("init", urdf, "--out", problem)
    if made.returncode != 0:
        row["init"] = "init: " + first_line(made.stderr)
        return row
    text = problem.read_text()
    row["feet"] = text.count("[[contacts.point]]") - text.count("# [[contacts.point]]")
    checked = run("check", problem)
    row["init"] = "ok" if checked.returncode == 0 else "check: " + first_line(checked.stderr)
    return row


def table(rows, version, pinocchio):
    loaded = [r for r in rows if "error" not in r]
    passed = [r for r in loaded if r.get("init") == "ok"]
    out = [
        "# URDFs from example-robot-data",
        "",
        f"Every URDF of the PyPI package `example-robot-data` {version} as vito reads it: `vito",
        "inspect` (base chosen by `--base auto`, coordinates, inputs, contacts, warnings), then",
        "`vito init` and `vito check` on the starter it writes"
        + (", and whether Pinocchio (`pin`) loads the file." if pinocchio else "."),
        "Written by `make robots-table` (tools/robots_table.py) from the installed package;",
        "`tests/python/test_robot_files.py` runs the same on every file.",
        "",
        f"vito loads {len(loaded)} of {len(rows)}; `init` then `check` pass on {len(passed)} of"
        f" those {len(loaded)}.",
        "",
    ]
    head = "| URDF | base | coordinates | inputs | contacts | warnings | init + check |"
    rule = "| --- | --- | ---: | ---: | ---: | ---: | --- |"
    if pinocchio:
        head += " Pinocchio |"
        rule += " --- |"
    out += [head, rule]
    for r in rows:
        name = f"`{r['name']}`"
        if "error" in r:
            cells = [name, "refused", "", "", "", "", r["error"].replace("|", "\\|")]
        else:
            feet = r.get("feet", 0)
            contacts = str(r["contacts"]) if r["contacts"] or not feet else f"{feet} end link" + ("s" if feet > 1 else "")
            cells = [
                name,
                r["base"],
                str(r["coordinates"]),
                str(r["inputs"]),
                contacts,
                str(r["warnings"]),
                r["init"].replace("|", "\\|"),
            ]
        if pinocchio:
            cells.append({True: "loads", False: "refuses"}.get(r.get("pinocchio"), ""))
        out.append("| " + " | ".join(cells) + " |")
    out += [
        "",
        "`contacts`: the URDF's collision spheres; without them, the end links `vito init`",
        "stands the robot on (named like feet, else the lowest). `base`: `--base auto`'s choice,",
        "`fixed` for a robot bolted down (a `world` root link, or no end link below its root),",
        "`floating` otherwise; `vito inspect` prints the reason ([init.md](init.md)). `warnings`:",
        "what vito reads differently from the file or ignores, each naming its line",
        "([inspect.md](inspect.md)).",
        "",
    ]
    return "\n".join(out)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--vito", default=str(ROOT / "target" / "release" / "vito"))
    parser.add_argument("--out", help="write the table here (default: print it)")
    args = parser.parse_args()
    robots = robots_dir()
    if robots is None:
        sys.exit("robots_table: the PyPI package example-robot-data is not installed "
                 "(pip install example-robot-data)")
    urdfs = sorted(robots.rglob("*.urdf"), key=lambda p: (p.name, str(p)))
    pinocchio = pinocchio_loads(urdfs[0]) is not None if urdfs else False
    rows = []
    with tempfile.TemporaryDirectory() as scratch:
        for urdf in urdfs:
            row = survey(args.vito, urdf, pathlib.Path(scratch))
            # The path under robots/ where two files share a name (anymal.urdf).
            twins = sum(u.name == urdf.name for u in urdfs) > 1
            row["name"] = str(urdf.relative_to(robots)) if twins else urdf.name
            if pinocchio:
                row["pinocchio"] = pinocchio_loads(urdf)
            rows.append(row)
            print(f"{urdf.name}: {row.get('error') or row.get('init')}", file=sys.stderr)
    text = table(rows, package_version(), pinocchio)
    if args.out:
        pathlib.Path(args.out).write_text(text)
        print(f"robots_table: wrote {args.out}", file=sys.stderr)
    else:
        print(text)


if __name__ == "__main__":
    main()
