#!/bin/bash
# Makes the quick study's synthetic recordings with the engine: the quick
# Sandglass at (mu_r, mu_s) = (0.25, 0.45) -- not a design point -- with three
# seeds the design does not use (101, 102, 103); the recorded value is their
# mean, and sigma the standard error of that mean combined with a stated
# instrument uncertainty (AoR 0.5 deg, time 0.01 s), as a laboratory would
# report a mean of three repeats.
# usage: make_recordings.sh [DEMCAL] > studies/quick/recordings.csv
set -eu
here=$(dirname "$(readlink -f "$0")")
DEMCAL=${1:-$here/../../build/cli/demcal}
tmp=$(mktemp -d)
for s in 101 102 103; do
  "$DEMCAL" simulate "$here/study.toml" --quiet --set mu_r=0.25 --set mu_s=0.45 --set study.seed=$s \
    --output "$tmp/s$s" > /dev/null
done
python3 - "$tmp" <<'PY'
import json, math, pathlib, sys
runs = [json.load(open(p)) for p in sorted(pathlib.Path(sys.argv[1]).glob("s*/run.json"))]
print("setup,observable,value,sigma,unit")
for name, unit, instrument in (("angle_of_repose_deg", "deg", 0.5), ("discharge_time_s", "s", 0.01)):
    v = [r["observables"][name] for r in runs]
    m = sum(v) / len(v)
    se = math.sqrt(sum((x - m) ** 2 for x in v) / (len(v) - 1) / len(v))
    print(f"sandglass,{name},{m:.4f},{math.sqrt(se * se + instrument * instrument):.4f},{unit}")
PY
rm -rf "$tmp"
