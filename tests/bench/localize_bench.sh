#!/usr/bin/env bash
# Localization on a stored map, on every benchmark log: each log (NAME/NAME.clf with
# NAME/NAME.relations in the shared data) is cut by time at the midpoint of its records, the first
# half mapped (`pslam run --no-predict`, seed 1), and the second half localized on that map from
# the first half's last pose (`pslam localize`), once per seed. Both are scored on the relations
# whose two stamps lie in the second half, against mapping the second half alone at the same seed:
# a localizer on a good map should do no worse than mapping. Two more runs per seed tell the
# localizer's error from its map's: localizing on the map of the whole log (mapped at seed 1, so
# it holds what the second half sees), and extending the first half's map (`pslam run
# --prior-map`, which maps what it lacks). Prints one markdown table.
#
# Usage: tests/bench/localize_bench.sh [--seeds LIST] [--logs NAME,...] [--jobs J]
#                                      [--set NAME=VALUE]... [--data DIR] [--keep DIR]
#   --seeds LIST     e.g. 1-5, 1,3,7 or 1-3,9 (default 1-3)
#   --logs LIST      some of the logs, e.g. aces,fr079 (default: every one found)
#   --jobs J         runs at once (default 1); CPU per scan is comparable only at 1
#   --set NAME=VALUE passed on to `pslam localize` (see `pslam localize --help`); repeatable
#   --data DIR       the shared data folder (default: $PSLAM_DATA_DIR, else ../shared/data)
#   --keep DIR       keep the halves, maps and trajectories there (default: a temporary folder)
# PSLAM_BIN=PATH runs that pslam binary instead of build/bin/pslam.
set -euo pipefail
cd "$(dirname "$0")/../.."
source tests/bench/log_runs.sh  # usage, die, seeds and parallel runs

seed_list=1-3
log_list=
jobs=1
sets=()
keep=
data="${PSLAM_DATA_DIR:-../shared/data}"
while (( $# )); do
  case $1 in
    --seeds) seed_list=${2:?}; shift ;;
    --logs) log_list=${2:?}; shift ;;
    --jobs) jobs=${2:?}; shift ;;
    --set) sets+=(--set "${2:?}"); shift ;;
    --data) data=${2:?}; shift ;;
    --keep) keep=${2:?}; shift ;;
    -h|--help) usage ;;
    *) echo "localize_bench: unknown option '$1'" >&2; usage ;;
  esac
  shift
done
check_jobs

parse_seeds "$seed_list"
find_logs "$data" "$log_list"

find_pslam

work_dir "$keep"

# Runs a pslam command, its output to $2.out and errors to $2.err; on failure names it and stops.
run_pslam() {
  local what=$1 base=$2 status=0
  shift 2
  "$pslam" "$@" >"$base.out" 2>"$base.err" || status=$?
  (( status == 0 )) && return 0
  echo "localize_bench: pslam $what failed (exit status $status):" >&2
  head -n 5 "$base.err" >&2
  return 1
}

# Cuts LOG at the midpoint of its records' ipc timestamps (the third field from the end);
# comments and PARAM lines go to both halves. Maps the first half and keeps the relations whose
# two stamps lie in the second.
prepare() {
  local log=$1 base=$tmp/$log
  local mid
  mid=$(awk '!/^#/ && $1 != "PARAM" && NF > 3 {t = $(NF - 2) + 0; if (!n++ || t < lo) lo = t; if (t > hi) hi = t}
             END {if (n) printf "%.6f", (lo + hi) / 2}' "$data/$log/$log.clf")
  [[ -n $mid ]] || die "$log.clf has no timestamped record"
  awk -v mid="$mid" -v first="$base.first.clf" -v second="$base.second.clf" '
    /^#/ || $1 == "PARAM" || NF <= 3 {print > first; print > second; next}
    {if ($(NF - 2) + 0 < mid) print > first; else print > second}' "$data/$log/$log.clf"
  awk -v mid="$mid" '$1 + 0 >= mid && $2 + 0 >= mid' "$data/$log/$log.relations" >"$base.relations"
  [[ -s $base.relations ]] || die "$log: no relation lies in the second half"
  run_pslam "run (first half of $log)" "$base.map" run --quiet --no-predict --seed 1 --log "$base.first.clf" \
    --map "$base.first" --trajectory "$base.first.trajectory"
  run_pslam "run (whole $log)" "$base.whole_map" run --quiet --no-predict --seed 1 --log "$data/$log/$log.clf" \
    --map "$base.whole" --trajectory "$base.whole.trajectory"
  echo "$mid" >"$base.mid"
  echo "localize_bench: $log cut at $mid s; first half mapped, $(wc -l <"$base.relations") relations in the second" >&2
}

# Scores TRAJECTORY on LOG's second-half relations; prints "translation_m rotation_deg".
score() {
  local log=$1 trajectory=$2 base=$3
  run_pslam "eval ($trajectory)" "$base" eval --json --trajectory "$trajectory" --relations "$tmp/$log.relations" || return 1
  echo "$(json_field trans_mean_m "$base.out") $(json_field rot_mean_deg "$base.out")"
}

# Localizes the second half of LOG at SEED on the first half's map and on the whole log's, extends
# the first half's map with it and maps it alone; leaves "loc_trans loc_rot map_trans map_rot cpu_ms
# localized_percent whole_loc_trans extend_trans" in $tmp/LOG.SEED.row.
run_one() {
  local log=$1 seed=$2 base=$tmp/$log.$seed
  local pose whole_pose
  pose=$(awk '!/^#/ {p = $2 "," $3 "," $4} END {print p}' "$tmp/$log.first.trajectory")
  whole_pose=$(awk -v mid="$(cat "$tmp/$log.mid")" '!/^#/ && $1 + 0 < mid {p = $2 "," $3 "," $4} END {print p}' \
    "$tmp/$log.whole.trajectory")
  run_pslam "localize ($log seed $seed)" "$base.localize" localize --map "$tmp/$log.first.yaml" \
    --log "$tmp/$log.second.clf" --initial-pose "$pose" --seed "$seed" --trajectory "$base.localized" "${sets[@]}" || return 1
  run_pslam "localize on the whole map ($log seed $seed)" "$base.localize_whole" localize --map "$tmp/$log.whole.yaml" \
    --log "$tmp/$log.second.clf" --initial-pose "$whole_pose" --seed "$seed" --trajectory "$base.localized_whole" \
    "${sets[@]}" || return 1
  run_pslam "run --prior-map ($log seed $seed)" "$base.extend" run --quiet --no-predict --seed "$seed" \
    --log "$tmp/$log.second.clf" --prior-map "$tmp/$log.first.yaml" --initial-pose "$pose" --trajectory "$base.extended" || return 1
  run_pslam "run (second half of $log, seed $seed)" "$base.mapping" run --quiet --no-predict --seed "$seed" \
    --log "$tmp/$log.second.clf" --trajectory "$base.mapped" || return 1
  local localized mapped whole extended cpu share
  localized=$(score "$log" "$base.localized" "$base.rpe_localized") || return 1
  mapped=$(score "$log" "$base.mapped" "$base.rpe_mapped") || return 1
  whole=$(score "$log" "$base.localized_whole" "$base.rpe_localized_whole") || return 1
  extended=$(score "$log" "$base.extended" "$base.rpe_extended") || return 1
  cpu=$(awk '/^CPU per scan/ {print $4}' "$base.localize.out")
  share=$(awk '/^localized/ {for (i = 1; i <= NF; ++i) if ($i == "%") print $(i - 1)}' "$base.localize.out")
  echo "$localized $mapped ${cpu:-?} ${share:-0} ${whole% *} ${extended% *}" >"$base.row"
  echo "localize_bench: $log seed $seed done:" "$(awk '{printf "localized %.4f m, mapped %.4f m", $1, $3}' "$base.row")" >&2
}

trap 'stop_runs; echo "localize_bench: interrupted" >&2; exit 130' INT TERM
for log in "${logs[@]}"; do spawn prepare "$log"; done
drain
for log in "${logs[@]}"; do
  for seed in "${seeds[@]}"; do spawn run_one "$log" "$seed"; done
done
drain

echo "pslam localize${sets[*]:+ ${sets[*]}} on second halves at $(measured_revision)"
echo
for log in "${logs[@]}"; do
  for seed in "${seeds[@]}"; do echo "$log $seed $(cat "$tmp/$log.$seed.row")"; done
done | awk '
  BEGIN {
    print "| log | seed | localizing: RPE translation (m) / rotation (deg) | mapping the second half alone | localizing / mapping | CPU per scan localizing (ms) | scans localized (%) | localizing on a map of the whole log (m) | extending the map of the first half (m) |"
    print "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"
  }
  function summary(name) {
    printf "| %s | mean of %d | %.4f / %.3f | %.4f / %.3f | x%.2f | %.2f | %.0f | %.4f (x%.2f) | %.4f (x%.2f) |\n", name, n,
           lt / n, lr / n, mt / n, mr / n, lt / mt, c / n, p / n, wt / n, wt / mt, et / n, et / mt
    printf "| %s | worse than mapping | %d of %d | | | | | %d of %d | %d of %d |\n", name, worse, n, wworse, n, eworse, n
  }
  $1 != name && n { summary(name); n = 0 }
  {
    name = $1
    if (n++ == 0) lt = lr = mt = mr = c = p = wt = et = worse = wworse = eworse = 0
    lt += $3; lr += $4; mt += $5; mr += $6; c += $7; p += $8; wt += $9; et += $10
    if ($3 > $5) worse++
    if ($9 > $5) wworse++
    if ($10 > $5) eworse++
    printf "| %s | %s | %.4f / %.3f | %.4f / %.3f | x%.2f | %s | %s | %.4f | %.4f |\n", $1, $2, $3, $4, $5, $6, $3 / $5, $7, $8,
           $9, $10
  }
  END { if (n) summary(name) }
'
