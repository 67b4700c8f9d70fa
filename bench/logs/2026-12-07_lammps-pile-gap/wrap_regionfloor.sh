#!/bin/sh
# Replace the floor's fix wall/gran zplane by a wall/gran/region on a plane region (same law).
cp in.demcal in.demcal.as_written
sed -E -i 's/^fix +wall_floor all wall\/gran (granular .*) zplane 0 NULL$/region floorplane plane 0 0 0 0 0 1 side in units box\nfix wall_floor all wall\/gran\/region \1 region floorplane/' in.demcal
exec "$@"
