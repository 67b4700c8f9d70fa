#!/usr/bin/env python3
"""Recovery of a known (mu_r, mu_s) over repeated noise seeds (issue 5, "Recovery").

The truth: DEM runs of the study's apparatus at its reference point, seeds 101, 102, ...,
none of them a design seed and the point not a design point (truth_runs.csv, made by
`--make-truth N`). For each noise seed k a laboratory records the Sandglass ten times:
  - its ten tests: truth runs 10(k-1) .. 10k-1, its own, when truth_runs.csv holds ten per
    seed; otherwise a bootstrap resample of all of them (then the seeds share those runs'
    mean and its error, and are not independent laboratories: the summary says which);
  - their mean plus a Gaussian instrument error (AoR 0.5 deg, discharge time 1 %),
    recorded with that sigma and repeats = 10 (demcal adds the DEM's scatter / sqrt(10)).
Each set is calibrated on the study's checked-in design table (doe.csv) on AoR + time and
on AoR alone; this script counts how often the AoR + time 95 % region holds the truth and
how much larger the AoR-alone region is.

usage: recovery_check.py [--study DIR] [--demcal PATH] [--seeds N] [--make-truth N [--jobs J]] [--map]
DIR (default: this script's folder) holds study.toml, doe.csv and truth_runs.csv; the truth
is its [calibration] reference_point. Prints a table and writes
out/<DIR's name>/check/summary.json; --map instead puts the
truth at every design point in turn (recordings = the mean of its 4 runs, same sigmas and
repeats, no noise) and prints the area ratio there: where in the plane the time helps
"""

import argparse
import concurrent.futures
import csv
import json
import pathlib
import random
import statistics
import subprocess
import sys
import tomllib

ROOT = pathlib.Path(__file__).resolve().parent.parent.parent
TRUTH_SEED0 = 101
TESTS_PER_LABORATORY = 10
INSTRUMENT = {"angle_of_repose_deg": ("deg", 0.5, 0.0), "discharge_time_s": ("s", 0.0, 0.01)}


class Study:
    """The study folder's files, and the truth as its config states it."""

    def __init__(self, folder):
        self.dir = pathlib.Path(folder).resolve()
        self.toml = self.dir / "study.toml"
        cfg = tomllib.loads(self.toml.read_text())
        self.name = cfg["study"]["name"]
        self.truth = tuple(cfg["calibration"]["reference_point"])
        # Keys a design parameter drags along (also_sets) must move with it in the truth runs too.
        params = cfg["design"]["parameters"]
        self.tied = {name: spec.get("also_sets", []) for name, spec in params.items()}
        self.out = ROOT / "out" / self.dir.name / "check"

    def calibration_json(self):
        return json.load(open(self.out / self.name / "reports" / "calibration" / "calibration.json"))


def truth_run(demcal, study, s):
    run_dir = study.out / "truth" / f"seed{s}"
    if not (run_dir / "run.json").exists():
        sets = [f"study.seed={s}"]
        for name, value in zip(("mu_r", "mu_s"), study.truth):
            sets += [f"{key}={value}" for key in [name] + study.tied.get(name, [])]
        cmd = [demcal, "simulate", str(study.toml), "--quiet", "--threads", "1", "--overwrite", "--output",
               str(run_dir)]
        for x in sets:
            cmd += ["--set", x]
        subprocess.run(cmd, check=True, capture_output=True)
    obs = json.load(open(run_dir / "run.json"))["observables"]
    return {"seed": s, **{k: repr(obs[k]) for k in INSTRUMENT}}


def make_truth(demcal, study, count, jobs):
    with concurrent.futures.ThreadPoolExecutor(jobs) as pool:
        rows = list(pool.map(lambda s: truth_run(demcal, study, s), range(TRUTH_SEED0, TRUTH_SEED0 + count)))
    with open(study.dir / "truth_runs.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0].keys()), lineterminator="\n")
        w.writeheader()
        w.writerows(rows)


def fresh_laboratories(truth, seeds):
    """Whether every noise seed can have ten DEM tests of its own."""
    return len(truth) >= TESTS_PER_LABORATORY * seeds


def recordings(truth, k, fresh):
    rng = random.Random(k)
    if fresh:
        # Noise seed k's laboratory: its own ten tests, shared with no other seed.
        sample = truth[TESTS_PER_LABORATORY * (k - 1):TESTS_PER_LABORATORY * k]
    else:
        # Too few truth runs for that: the ten tests drawn again from the same runs. Every seed then shares
        # those runs' mean, and with it their mean's error: the seeds are not independent laboratories.
        sample = [rng.choice(truth) for _ in range(TESTS_PER_LABORATORY)]
    means = {name: sum(float(r[name]) for r in sample) / len(sample) for name in INSTRUMENT}
    noisy = {name: mean + rng.gauss(0.0, instrument_sigma(name, mean)) for name, mean in means.items()}
    return recordings_csv(noisy, means, len(sample))


def instrument_sigma(name, mean):
    _, sd_abs, sd_rel = INSTRUMENT[name]
    return sd_abs + sd_rel * mean


def recordings_csv(values, means, repeats):
    """The recordings file: each value with the instrument's sigma at its noise-free mean."""
    lines = ["setup,observable,value,sigma,unit,repeats"]
    for name, (unit, _, _) in INSTRUMENT.items():
        lines.append(f"sandglass,{name},{values[name]:.6g},{instrument_sigma(name, means[name]):.3g},{unit},{repeats}")
    return "\n".join(lines) + "\n"


def ratio_map(demcal, study, common):
    points = {}
    for r in csv.DictReader(open(study.dir / "doe.csv")):
        points.setdefault((float(r["mu_r"]), float(r["mu_s"])), []).append(r)
    ratios = []
    for (mr, ms), runs in sorted(points.items(), key=lambda kv: (-kv[0][1], kv[0][0])):
        means = {}
        for name in INSTRUMENT:
            values = [float(r[name]) for r in runs if r[name]]
            if values:
                means[name] = sum(values) / len(values)
        missing = [name for name in INSTRUMENT if name not in means]
        if missing:
            # E.g. the lined Sandglass at mu_s = 0.2: the pile slides apart on the floor, no AoR to record.
            print(f"truth ({mr:.3f}, {ms:.3f}): no run gave a value of {', '.join(missing)}: skipped")
            continue
        rec = study.out / "recordings-map.csv"
        rec.write_text(recordings_csv(means, means, TESTS_PER_LABORATORY))
        subprocess.run([demcal, "calibrate", str(study.toml)] + common +
                       ["--set", f"calibration.recordings={rec}", "--set", "calibration.mcmc_samples=2000",
                        "--set", f"calibration.reference_point=[{mr}, {ms}]"], check=True, capture_output=True)
        c = study.calibration_json()["comparison"]
        ratios.append(c["ratio"])
        print(f"truth ({mr:.3f}, {ms:.3f}): area ratio {c['ratio']:5.2f}  ({c['area_a']:.3f} / {c['area_b']:.3f})")
    print(f"\narea ratio over the {len(ratios)} design points: median {statistics.median(ratios):.2f}, "
          f"min {min(ratios):.2f}, max {max(ratios):.2f}, >= 3 at {sum(x >= 3 for x in ratios)}")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--study", default=str(pathlib.Path(__file__).resolve().parent),
                   help="the study folder (study.toml, doe.csv, truth_runs.csv)")
    p.add_argument("--demcal", default=str(ROOT / "build" / "cli" / "demcal"))
    p.add_argument("--seeds", type=int, default=20)
    p.add_argument("--make-truth", type=int, metavar="N", default=0,
                   help="run N truth runs, seeds 101.. (about 25 CPU-s each; kept runs are reused)")
    p.add_argument("--jobs", type=int, default=2, help="truth runs at a time")
    p.add_argument("--map", action="store_true", help="the area ratio with the truth at each design point")
    a = p.parse_args()
    study = Study(a.study)
    study.out.mkdir(parents=True, exist_ok=True)
    if a.make_truth:
        make_truth(a.demcal, study, a.make_truth, a.jobs)
    truth = list(csv.DictReader(open(study.dir / "truth_runs.csv")))
    common = ["--output", str(study.out), "--doe", str(study.dir / "doe.csv"), "-q"]
    subprocess.run([a.demcal, "fit", str(study.toml)] + common, check=True, capture_output=True)
    if a.map:
        ratio_map(a.demcal, study, common)
        return
    fresh = fresh_laboratories(truth, a.seeds)
    print(f"{len(truth)} truth runs: " + ("each noise seed has ten tests of its own" if fresh else
                                          "each noise seed is a bootstrap of them (too few for ten each)"))
    results = []
    for k in range(1, a.seeds + 1):
        rec = study.out / f"recordings-seed{k}.csv"
        rec.write_text(recordings(truth, k, fresh))
        r = subprocess.run([a.demcal, "calibrate", str(study.toml)] + common +
                           ["--set", f"calibration.recordings={rec}", "--set", "calibration.mcmc_samples=4000"],
                           capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit(r.stderr)
        j = study.calibration_json()
        ref = j["references"][0]
        c = j["comparison"]
        best = j["joint"]["minima"][0]["theta"]
        row = {"seed": k, "ratio": c["ratio"], "area_joint": c["area_b"], "area_alone": c["area_a"],
               "joint_inside_alone": c["overlap_fraction_b"], "truth_dchi2": ref["delta_chi_square_joint"],
               "truth_inside": ref["inside_joint"], "truth_inside_alone": ref["inside_alone"],
               "best_mu_r": best[0], "best_mu_s": best[1],
               "joint_identified": j["joint"]["identified"], "alone_identified": j["alone"]["identified"],
               "joint_extent": [[e["lower"], e["upper"]] for e in j["joint"]["region"]["extent"]]}
        results.append(row)
        print(f"seed {k:2d}: ratio {row['ratio']:5.2f}  areas {row['area_alone']:.3f} / {row['area_joint']:.3f}  "
              f"truth dchi2 {row['truth_dchi2']:5.2f} {'inside' if row['truth_inside'] else 'OUTSIDE'}  "
              f"best ({best[0]:.3f}, {best[1]:.3f})", flush=True)
    ratios = [r["ratio"] for r in results]
    for i, name in enumerate(("mu_r", "mu_s")):
        print(f"{name} identified (95 % region clear of both bounds): with AoR + time in "
              f"{sum(r['joint_identified'][i] for r in results)}/{len(results)} seeds, with AoR alone in "
              f"{sum(r['alone_identified'][i] for r in results)}/{len(results)}")
    print(f"AoR + time region inside the AoR-alone one (>= 95 % of its area) in "
          f"{sum(r['joint_inside_alone'] >= 0.95 for r in results)}/{len(results)} seeds")
    summary = {
        "seeds": len(results),
        "laboratories": "fresh" if fresh else "bootstrap",
        "truth_inside_joint": sum(r["truth_inside"] for r in results),
        "truth_inside_alone": sum(r["truth_inside_alone"] for r in results),
        "ratio_median": statistics.median(ratios), "ratio_min": min(ratios), "ratio_max": max(ratios),
        "ratio_at_least_3": sum(x >= 3.0 for x in ratios),
        "results": results,
    }
    (study.out / "summary.json").write_text(json.dumps(summary, indent=1) + "\n")
    print(f"\ntruth inside the AoR + time 95 % region: {summary['truth_inside_joint']}/{len(results)}; "
          f"area ratio (AoR alone / AoR + time): median {summary['ratio_median']:.2f}, "
          f"min {summary['ratio_min']:.2f}, max {summary['ratio_max']:.2f}, "
          f">= 3 in {summary['ratio_at_least_3']}/{len(results)}")


if __name__ == "__main__":
    main()
