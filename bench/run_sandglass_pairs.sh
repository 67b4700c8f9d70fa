#!/usr/bin/env bash
# The quick Sandglass (studies/sandglass-quick, 1 thread) timed for two demcal
# binaries side by side: issue 13's "unit of every design" figure.
#
#   bench/run_sandglass_pairs.sh OLD_DEMCAL NEW_DEMCAL SEED...
#
# For each seed the two binaries run at the same time, one per core (taskset),
# then again with the cores swapped: on a shared VM the two cores often differ
# in speed and the machine drifts from minute to minute, and a simultaneous,
# swapped couple cancels both. Prints, per run couple: seed, swap (0: OLD on
# core 0), the CPU seconds (user + system, /usr/bin/time) of OLD and NEW, NEW /
# OLD, then each binary's angle of repose, discharge time and step count (the
# same numbers to the last digit show the same run). The figure to quote is
# the median over seeds of each seed's geometric mean of its two ratios.
# Needs two idle cores; run nothing else meanwhile.
set -euo pipefail
if [[ $# -lt 3 ]]; then
  echo "usage: $0 OLD_DEMCAL NEW_DEMCAL SEED..." >&2
  exit 2
fi
old=$1
new=$2
shift 2
for b in "$old" "$new"; do
  [[ -x $b ]] || { echo "$0: $b: not an executable" >&2; exit 2; }
done
study="$(cd "$(dirname "$0")/.." && pwd)/studies/sandglass-quick/study.toml"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

run() {  # binary core tag seed
  taskset -c "$2" /usr/bin/time -f "%U %S" -o "$work/$3.time" \
    "$1" simulate "$study" --output "$work/$3" -q --set "study.seed=$4" > /dev/null
}
for seed in "$@"; do
  for swap in 0 1; do
    rm -rf "$work/old" "$work/new"
    run "$old" "$swap" old "$seed" &
    run "$new" $((1 - swap)) new "$seed" &
    wait
    python3 - "$work" "$seed" "$swap" <<'PY'
import json, sys
work, seed, swap = sys.argv[1:4]
row = [seed, swap]
cpu, obs = {}, []
for tag in ("old", "new"):
    cpu[tag] = sum(float(x) for x in open(f"{work}/{tag}.time").read().split()[-2:])
    run = json.load(open(f"{work}/{tag}/run.json"))
    o = run["observables"]
    obs.append(f'{o.get("angle_of_repose_deg")} {o.get("discharge_time_s")} {run["results"]["steps"]}')
print(seed, swap, f'{cpu["old"]:.2f}', f'{cpu["new"]:.2f}', f'{cpu["new"] / cpu["old"]:.3f}',
      "|", obs[0], "|", obs[1], flush=True)
PY
  done
done
