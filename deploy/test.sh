#!/usr/bin/env bash
# Sets up a fresh Debian machine and runs every test of the project.
set -euo pipefail
cd "$(dirname "$0")/.."
deploy/bootstrap.sh --web
deploy/build.sh
# One test per core at a time: most of them wait on sockets and child processes (5.9 → 3.2 min).
ctest --test-dir build --output-on-failure --timeout 600 -j"$(nproc)"
# A short libFuzzer run of every decoder of outside input (ASan + UBSan); a finding fails the test.
tests/fuzz/run.sh --seconds 5
# Three random kill -9 of server or agent while streaming: nothing lost, nothing stored twice.
tests/bench/chaos.sh --kills 3
# The web viewer: npm ci, build, unit tests, browser tests against build/bin/pslam-server.
web/test.sh
