#!/usr/bin/python3
"""Helpers of run_side_by_side.sh (Debian's python3; numpy not needed).

  summarize.py lammps-pour LOG TIMEFILE NP
      BENCH line for a LAMMPS pile.in run. Particle-steps are integrated like
      peers/tools/lmp_perf.py (trapezoid over the thermo rows) plus the last
      stretch from the last thermo row to the step where fix halt stopped the run
      at full N (lmp_perf.py leaves it out: ~1 % of a run).
  summarize.py lammps-static LOG TIMEFILE NP
      BENCH line for a bench_static.in run (the last 'Loop time', the timed run).
  summarize.py time TIMEFILE
      'TIME wall_s W cpu_percent P maxRSS_MiB M' from /usr/bin/time -v output.
  summarize.py table LOG...
      medians over the repetitions in each log and the demcal/LAMMPS ratios.
"""
import os
import re
import statistics
import sys
from collections import defaultdict


# A run was disturbed when other processes used more than the cores it left free + QUIET.
QUIET = 0.5


def parse_time(path):
    wall = rss = cpu = None
    with open(path) as f:
        for ln in f:
            if "Elapsed (wall clock)" in ln:
                t = ln.split("):")[-1].strip().split(":")
                wall = sum(float(x) * 60 ** i for i, x in enumerate(reversed(t)))
            elif "Maximum resident set size" in ln:
                rss = int(ln.split(":")[-1]) / 1024.0
            elif "Percent of CPU" in ln:
                cpu = ln.split(":")[-1].strip().rstrip("%")
    return wall, cpu, rss


def lammps_pour(log, timefile, np_):
    ps = 0.0
    steps = 0
    loop = 0.0
    hdr = prev = None
    halt_step = None
    natoms = None
    with open(log) as f:
        for ln in f:
            if ln.startswith("Step "):
                hdr, prev = ln.split(), None
                continue
            m = re.match(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", ln)
            if m:
                loop += float(m.group(1))
                natoms = int(m.group(4))
                hdr = None
                continue
            m = re.match(r"PILE_DONE steps (\d+)", ln)
            if m:
                halt_step = int(m.group(1))
            if hdr is None:
                continue
            parts = ln.split()
            if len(parts) != len(hdr):
                continue
            try:
                row = dict(zip(hdr, map(float, parts)))
            except ValueError:
                continue
            s, n = row["Step"], row["Atoms"]
            if prev is not None:
                ps += 0.5 * (n + prev[1]) * (s - prev[0])
            prev = (s, n)
    if halt_step is not None and prev is not None and halt_step > prev[0]:
        ps += natoms * (halt_step - prev[0])
    steps = halt_step if halt_step is not None else int(prev[0])
    _, _, rss = parse_time(timefile)
    rate = ps / loop
    print(f"BENCH lammps mode pour threads {np_} N {natoms} steps {steps} particle_steps {ps:.6e} "
          f"loop_s {loop:.3f} PS/s {rate:.4e} PS/s/core {rate / int(np_):.4e} maxRSS_MiB {rss:.1f}")


def lammps_static(log, timefile, np_):
    loop = None
    with open(log) as f:
        for ln in f:
            m = re.match(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", ln)
            if m:  # the last run is the timed one (the first is bench_static.in's 500-step warm-up)
                loop, steps, natoms = float(m.group(1)), int(m.group(3)), int(m.group(4))
    _, _, rss = parse_time(timefile)
    ps = float(steps) * natoms
    rate = ps / loop
    print(f"BENCH lammps mode static threads {np_} N {natoms} steps {steps} particle_steps {ps:.6e} "
          f"loop_s {loop:.3f} PS/s {rate:.4e} PS/s/core {rate / int(np_):.4e} maxRSS_MiB {rss:.1f}")


def fields(line):
    t = line.split()
    return {t[i]: t[i + 1] for i in range(0, len(t) - 1)}


def table(logs):
    # key: (case, engine, threads) -> list of dicts
    runs = defaultdict(list)
    free = {}
    for path in logs:
        m = re.match(r"(\d{4}-\d{2}-\d{2})_([a-z]+\d+)_([a-z]+)_(\d+)t_.*-(\d+)c\.log$", os.path.basename(path))
        if not m:
            continue
        key = (m.group(2), m.group(3), int(m.group(4)))
        free[key] = int(m.group(5)) - int(m.group(4))
        cur = None
        with open(path) as f:
            for ln in f:
                if ln.startswith("BENCH"):
                    b = fields(ln)
                    cur = dict(rate=float(b["PS/s/core"]), rss=float(b["maxRSS_MiB"]),
                               steps=int(b["steps"]), ps=float(b["particle_steps"]),
                               loop=float(b["loop_s"]))
                    runs[key].append(cur)
                elif ln.startswith("AOR") and cur is not None:
                    cur["aor"] = float(ln.split("mean")[1].split()[0])
                elif ln.startswith("TIME") and cur is not None:
                    t = fields(ln)
                    cur["cpu"] = t.get("cpu_percent")
                    if "others_cores" in t:
                        cur["others"] = float(t["others_cores"])
                    if t.get("maxRSS_MiB") not in (None, "None"):
                        cur["rss_time"] = float(t["maxRSS_MiB"])
    if not runs:
        print("no logs")
        return
    med = lambda xs: statistics.median(xs) if xs else float("nan")
    quiet = lambda key: [r for r in runs[key] if r.get("others", 0.0) < free[key] + QUIET]
    print(f"{'case':<11} {'engine':<7} {'thr':>3} {'n':>2} {'median PS/s/core':>16} {'quiet n':>7} {'quiet median':>12} {'min':>9} {'max':>9} "
          f"{'steps':>7} {'PS':>9} {'maxRSS MiB':>10} {'AoR deg':>8} {'others':>6}")
    summary = {}
    qsummary = {}
    for key in sorted(runs):
        rs = runs[key]
        rates = [r["rate"] for r in rs]
        rss = [r.get("rss_time", r["rss"]) for r in rs]
        aors = [r["aor"] for r in rs if "aor" in r]
        summary[key] = med(rates)
        qr = [r["rate"] for r in quiet(key)]
        qsummary[key] = med(qr)
        print(f"{key[0]:<11} {key[1]:<7} {key[2]:>3} {len(rs):>2} {med(rates):>16.3e} {len(qr):>7} {med(qr):>12.3e} "
              f"{min(rates):>9.2e} "
              f"{max(rates):>9.2e} {int(med([r['steps'] for r in rs])):>7} {med([r['ps'] for r in rs]):>9.3e} "
              f"{med(rss):>10.1f} {med(aors):>8.2f} {med([r['others'] for r in rs if 'others' in r]):>6.2f}")
    print(f"(others: cores used by other processes during the run, median; quiet: runs with others < free cores + {QUIET}; "
          "steps, PS: median run length)")
    print()
    # The script runs each repetition's demcal and LAMMPS runs back to back, so the k-th
    # run of each log form the k-th interleaved pair; the figure BENCHMARKS.md quotes is
    # the median of those pairs' ratios (it differs from the ratio of the medians when
    # the machine drifts between repetitions).
    print(f"{'case':<11} {'thr':>3} {'demcal/LAMMPS (PS/s/core, medians)':>36} {'quiet runs only':>16} "
          f"{'median of pair ratios':>22} {'pairs':>5}")
    for (case, eng, thr), v in sorted(summary.items()):
        if eng != "demcal":
            continue
        peer = summary.get((case, "lammps", thr))
        if peer:
            qp = qsummary.get((case, "lammps", thr))
            pairs = [d["rate"] / l["rate"] for d, l in zip(runs[(case, eng, thr)], runs[(case, "lammps", thr)])]
            print(f"{case:<11} {thr:>3} {v / peer:>36.3f} {qsummary[(case, eng, thr)] / qp:>16.3f} "
                  f"{med(pairs):>22.3f} {len(pairs):>5}")


if __name__ == "__main__":
    cmd = sys.argv[1]
    if cmd == "lammps-pour":
        lammps_pour(*sys.argv[2:5])
    elif cmd == "lammps-static":
        lammps_static(*sys.argv[2:5])
    elif cmd == "time":
        w, c, r = parse_time(sys.argv[2])
        print(f"TIME wall_s {w} cpu_percent {c} maxRSS_MiB {r}")
    elif cmd == "table":
        table(sys.argv[2:])
    else:
        sys.exit(__doc__)
