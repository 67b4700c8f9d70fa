#!/bin/bash
# Hopper cross-check, demcal side: hopper.toml at the three friction pairs of the
# peers' README and several fill seeds; each m(t) is written in the format of the
# peers' tools/discharge.py and analysed by it (the same t90 rule as LAMMPS's
# figures in README.md), and by demcal's own analysis (run.json).
# usage: run_hopper_crosscheck.sh PEERS_DIR OUTDIR
#   env: DEMCAL (build/cli/demcal), SEEDS ("8812 2 3"), PAIRS ("0.3:0.05 0.5:0.1 0.5:0.3"), JOBS (1)
# Finished runs are kept and skipped, so the script resumes.
set -eu
here=$(dirname "$(readlink -f "$0")")
root=$(readlink -f "$here/../..")
PEERS=$(readlink -f "${1:?usage: run_hopper_crosscheck.sh PEERS_DIR OUTDIR}")
OUT=${2:?usage: run_hopper_crosscheck.sh PEERS_DIR OUTDIR}; mkdir -p "$OUT"; OUT=$(readlink -f "$OUT")
DEMCAL=${DEMCAL:-$root/build/cli/demcal}
SEEDS=${SEEDS:-"8812 2 3"}; PAIRS=${PAIRS:-"0.3:0.05 0.5:0.1 0.5:0.3"}; JOBS=${JOBS:-1}
run_one() {
  mus=$1 mur=$2 s=$3
  b=$OUT/demcal_mus${mus}_mur${mur}_s$s
  if [ ! -f "$b/run.json" ]; then
    "$DEMCAL" simulate "$here/hopper.toml" --quiet --threads 1 --output "$b.part" --overwrite \
      --set mu_s=$mus --set mu_r=$mur --set study.seed=$s > "$b.log" 2>&1 \
      || { echo "failed: $b (see $b.log)" >&2; return 1; }
    rm -rf "$b" && mv "$b.part" "$b"
  fi
  /usr/bin/python3 - "$b/run.json" > "$b.txt" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
s = r["series"]["discharged_mass"]
n0 = r["details"]["particles"]; mp = r["details"]["fill_mass_kg"] / n0
print(f"# hopper discharge (demcal): N0={n0} m_p={mp:.10g} kg")
print("# t_since_opening[s] discharged_mass[kg]")
for t, m in zip(s["time_s"], s["mass_kg"]):
    print(f"{t:.6f} {m:.10g}")
PY
  /usr/bin/python3 "$PEERS/tools/discharge.py" "$b.txt" > "$b.discharge"
  echo "done mus=$mus mur=$mur seed=$s" >&2
}
export -f run_one; export OUT DEMCAL here PEERS
for p in $PAIRS; do for s in $SEEDS; do echo "${p%:*} ${p#*:} $s"; done; done |
  xargs -P "$JOBS" -L 1 bash -c 'run_one $0 $1 $2'
/usr/bin/python3 "$here/hopper_table.py" "$OUT" "$PAIRS" "$SEEDS"
