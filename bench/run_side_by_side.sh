#!/bin/bash
# demcal against LAMMPS on the peer pile case, back to back on this machine.
#
# usage: bench/run_side_by_side.sh [PEERS_DIR]        (default: ../shared/peers next to the repo)
#
# PEERS_DIR is copied to a mktemp dir (the LAMMPS scripts write runs/ next to themselves).
# For each case and each repetition, interleaved so that machine noise hits both engines:
#   demcal 1 thread, LAMMPS 1 rank, demcal 2 threads, LAMMPS 2 ranks
# Cases (CASES, space separated):
#   pile<N>    poured pile of N to rest (pour figure) AND fixed-N steps on the settled pile
#              (static figure). demcal: one `--mode static` run gives both figures (its pour
#              phase is exactly the pour-mode run). LAMMPS: run_pile.sh, then run_bench.sh on
#              LAMMPS's own settled pile (the 1-rank dump of the first repetition).
#   pour<N>    pour figure only.      static<N>  static figure only.
#   tile<N>x<K>  the larger case (issue 13): static figure at N*K particles. Each engine pours
#              its own pile of N, as for static<N>, and copies it K times across the periodic
#              slab thickness (K*5 d): demcal `--tile-y K`; LAMMPS `replicate 1 K 1` after
#              read_dump, in a copy of bench_static.in made here (the peer's own file is not
#              touched). Logged as static<N*K>; the pour of N is not timed. STATIC_STEPS_TILE
#              (default 5000) timed steps.
# Environment (defaults):
#   R=3             repetitions          R6000=$R   repetitions for cases with N >= 6000
#   CASES="pile3000 pour6000"          THREADS="1 2"
#   STATIC_STEPS=20000  MUS=0.5  MUR=0.1  SEED=4767
#   ORDER=spatial   demcal's particle order (--particle-order; spatial is the config readers'
#                   default since issue 13, the benchmark binary's own default is insertion);
#                   each BENCH line records it ("order ...")
#   DEMCAL_BENCH=<repo>/build-bench/bench/demcal_bench_pile
#   LAMMPS_PILE=<dump>   a settled LAMMPS pile of the case's N (a pile.in dump, e.g. from an
#                   earlier run's runs/ folder) used for the static figures instead of pouring one
#   LOGDIR=<repo>/bench/logs   RUN_TIMEOUT=900 (s; a demcal run taking longer is logged as TIMEOUT)
#   QUIET_BUSY=0.3  QUIET_WAIT=120   before a multi-thread run, wait (at most QUIET_WAIT s) until
#                                    the other processes use less than QUIET_BUSY cores
# Logs (summary lines only): bench/logs/<date>_<case><N>_<engine>_<threads>t_<machine>.log,
# appended to; the medians and ratios over all of today's logs of this machine are printed at
# the end (bench/summarize.py table).
set -euo pipefail

REPO=$(cd "$(dirname "$0")/.." && pwd)
SRC_PEERS=${1:-$REPO/../shared/peers}
R=${R:-3}
R6000=${R6000:-$R}
CASES=${CASES:-"pile3000 pour6000"}
THREADS=${THREADS:-"1 2"}
STATIC_STEPS=${STATIC_STEPS:-20000}
STATIC_STEPS_TILE=${STATIC_STEPS_TILE:-5000}
MUS=${MUS:-0.5}
MUR=${MUR:-0.1}
SEED=${SEED:-4767}
ORDER=${ORDER:-spatial}
QUIET_BUSY=${QUIET_BUSY:-0.3}
QUIET_WAIT=${QUIET_WAIT:-120}
RUN_TIMEOUT=${RUN_TIMEOUT:-900}
BIN=${DEMCAL_BENCH:-$REPO/build-bench/bench/demcal_bench_pile}
PY=/usr/bin/python3
SUM="$PY $REPO/bench/summarize.py"

[ -x "$BIN" ] || { echo "no demcal benchmark at $BIN (build target demcal_bench_pile or set DEMCAL_BENCH)" >&2; exit 1; }
[ -f "$SRC_PEERS/lammps/pile.in" ] || { echo "no peer scripts in $SRC_PEERS" >&2; exit 1; }
command -v lmp >/dev/null || { echo "lmp (LAMMPS) not found" >&2; exit 1; }

PEERS=$(mktemp -d /tmp/demcal_peers.XXXXXX)
cp -r "$SRC_PEERS"/. "$PEERS"/
rm -rf "$PEERS/lammps/runs"
mkdir -p "$PEERS/lammps/runs"
TMP=$(mktemp -d /tmp/demcal_bench.XXXXXX)
echo "peers copied to $PEERS; scratch in $TMP"

DATE=$(date +%F)
MODEL=$(lscpu | sed -n 's/^Model name: *//p' | head -1)
MACHINE=$(echo "$MODEL" | tr 'A-Z' 'a-z' | sed 's/([^)]*)//g; s/[^a-z0-9]\+/-/g; s/^-//; s/-$//')-$(nproc)c
# the version the benchmark binary was built from (a binary without --version: the tree's)
VERSION=$("$BIN" --version 2>/dev/null | tail -1) || true
[ -n "$VERSION" ] || VERSION="tree-$(git -C "$REPO" describe --always --dirty 2>/dev/null || echo unknown)"
LOGDIR=${LOGDIR:-$REPO/bench/logs}
mkdir -p "$LOGDIR"
LMPVER=$(lmp -h 2>/dev/null | sed -n 's/^Large-scale.* - \(2.*\)/\1/p' | head -1)
LMPDEB=$(dpkg-query -W -f='${Version}' lammps 2>/dev/null || true)
echo "machine: $MODEL, $(nproc) cores, kernel $(uname -r); demcal $VERSION (order $ORDER); LAMMPS $LMPVER (Debian $LMPDEB), MPI only"

logfile() { echo "$LOGDIR/${DATE}_$1_$2_$3t_${MACHINE}.log"; }

# cores kept busy by other processes over 2 s (from /proc/stat; none of ours runs meanwhile)
busy_cores() {
  local a b
  a=$(head -1 /proc/stat); sleep 2; b=$(head -1 /proc/stat)
  echo "$a" "$b" | awk -v n="$(nproc)" '{t1=0; for(i=2;i<=9;i++) t1+=$i; i1=$5+$6;
    t2=0; for(i=13;i<=20;i++) t2+=$i; i2=$16+$17; printf "%.2f", n*(1-(i2-i1)/(t2-t1))}'
}

# before a multi-thread run, wait for a quiet machine (at most QUIET_WAIT s)
BUSY=0
wait_quiet() {
  local t=$1 waited=0
  BUSY=$(busy_cores)
  while [ "$t" -gt 1 ] && awk -v b="$BUSY" -v q="$QUIET_BUSY" 'BEGIN{exit !(b > q)}' && [ $waited -lt "$QUIET_WAIT" ]; do
    sleep 3; waited=$((waited + 5)); BUSY=$(busy_cores)
  done
}

# jiffies "busy total" of all cores, to measure what other processes used during a run
cpu_snap() { head -1 /proc/stat | awk '{t=0; for(i=2;i<=9;i++) t+=$i; print t-$5-$6, t}'; }
# others_cores = (all cores' busy time - this run's user+sys) / wall, over the run
others_cores() {  # snap_before snap_after timefile
  local hz; hz=$(getconf CLK_TCK)
  echo "$1 $2" | awk -v hz="$hz" -v tf="$3" '{
    while ((getline ln < tf) > 0) {
      if (ln ~ /User time/) { split(ln, a, ": "); u = a[2] }
      if (ln ~ /System time/) { split(ln, a, ": "); s = a[2] }
      if (ln ~ /Elapsed/) { n = split(ln, a, ": "); m = split(a[n], p, ":"); w = 0; for (i = 1; i <= m; i++) w = w * 60 + p[i] }
    }
    o = (($3 - $1) / hz - u - s) / w; if (o < 0) o = 0; printf "%.2f", o }'
}

header() {  # rep threads
  echo "# rep $1 $(date -Is) demcal $VERSION busy_cores_before $BUSY loadavg $(cut -d' ' -f1-3 /proc/loadavg)"
}

aor_of() { $PY "$PEERS/tools/aor.py" "$1" | tail -1; }

run_demcal() {  # N threads mode rep [tiles]
  local n=$1 t=$2 mode=$3 rep=$4 tiles=${5:-1} out=$TMP/demcal.out tf=$TMP/demcal.time dump=$TMP/demcal_pile.txt
  local steps=$STATIC_STEPS; [ "$tiles" -gt 1 ] && steps=$STATIC_STEPS_TILE
  wait_quiet "$t"
  local h; h=$(header "$rep")
  local s0; s0=$(cpu_snap)
  local rc=0
  timeout "$RUN_TIMEOUT" /usr/bin/time -v "$BIN" --particles "$n" --threads "$t" --mode "$mode" \
    --static-steps "$steps" --seed "$SEED" --mus "$MUS" --mur "$MUR" --particle-order "$ORDER" \
    --tile-y "$tiles" --dump "$dump" > "$out" 2> "$tf" || rc=$?
  if [ $rc = 124 ]; then  # a disturbed multi-thread run can crawl; log it and go on
    local lt="pour$n"; [ "$tiles" -gt 1 ] && lt="static$((n * tiles))"
    echo "$h TIMEOUT after $RUN_TIMEOUT s, others_cores $(others_cores "$s0" "$(cpu_snap)" /dev/null)" | tee -a "$(logfile "$lt" demcal "$t")"
    return 0
  elif [ $rc != 0 ]; then
    echo "demcal run failed:"; cat "$out" "$tf"; exit 1
  fi
  local s1; s1=$(cpu_snap)
  local aor tl; aor=$(aor_of "$dump"); tl="$($SUM time "$tf") others_cores $(others_cores "$s0" "$s1" "$tf")"
  if [ "$tiles" = 1 ]; then  # a tiled run's pour is the untiled case's figure: not logged twice
    local lp; lp=$(logfile "pour$n" demcal "$t")
    { echo "$h"; grep '^PILE' "$out"; grep '^BENCH.* mode pour ' "$out"; echo "$aor"; echo "$tl"; } >> "$lp"
  fi
  grep '^BENCH.* mode pour ' "$out"
  if [ "$mode" = static ]; then
    local ls; ls=$(logfile "static$((n * tiles))" demcal "$t")
    { echo "$h"; grep '^BENCH.* mode static ' "$out"; echo "$aor"; echo "$tl"; } >> "$ls"
    grep '^BENCH.* mode static ' "$out"
  fi
  echo "  $aor"
}

STATIC_DUMP=""
run_lammps_pour() {  # N ranks rep
  local n=$1 np=$2 rep=$3
  wait_quiet "$np"
  local h; h=$(header "$rep")
  local s0; s0=$(cpu_snap)
  (cd "$PEERS/lammps" && SEED=$SEED TAG=r$rep ./run_pile.sh "$MUS" "$MUR" "$np" "$n" > "$TMP/lmp.out" 2>&1) || {
    echo "LAMMPS pour failed:"; cat "$TMP/lmp.out"; exit 1; }
  local s1; s1=$(cpu_snap)
  local b="$PEERS/lammps/runs/pile_N${n}_mus${MUS}_mur${MUR}_np${np}_s${SEED}_r$rep"
  local lp; lp=$(logfile "pour$n" lammps "$np")
  local bl; bl=$($SUM lammps-pour "$b.log" "$b.time" "$np")
  { echo "$h"; grep '^PILE_DONE' "$b.log"; echo "$bl"; aor_of "$b.txt"; echo "$($SUM time "$b.time") others_cores $(others_cores "$s0" "$s1" "$b.time")"; } >> "$lp"
  echo "$bl"; echo "  $(aor_of "$b.txt")"
  if [ -z "$STATIC_DUMP" ] && [ "$np" = 1 ]; then STATIC_DUMP="$b.txt"; fi
}

run_lammps_static() {  # N ranks rep
  local n=$1 np=$2 rep=$3
  if [ -z "$STATIC_DUMP" ]; then  # static only: pour LAMMPS's own pile once (not logged)
    (cd "$PEERS/lammps" && SEED=$SEED TAG=prep ./run_pile.sh "$MUS" "$MUR" 1 "$n" > /dev/null 2>&1)
    STATIC_DUMP="$PEERS/lammps/runs/pile_N${n}_mus${MUS}_mur${MUR}_np1_s${SEED}_prep.txt"
  fi
  wait_quiet "$np"
  local h; h=$(header "$rep")
  local s0; s0=$(cpu_snap)
  (cd "$PEERS/lammps" && ./run_bench.sh "runs/$(basename "$STATIC_DUMP")" "$np" "$STATIC_STEPS" > "$TMP/lmpb.out" 2>&1) || {
    echo "LAMMPS static failed:"; cat "$TMP/lmpb.out"; exit 1; }
  local s1; s1=$(cpu_snap)
  local b; b="$PEERS/lammps/runs/bench_$(basename "$STATIC_DUMP" .txt)_np$np"
  local bl; bl=$($SUM lammps-static "$b.log" "$b.time" "$np")
  local ls; ls=$(logfile "static$n" lammps "$np")
  { echo "$h"; echo "$bl"; echo "$(aor_of "$STATIC_DUMP") (input pile)"; echo "$($SUM time "$b.time") others_cores $(others_cores "$s0" "$s1" "$b.time")"; } >> "$ls"
  echo "$bl"
}

# The tiled LAMMPS case: bench_static.in with `replicate 1 K 1` after read_dump (a copy).
run_lammps_tiled() {  # N K ranks rep
  local n=$1 k=$2 np=$3 rep=$4
  if [ -z "$STATIC_DUMP" ]; then
    (cd "$PEERS/lammps" && SEED=$SEED TAG=prep ./run_pile.sh "$MUS" "$MUR" 1 "$n" > /dev/null 2>&1)
    STATIC_DUMP="$PEERS/lammps/runs/pile_N${n}_mus${MUS}_mur${MUR}_np1_s${SEED}_prep.txt"
  fi
  local in=$PEERS/lammps/bench_static_tiled.in
  sed '/^read_dump/a replicate       1 ${tiles} 1' "$PEERS/lammps/bench_static.in" > "$in"
  grep -q '^replicate' "$in" || { echo "could not add replicate to bench_static.in" >&2; exit 1; }
  wait_quiet "$np"
  local h; h=$(header "$rep")
  local s0; s0=$(cpu_snap)
  local b="$PEERS/lammps/runs/bench_tiled_N${n}x${k}_np$np"
  local c="lmp"; [ "$np" = 1 ] || c="mpirun --allow-run-as-root -np $np lmp"
  (cd "$PEERS/lammps" && OMP_NUM_THREADS=1 /usr/bin/time -v $c -in "$in" -var in "$STATIC_DUMP" \
     -var nstep "$(sed -n 2p "$STATIC_DUMP")" -var steps "$STATIC_STEPS_TILE" -var tiles "$k" \
     -log "$b.log" -screen none 2> "$b.time") || { echo "LAMMPS tiled static failed:"; cat "$b.time"; exit 1; }
  local s1; s1=$(cpu_snap)
  local bl; bl=$($SUM lammps-static "$b.log" "$b.time" "$np")
  local ls; ls=$(logfile "static$((n * k))" lammps "$np")
  { echo "$h"; echo "$bl"; echo "$(aor_of "$STATIC_DUMP") (input pile, tiled ${k}x)"; echo "$($SUM time "$b.time") others_cores $(others_cores "$s0" "$s1" "$b.time")"; } >> "$ls"
  echo "$bl"
}

for c in $CASES; do
  kind=${c%%[0-9]*}; n=${c#"$kind"}
  tiles=1 STATIC_DUMP=${LAMMPS_PILE:-}  # each case settles its own LAMMPS pile of its N
  if [ "$kind" = tile ]; then tiles=${n#*x}; n=${n%%x*}; fi
  reps=$R; [ "$n" -ge 6000 ] && reps=$R6000
  echo "=== case $c ($reps repetitions)"
  for rep in $(seq 1 "$reps"); do
    for t in $THREADS; do
      echo "--- $c rep $rep, $t thread(s)/rank(s); $(uptime | sed 's/.*load/load/')"
      case $kind in
        pile)   run_demcal "$n" "$t" static "$rep"; run_lammps_pour "$n" "$t" "$rep"; run_lammps_static "$n" "$t" "$rep" ;;
        pour)   run_demcal "$n" "$t" pour "$rep";   run_lammps_pour "$n" "$t" "$rep" ;;
        static) run_demcal "$n" "$t" static "$rep"; run_lammps_static "$n" "$t" "$rep" ;;
        tile)   run_demcal "$n" "$t" static "$rep" "$tiles"; run_lammps_tiled "$n" "$tiles" "$t" "$rep" ;;
        *) echo "unknown case $c" >&2; exit 1 ;;
      esac
    done
  done
done

echo
echo "=== medians over today's logs on this machine ($LOGDIR/${DATE}_*_${MACHINE}.log)"
$SUM table "$LOGDIR/${DATE}"_*_"${MACHINE}".log
rm -rf "$TMP"
echo "(LAMMPS runs kept in $PEERS/lammps/runs)"
