#!/usr/bin/env bash
# A short run of explore_bench.sh for the test suite: the maze at seed 1 for 200 simulated
# seconds. Passes when the table has the run's row, flagged as having hit the time limit, with the
# full-coverage run's mean position error within 0.3 m, and the summary row: a benchmark that
# scored the wrong run, or lost a flag, does not.
set -euo pipefail
cd "$(dirname "$0")/../.."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
table=$(tests/bench/explore_bench.sh --worlds maze --seeds 1 -- --time-limit 200 2>"$tmp/progress") ||
  { cat "$tmp/progress" >&2; exit 1; }
echo "$table"
row=$(grep -m1 '^| maze | 1 |' <<<"$table") || { echo "no row for maze seed 1" >&2; exit 1; }
grep -q 'time_limit_hit' <<<"$row" || { echo "the 200 s run is not flagged as hitting the time limit" >&2; exit 1; }
awk -F'|' '{split($4, full, " "); if (!(full[1] + 0 > 0 && full[1] + 0 <= 0.3)) {
  print "full coverage position error " full[1] " m is not within 0.3 m" > "/dev/stderr"; exit 1}}' <<<"$row"
grep -q '^| maze | 1 | ' <<<"$(grep -A3 '^| world | runs |' <<<"$table")" || { echo "no summary row for the maze" >&2; exit 1; }
