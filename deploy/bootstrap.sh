#!/usr/bin/env bash
# Installs everything the project needs to build and test, from Debian packages only.
# Idempotent: packages already present are skipped, so a second run costs a few seconds.
# Usage: deploy/bootstrap.sh [--web]   (--web adds Node.js, npm and Chromium for the viewer and its tests)
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config curl ca-certificates python3
  libeigen3-dev nlohmann-json3-dev libsqlite3-dev sqlite3 zlib1g-dev libbz2-dev libpng-dev
  libpq-dev postgresql redis-server libhiredis-dev  # a fleet's storage and live fan-out; tests start their own on loopback
  libboost-dev libboost-system-dev
  libopencv-dev libceres-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  clang lld libclang-rt-14-dev  # tests/fuzz: libFuzzer and the sanitizer runtimes come with clang
)
if [[ "${1:-}" == "--web" ]]; then
  packages+=(chromium)
  # A machine may already carry a newer Node.js (with npm inside) than Debian's; use it when present.
  command -v npm >/dev/null 2>&1 || packages+=(nodejs npm)
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if (( ${#missing[@]} == 0 )); then
  echo "bootstrap: all ${#packages[@]} packages present"
  exit 0
fi

sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then sudo_cmd=(sudo); fi
echo "bootstrap: installing ${missing[*]}"
"${sudo_cmd[@]}" apt-get update -qq
DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
