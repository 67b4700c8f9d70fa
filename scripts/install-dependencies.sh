#!/usr/bin/env bash
# Debian 12 packages demcal builds, tests and runs with (as root).
set -euo pipefail
export DEBIAN_FRONTEND=noninteractive
apt-get update
apt-get install -y --no-install-recommends $(grep -v '^#' "$(dirname "$0")/debian-packages.txt")
