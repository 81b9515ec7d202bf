#!/usr/bin/env bash
# `pslam run` against GMapping (OpenSLAM's gfs_nogui, Grisetti et al. 2007) on the same logs, seeds
# and machine: relative pose error, wall time and peak memory of each, and how many times faster
# pslam is. GMapping is built from a checkout of its source that you give (it is not packaged in
# Debian): git clone https://github.com/ros-perception/openslam_gmapping
# Both run with their defaults at the same particle count, pslam as the plain RBPF (--no-predict) on
# one thread unless told otherwise. gfs_nogui's main thread polls for the end of the run and keeps a second core busy,
# so runs go one at a time and the machine needs two free cores for fair times.
#
# Usage: tests/bench/gmapping_bench.sh --source DIR [--seeds LIST] [--particles N] [--logs NAME,...]
#                                      [--threads N] [--data DIR]
#   --source DIR     a checkout of openslam_gmapping; built into build/gmapping (again for another DIR)
#   --seeds LIST     e.g. 1-3 (default), 1,3,7 or 1-3,9
#   --particles N    particles for both (30, GMapping's default)
#   --logs LIST      some of the logs, e.g. intel,aces (default: every one found)
#   --threads N      threads for pslam (1; 0: every core, its default)
#   --data DIR       the shared data folder (default: $PSLAM_DATA_DIR, else ../shared/data)
# PSLAM_BIN=PATH runs that pslam binary instead of build/bin/pslam.
set -euo pipefail
cd "$(dirname "$0")/../.."
source tests/bench/log_runs.sh  # usage, die, seeds, logs

source_dir=
seed_list=1-3
particles=30
log_list=
threads=1
data="${PSLAM_DATA_DIR:-../shared/data}"
while (( $# )); do
  case $1 in
    --source) source_dir=${2:?}; shift ;;
    --seeds) seed_list=${2:?}; shift ;;
    --particles) particles=${2:?}; shift ;;
    --logs) log_list=${2:?}; shift ;;
    --threads) threads=${2:?}; shift ;;
    --data) data=${2:?}; shift ;;
    -h|--help) usage ;;
    *) echo "gmapping_bench: unknown option '$1'" >&2; usage ;;
  esac
  shift
done
[[ -n $source_dir ]] || die "--source DIR is required (a checkout of openslam_gmapping)"
[[ $source_dir == /* ]] || source_dir=$OLDPWD/$source_dir  # relative to where the script was called
[[ -f $source_dir/gridfastslam/gridslamprocessor.cpp ]] || die "$source_dir is not an openslam_gmapping checkout"
[[ $particles =~ ^[1-9][0-9]*$ ]] || die "--particles must be a positive integer, got '$particles'"
[[ $threads =~ ^[0-9]+$ ]] || die "--threads must be a number, got '$threads'"
[[ -x /usr/bin/time ]] || die "needs /usr/bin/time (Debian package 'time') for peak memory"
parse_seeds "$seed_list"
find_logs "$data" "$log_list"
find_pslam

out=$PWD/build/gmapping
# Builds gfs_nogui (the SLAM run without a GUI) and gfs2log (the best particle's path) as its
# CMake build would, in Release. Its CMake build generates one export header per library; they
# only mark symbols for shared libraries, so empty ones do for a static link.
build_gmapping() {
  local src=$source_dir lib
  mkdir -p "$out/include"
  for lib in configfile gridfastslam log scanmatcher sensor/sensor_base sensor/sensor_odometry \
             sensor/sensor_range utils; do
    mkdir -p "$out/include/gmapping/$lib"
    printf '#pragma once\n#define %s_EXPORT\n' "$(basename "$lib" | tr a-z A-Z)" \
      >"$out/include/gmapping/$lib/$(basename "$lib")_export.h"
  done
  local common=(sensor/sensor_base/sensor.cpp sensor/sensor_base/sensorreading.cpp
                sensor/sensor_odometry/odometryreading.cpp sensor/sensor_odometry/odometrysensor.cpp
                sensor/sensor_range/rangereading.cpp sensor/sensor_range/rangesensor.cpp utils/movement.cpp)
  local slam=(configfile/configfile.cpp gridfastslam/gridslamprocessor.cpp
              gridfastslam/gridslamprocessor_tree.cpp gridfastslam/motionmodel.cpp
              log/carmenconfiguration.cpp log/configuration.cpp log/sensorlog.cpp log/sensorstream.cpp
              scanmatcher/eig3.cpp scanmatcher/scanmatcher.cpp scanmatcher/scanmatcherprocessor.cpp
              scanmatcher/smmap.cpp utils/stat.cpp gui/gsp_thread.cpp gui/gfs_nogui.cpp)
  # gnu++03: gsp_thread.cpp streams an ostream into an ostream, which only C++03 accepts.
  local flags=(-O3 -DNDEBUG -std=gnu++03 -w -I"$src/include" -I"$out/include")
  echo "gmapping_bench: building GMapping from $src ..." >&2
  (cd "$src" && g++ "${flags[@]}" "${common[@]}" "${slam[@]}" -o "$out/gfs_nogui" -lpthread &&
   g++ "${flags[@]}" "${common[@]}" gridfastslam/gfs2log.cpp gridfastslam/gfsreader.cpp -o "$out/gfs2log") ||
    die "could not build GMapping from $src"
  echo "$src" >"$out/source"
}
# Built again when asked for another checkout.
[[ -x $out/gfs_nogui && -x $out/gfs2log && $(cat "$out/source" 2>/dev/null) == "$source_dir" ]] || build_gmapping

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# "trans rot wall mem" of one run's trajectory and /usr/bin/time output.
summarize() {
  local trajectory=$1 relations=$2 time=$3
  "$pslam" eval --json --trajectory "$trajectory" --relations "$relations" >"$tmp/rpe" ||
    die "pslam eval failed on $trajectory"
  echo "$(json_field trans_mean_m "$tmp/rpe") $(json_field rot_mean_deg "$tmp/rpe")" \
    "$(awk '/Elapsed/ {n = split($NF, t, ":"); s = 0; for (i = 1; i <= n; i++) s = s * 60 + t[i]; print s}
                    /Maximum resident/ {printf "%.0f", $NF / 1024}' "$time" | paste -sd' ')"
}

rows=()
for log in "${logs[@]}"; do
  clf=$(realpath "$data/$log/$log.clf") relations=$data/$log/$log.relations
  for seed in "${seeds[@]}"; do
    echo "gmapping_bench: $log seed $seed: GMapping ..." >&2
    # In $tmp: gfs_nogui also writes rawpath.dat and a w-NNN.dat per particle where it runs.
    (cd "$tmp" && /usr/bin/time -v -o g.time "$out/gfs_nogui" -filename "$clf" -particles "$particles" \
      -randseed "$seed" -outfilename g.gfs >g.out 2>g.err) ||
      die "GMapping failed on $log seed $seed: $(tail -n 3 "$tmp/g.err")"
    "$out/gfs2log" "$tmp/g.gfs" "$tmp/g.log" >/dev/null || die "gfs2log failed on $log seed $seed"
    # gfs2log writes the best particle's pose at every laser scan as an ODOM line stamped with it.
    awk '$1 == "ODOM" && $8 > 0 {print $8, $2, $3, $4}' "$tmp/g.log" >"$tmp/g.trajectory"
    g=$(summarize "$tmp/g.trajectory" "$relations" "$tmp/g.time")
    echo "gmapping_bench: $log seed $seed: pslam ..." >&2
    /usr/bin/time -v -o "$tmp/p.time" "$pslam" run --quiet --log "$clf" --particles "$particles" \
      --seed "$seed" --no-predict --set threads="$threads" --trajectory "$tmp/p.trajectory" >/dev/null 2>"$tmp/p.err" ||
      die "pslam run failed on $log seed $seed: $(tail -n 3 "$tmp/p.err")"
    p=$(summarize "$tmp/p.trajectory" "$relations" "$tmp/p.time")
    rows+=("$log $seed $g $p")
    echo "gmapping_bench: $log seed $seed: GMapping $g, pslam $p" >&2
  done
done

echo "GMapping (gfs_nogui) and pslam run --no-predict --set threads=$threads, $particles particles, at $(measured_revision)"
echo
printf '%s\n' "${rows[@]}" | awk '
  BEGIN {
    print "| log | seed | GMapping RPE | pslam RPE | GMapping wall | pslam wall | pslam faster | GMapping / pslam peak memory |"
    print "| --- | --- | --- | --- | --- | --- | --- | --- |"
  }
  function row(name, seed, gt, gr, gw, gm, pt, pr, pw, pm) {
    printf "| %s | %s | %.4f m, %.2f° | %.4f m, %.2f° | %.1f s | %.1f s | %.2f× | %d / %d MiB |\n",
           name, seed, gt, gr, pt, pr, gw, pw, gw / pw, gm, pm
  }
  {
    row($1, $2, $3, $4, $5, $6, $7, $8, $9, $10)
    n[$1]++; for (i = 3; i <= 10; i++) sum[$1, i] += $i
    if (!($1 in seen)) { seen[$1] = 1; order[++logs] = $1 }
  }
  END {
    for (l = 1; l <= logs; l++) {
      k = order[l]
      row(k, "mean", sum[k,3]/n[k], sum[k,4]/n[k], sum[k,5]/n[k], sum[k,6]/n[k],
          sum[k,7]/n[k], sum[k,8]/n[k], sum[k,9]/n[k], sum[k,10]/n[k])
    }
  }'
