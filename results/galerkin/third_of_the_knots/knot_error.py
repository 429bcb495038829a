"""RMS configuration error at a plan's knots of a tracking simulation (q linear between the
simulation's steps), and the largest deviation of any coordinate; both trajectory.csv files
as vito writes them (time first, then the n coordinates)."""
import csv, math, sys

def read(path, n):
    with open(path) as f:
        rows = list(csv.reader(f))
    return [[float(v) for v in r[: n + 1]] for r in rows[1:]]

plan_path, sim_path, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
plan, sim = read(plan_path, n), read(sim_path, n)
total, count, worst = 0.0, 0, 0.0
for row in plan:
    t = row[0]
    if t > sim[-1][0] + 1e-9:
        continue
    j = max(1, min(len(sim) - 1, next((i for i, s in enumerate(sim) if s[0] > t), len(sim) - 1)))
    a, b = sim[j - 1], sim[j]
    s = 0.0 if b[0] == a[0] else min(1.0, max(0.0, (t - a[0]) / (b[0] - a[0])))
    for i in range(1, n + 1):
        d = a[i] + s * (b[i] - a[i]) - row[i]
        total += d * d
        worst = max(worst, abs(d))
    count += 1
print(f"knots {len(plan)}  RMS error at the knots {math.sqrt(total / count):.4e}  max |dq| at the knots {worst:.4e}")
