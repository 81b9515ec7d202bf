#!/usr/bin/env bash
# Accuracy, speed and memory of `pslam run` on the full Intel log at several particle counts.
# Usage: tests/bench/intel_bench.sh [PARTICLES...]   (default: 10 30 100 200)
# PSLAM_RUN_ARGS adds options to `pslam run` (default: --no-predict, the plain RBPF).
set -euo pipefail
cd "$(dirname "$0")/../.."
data="${PSLAM_DATA_DIR:-../shared/data}/intel"
[[ -x build/bin/pslam ]] || deploy/build.sh
out=$(mktemp -d)
counts=("$@")
(( ${#counts[@]} )) || counts=(10 30 100 200)
printf "%-9s %9s %9s %9s %11s %11s %8s\n" particles wall_s peak_MiB scans/s trans_mean rot_mean updates
for n in "${counts[@]}"; do
  # shellcheck disable=SC2086  # word splitting of the extra options is intended
  summary=$(build/bin/pslam run --quiet --log "$data/intel.clf" --particles "$n" --trajectory "$out/t$n.txt" ${PSLAM_RUN_ARGS---no-predict})
  rpe=$(build/bin/pslam eval --json --trajectory "$out/t$n.txt" --relations "$data/intel.relations")
  wall=$(awk '/^wall time/ {print $3}' <<<"$summary")
  mem=$(awk '/^peak memory/ {print $3}' <<<"$summary")
  rate=$(awk '/^scans\/s/ {print $2}' <<<"$summary")
  updates=$(awk '/^scans processed/ {gsub(/\(/, "", $4); print $4}' <<<"$summary")
  trans=$(grep -o '"trans_mean_m": *[0-9.e-]*' <<<"$rpe" | awk -F: '{print $2}')
  rot=$(grep -o '"rot_mean_deg": *[0-9.e-]*' <<<"$rpe" | awk -F: '{print $2}')
  printf "%-9s %9s %9s %9s %9.4f m %7.3f deg %8s\n" "$n" "$wall" "$mem" "$rate" "$trans" "$rot" "$updates"
done
rm -rf "$out"
