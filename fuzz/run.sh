#!/usr/bin/env bash
# Runs each libFuzzer harness of fuzz/ for a stated time, at the lowest CPU
# priority, seeded from the repository's own files; see fuzz/README.md.
#
#   fuzz/run.sh [--seconds N] [--jobs J] [--build DIR] [--work DIR] [harness ...]
#
# harness: study_toml recordings_csv doe_csv run_record raw_recordings (default: all five).
# N seconds each (default 1800), J harnesses at a time (default 2). Builds the
# harnesses in DIR (default build-fuzz, clang++ with -DDEMCAL_FUZZ=ON) when
# they are missing. Each harness keeps its corpus in WORK/<harness>/corpus
# (default WORK = fuzz-work, ignored by git) and its log in WORK/<harness>.log;
# a crash, leak, timeout or sanitizer report leaves a file WORK/<harness>/crash-*
# (or leak-*, timeout-*, oom-*) and makes the script exit 1. The last lines of
# the summary give each harness' execs, cov and ft.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=1800
jobs=2
build=build-fuzz
work=fuzz-work
harnesses=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) seconds=$2; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    --build) build=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    -h|--help) sed -n '2,16p' "$0"; exit 0 ;;
    *) harnesses+=("$1"); shift ;;
  esac
done
[ ${#harnesses[@]} -gt 0 ] || harnesses=(study_toml recordings_csv doe_csv run_record raw_recordings)

missing=0
for h in "${harnesses[@]}"; do [ -x "$build/fuzz/fuzz_$h" ] || missing=1; done
if [ $missing = 1 ]; then
  cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
    -DDEMCAL_FUZZ=ON -DDEMCAL_BUILD_TESTS=OFF -DDEMCAL_MPI=OFF > /dev/null
  nice -n 10 cmake --build "$build" --target $(printf 'fuzz_%s ' "${harnesses[@]}")
fi

seed() {  # harness -> copies the repository's files of that kind into its corpus
  local h=$1 dir=$2 f i=0
  mkdir -p "$dir"
  case $h in
    study_toml) files=$(ls studies/*/study.toml tests/data/*/*.toml tests/concealed/*.toml.in 2>/dev/null || true) ;;
    recordings_csv) files=$(ls studies/*/recordings*.csv tests/bad_input/base/recordings.csv 2>/dev/null || true) ;;
    doe_csv) files=$(ls studies/*/doe.csv studies/*/truth_runs.csv tests/concealed/truth/runs.csv 2>/dev/null || true) ;;
    run_record) files=$(ls fuzz/seeds/run_record*.json) ;;
    raw_recordings) files=$(ls fuzz/seeds/raw_*.csv) ;;
  esac
  for f in $files; do
    # Large tables are cut to their first 40 lines (the reader is line by line);
    # TOML files are taken whole.
    case $h in
      study_toml) cp "$f" "$dir/seed-$i-$(basename "$f")" ;;
      *) head -n 40 "$f" > "$dir/seed-$i-$(basename "$f")" ;;
    esac
    i=$((i + 1))
  done
}

run_one() {
  local h=$1 dir="$work/$h"
  mkdir -p "$dir"
  seed "$h" "$dir/corpus"
  # -timeout: a single input taking 10 s is a hang; -rss_limit_mb: a runaway allocation.
  ( cd "$dir" && nice -n 19 "$build/fuzz/fuzz_$h" corpus -max_total_time="$seconds" \
      -timeout=10 -rss_limit_mb=2048 -max_len=16384 -print_final_stats=1 > "$work/$h.log" 2>&1 ) || true
}

mkdir -p "$work"
work=$(cd "$work" && pwd)
build=$(cd "$build" && pwd)
running=0
for h in "${harnesses[@]}"; do
  run_one "$h" &
  running=$((running + 1))
  if [ $running -ge "$jobs" ]; then wait -n || true; running=$((running - 1)); fi
done
wait || true

status=0
echo "harness         seconds  execs      cov    ft     findings"
for h in "${harnesses[@]}"; do
  log="$work/$h.log"
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo '?')
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*' || echo '?')
  ft=$(grep -o 'ft: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*' || echo '?')
  findings=$(ls "$work/$h" | grep -cE '^(crash|leak|timeout|oom|slow-unit)-' || true)
  if grep -qE 'ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer)|runtime error:' "$log"; then findings=$((findings + 1)); fi
  [ "$findings" = 0 ] || status=1
  printf '%-15s %-8s %-10s %-6s %-6s %s\n' "$h" "$seconds" "$execs" "$cov" "$ft" "$findings"
done
exit $status
