#!/usr/bin/env python3
"""Recovery of a known (mu_r, mu_s) over repeated noise seeds (issue 5, "Recovery").

The truth: ten runs of the quick Sandglass at (0.25, 0.45) with seeds 101-110, none of
them a design seed and the point not a design point (truth_runs.csv, made by
`--make-truth`). For each noise seed k the laboratory's recordings are drawn anew:
  - the ten tests: a bootstrap resample of the ten DEM runs (the test-to-test scatter
    drawn again, not fixed once);
  - their mean plus a Gaussian instrument error (AoR 0.5 deg, discharge time 1 %),
    recorded with that sigma and repeats = 10 (demcal adds the DEM's scatter / sqrt(10)).
Each set is calibrated on the checked-in design table (doe.csv: 5 x 5 points x 4
replicates) on AoR + time and on AoR alone; this script counts how often the AoR + time
95 % region holds the truth and how much larger the AoR-alone region is.

usage: recovery_check.py [--demcal PATH] [--seeds N] [--make-truth] [--map]
prints a table and writes out/sandglass-recovery/check/summary.json; --map instead puts the
truth at every design point in turn (recordings = the mean of its 4 runs, same sigmas and
repeats, no noise) and prints the area ratio there: where in the plane the time helps
"""

import argparse
import csv
import json
import pathlib
import random
import statistics
import subprocess
import sys

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent.parent
STUDY = HERE / "study.toml"
OUT = ROOT / "out" / "sandglass-recovery" / "check"
TRUTH = (0.25, 0.45)
TRUTH_SEEDS = range(101, 111)
INSTRUMENT = {"angle_of_repose_deg": ("deg", 0.5, 0.0), "discharge_time_s": ("s", 0.0, 0.01)}


def make_truth(demcal):
    rows = []
    for s in TRUTH_SEEDS:
        run_dir = OUT / "truth" / f"seed{s}"
        if not (run_dir / "run.json").exists():
            subprocess.run([demcal, "simulate", str(ROOT / "studies" / "quick" / "study.toml"), "--quiet", "--threads",
                            "1", "--overwrite", "--output", str(run_dir), "--set", f"mu_r={TRUTH[0]}", "--set",
                            f"mu_s={TRUTH[1]}", "--set", f"study.seed={s}"], check=True, capture_output=True)
        obs = json.load(open(run_dir / "run.json"))["observables"]
        rows.append({"seed": s, **{k: repr(obs[k]) for k in INSTRUMENT}})
    with open(HERE / "truth_runs.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)


def recordings(truth, k):
    rng = random.Random(k)
    sample = [rng.choice(truth) for _ in truth]
    lines = ["setup,observable,value,sigma,unit,repeats"]
    for name, (unit, sd_abs, sd_rel) in INSTRUMENT.items():
        mean = sum(float(r[name]) for r in sample) / len(sample)
        sigma = sd_abs + sd_rel * mean
        lines.append(f"sandglass,{name},{mean + rng.gauss(0.0, sigma):.6g},{sigma:.3g},{unit},{len(sample)}")
    return "\n".join(lines) + "\n"


def ratio_map(demcal, common):
    points = {}
    for r in csv.DictReader(open(HERE / "doe.csv")):
        points.setdefault((float(r["mu_r"]), float(r["mu_s"])), []).append(r)
    ratios = []
    for (mr, ms), runs in sorted(points.items(), key=lambda kv: (-kv[0][1], kv[0][0])):
        lines = ["setup,observable,value,sigma,unit,repeats"]
        for name, (unit, sd_abs, sd_rel) in INSTRUMENT.items():
            mean = sum(float(r[name]) for r in runs) / len(runs)
            lines.append(f"sandglass,{name},{mean:.6g},{sd_abs + sd_rel * mean:.3g},{unit},10")
        rec = OUT / "recordings-map.csv"
        rec.write_text("\n".join(lines) + "\n")
        subprocess.run([demcal, "calibrate", str(STUDY)] + common +
                       ["--set", f"calibration.recordings={rec}", "--set", "calibration.mcmc_samples=2000",
                        "--set", f"calibration.reference_point=[{mr}, {ms}]"], check=True, capture_output=True)
        c = json.load(open(OUT / "sandglass-recovery" / "reports" / "calibration" / "calibration.json"))["comparison"]
        ratios.append(c["ratio"])
        print(f"truth ({mr:.3f}, {ms:.3f}): area ratio {c['ratio']:5.2f}  ({c['area_a']:.3f} / {c['area_b']:.3f})")
    print(f"\narea ratio over the {len(ratios)} design points: median {statistics.median(ratios):.2f}, "
          f"min {min(ratios):.2f}, max {max(ratios):.2f}, >= 3 at {sum(x >= 3 for x in ratios)}")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--demcal", default=str(ROOT / "build" / "cli" / "demcal"))
    p.add_argument("--seeds", type=int, default=20)
    p.add_argument("--make-truth", action="store_true", help="run the ten truth runs (about 3 CPU-min)")
    p.add_argument("--map", action="store_true", help="the area ratio with the truth at each design point")
    a = p.parse_args()
    OUT.mkdir(parents=True, exist_ok=True)
    if a.make_truth:
        make_truth(a.demcal)
    truth = list(csv.DictReader(open(HERE / "truth_runs.csv")))
    common = ["--output", str(OUT), "--doe", str(HERE / "doe.csv"), "-q"]
    subprocess.run([a.demcal, "fit", str(STUDY)] + common, check=True, capture_output=True)
    if a.map:
        ratio_map(a.demcal, common)
        return
    results = []
    for k in range(1, a.seeds + 1):
        rec = OUT / f"recordings-seed{k}.csv"
        rec.write_text(recordings(truth, k))
        r = subprocess.run([a.demcal, "calibrate", str(STUDY)] + common +
                           ["--set", f"calibration.recordings={rec}", "--set", "calibration.mcmc_samples=4000"],
                           capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit(r.stderr)
        j = json.load(open(OUT / "sandglass-recovery" / "reports" / "calibration" / "calibration.json"))
        ref = j["references"][0]
        c = j["comparison"]
        best = j["joint"]["minima"][0]["theta"]
        row = {"seed": k, "ratio": c["ratio"], "area_joint": c["area_b"], "area_alone": c["area_a"],
               "joint_inside_alone": c["overlap_fraction_b"], "truth_dchi2": ref["delta_chi_square_joint"],
               "truth_inside": ref["inside_joint"], "truth_inside_alone": ref["inside_alone"],
               "best_mu_r": best[0], "best_mu_s": best[1]}
        results.append(row)
        print(f"seed {k:2d}: ratio {row['ratio']:5.2f}  areas {row['area_alone']:.3f} / {row['area_joint']:.3f}  "
              f"truth dchi2 {row['truth_dchi2']:5.2f} {'inside' if row['truth_inside'] else 'OUTSIDE'}  "
              f"best ({best[0]:.3f}, {best[1]:.3f})", flush=True)
    ratios = [r["ratio"] for r in results]
    summary = {
        "seeds": len(results),
        "truth_inside_joint": sum(r["truth_inside"] for r in results),
        "truth_inside_alone": sum(r["truth_inside_alone"] for r in results),
        "ratio_median": statistics.median(ratios), "ratio_min": min(ratios), "ratio_max": max(ratios),
        "ratio_at_least_3": sum(x >= 3.0 for x in ratios),
        "results": results,
    }
    (OUT / "summary.json").write_text(json.dumps(summary, indent=1) + "\n")
    print(f"\ntruth inside the AoR + time 95 % region: {summary['truth_inside_joint']}/{len(results)}; "
          f"area ratio (AoR alone / AoR + time): median {summary['ratio_median']:.2f}, "
          f"min {summary['ratio_min']:.2f}, max {summary['ratio_max']:.2f}, "
          f">= 3 in {summary['ratio_at_least_3']}/{len(results)}")


if __name__ == "__main__":
    main()
