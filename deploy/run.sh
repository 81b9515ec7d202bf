#!/usr/bin/env bash
# Sets up a fresh Debian machine and runs the main job: maps the Intel Research Lab log with the
# particle filter and writes the map (PGM + YAML + PNG) and the trajectory to out/.
set -euo pipefail
cd "$(dirname "$0")/.."
deploy/bootstrap.sh
deploy/build.sh
log="${PSLAM_LOG:-../shared/data/intel/intel.clf}"
if [[ ! -f "$log" ]]; then
  echo "No log at $log: set PSLAM_LOG to a CARMEN log (see README, 'Data sets')." >&2
  exit 1
fi
mkdir -p out
build/bin/pslam run --log "$log" --particles 30 --trajectory out/trajectory.txt --map out/map
echo "map written to out/map.png (and out/map.pgm + out/map.yaml); trajectory to out/trajectory.txt"
