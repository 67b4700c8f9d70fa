#!/bin/bash
# Makes the quick study's synthetic recordings with the engine: the quick
# Sandglass, its hopper lined (the walls' sliding friction is mu_s too, as the
# design's also_sets makes it) above the bare floor study.toml gives its own
# friction, at (mu_r, mu_s) = (0.25, 0.45) -- not a design point -- run with
# five seeds the design does not use, as a laboratory repeats a test five
# times. The recorded value is the mean of the five plus a Gaussian instrument
# error (AoR 0.5 deg, time 0.01 s) drawn with NOISE_SEED; sigma is that
# instrument uncertainty and `repeats` is 5: demcal adds the test-to-test
# scatter itself (the DEM's replicate scatter / sqrt(repeats)), so it is not
# put into sigma as well.
# usage: [SEEDS="101 102 103 104 105"] [NOISE_SEED=1] [JOBS=<cores>] make_recordings.sh [DEMCAL] > studies/quick/recordings.csv
set -eu
here=$(dirname "$(readlink -f "$0")")
DEMCAL=${1:-$here/../../build/cli/demcal}
SEEDS=${SEEDS:-"101 102 103 104 105"}
NOISE_SEED=${NOISE_SEED:-1}
tmp=$(mktemp -d)
# The repeats are independent runs: JOBS of them at once (default: one per core).
printf '%s\n' $SEEDS | xargs -P "${JOBS:-$(nproc)}" -I{} \
  "$DEMCAL" simulate "$here/study.toml" --quiet --threads 1 --set mu_r=0.25 --set mu_s=0.45 \
    --set interaction.particle_wall.sliding_friction=0.45 --set study.seed={} \
    --output "$tmp/s{}" > /dev/null
python3 - "$tmp" "$NOISE_SEED" <<'PY'
import json, pathlib, random, sys
runs = [json.load(open(p)) for p in sorted(pathlib.Path(sys.argv[1]).glob("s*/run.json"))]
rng = random.Random(int(sys.argv[2]))
print("setup,observable,value,sigma,unit,repeats")
for name, unit, instrument in (("angle_of_repose_deg", "deg", 0.5), ("discharge_time_s", "s", 0.01)):
    v = [r["observables"][name] for r in runs]
    m = sum(v) / len(v) + rng.gauss(0.0, instrument)
    print(f"sandglass,{name},{m:.4f},{instrument},{unit},{len(v)}")
PY
rm -rf "$tmp"
