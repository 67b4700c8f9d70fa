#!/bin/sh
# A stand-in for LIGGGHTS (or LAMMPS) in demcal's tests, so that the dispatch
# of a design point to another engine (study/engine_evaluator.hpp), the run
# store and the measurement are tested where neither engine is installed.
# It takes the engine's command line (-in DECK -log LOG [-screen none]), writes
# a log whose first line names it as the real engine does, and, for a pile
# deck, writes the final custom dump an engine would: a heap of equal spheres
# on the floor (z = 0), filling the deck's box across x, one layer thick, in
# the middle of the box in y, whose flanks rise at atan(0.3 + mu_r) with mu_r
# the particle-particle rolling friction the deck states (LIGGGHTS's
# coefficientRollingFriction, or LAMMPS's "rolling sds k g mu_r"). So the
# measured angle follows the parameter mapping, and a test can check it.
# An empty deck is the version query: the log is written and nothing else.
# A deck with a discharge (a mass series) is refused with an ERROR line.
set -eu
deck=""
log="log.lammps"
while [ $# -gt 0 ]; do
  case "$1" in
    -in) deck="$2"; shift 2 ;;
    -log) log="$2"; shift 2 ;;
    -screen) shift 2 ;;
    *) echo "fake engine: unknown argument $1" >&2; exit 2 ;;
  esac
done
[ -n "$deck" ] || { echo "fake engine: no -in" >&2; exit 2; }
label="${DEMCAL_FAKE_ENGINE_NAME:-LIGGGHTS}"
echo "$label (Version fake-engine 1.0 for demcal's tests)" > "$log"
[ -s "$deck" ] || exit 0
if grep -q "mass_series" "$deck"; then
  echo "ERROR: the fake engine does not run discharges" >> "$log"
  exit 1
fi
awk -v logfile="$log" '
  $1 == "region" && $2 == "box" && $3 == "block" {
    xlo = $4; xhi = $5; ylo = $6; yhi = $7
  }
  $5 == "coefficientRollingFriction" { mu_r = $8; have = 1 }
  $1 == "pair_coeff" { for (i = 1; i <= NF; ++i) if ($i == "sds") { mu_r = $(i + 3); have = 1 } }
  $1 == "dump" && $2 == "final" { dump = $6 }
  $1 == "write_dump" { dump = $4 }
  END {
    if (!have || dump == "" || xhi == "") {
      print "ERROR: the fake engine found no rolling friction, box or final dump" >> logfile
      exit 1
    }
    r = 0.0015
    slope = 0.3 + mu_r
    half = 0.8 * (xhi - xlo) / 2
    y = (ylo + yhi) / 2
    n = 0
    for (x = -half + r; x <= half - r; x += 2 * r) {
      top = slope * (half - (x < 0 ? -x : x))
      for (z = r; z <= top; z += 2 * r) { ++n; px[n] = x; pz[n] = z }
    }
    print "ITEM: TIMESTEP" > dump
    print 1000 > dump
    print "ITEM: NUMBER OF ATOMS" > dump
    print n > dump
    print "ITEM: BOX BOUNDS ff pp ff" > dump
    print xlo, xhi > dump
    print ylo, yhi > dump
    print -0.001, 1 > dump
    print "ITEM: ATOMS id type x y z radius vx vy vz" > dump
    for (i = 1; i <= n; ++i) printf "%d 1 %.9g %.9g %.9g %.9g 0 0 0\n", i, px[i], y, pz[i], r > dump
    print "Total wall time: 0:00:00" >> logfile
  }' "$deck"
