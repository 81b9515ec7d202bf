# Shared by the benchmark scripts (logs_bench.sh, localize_bench.sh, explore_bench.sh); sourced, not
# run. The caller sets $tmp before it starts runs.

# The calling script's usage: its header from "# Usage:" up to the "# PSLAM_BIN" line.
usage() {
  sed -n '/^# Usage:/,/^# PSLAM_BIN/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//' >&2
  exit 2
}
die() {
  echo "$(basename "$0" .sh): $*" >&2
  exit 1
}

# Dies unless $jobs is a positive integer.
check_jobs() {
  [[ $jobs =~ ^[1-9][0-9]*$ ]] || die "--jobs must be a positive integer, got '$jobs'"
}

# Sets 'pslam' to the binary under test: $PSLAM_BIN (another build's, to compare two builds) or
# this build's.
find_pslam() {
  pslam=${PSLAM_BIN:-build/bin/pslam}
  [[ -x $pslam ]] || die "$pslam not found: build it with 'cmake --build build --target pslam'"
}

# Fills 'seeds' from a list of numbers and ranges such as 1-5,9.
parse_seeds() {
  local list=$1 part parts
  seeds=()
  IFS=, read -ra parts <<<"$list"
  for part in "${parts[@]}"; do
    if [[ $part =~ ^([0-9]+)-([0-9]+)$ ]]; then
      mapfile -t -O "${#seeds[@]}" seeds < <(seq "${BASH_REMATCH[1]}" "${BASH_REMATCH[2]}")
    elif [[ $part =~ ^[0-9]+$ ]]; then
      seeds+=("$part")
    else
      die "--seeds: expected numbers and ranges like 1-5,9, got '$list'"
    fi
  done
  (( ${#seeds[@]} )) || die "--seeds gives no seed: '$list'"
}

# Fills 'logs' with the names in a comma-separated list, or with every NAME/ folder of DATA that
# holds NAME.clf and NAME.relations when the list is empty; each must have both files.
find_logs() {
  local data=$1 list=$2 dir name log
  [[ -d $data ]] || die "no data folder $data (set --data or PSLAM_DATA_DIR)"
  logs=()
  if [[ -n $list ]]; then
    IFS=, read -ra logs <<<"$list"
  else
    for dir in "$data"/*/; do
      name=$(basename "$dir")
      [[ -f $dir/$name.clf && -f $dir/$name.relations ]] && logs+=("$name")
    done
  fi
  (( ${#logs[@]} )) || die "no log in $data (a log is NAME/NAME.clf with NAME/NAME.relations)"
  for log in "${logs[@]}"; do
    [[ -f $data/$log/$log.clf && -f $data/$log/$log.relations ]] ||
      die "log '$log' needs $data/$log/$log.clf and $data/$log/$log.relations"
  done
}

# A number from the JSON `pslam eval --json` writes: json_field NAME FILE.
json_field() { grep -o "\"$1\": *[-0-9.eE+naif]*" "$2" | awk -F': *' '{print $2}'; }

# The commit measured, marked when the tree has changes.
measured_revision() {
  echo "$(git rev-parse --short HEAD 2>/dev/null || echo '?')$(git diff --quiet HEAD 2>/dev/null || echo '+changes')"
}

# Sets $tmp, the folder the runs write to: DIR (made if missing) when given, else a temporary
# folder removed on exit. work_dir [DIR]
work_dir() {
  if [[ -n ${1:-} ]]; then
    mkdir -p "$1"
    tmp=$(cd "$1" && pwd)
  else
    tmp=$(mktemp -d)
    trap 'rm -rf "$tmp"' EXIT
  fi
}

# Runs in the background, at most $jobs at once, each in its own process group (set -m) so that
# stopping the script stops whole runs. When one fails the others are stopped and the script ends,
# keeping $tmp for a look.
set -m
pids=()
running=0
stop_runs() {
  local pid
  for pid in "${pids[@]}"; do kill -- "-$pid" 2>/dev/null || true; done
  wait 2>/dev/null || true
}
run_failed() {
  stop_runs
  trap - EXIT
  die "a run failed (see above); intermediate files kept in $tmp"
}
spawn() {
  if (( running >= jobs )); then
    wait -n || run_failed
    running=$((running - 1))
  fi
  "$@" &
  pids+=($!)
  running=$((running + 1))
}
drain() {
  while (( running > 0 )); do
    wait -n || run_failed
    running=$((running - 1))
  done
}
