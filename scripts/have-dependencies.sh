#!/usr/bin/env bash
# Exit 0 when every package of debian-packages.txt is installed.
for p in $(grep -v '^#' "$(dirname "$0")/debian-packages.txt"); do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || exit 1
done
