#!/bin/bash
# Interleaved whole runs of one binary (0ff43a8's demcal_bench_pile), N = 48 000
# static pile, 1 thread: glibc's default malloc against
# GLIBC_TUNABLES=glibc.malloc.hugetlb=1 (malloc asks for transparent huge pages
# with madvise; this machine's THP mode is "madvise"). That huge pages were in
# use was checked during a run: AnonHugePages in /proc/PID/smaps_rollup was
# 8192 kB in the "thp" runs, 0 in the "plain" ones.
for r in 1 2 3; do
  for mode in plain thp; do
    if [ $mode = thp ]; then export GLIBC_TUNABLES=glibc.malloc.hugetlb=1; else unset GLIBC_TUNABLES; fi
    out=$(./bench-0ff43a8 --particles 6000 --tile-y 8 --mode static --static-steps 5000 --threads 1 --particle-order spatial 2>&1)
    echo "rep $r $mode load $(cut -d' ' -f1 /proc/loadavg)"
    echo "$out" | grep BENCH | sed 's/version.*//'
  done
done
