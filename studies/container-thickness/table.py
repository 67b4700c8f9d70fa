#!/usr/bin/env python3
"""Table of the container-thickness sweep: AoR versus t/d for walls and periodic
boundaries (mean, seed standard deviation, n), and the critical thickness of each.

Critical-thickness rule: the thickest point is the thick limit. A thickness
t is "within the noise" of it when |AoR(t) - AoR(thick)| <= 2 * sqrt(se_t^2 +
se_thick^2) (se = seed standard deviation / sqrt(n)), with the seed standard
deviation pooled over the sweep for a stable estimate. The critical thickness is
the smallest t from which every thicker point is within the noise.

usage: table.py OUTDIR [--save]   (the directory run_thickness_sweep.sh wrote)

Runs are deterministic for a seed and thread count, so the AoR of every run
of the sweep is kept in results.csv beside this script (boundary, t_d, seed,
aor_deg, and the run's engine version): --save adds the runs of OUTDIR to it,
and the table is made from both, a run in OUTDIR taking precedence."""
import json, math, pathlib, re, sys
from collections import defaultdict

import csv
out = pathlib.Path(sys.argv[1])
save = "--save" in sys.argv[2:]
kept_file = pathlib.Path(__file__).with_name("results.csv")
runs = {}  # (boundary, t, seed) -> (aor, engine)
if kept_file.exists():
    for r in csv.DictReader(open(kept_file)):
        runs[(r["boundary"], float(r["t_d"]), int(r["seed"]))] = (float(r["aor_deg"]), r["engine"])
failed = []
for f in sorted(out.glob("*_t*_s*/run.json")):
    m = re.match(r"(walls|periodic)_t([0-9.]+)_s(\d+)$", f.parent.name)
    if not m:
        continue
    r = json.load(open(f))
    aor = r["observables"].get("angle_of_repose_deg")
    if aor is None:
        failed.append((f.parent.name, r["details"].get("angle_of_repose_error", "?")[:90]))
        continue
    runs[(m[1], float(m[2]), int(m[3]))] = (aor, str(r.get("engine", {}).get("version", r.get("engine", "")))
                                            if isinstance(r.get("engine"), dict) else str(r.get("engine", "")))
if save:
    with open(kept_file, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["boundary", "t_d", "seed", "aor_deg", "engine"])
        for (b, t, sd), (aor, eng) in sorted(runs.items()):
            w.writerow([b, f"{t:g}", sd, f"{aor:.4f}", eng])
rows = defaultdict(list)
for (b, t, sd), (aor, _) in sorted(runs.items()):
    rows[(b, t)].append(aor)

def stats(v):
    n = len(v); mu = sum(v) / n
    sd = math.sqrt(sum((x - mu) ** 2 for x in v) / (n - 1)) if n > 1 else float("nan")
    return mu, sd, n

pooled_all = [stats(v)[1] for v in rows.values() if len(v) > 1]
sd_pool_all = math.sqrt(sum(s * s for s in pooled_all) / len(pooled_all)) if pooled_all else float("nan")
result = {}
print("| boundary | t/d | AoR mean (deg) | seed sd (deg) | n | seeds |")
print("|---|---|---|---|---|---|")
for b in ("walls", "periodic"):
    ts = sorted(t for (bb, t) in rows if bb == b)
    if not ts:
        continue
    sd_pool = sd_pool_all
    for t in ts:
        mu, sd, n = stats(rows[(b, t)])
        print(f"| {b} | {t:g} | {mu:.1f} | {sd:.1f} | {n} | {', '.join(f'{x:.1f}' for x in rows[(b, t)])} |")
    ref_mu, _, ref_n = stats(rows[(b, ts[-1])])
    crit = ts[-1]
    for t in reversed(ts):
        mu, _, n = stats(rows[(b, t)])
        tol = 2.0 * sd_pool * math.sqrt(1.0 / n + 1.0 / ref_n)
        if abs(mu - ref_mu) <= tol:
            crit = t
        else:
            break
    result[b] = dict(thick_limit_deg=ref_mu, thick_limit_t_d=ts[-1], pooled_seed_sd_deg=sd_pool,
                     critical_thickness_d=crit)
print()
paper = {"walls": 32, "periodic": 4}
for b, v in result.items():
    print(f"{b}: thick limit {v['thick_limit_deg']:.1f} deg at t = {v['thick_limit_t_d']:g} d, pooled seed sd "
          f"{v['pooled_seed_sd_deg']:.2f} deg; critical thickness {v['critical_thickness_d']:g} d "
          f"(paper: {paper[b]} d)")
for name, why in failed:
    print(f"no AoR: {name}: {why}")
json.dump({"points": {f"{b}_t{t:g}": v for (b, t), v in rows.items()}, "critical": result},
          open(out / "container_thickness.json", "w"), indent=1)
