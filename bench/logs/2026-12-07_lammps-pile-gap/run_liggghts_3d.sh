#!/bin/bash
# usage: run_liggghts_3d.sh NAME SEEDS -- extra --set args...   (as run_variant.sh, LIGGGHTS in place of LAMMPS)
name=$1; seeds=$2; shift 3
D=/work/main/build/cli/demcal
S=/work/main/studies/sandglass-single/study.toml
base=(--set apparatus.sandglass.fill_mass_kg=0.06 --set apparatus.sandglass.upper_height_m=0.07)
mkdir -p $name
for s in $seeds; do echo $s; done | xargs -P2 -I{} sh -c "[ -f $name/d{}/run.json ] || $D simulate $S --quiet --output $name/d{} ${base[*]} $* --set study.seed={} > $name/d{}.log 2>&1"
for s in $seeds; do [ -f $name/l$s/run.json ] || $D simulate $S --quiet --output $name/l$s ${base[*]} "$@" --set study.seed=$s --set engine.kind=liggghts --set 'engine.launch=mpirun --allow-run-as-root --oversubscribe -np 2 liggghts' > $name/l$s.log 2>&1; done
python3 "$(dirname "$0")/summ.py" $name
