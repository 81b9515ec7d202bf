#!/usr/bin/env bash
# Accuracy, time and memory of `pslam run` on the benchmark logs of Kümmerle et al. 2009 (every
# NAME/ folder of the shared data holding NAME.clf and NAME.relations) at several seeds. Prints
# one markdown table: a row per run, then per log the mean and the worst (largest) value of each
# column, with the ratio of the errors to Cartographer's (Hess et al., ICRA 2016, Table II), and
# how many runs failed: above 0.06 m, the published RBPF level. Wall time and peak memory are those
# `pslam run` reports for mapping the log; with --predict, the share of filter updates whose
# weights used predictions is given too.
#
# Usage: tests/bench/logs_bench.sh [--seeds LIST] [--particles N] [--logs NAME,...] [--predict]
#                                  [--jobs J] [--set NAME=VALUE]... [--data DIR]
#   --seeds LIST     e.g. 1-5 (default), 1,3,7 or 1-3,9
#   --particles N    particles per run (30)
#   --logs LIST      some of the logs, e.g. intel,aces (default: every one found)
#   --predict        P-SLAM with predictions (default: --no-predict, the plain RBPF)
#   --jobs J         runs at once (1). A run uses every core unless given --set threads=N, and
#                    runs sharing cores slow each other down: wall times are then not comparable.
#   --set NAME=VALUE passed on to `pslam run` (see `pslam run --help`); repeatable
#   --data DIR       the shared data folder (default: $PSLAM_DATA_DIR, else ../shared/data)
# PSLAM_BIN=PATH runs that pslam binary instead of build/bin/pslam.
# Progress goes to stderr. When a run or its evaluation fails, the script stops the other runs,
# names the one that failed, keeps its intermediate files and exits with status 1.
set -euo pipefail
cd "$(dirname "$0")/../.."
source tests/bench/log_runs.sh  # usage, die, seeds and parallel runs

seed_list=1-5
particles=30
log_list=
mode=(--no-predict)
jobs=1
sets=()
data="${PSLAM_DATA_DIR:-../shared/data}"
while (( $# )); do
  case $1 in
    --seeds) seed_list=${2:?}; shift ;;
    --particles) particles=${2:?}; shift ;;
    --logs) log_list=${2:?}; shift ;;
    --predict) mode=() ;;
    --jobs) jobs=${2:?}; shift ;;
    --set) sets+=(--set "${2:?}"); shift ;;
    --data) data=${2:?}; shift ;;
    -h|--help) usage ;;
    *) echo "logs_bench: unknown option '$1'" >&2; usage ;;
  esac
  shift
done
[[ $particles =~ ^[1-9][0-9]*$ ]] || die "--particles must be a positive integer, got '$particles'"
check_jobs

parse_seeds "$seed_list"
find_logs "$data" "$log_list"

find_pslam
# /usr/bin/time measures the peak memory in case `pslam run` does not print it.
timer=()
[[ -x /usr/bin/time ]] && timer=(/usr/bin/time -v -o)

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# Names the step that failed and shows the start of its error output.
report_failure() {
  echo "logs_bench: pslam $1 failed on $2 seed $3 (exit status $4):" >&2
  head -n 5 "$5" >&2
}

# One run and its evaluation; leaves "trans rot used missing wall mem predicted" in $tmp/LOG.SEED.row.
run_one() {
  local log=$1 seed=$2 status=0
  local base=$tmp/$log.$seed measure=()
  (( ${#timer[@]} )) && measure=("${timer[@]}" "$base.time")
  "${measure[@]}" "$pslam" run --quiet --log "$data/$log/$log.clf" --particles "$particles" --seed "$seed" \
    --trajectory "$base.trajectory" "${mode[@]}" "${sets[@]}" >"$base.run" 2>"$base.err" || status=$?
  (( status == 0 )) || { report_failure run "$log" "$seed" "$status" "$base.err"; return 1; }
  "$pslam" eval --json --trajectory "$base.trajectory" --relations "$data/$log/$log.relations" \
    >"$base.rpe" 2>"$base.err" || status=$?
  (( status == 0 )) || { report_failure eval "$log" "$seed" "$status" "$base.err"; return 1; }
  local wall mem predicted
  wall=$(awk '/^wall time/ {print $3}' "$base.run")
  # "updates weighed   W with hypothesis points, U used them" against "scans processed S (N filter updates)"
  predicted=$(awk '/^scans processed/ {gsub(/\(/, "", $4); n = $4}
                   /^updates weighed/ {u = $7} END {if (u != "" && n > 0) printf "%.1f", 100 * u / n; else print "-"}' "$base.run")
  mem=$(awk '/^peak memory/ {print $3}' "$base.run")
  if [[ -z $mem && -f $base.time ]]; then
    mem=$(awk -F': *' '/Maximum resident set size/ {printf "%.1f", $2 / 1024}' "$base.time")
  fi
  echo "$(json_field trans_mean_m "$base.rpe") $(json_field rot_mean_deg "$base.rpe")" \
    "$(json_field used "$base.rpe") $(json_field missing "$base.rpe") ${wall:-?} ${mem:-?} $predicted" >"$base.row"
  echo "logs_bench: $log seed $seed done:" "$(awk '{printf "%.4f m, %.3f deg", $1, $2}' "$base.row"), ${wall:-?} s" >&2
}

trap 'stop_runs; echo "logs_bench: interrupted" >&2; exit 130' INT TERM

describe="pslam run ${mode[*]:-(with predictions)} --particles $particles${sets[*]:+ ${sets[*]}}"
echo "logs_bench: $describe on ${#logs[@]} log(s) x ${#seeds[@]} seed(s), $jobs at once" >&2
for log in "${logs[@]}"; do
  for seed in "${seeds[@]}"; do
    echo "logs_bench: $log seed $seed ..." >&2
    spawn run_one "$log" "$seed"
  done
done
drain

echo "$describe at $(measured_revision)"
echo
for log in "${logs[@]}"; do
  for seed in "${seeds[@]}"; do echo "$log $seed $(cat "$tmp/$log.$seed.row")"; done
done | awk '
  BEGIN {
    # Cartographer, mean absolute translational (m) and rotational (deg) error.
    ref_t["intel"] = 0.0229; ref_r["intel"] = 0.45
    ref_t["aces"] = 0.0375; ref_r["aces"] = 0.37
    ref_t["fr079"] = 0.0452; ref_r["fr079"] = 0.54
    failed_above = 0.06  # m: the GMapping-class RBPF of Kümmerle et al. 2009
    print "| log | seed | RPE translation mean (m) | RPE rotation mean (deg) | vs Cartographer (translation / rotation) | relations used / missing | wall (s) | peak memory (MiB) | updates using predictions (%) |"
    print "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"
  }
  function one_decimal(v) { return v ~ /^[0-9.]+$/ ? sprintf("%.1f", v) : v }
  function ratio(name, t, r) {
    if (!(name in ref_t)) return "-"
    return sprintf("x%.2f / x%.2f", t / ref_t[name], r / ref_r[name])
  }
  function summary(name,   ref) {
    ref = (name in ref_t) ? sprintf(" of %.4f m / %.2f deg", ref_t[name], ref_r[name]) : ""
    printf "| %s | mean of %d | %.4f | %.3f | %s%s | | %.1f | %.1f | %s |\n", name, n, st / n, sr / n,
           ratio(name, st / n, sr / n), ref, sw / n, sm / n, np ? sprintf("%.1f", sp / np) : "-"
    printf "| %s | worst | %.4f | %.3f | %s | | %.1f | %.1f | |\n", name, wt, wr, ratio(name, wt, wr), ww, wm
    printf "| %s | failed (> %.2f m) | %d of %d | | | | | | |\n", name, failed_above, failed, n
  }
  $1 != name && n { summary(name); n = 0 }
  {
    name = $1
    if (n++ == 0) { st = sr = sw = sm = sp = np = failed = 0; wt = wr = ww = wm = 0 }
    st += $3; sr += $4; sw += $7; sm += $8
    if ($9 != "-") { sp += $9; np++ }
    if ($3 > failed_above) failed++
    if ($3 > wt) wt = $3
    if ($4 > wr) wr = $4
    if ($7 > ww) ww = $7
    if ($8 > wm) wm = $8
    printf "| %s | %s | %.4f | %.3f | %s | %s / %s | %s | %s | %s |\n", $1, $2, $3, $4, ratio($1, $3, $4), $5, $6,
           one_decimal($7), one_decimal($8), $9
  }
  END { if (n) summary(name) }
'
