#!/bin/bash
# The container-thickness sweep: AoR versus t/d with walls and with periodic
# boundaries, several seeds per point, JOBS runs at a time (one thread each).
# usage: run_thickness_sweep.sh OUTDIR
#   env: DEMCAL (build/cli/demcal), SEEDS ("1 2 3"), WALLS ("2 4 8 16 24 32 48"),
#        PERIODIC ("4 8 16 32 48"), JOBS (2)
# Finished runs (run.json present) are kept and skipped, so the sweep resumes.
set -eu
here=$(dirname "$(readlink -f "$0")")
root=$(readlink -f "$here/../..")
OUT=${1:?usage: run_thickness_sweep.sh OUTDIR}
DEMCAL=${DEMCAL:-$root/build/cli/demcal}
SEEDS=${SEEDS:-"1 2 3"}; WALLS=${WALLS:-"2 4 8 16 24 32 48"}; PERIODIC=${PERIODIC:-"4 8 16 32 48"}
JOBS=${JOBS:-2}
mkdir -p "$OUT"
jobs() {  # thickest first, so the two lanes finish together
  for b in walls periodic; do
    list=$WALLS; [ $b = periodic ] && list=$PERIODIC
    for t in $list; do for s in $SEEDS; do echo "$t $b $s"; done; done
  done | sort -k1,1nr
}
run_one() {
  t=$1 b=$2 s=$3
  dir=$OUT/${b}_t${t}_s$s
  [ -f "$dir/run.json" ] && return 0
  mass=$(python3 -c "print(0.01375*$t)")
  "$DEMCAL" simulate "$here/study.toml" --quiet --threads 1 --output "$dir.part" --overwrite \
    --set apparatus.rectangular_container.thickness_diameters=$t \
    --set apparatus.rectangular_container.boundary=$b \
    --set apparatus.rectangular_container.fill_mass_kg=$mass \
    --set study.seed=$s > "$dir.log" 2>&1 || { echo "failed: $dir (see $dir.log)" >&2; return 1; }
  rm -rf "$dir" && mv "$dir.part" "$dir"
  echo "done $b t=$t seed=$s" >&2
}
export -f run_one; export OUT DEMCAL here
jobs | xargs -P "$JOBS" -L 1 bash -c 'run_one $0 $1 $2'
python3 "$here/table.py" "$OUT"
