#!/bin/bash
# The Beverloo sweep: the steady mass flow rate of the full sandglass at several
# orifice diameters (in mean particle diameters), then the fit of C and k.
# usage: run_beverloo_sweep.sh OUTDIR
#   env: DEMCAL (build/cli/demcal), ORIFICES_D ("5 6.5 7.72 10"), SEEDS ("1"), JOBS (1)
# Finished runs (run.json present) are kept and skipped, so the sweep resumes.
set -eu
here=$(dirname "$(readlink -f "$0")")
root=$(readlink -f "$here/../..")
OUT=${1:?usage: run_beverloo_sweep.sh OUTDIR}
DEMCAL=${DEMCAL:-$root/build/cli/demcal}
ORIFICES_D=${ORIFICES_D:-"5 6.5 7.72 10"}; SEEDS=${SEEDS:-"1"}; JOBS=${JOBS:-1}
D_MEAN=0.0027965092553584726   # the run's particle_diameter_m: 6 x the mean of U(300, 600) um, as the engine computes it
mkdir -p "$OUT"
run_one() {
  n=$1 s=$2
  dir=$OUT/orifice_${n}d_s$s
  [ -f "$dir/run.json" ] && return 0
  d0=$(python3 -c "print($n*$D_MEAN)")
  "$DEMCAL" simulate "$here/study.toml" --quiet --threads 1 --output "$dir.part" --overwrite \
    --set apparatus.sandglass.orifice_diameter_m=$d0 --set study.seed=$s > "$dir.log" 2>&1 \
    || { echo "failed: $dir (see $dir.log)" >&2; return 1; }
  rm -rf "$dir" && mv "$dir.part" "$dir"
  echo "done orifice ${n} d seed $s" >&2
}
export -f run_one; export OUT DEMCAL here D_MEAN
for n in $ORIFICES_D; do for s in $SEEDS; do echo "$n $s"; done; done |
  xargs -P "$JOBS" -L 1 bash -c 'run_one $0 $1'
python3 "$here/beverloo_table.py" "$OUT"
