#!/usr/bin/env bash
# A short run of localize_bench.sh for the test suite: the first 240 s of the ACES log (its
# relations among them), cut in two by the benchmark, at seed 1. Passes when the table has the
# run's row and the second half scores within 0.1 m RPE localized on the first half's map, on the
# whole log's map and extending the first half's: a localizer that lost the robot, or a benchmark
# that scored the wrong poses, does not.
set -euo pipefail
cd "$(dirname "$0")/../.."
data="${PSLAM_DATA_DIR:-../shared/data}"
[[ -f $data/aces/aces.clf && -f $data/aces/aces.relations ]] || { echo "no ACES log in $data" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir "$tmp/aces"
awk '/^#/ || $1 == "PARAM" || NF <= 3 {print; next} {if (!n++) start = $(NF - 2); if ($(NF - 2) - start < 240) print}' \
  "$data/aces/aces.clf" >"$tmp/aces/aces.clf"
last=$(awk '!/^#/ && $1 != "PARAM" && NF > 3 {t = $(NF - 2)} END {print t}' "$tmp/aces/aces.clf")
awk -v last="$last" '$1 <= last && $2 <= last' "$data/aces/aces.relations" >"$tmp/aces/aces.relations"
table=$(tests/bench/localize_bench.sh --seeds 1 --data "$tmp" 2>"$tmp/progress") || { cat "$tmp/progress" >&2; exit 1; }
echo "$table"
row=$(grep '^| aces | 1 |' <<<"$table") || { echo "no row for aces seed 1" >&2; exit 1; }
awk -F'|' '
  function check(what, rpe) {
    if (!(rpe + 0 > 0 && rpe + 0 < 0.1)) {print what " RPE " rpe " m is not within 0.1 m" > "/dev/stderr"; failed = 1}
  }
  {split($4, rpe, "/"); check("localized", rpe[1]); check("localized on the whole map", $9); check("extended", $10)}
  END {exit failed}' <<<"$row"
