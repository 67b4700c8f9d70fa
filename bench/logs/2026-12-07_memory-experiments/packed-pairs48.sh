#!/bin/bash
# interleaved whole runs, old/new alternating order: N=48000 static, 1 thread
N=${N:-6000}; T=${T:-8}; S=${S:-5000}; TH=${TH:-1}
for r in 1 2 3; do
  if [ $((r % 2)) = 1 ]; then order="bench-0ff43a8 bench-packed"; else order="bench-packed bench-0ff43a8"; fi
  for b in $order; do
    out=$(./$b --particles $N --tile-y $T --mode static --static-steps $S --threads $TH --particle-order spatial 2>&1)
    echo "rep $r $b load $(cut -d' ' -f1 /proc/loadavg) $(echo "$out" | grep 'mode static' | sed 's/.*PS\/s\/core \([^ ]*\) maxRSS_MiB \([^ ]*\).*/PSpc \1 rss \2/') $(echo "$out" | grep AOR)"
  done
done
