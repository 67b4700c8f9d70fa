#!/usr/bin/python3
"""Table of the pile cross-check.

Reads OUTDIR/<engine>_mus<MUS>_mur<MUR>_s<SEED>.aor (the last line of the peers' tools/aor.py
for that pile) and prints, per friction pair, mean ± sd over the seeds for each engine and
the difference demcal − reference, with whether it is within 1.5°.
Engines: demcal, lammps (pile.in as given) and, when present, lammpsld (pile.in with
-var ld 1 -var etsuji 0.43: limit_damping, measured e = 0.60 still).
usage: table.py OUTDIR "0.3:0.05 0.5:0.1 0.5:0.3" "1 2 3"
"""
import os
import statistics as st
import sys

out, pairs, seeds = sys.argv[1], sys.argv[2].split(), sys.argv[3].split()
TOL = 1.5
NAMES = {"demcal": "demcal", "lammps": "LAMMPS", "lammpsld": "LAMMPS limit_damping"}


def aor(path):
    try:
        w = open(path).read().split()
        return float(w[w.index("mean") + 1])
    except (OSError, ValueError, IndexError):
        return None


def load(eng, mus, mur):
    return [aor(os.path.join(out, f"{eng}_mus{mus}_mur{mur}_s{s}.aor")) for s in seeds]


def fmt(v):
    v = [x for x in v if x is not None]
    if not v:
        return "n/a", None
    m = st.mean(v)
    sd = f"{st.stdev(v):.2f}" if len(v) > 1 else "—"
    return f"{m:.2f} ± {sd}" + (f" (n={len(v)})" if len(v) != len(seeds) else ""), m


refs = [e for e in ("lammps", "lammpsld")
        if any(os.path.exists(os.path.join(out, f"{e}_mus{p.split(':')[0]}_mur{p.split(':')[1]}_s{s}.aor"))
               for p in pairs for s in seeds)]
head = "| mu_s, mu_r | demcal AoR° | " + " | ".join(
    f"{NAMES[r]} AoR° | demcal − {NAMES[r]} | within {TOL}°?" for r in refs) + " |"
print(f"AoR, mean of both sides, mean ± sd over seeds {' '.join(seeds)} (tools/aor.py on every final pile)")
print(head)
print("|" + "---|" * (2 + 3 * len(refs)))
per = []
for p in pairs:
    mus, mur = p.split(":")
    dv = load("demcal", mus, mur)
    ds, dm = fmt(dv)
    row = f"| {mus}, {mur} | {ds} |"
    line = f"{mus}, {mur}: demcal " + " ".join("—" if x is None else f"{x:.2f}" for x in dv)
    for r in refs:
        rv = load(r, mus, mur)
        rs, rm = fmt(rv)
        if dm is None or rm is None:
            row += f" {rs} | n/a | n/a |"
        else:
            diff = dm - rm
            row += f" {rs} | {diff:+.2f} | {'yes' if abs(diff) <= TOL else '**no**'} |"
        line += f"; {NAMES[r]} " + " ".join("—" if x is None else f"{x:.2f}" for x in rv)
    print(row)
    per.append(line)
print()
print("per seed (" + " ".join(seeds) + "):")
for line in per:
    print("  " + line)
