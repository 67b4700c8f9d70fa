#!/usr/bin/env python3
"""The blind test of `demcal diagnose` (issue 6): concealed effects, several noise seeds.

Each studies/concealed-<effect>/ is the same base model (written from
base_study.toml.in by `studies`). Its recordings were made by the engine with one
effect switched on -- the truth, in truth/<study>.toml, which nothing the diagnosis
reads points to -- or with none (concealed-null). This script

  studies      writes studies/concealed-*/study.toml from the template
  truth        runs the DEM at each truth: every setup, REPEATS seeds per noise seed
               (seeds 100 k + 1 .. 100 k + REPEATS for noise seed k, none of them a
               design seed), into out/concealed/truth/, and collects truth/runs.csv
  recordings   per study and noise seed: the mean of the REPEATS runs plus a Gaussian
               instrument error (its own seed), with sigma = that instrument
               uncertainty and repeats = REPEATS -> studies/<study>/recordings[-seedK].csv
  diagnose     `demcal diagnose` on every study and noise seed, all sharing one run
               store (out/concealed/runs), then scores each verdict against the truth
               -> tests/concealed/results.csv, the table on stdout, the study READMEs
  table        the table and the study READMEs again, from results.csv
  all          the four in order
  check        exit 1 unless the results meet the blind test's goal, stated before
               any run: the hidden effect named right in >= --min-identified of the
               effect cases (0.8) and no false alarm on the null study
  verify       diagnose, then check: what ctest runs (tests/CMakeLists.txt, label
               `concealed`, only with -DDEMCAL_LONG_TESTS=ON), with --out and
               --results in the build tree and --no-readmes, so that nothing in the
               source tree is written

Every step is resumable: DEM runs already done are reused (run store, truth runs).
Usage: harness.py [--demcal PATH] [--jobs N] [--seeds 1,2,3] [--out DIR] [--results CSV]
                  [--no-readmes] [--min-identified F] STEP
"""

import argparse
import csv
import json
import math
import pathlib
import random
import subprocess
import sys
import time
import tomllib
from concurrent.futures import ThreadPoolExecutor

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent.parent
TRUTH = HERE / "truth"
STUDIES = ROOT / "studies"  # where the studies are written; --truth-set fresh moves both
OUT = ROOT / "out" / "concealed"  # --out replaces it
REPEATS = 3
SETUPS = ["sandglass", "container_walls", "container_periodic"]
# Instrument uncertainty of each recording: (observable, unit, absolute sd, relative sd).
INSTRUMENT = [
    ("angle_of_repose_deg", "deg", 0.5, 0.0),      # a protractor on a photograph
    ("discharge_time_s", "s", 0.0, 0.01),          # stopwatch / video, 1 %
    ("bulk_density_kg_m3", "kg/m3", 0.0, 0.005),   # mass and volume of the fill, 0.5 %
    # m(t) from a balance under the lower chamber, read at 25, 50, 75 % of the mass passed
    ("discharge_t25_s", "s", 0.0, 0.01),
    ("discharge_t50_s", "s", 0.0, 0.01),
    ("discharge_t75_s", "s", 0.0, 0.01),
]


def set_out(path):
    global OUT
    OUT = path.resolve()


def set_truth_set(name):
    """`original`: the five truths the method was developed on (truth/, studies/concealed-*).
    `fresh`: truths made after the method was frozen, never used to tune anything
    (truth-fresh/, their studies under fresh/studies/; tests/concealed/README.md).
    `lammps`: the truths made in LAMMPS through demcal's deck writer, the model still
    demcal's (lammps/truth/, their studies under lammps/studies/; lammps/README.md).
    `lammps-fresh`: LAMMPS truths made after the cross-engine method was frozen, with
    frictions and strengths of their own (lammps/truth-fresh/, their studies under
    lammps/fresh/studies/; lammps/README.md "Fresh truths").
    `lammps-stage3`: LAMMPS truths written after stage 3's method was frozen
    (lammps/truth-stage3/, their studies under lammps/stage3/studies/; lammps/README.md
    "Stage 3").
    `lammps-stage4`: LAMMPS truths written after stage 4's method was frozen
    (lammps/truth-stage4/, their studies under lammps/stage4/studies/; lammps/README.md
    "Stage 4").
    `stage3`: same-engine truths written after stage 3's method was frozen, with frictions
    and strengths of their own (truth-stage3/, their studies under stage3/studies/;
    README.md "Stage 3 on the same engine").
    `stage6`: same-engine truths written after stage 6's method was frozen (truth-stage6/,
    their studies under stage6/studies/; stage6/README.md)."""
    global TRUTH, STUDIES
    if name == "fresh":
        TRUTH = HERE / "truth-fresh"
        STUDIES = HERE / "fresh" / "studies"
    elif name == "lammps":
        TRUTH = HERE / "lammps" / "truth"
        STUDIES = HERE / "lammps" / "studies"
    elif name == "lammps-fresh":
        TRUTH = HERE / "lammps" / "truth-fresh"
        STUDIES = HERE / "lammps" / "fresh" / "studies"
    elif name == "lammps-stage3":
        TRUTH = HERE / "lammps" / "truth-stage3"
        STUDIES = HERE / "lammps" / "stage3" / "studies"
    elif name == "lammps-stage4":
        TRUTH = HERE / "lammps" / "truth-stage4"
        STUDIES = HERE / "lammps" / "stage4" / "studies"
    elif name == "stage3":
        TRUTH = HERE / "truth-stage3"
        STUDIES = HERE / "stage3" / "studies"
    elif name == "stage6":
        TRUTH = HERE / "truth-stage6"
        STUDIES = HERE / "stage6" / "studies"


def series_observables(rec):
    """The m(t) segments of a run record as demcal reads them (study/run_record.hpp,
    series_observables): for runs recorded before demcal wrote them itself."""
    out = {}
    obs, series = rec.get("observables", {}), rec.get("series", {})
    m = series.get("discharged_mass")
    if obs.get("discharge_time_s") is None or not m or not m.get("mass_kg") or not m["mass_kg"][-1] > 0:
        return out
    t, mass = m["time_s"], m["mass_kg"]
    for name, f in (("discharge_t25_s", 0.25), ("discharge_t50_s", 0.5), ("discharge_t75_s", 0.75)):
        target = f * mass[-1]
        for i, v in enumerate(mass):
            if v >= target:
                out[name] = t[i] if i == 0 or not v > mass[i - 1] else \
                    t[i - 1] + (target - mass[i - 1]) / (v - mass[i - 1]) * (t[i] - t[i - 1])
                break
    return out
TITLES = {
    "concealed-cohesion": "Concealed-effect study: cohesion",
    "concealed-wall-friction": "Concealed-effect study: particle-wall friction",
    "concealed-air-drag": "Concealed-effect study: air drag",
    "concealed-size-spread": "Concealed-effect study: size spread",
    "concealed-null": "Concealed-effect study: the null case (nothing concealed)",
}


def truths():
    out = []
    for f in sorted(TRUTH.glob("*.toml")):
        with open(f, "rb") as fh:
            t = tomllib.load(fh)
        t["file"] = f
        out.append(t)
    return out


# The key each candidate's parameter is (config/physics_candidates.cpp), and its value when a
# truth switches the effect on without giving one.
HIDDEN_KEY = {
    "cohesion": ("interaction.particle_particle.surface_energy_j_m2", None),
    "grain_cohesion": ("interaction.particle_particle.surface_energy_j_m2", None),
    "wall_friction": ("interaction.particle_wall.sliding_friction", None),
    "air_drag": ("air.drag_scale", 1.0),
    "size_spread": ("material.size.relative_half_width", None),
}


def hidden_value(t):
    """The concealed parameter's value in a truth, or None (the null)."""
    if t["effect"] not in HIDDEN_KEY:
        return None
    key, default = HIDDEN_KEY[t["effect"]]
    for kv in t["set"]:
        k, _, v = kv.partition("=")
        if k.strip() == key:
            return float(v)
    return default


def study_file(name):
    return STUDIES / name / "study.toml"


def recordings_name(seed):
    return "recordings.csv" if seed == 1 else f"recordings-seed{seed}.csv"


def step_studies(args):
    template = (HERE / "base_study.toml.in").read_text()
    for t in truths():
        f = study_file(t["study"])
        f.parent.mkdir(parents=True, exist_ok=True)
        title = t.get("title", TITLES.get(t["study"], t["study"]))
        text = template.replace("@NAME@", t["study"]).replace("@TITLE@", title)
        if not f.exists() or f.read_text() != text:
            f.write_text(text)
            print("wrote", f.relative_to(ROOT))


def truth_seeds(noise_seed):
    return [100 * noise_seed + j for j in range(1, REPEATS + 1)]


def step_truth(args):
    jobs = []
    for t in truths():
        for k in args.seeds:
            for s in truth_seeds(k):
                for setup in SETUPS:
                    run_dir = OUT / "truth" / t["study"] / f"seed{s}" / setup
                    jobs.append((t, s, setup, run_dir))

    def run(job):
        t, s, setup, run_dir = job
        if (run_dir / "run.json").exists():
            return job
        cmd = [args.demcal, "simulate", str(study_file(t["study"])), "--apparatus", setup, "--quiet",
               "--threads", "1", "--overwrite", "--output", str(run_dir), "--set", f"mu_r={t['mu_r']}",
               "--set", f"mu_s={t['mu_s']}", "--set", f"study.seed={s}"]
        for kv in t["set"]:
            cmd += ["--set", kv]
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit(f"truth run failed: {' '.join(cmd)}\n{r.stderr}")
        return job

    todo = [j for j in jobs if not (j[3] / "run.json").exists()]
    print(f"truth: {len(jobs)} runs, {len(todo)} to do", flush=True)
    started = time.time()
    with ThreadPoolExecutor(args.jobs) as pool:
        for i, _ in enumerate(pool.map(run, todo), 1):
            if i % 10 == 0:
                print(f"  {i}/{len(todo)} ({time.time() - started:.0f} s)", flush=True)
    rows = []
    for t, s, setup, run_dir in jobs:
        rec = json.load(open(run_dir / "run.json"))
        derived = series_observables(rec)
        for name, _, _, _ in INSTRUMENT:
            v = rec["observables"].get(name, derived.get(name))
            if v is not None:
                rows.append({"study": t["study"], "seed": s, "setup": setup, "observable": name, "value": repr(v),
                             "wall_time_s": f"{rec['results']['wall_time_s']:.2f}"})
    with open(TRUTH / "runs.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    print("wrote", (TRUTH / "runs.csv").relative_to(ROOT))


def step_recordings(args):
    runs = list(csv.DictReader(open(TRUTH / "runs.csv")))
    for t in truths():
        for k in args.seeds:
            seeds = set(truth_seeds(k))
            # The instrument's error has its own seed, apart from the DEM's.
            rng = random.Random(f"{t['study']}:{k}")
            lines = ["setup,observable,value,sigma,unit,repeats"]
            for setup in SETUPS:
                for name, unit, sd_abs, sd_rel in INSTRUMENT:
                    v = [float(r["value"]) for r in runs if r["study"] == t["study"] and r["setup"] == setup
                         and r["observable"] == name and int(r["seed"]) in seeds]
                    measured = any(r["setup"] == setup and r["observable"] == name for r in runs)
                    if not v and not measured:
                        continue  # this setup never measures it (a container has no discharge time)
                    if not v:
                        # Every test of this noise seed failed to give it (a pile too small to fit, a
                        # clog): a laboratory would record nothing either.
                        print(f"note: {t['study']} noise seed {k}: no {setup} {name} in {REPEATS} runs; not recorded")
                        continue
                    if len(v) != REPEATS:
                        print(f"note: {t['study']} noise seed {k}: {setup} {name} from {len(v)} of {REPEATS} runs")
                    mean = sum(v) / len(v)
                    sigma = sd_abs + sd_rel * abs(mean)
                    value = mean + rng.gauss(0.0, sigma)
                    lines.append(f"{setup},{name},{value:.6g},{sigma:.3g},{unit},{len(v)}")
            f = study_file(t["study"]).parent / recordings_name(k)
            f.write_text("\n".join(lines) + "\n")
            print("wrote", f.relative_to(ROOT))


def base_theta(d):
    """The base model's calibrated point in a diagnosis.json, or [] when it has none."""
    minima = (d.get("base") or {}).get("minima") or []
    return minima[0].get("theta", []) if minima else []


def step_diagnose(args):
    results = []
    for t in truths():
        for k in args.seeds:
            name = f"{t['study']}-seed{k}"
            cmd = [args.demcal, "diagnose", str(study_file(t["study"])), "--quiet", "--jobs", str(args.jobs),
                   "--output", str(OUT), "--run-store", str(OUT / "runs"), "--set", f"study.name={name}",
                   "--set", f"calibration.recordings={recordings_name(k)}"]
            started = time.time()
            r = subprocess.run(cmd, capture_output=True, text=True)
            elapsed = time.time() - started
            if r.returncode != 0:
                sys.exit(f"diagnose failed ({r.returncode}): {' '.join(cmd)}\n{r.stdout}\n{r.stderr}")
            d = json.load(open(OUT / name / "reports" / "diagnosis" / "diagnosis.json"))
            chosen = d.get("chosen") or "none"
            truth = t["effect"]
            if truth == "none" and t.get("model_form_error", False):
                # The truth's engine is not the model, so the recordings differ from every
                # friction pair by the engines' difference: the right answer is to name no
                # physics, whether the mismatch is seen ("unexplained") or not.
                verdict = "false alarm" if chosen != "none" else "right"
            elif truth == "none":
                verdict = "right" if d["outcome"] == "reproduced" else "false alarm"
            elif chosen == truth:
                verdict = "right"
            elif d["outcome"] in ("reproduced", "untestable"):
                verdict = "missed"
            elif d["outcome"] == "unexplained":
                verdict = "unexplained"  # a mismatch seen, no candidate named
            else:
                verdict = "wrong"
            chosen_fit = next((f for f in d.get("fits", []) if f["name"] == chosen), None)
            row = {
                "study": t["study"], "noise_seed": k, "truth": truth, "outcome": d["outcome"], "named": chosen,
                "verdict": verdict,
                "chi2_dof_before": d.get("chi_square_per_dof_before", d["detection"].get("chi_square_per_dof")),
                "chi2_dof_after": d.get("chi_square_per_dof_after"),
                "p_value": d["detection"].get("p_value"),
                "bayes_factor": d.get("bayes_factor_over_base"),
                "value": chosen_fit.get("phi") if chosen_fit else None,
                "value_lower": chosen_fit.get("phi_lower") if chosen_fit else None,
                "value_upper": chosen_fit.get("phi_upper") if chosen_fit else None,
                "hidden_value": hidden_value(t),
                "hidden_inside": (chosen_fit["phi_lower"] <= hidden_value(t) <= chosen_fit["phi_upper"])
                if chosen_fit and hidden_value(t) is not None and chosen == truth
                and chosen_fit.get("phi_lower") is not None and chosen_fit.get("phi_upper") is not None else None,
                "dem_runs_executed": d.get("dem_runs_executed"), "wall_time_s": round(elapsed, 1),
                "cpu_time_s": round(d["cpu_time_s"], 1) if d.get("cpu_time_s") is not None else None,
                # How often the base design grew before the verdict, and where the base fit ended.
                "design_rounds": len(d.get("design_extension", {}).get("rounds", [])),
                "base_fit": " ".join(f"{v:.3g}" for v in base_theta(d)),
                "summary": d["summary"],
            }
            results.append(row)
            print(f"{name}: {verdict} ({d['outcome']}, named {chosen}); {d['summary']}", flush=True)
    args.results.parent.mkdir(parents=True, exist_ok=True)
    with open(args.results, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(results[0].keys()))
        w.writeheader()
        w.writerows(results)
    print_table(results)
    if not args.no_readmes:
        write_readmes(results, args)


def step_check(args):
    """The goal of the blind test, fixed before any run (issue 6, restated in issue 19)."""
    results = list(csv.DictReader(open(args.results)))
    effects = [r for r in results if r["truth"] != "none"]
    nulls = [r for r in results if r["truth"] == "none"]
    right = sum(r["verdict"] == "right" for r in effects)
    alarms = sum(r["verdict"] == "false alarm" for r in nulls)
    failures = []
    if not effects or right < args.min_identified * len(effects):
        failures.append(f"the hidden effect named right in {right} of {len(effects)} cases, "
                        f"fewer than {args.min_identified:.0%}")
    if not nulls:
        failures.append("no null case among the results: false alarms cannot be counted")
    if alarms > 0:
        failures.append(f"{alarms} false alarm(s) in {len(nulls)} null cases")
    print(f"{args.results}: named right {right}/{len(effects)}, false alarms {alarms}/{len(nulls)}")
    if failures:
        sys.exit("blind test failed: " + "; ".join(failures))


STUDY_README = """# {title}

A concealed-effect study of the blind test of `demcal diagnose` (`tests/concealed/README.md`
says how the recordings were made and how verdicts are scored). The study is the base
model of `tests/concealed/base_study.toml.in`; its recordings (`recordings.csv` = noise seed
1, `recordings-seed2.csv`, `recordings-seed3.csv`) were made by {engine} with {hidden}.
The truth is kept in `{truth_file}`, which nothing here reads.

    ./build/cli/demcal diagnose {study_path}     # noise seed 1
    python3 tests/concealed/harness.py{truth_set} diagnose     # every study, every noise seed

## What the diagnosis said (harness run of {date}; `{results}`)

| noise seed | outcome | named | verdict | chi²/dof before | after | Bayes factor | DEM runs | wall s |
|---|---|---|---|---|---|---|---|---|
{rows}

{summaries}

Over the whole blind test (five studies, three noise seeds each): {overall}. The "DEM runs"
column counts the runs a diagnosis executed itself; the studies share one run store
(`out/concealed/runs`), so the base design, the probes at a shared base fit and the
extended designs run once for all (cost of the whole test: `tests/concealed/README.md`).
"""


def write_readmes(results, args):
    hidden = {
        "cohesion": "one effect switched on that the base model leaves out (its name is the folder's)",
        "grain_cohesion": "one effect switched on that the base model leaves out (its name is the folder's)",
        "wall_friction": "one effect switched on that the base model leaves out (its name is the folder's)",
        "air_drag": "one effect switched on that the base model leaves out (its name is the folder's)",
        "size_spread": "one effect switched on that the base model leaves out (its name is the folder's)",
        "none": "nothing missing: the base model's own physics, noise added",
    }
    effects = [r for r in results if r["truth"] != "none"]
    nulls = [r for r in results if r["truth"] == "none"]
    overall = (f"the hidden effect named in {sum(r['verdict'] == 'right' for r in effects)} of {len(effects)} "
               f"cases, {sum(r['verdict'] == 'false alarm' for r in nulls)} false alarms in {len(nulls)} null cases")
    for t in truths():
        mine = [r for r in results if r["study"] == t["study"]]
        if not mine:
            continue
        rows = "\n".join(
            f"| {r['noise_seed']} | {r['outcome']} | {r['named']} | {r['verdict']} | {fmt(r['chi2_dof_before'])} | "
            f"{fmt(r['chi2_dof_after'])} | {fmt(r['bayes_factor'])} | {r['dem_runs_executed']} | {r['wall_time_s']} |"
            for r in mine)
        summaries = "\n\n".join(f"Noise seed {r['noise_seed']}: {r['summary']}" for r in mine)
        title = t.get("title", TITLES.get(t["study"], t["study"]))
        engine = "the engine"
        hidden_text = hidden[t["effect"]]
        if t.get("model_form_error", False):
            engine = "another engine (its `engine.*` lines in the truth file)"
            if t["effect"] == "none":
                hidden_text = "no effect switched on: the base model's physics as that engine has it"
        results_path = pathlib.Path(args.results).resolve()
        text = STUDY_README.format(title=title, hidden=hidden_text, study=t["study"], engine=engine,
                                   study_path=study_file(t["study"]).relative_to(ROOT),
                                   truth_set="" if args.truth_set == "original" else f" --truth-set {args.truth_set}",
                                   results=results_path.relative_to(ROOT) if results_path.is_relative_to(ROOT)
                                   else results_path.name,
                                   truth_file=t["file"].relative_to(ROOT),
                                   date=time.strftime("%Y-%m-%d"), rows=rows, summaries=summaries, overall=overall)
        (study_file(t["study"]).parent / "README.md").write_text(text)


def fmt(v, digits=3):
    if v is None or v == "":
        return "-"
    try:
        x = float(v)
    except ValueError:
        return str(v)
    if math.isnan(x):
        return "-"
    return f"{x:.{digits}g}"


def print_table(results):
    print("\n| study | noise seed | truth | outcome | named | verdict | chi2/dof before | after | DEM runs | wall s |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in results:
        print(f"| {r['study']} | {r['noise_seed']} | {r['truth']} | {r['outcome']} | {r['named']} | {r['verdict']} | "
              f"{fmt(r['chi2_dof_before'])} | {fmt(r['chi2_dof_after'])} | {r['dem_runs_executed']} | "
              f"{r['wall_time_s']} |")
    effects = [r for r in results if r["truth"] != "none"]
    nulls = [r for r in results if r["truth"] == "none"]
    right = sum(r["verdict"] == "right" for r in effects)
    alarms = sum(r["verdict"] == "false alarm" for r in nulls)
    print(f"\nidentification: {right}/{len(effects)} named right"
          f" ({100.0 * right / max(1, len(effects)):.0f} %); false alarms on the null study: {alarms}/{len(nulls)}")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("step", choices=["studies", "truth", "recordings", "diagnose", "table", "all", "check", "verify"])
    p.add_argument("--demcal", default=str(ROOT / "build" / "cli" / "demcal"))
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--seeds", default="1,2,3", help="noise seeds, comma-separated")
    p.add_argument("--out", type=pathlib.Path, default=OUT, help="run store and diagnoses")
    p.add_argument("--results", type=pathlib.Path, default=HERE / "results.csv")
    p.add_argument("--no-readmes", action="store_true", help="do not rewrite the study READMEs")
    p.add_argument("--min-identified", type=float, default=0.8)
    p.add_argument("--truth-set", choices=["original", "fresh", "stage3", "stage6", "lammps", "lammps-fresh", "lammps-stage3", "lammps-stage4"], default="original",
                   help="original: truth/ (the development set); fresh: truth-fresh/ (made after the method was "
                        "frozen); lammps: lammps/truth/ (recordings made in LAMMPS, the model demcal's); lammps-fresh: "
                        "lammps/truth-fresh/ (LAMMPS truths made after the cross-engine method was frozen); "
                        "lammps-stage3: lammps/truth-stage3/ (written after stage 3 was frozen); lammps-stage4: lammps/truth-stage4/ "
                        "(written after stage 4 was frozen); stage6: truth-stage6/ (written after stage 6 was frozen); stage3: truth-stage3/ "
                        "(same-engine truths written after stage 3 was frozen)")
    args = p.parse_args()
    args.seeds = [int(s) for s in args.seeds.split(",")]
    set_out(args.out)
    set_truth_set(args.truth_set)
    if args.step == "check":
        step_check(args)
        return
    if args.step == "verify":
        step_diagnose(args)
        step_check(args)
        return
    if args.step == "table":
        results = list(csv.DictReader(open(args.results)))
        print_table(results)
        write_readmes(results, args)
        return
    for step, fn in (("studies", step_studies), ("truth", step_truth), ("recordings", step_recordings),
                     ("diagnose", step_diagnose)):
        if args.step in (step, "all"):
            fn(args)


if __name__ == "__main__":
    main()
