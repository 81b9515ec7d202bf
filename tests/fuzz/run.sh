#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan) into build-fuzz/ and runs each for a while,
# starting from the seeds in tests/fuzz/corpus/<name> plus what earlier runs found.
# Usage: tests/fuzz/run.sh [--seconds N] [TARGET...]   (default: 5 s each, every target)
# Exits non-zero if a target crashes, leaks, times out or trips a sanitizer; the input that did it
# is kept as build-fuzz/artifacts/<target>-crash-… (replay: build-fuzz/bin/<target> FILE).
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds=5
targets=()
while (( $# )); do
  case "$1" in
    --seconds) seconds="$2"; shift 2 ;;
    -h|--help) sed -n 2,6p "$0"; exit 0 ;;
    *) targets+=("fuzz_$1"); shift ;;
  esac
done
(( ${#targets[@]} )) || targets=(fuzz_carmen_reader fuzz_ingest_text fuzz_ingest_binary fuzz_settings fuzz_p2os fuzz_sick
                                 fuzz_query fuzz_live_envelope fuzz_agent_messages)

launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DPSLAM_FUZZ=ON -DCMAKE_BUILD_TYPE=Debug "${launcher[@]}" >/dev/null
cmake --build build-fuzz -j"$(nproc)" --target "${targets[@]}"

mkdir -p build-fuzz/artifacts
failed=()
for target in "${targets[@]}"; do
  name=${target#fuzz_}
  corpus=build-fuzz/corpus/$name  # grows across runs; the committed seeds stay read-only
  mkdir -p "$corpus"
  echo "fuzz: $name for ${seconds} s"
  log=build-fuzz/artifacts/$name.log
  # -timeout: one input taking 10 s is a hang; -rss_limit_mb: an input that makes it allocate
  # gigabytes is a finding too.
  if build-fuzz/bin/"$target" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
       -artifact_prefix=build-fuzz/artifacts/"$name"- "$corpus" tests/fuzz/corpus/"$name" >"$log" 2>&1; then
    grep -E '^stat::number_of_executed_units|^Done ' "$log" | tr '\n' ' ' | sed 's/^/  /'
    echo
  else
    tail -n 40 "$log"
    failed+=("$name")
  fi
done
if (( ${#failed[@]} )); then
  echo "fuzz: FAILED: ${failed[*]} (inputs in build-fuzz/artifacts/, logs beside them)" >&2
  exit 1
fi
echo "fuzz: ${#targets[@]} target(s) ran ${seconds} s each without a finding"
