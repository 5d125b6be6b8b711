#!/usr/bin/env bash
# Measures the README table: per scene, its statistics and frame times of the best and the
# cheapest configuration (and of each knob alone at its cheapest) at 640x360 on this machine.
#   testapps/demo/measure.sh [build dir (build)] [timed frames per configuration (5)]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$root/build}
frames=${2:-5}
demo="$build/testapps/demo/demo"
echo "# demo measurements, $(date -u +%Y-%m-%dT%H:%MZ), $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"
echo "# $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
for scene in hall sponza valley subway; do
  "$demo" --scene "$scene" --stats
  echo
  "$demo" --scene "$scene" --width 640 --height 360 --frames "$frames" --start-frame 30 --bench
  echo
done
