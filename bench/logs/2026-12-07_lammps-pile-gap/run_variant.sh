#!/bin/bash
# usage: [ENGINE=lammps|liggghts] run_variant.sh NAME SEEDS -- extra --set args...
# demcal on 2 jobs, then the other engine (default LAMMPS) on 2 MPI ranks, both measured by demcal.
name=$1; seeds=$2; shift 3
engine=${ENGINE:-lammps}
binary=$([ "$engine" = liggghts ] && echo liggghts || echo lmp)
D=/work/main/build/cli/demcal
S=/work/main/studies/sandglass-single/study.toml
base=(--set apparatus.sandglass.fill_mass_kg=0.06 --set apparatus.sandglass.upper_height_m=0.07)
mkdir -p $name
for s in $seeds; do echo $s; done | xargs -P2 -I{} sh -c "[ -f $name/d{}/run.json ] || $D simulate $S --quiet --output $name/d{} ${base[*]} $* --set study.seed={} > $name/d{}.log 2>&1"
for s in $seeds; do [ -f $name/l$s/run.json ] || $D simulate $S --quiet --output $name/l$s ${base[*]} "$@" --set study.seed=$s --set engine.kind=$engine --set "engine.launch=mpirun --allow-run-as-root --oversubscribe -np 2 $binary" > $name/l$s.log 2>&1; done
python3 "$(dirname "$0")/summ.py" $name   # its "lammps" column is the other engine
