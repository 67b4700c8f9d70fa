#!/bin/bash
# Insertion against spatial particle order (dem/particle_order.hpp) on the pile
# case, interleaved: per repetition, demcal_bench_pile at each thread count in
# THREADS, first with --particle-order insertion, then spatial, each under
# /usr/bin/time (user and system CPU seconds) and with the load average at its end.
#
# usage: bench/run_order_pairs.sh [BENCH_BINARY]
#   (default <repo>/build/bench/demcal_bench_pile)
# Environment (defaults): R=3  N=3000  MODE=static  STATIC_STEPS=10000  THREADS="1"
#   BUSY=0     1 runs one shell busy loop (`while :; do :; done`) beside every run, as
#              bench/run_contended.sh does; it is killed at the end.
#   TAG=order  the log is bench/logs/<date>_<TAG>_<machine>.log
set -euo pipefail
REPO=$(cd "$(dirname "$0")/.." && pwd)
BIN=${1:-$REPO/build/bench/demcal_bench_pile}
R=${R:-3}
N=${N:-3000}
MODE=${MODE:-static}
STATIC_STEPS=${STATIC_STEPS:-10000}
THREADS=${THREADS:-1}
BUSY=${BUSY:-0}
TAG=${TAG:-order}
[ -x "$BIN" ] || { echo "no demcal benchmark at $BIN" >&2; exit 1; }
MODEL=$(lscpu | sed -n 's/^Model name: *//p' | head -1)
MACHINE=$(echo "$MODEL" | tr 'A-Z' 'a-z' | sed 's/([^)]*)//g; s/[^a-z0-9]\+/-/g; s/^-//; s/-$//')-$(nproc)c
mkdir -p "$REPO/bench/logs"
LOG="$REPO/bench/logs/$(date +%F)_${TAG}_${MACHINE}.log"
echo "# $(date -Is) $("$BIN" --version | tail -1) N $N mode $MODE static_steps $STATIC_STEPS threads '$THREADS' busy $BUSY" | tee -a "$LOG"
if [ "$BUSY" = 1 ]; then
  bash -c 'while :; do :; done' &
  BUSY_PID=$!
  trap 'kill $BUSY_PID 2>/dev/null || true' EXIT
fi
for rep in $(seq 1 "$R"); do
  echo "# rep $rep $(date -Is)" | tee -a "$LOG"
  for t in $THREADS; do
    for order in insertion spatial; do
      out=$(mktemp); cpu=$(mktemp)
      t0=$(date +%s.%N)
      /usr/bin/time -f "%U %S" -o "$cpu" "$BIN" -N "$N" -t "$t" --mode "$MODE" \
        --static-steps "$STATIC_STEPS" --particle-order "$order" > "$out" 2>&1 || true
      wall=$(echo "$(date +%s.%N) - $t0" | bc)
      awk -v warm=500 -v o="$order" -v t="$t" -v w="$wall" -v cpu="$(tail -1 "$cpu")" -v la="$(cut -d' ' -f1-3 /proc/loadavg)" '
        /mode pour/ {for (i = 1; i <= NF; i++) { if ($i == "PS/s/core") p = $(i + 1); if ($i == "particle_steps") ps += $(i + 1); if ($i == "N") n = $(i + 1) }}
        /mode static/ {for (i = 1; i <= NF; i++) { if ($i == "PS/s/core") s = $(i + 1); if ($i == "particle_steps") ps += $(i + 1) }}
        /^AOR/ {a = $9}
        END {split(cpu, c, " "); if (s != "") ps += n * warm;
             printf "order %s threads %s pour_PS/s/core %s static_PS/s/core %s aor_deg %s wall_s %.1f user_s %s sys_s %s PS_per_user_s %.4e loadavg %s\n", o, t, p, s, a, w, c[1], c[2], ps / c[1], la}' "$out" | tee -a "$LOG"
      rm -f "$out" "$cpu"
    done
  done
done
