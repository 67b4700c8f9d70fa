#!/bin/bash
# Pile cross-check demcal vs LAMMPS: AoR at the three friction pairs of the peers' README.
# usage: run_pile_crosscheck.sh PEERS_DIR DEMCAL_BENCH [OUTDIR]
#   env: N (3000), SEEDS ("1 2 3"), PAIRS ("0.3:0.05 0.5:0.1 0.5:0.3"),
#        LD=1: also LAMMPS with limit_damping (-var ld 1 -var etsuji 0.43, still e = 0.60),
#              run in the demcal lane after the demcal piles (the lanes take about as long)
# Runs demcal (1 thread) and LAMMPS (1 rank) side by side, one core each (two lanes),
# measures every final pile with the peers' tools/aor.py and prints the table.
set -u
PEERS=$(readlink -f "${1:?peers dir}"); BENCH=$(readlink -f "${2:?demcal_bench_pile binary}")
OUT=${3:-$(mktemp -d /tmp/lammps-crosscheck.XXXXXX)}; mkdir -p "$OUT"; OUT=$(readlink -f "$OUT")
N=${N:-3000}; SEEDS=${SEEDS:-"1 2 3"}; PAIRS=${PAIRS:-"0.3:0.05 0.5:0.1 0.5:0.3"}
PY=/usr/bin/python3
cp -r "$PEERS" "$OUT/peers"            # run_pile.sh writes runs/ next to itself
rm -rf "$OUT/peers/lammps/runs"
echo "output in $OUT" >&2

demcal_lane() {
  for p in $PAIRS; do mus=${p%:*}; mur=${p#*:}; for s in $SEEDS; do
    b=$OUT/demcal_mus${mus}_mur${mur}_s$s
    /usr/bin/time -v "$BENCH" --particles $N --threads 1 --mode pour --seed $s --mus $mus --mur $mur \
      --dump $b.txt > $b.log 2> $b.time
    echo "rc=$?" >> $b.log
    $PY "$PEERS/tools/aor.py" $b.txt | tail -1 > $b.aor
  done; done
}
lammps_lane() {  # [ld]
  local eng=lammps tag= extra=
  if [ "${1:-}" = ld ]; then eng=lammpsld; tag=_ld; extra="-var ld 1 -var etsuji 0.43"; fi
  for p in $PAIRS; do mus=${p%:*}; mur=${p#*:}; for s in $SEEDS; do
    b=$OUT/${eng}_mus${mus}_mur${mur}_s$s
    ( cd "$OUT/peers/lammps" && SEED=$s TAG=${tag#_} ./run_pile.sh $mus $mur 1 $N $extra ) > $b.log 2>&1
    $PY "$PEERS/tools/aor.py" "$OUT/peers/lammps/runs/pile_N${N}_mus${mus}_mur${mur}_np1_s$s$tag.txt" | tail -1 > $b.aor
  done; done
}
( demcal_lane; if [ "${LD:-0}" = 1 ]; then lammps_lane ld; fi ) & d=$!
lammps_lane & l=$!
wait $d $l
"$PY" "$(dirname "$(readlink -f "$0")")/table.py" "$OUT" "$PAIRS" "$SEEDS"
