#!/bin/bash
# demcal and LAMMPS on a shared machine: the static pile case with ONE other
# CPU-bound process running all the time (a shell busy loop, `while :; do :; done`,
# started by this script and killed at its end), as on a laptop or a shared node.
#
# usage: bench/run_contended.sh [PEERS_DIR]          (default: ../shared/peers next to the repo)
#
# Per repetition, interleaved: demcal 1 thread, demcal 2 threads, LAMMPS 2 ranks, and, when
# DEMCAL_BENCH_BEFORE is set (a benchmark binary of an older build), that binary at 1 and at
# 2 threads (in each of ORDERS), so a before/after comparison is measured under the same load.
# The log line of a build that has worker parking (dem/worker_parking.hpp) ends with where its
# rule settled at the end of the static phase (parked 0|1) and how often it switched.
# Environment (defaults): R=3  N=3000  STATIC_STEPS=10000  RUN_TIMEOUT=600 (s)
#   DEMCAL_BENCH=<repo>/build-bench/bench/demcal_bench_pile  DEMCAL_BENCH_BEFORE=(unset)
#   ORDERS="insertion"   particle orders of demcal (--particle-order) to run, each at 1 and 2
#                        threads within every repetition, e.g. ORDERS="insertion spatial"
#   LAMMPS=1             0 leaves LAMMPS out (demcal against itself only; lmp not needed)
# Each line of the log (bench/logs/<date>_contended_<machine>.log) holds the engine, the
# threads or ranks, the particle order, PS/s/core of the static phase, the wall time and the
# user and system CPU seconds of the whole run (/usr/bin/time) and the load average; a run that exceeds RUN_TIMEOUT is logged as TIMEOUT.
set -euo pipefail

REPO=$(cd "$(dirname "$0")/.." && pwd)
SRC_PEERS=${1:-$REPO/../shared/peers}
R=${R:-3}
N=${N:-3000}
STATIC_STEPS=${STATIC_STEPS:-10000}
RUN_TIMEOUT=${RUN_TIMEOUT:-600}
BIN=${DEMCAL_BENCH:-$REPO/build-bench/bench/demcal_bench_pile}
BEFORE=${DEMCAL_BENCH_BEFORE:-}
ORDERS=${ORDERS:-insertion}
LAMMPS=${LAMMPS:-1}
[ -x "$BIN" ] || { echo "no demcal benchmark at $BIN" >&2; exit 1; }
[ "$LAMMPS" = 0 ] || command -v lmp >/dev/null || { echo "lmp (LAMMPS) not found" >&2; exit 1; }

PEERS=$(mktemp -d /tmp/demcal_peers.XXXXXX)
cp -r "$SRC_PEERS"/. "$PEERS"/
rm -rf "$PEERS/lammps/runs"; mkdir -p "$PEERS/lammps/runs"
MODEL=$(lscpu | sed -n 's/^Model name: *//p' | head -1)
MACHINE=$(echo "$MODEL" | tr 'A-Z' 'a-z' | sed 's/([^)]*)//g; s/[^a-z0-9]\+/-/g; s/^-//; s/-$//')-$(nproc)c
mkdir -p "$REPO/bench/logs"
LOG="$REPO/bench/logs/$(date +%F)_contended_${MACHINE}.log"
VERSION=$("$BIN" --version 2>/dev/null | tail -1 || echo unknown)

echo "# $(date -Is) demcal $VERSION N $N static_steps $STATIC_STEPS; busy loop: one shell 'while :; do :; done'" | tee -a "$LOG"

# LAMMPS's own settled pile, made once before the busy loop starts.
if [ "$LAMMPS" != 0 ]; then
  (cd "$PEERS/lammps" && ./run_pile.sh 0.5 0.1 1 "$N" > /dev/null 2>&1)
  DUMP=$(ls "$PEERS"/lammps/runs/pile_N${N}_*np1*.txt | head -1)
fi

bash -c 'while :; do :; done' &
BUSY_PID=$!
trap 'kill $BUSY_PID 2>/dev/null || true' EXIT

run_demcal() {  # label binary threads [order]
  local out; out=$(mktemp)
  local cpu; cpu=$(mktemp)
  local order=${4:-insertion}
  local args=(--particles "$N" --threads "$3" --mode static --static-steps "$STATIC_STEPS")
  [ "$order" = insertion ] || args+=(--particle-order "$order")
  local t0; t0=$(date +%s.%N)
  if timeout "$RUN_TIMEOUT" /usr/bin/time -f "%U %S" -o "$cpu" "$2" "${args[@]}" > "$out" 2>&1; then
    local wall; wall=$(echo "$(date +%s.%N) - $t0" | bc)
    awk -v l="$1" -v w="$wall" -v o="$order" -v cpu="$(tail -1 "$cpu")" -v la="$(cut -d' ' -f1 /proc/loadavg)" '/mode pour/ {for (i = 1; i <= NF; i++) if ($i == "PS/s/core") p = $(i + 1)}
      /mode static/ {for (i = 1; i <= NF; i++) {if ($i == "PS/s/core") s = $(i + 1); if ($i == "parked") pk = " parked " $(i + 1); if ($i == "switches") sw = " switches " $(i + 1)}; t = $6}
      END {split(cpu, c, " "); printf "%s threads %s order %s pour_PS/s/core %s static_PS/s/core %s wall_s %.1f user_s %s sys_s %s loadavg %s%s%s\n", l, t, o, p, s, w, c[1], c[2], la, pk, sw}' "$out" | tee -a "$LOG"
  else
    echo "$1 threads $3 order $order TIMEOUT after $RUN_TIMEOUT s loadavg $(cut -d' ' -f1 /proc/loadavg)" | tee -a "$LOG"
  fi
  rm -f "$out" "$cpu"
}

run_lammps() {  # ranks
  local out
  out=$(cd "$PEERS/lammps" && timeout "$RUN_TIMEOUT" ./run_bench.sh "runs/$(basename "$DUMP")" "$1" "$STATIC_STEPS" 2>&1 | grep '^BENCH' || echo TIMEOUT)
  echo "lammps ranks $1 $out loadavg $(cut -d' ' -f1 /proc/loadavg)" | tee -a "$LOG"
}

for rep in $(seq 1 "$R"); do
  echo "# rep $rep $(date -Is)" | tee -a "$LOG"
  for order in $ORDERS; do
    run_demcal demcal "$BIN" 1 "$order"
    run_demcal demcal "$BIN" 2 "$order"
  done
  [ "$LAMMPS" = 0 ] || run_lammps 2
  if [ -n "$BEFORE" ]; then
    for order in $ORDERS; do
      run_demcal demcal-before "$BEFORE" 1 "$order"
      run_demcal demcal-before "$BEFORE" 2 "$order"
    done
  fi
done
