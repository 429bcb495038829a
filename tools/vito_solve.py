"""One `vito solve` as the measuring scripts (robustness.py, ladders.py) run it: one BLAS
thread, its output captured, timed; the summary it wrote, or None (with its error on stderr)
when it ended otherwise than solved or not solved (exit 0 or 1)."""

import json
import os
import subprocess
import sys
import time


def solve_summary(cmd, out):
    """Runs `cmd` (a `vito solve … --out out`); returns (summary.json read back or None, wall
    seconds of the command)."""
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    start = time.monotonic()
    done = subprocess.run(cmd, env=env, capture_output=True, text=True)
    wall = time.monotonic() - start
    if done.returncode not in (0, 1):
        sys.stderr.write(f"{' '.join(map(str, cmd))}: exit {done.returncode}\n{done.stderr}\n")
        return None, wall
    return json.loads((out / "summary.json").read_text()), wall
