#!/usr/bin/env bash
# Simulated explorations over several worlds and seeds in one table: for each world and seed, the
# pair `pslam experiment explore` runs (the plain RBPF with full coverage, P-SLAM skipping
# predicted regions), then per world the means and how many runs meet the targets: full coverage's
# mean position error <= 0.3 m and built map's Psi against the true world >= 0.75, the skip run's
# merged Psi >= 0.7, and the time saved at equal coverage. Map Psi is also given with the map laid
# onto the world first (map_alignment.hpp): what is left is the map's own inconsistency, not how
# far it sits off as a whole.
#
# Usage: tests/bench/explore_bench.sh [--worlds LIST] [--seeds LIST] [--jobs J] [--keep DIR]
#                                     [-- OPTIONS OF pslam experiment explore...]
#   --worlds LIST  shipped worlds by name (maze, office, irregular, repetitive_office: the files
#                  core/worlds/NAME.yaml) and generated ones as FAMILY:SEED (school:24);
#                  default maze
#   --seeds LIST   run seeds, e.g. 1-10 (default), 1,3,7 or 1-3,9
#   --jobs J       pairs at once (1); each pair runs on one thread
#   --keep DIR     keep each run's JSON and output there (default: a temporary folder)
#   after --        passed on, e.g. -- --set tracking_match.coarsest_level=1 --time-limit 600
# PSLAM_BIN=PATH runs that pslam binary instead of build/bin/pslam.
# Progress goes to stderr. When a run fails, the script stops the others, names the one that
# failed, keeps its intermediate files and exits with status 1.
set -euo pipefail
cd "$(dirname "$0")/../.."
source tests/bench/log_runs.sh  # usage, die, seeds and parallel runs

world_list=maze
seed_list=1-10
jobs=1
passed=()
keep=
while (( $# )); do
  case $1 in
    --worlds) world_list=${2:?}; shift ;;
    --seeds) seed_list=${2:?}; shift ;;
    --jobs) jobs=${2:?}; shift ;;
    --keep) keep=${2:?}; shift ;;
    --) shift; passed=("$@"); break ;;
    -h|--help) usage ;;
    *) echo "explore_bench: unknown option '$1'" >&2; usage ;;
  esac
  shift
done
check_jobs
parse_seeds "$seed_list"

find_pslam

# The `pslam experiment explore` arguments naming each world.
IFS=, read -ra worlds <<<"$world_list"
(( ${#worlds[@]} )) || die "--worlds names no world"
world_args() {
  local world=$1
  if [[ $world =~ ^([a-z]+):([0-9]+)$ ]]; then
    echo "--generated ${BASH_REMATCH[1]} --count 1 --first-seed ${BASH_REMATCH[2]}"
  elif [[ -f core/worlds/$world.yaml ]]; then
    echo "--world core/worlds/$world.yaml"
  else
    die "no world '$world': a shipped world is core/worlds/NAME.yaml, a generated one FAMILY:SEED"
  fi
}
for world in "${worlds[@]}"; do world_args "$world" >/dev/null; done

work_dir "$keep"

run_one() {
  local world=$1 seed=$2 status=0
  local base=$tmp/${world//:/_}.$seed
  # shellcheck disable=SC2046  # world_args gives several words on purpose
  "$pslam" experiment explore $(world_args "$world") --runs 1 --seed "$seed" --threads 1 --quiet \
    --json "$base.json" "${passed[@]}" >"$base.out" 2>"$base.err" || status=$?
  if (( status != 0 )); then
    echo "explore_bench: $world seed $seed failed (exit status $status):" >&2
    head -n 5 "$base.err" >&2
    return 1
  fi
  echo "explore_bench: $world seed $seed done" >&2
}

trap 'stop_runs; echo "explore_bench: interrupted" >&2; exit 130' INT TERM
echo "explore_bench: ${#worlds[@]} world(s) x ${#seeds[@]} seed(s), $jobs at once" >&2
for world in "${worlds[@]}"; do
  for seed in "${seeds[@]}"; do spawn run_one "$world" "$seed"; done
done
drain

echo "pslam experiment explore${passed[*]:+ ${passed[*]}} at $(measured_revision)"
echo
for world in "${worlds[@]}"; do
  for seed in "${seeds[@]}"; do echo "$world $seed $tmp/${world//:/_}.$seed.json"; done
done | python3 -c '
import json, sys

def fmt(v, pattern):
    return "-" if v is None else pattern % v

def mean(values):
    return "%.3f" % (sum(values) / len(values)) if values else "-"

def share(values, bound):
    return "%d of %d" % (sum(v >= bound for v in values), len(values)) if values else "-"

def mean_share(values, bound):
    return "%s; %s" % (mean(values), share(values, bound)) if values else "-"

rows = {}
print("| world | seed | full: position error, map Psi (laid onto the world first), state | skip: position error, map Psi (laid onto the world first), state | merged Psi (vs what can be seen) | saved at equal coverage | flags |")
print("| --- | --- | --- | --- | --- | --- | --- |")
for line in sys.stdin:
    world, seed, path = line.split()
    pair = json.load(open(path))["pairs"][0]
    full, skip = pair["full"], pair["skip"]
    flags = [f for f in ("time_limit_hit", "full_incomplete") if pair[f]]
    # As the experiment rules: such pairs are not timed; a skip run short of equal coverage saves 0.
    saved = None if flags else pair["saved_fraction"]
    if not pair["skip_reached_equal_coverage"]:
        flags.append("skip_below_equal_coverage")
    rows.setdefault(world, []).append((full, skip, saved))
    print("| %s | %s | %s m, %s (%s), %s | %s m, %s (%s), %s | %s (%s) | %s | %s |" % (
        world, seed, fmt(full["mean_position_error_m"], "%.3f"), fmt(full["map_psi"], "%.3f"),
        fmt(full["aligned_map_psi"], "%.3f"), full["state"],
        fmt(skip["mean_position_error_m"], "%.3f"), fmt(skip["map_psi"], "%.3f"),
        fmt(skip["aligned_map_psi"], "%.3f"), skip["state"],
        fmt(skip["merged_psi"], "%.3f"), fmt(skip.get("merged_psi_observable"), "%.3f"), fmt(None if saved is None else 100 * saved, "%.1f %%"),
        ", ".join(flags) or "-"))

print()
print("| world | runs | full: mean position error (worst) | full: <= 0.3 m | full: map Psi mean; >= 0.75 | full: laid onto the world first | merged Psi mean; >= 0.7 | vs what can be seen | saved at equal coverage, mean (pairs timed) |")
print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
for world, runs in rows.items():
    n = len(runs)
    errors = [f["mean_position_error_m"] for f, _, _ in runs]
    psis = [f["map_psi"] for f, _, _ in runs]
    aligned = [f["aligned_map_psi"] for f, _, _ in runs]
    merged = [s["merged_psi"] for _, s, _ in runs if s["merged_psi"] is not None]
    seen = [s["merged_psi_observable"] for _, s, _ in runs if s.get("merged_psi_observable") is not None]
    saved = [v for _, _, v in runs if v is not None]
    print("| %s | %d | %.3f m (%.3f) | %d of %d | %.3f; %d of %d | %.3f; %d of %d | %s | %s | %s |" % (
        world, n, sum(errors) / n, max(errors), sum(e <= 0.3 for e in errors), n,
        sum(psis) / n, sum(p >= 0.75 for p in psis), n, sum(aligned) / n, sum(p >= 0.75 for p in aligned), n,
        mean_share(merged, 0.7), mean_share(seen, 0.7),
        "%.1f %% (%d)" % (100 * sum(saved) / len(saved), len(saved)) if saved else "-"))

# The whole population at once, as the targets are stated: every pair, every hypothesis.
pairs = [r for runs in rows.values() for r in runs]
saved = [v for _, _, v in pairs if v is not None]
merged = [s["merged_psi"] for _, s, _ in pairs if s["merged_psi"] is not None]
seen = [s["merged_psi_observable"] for _, s, _ in pairs if s.get("merged_psi_observable") is not None]
hyp = [v for _, s, _ in pairs for v in s["psi_truth"] if v is not None]
hyp_seen = [v for _, s, _ in pairs for v in s.get("psi_observable", []) if v is not None]
print()
print("| all %d pairs | saved at equal coverage, mean (pairs timed) | merged Psi >= 0.7 (mean) | vs what can be seen | hypotheses Psi >= 0.4 (mean) | vs what can be seen |" % len(pairs))
print("| --- | --- | --- | --- | --- | --- |")
print("| | %s | %s (%s) | %s (%s) | %s (%s) | %s (%s) |" % (
    "%.1f %% (%d)" % (100 * sum(saved) / len(saved), len(saved)) if saved else "-",
    share(merged, 0.7), mean(merged), share(seen, 0.7), mean(seen),
    share(hyp, 0.4), mean(hyp), share(hyp_seen, 0.4), mean(hyp_seen)))
'
