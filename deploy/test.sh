#!/usr/bin/env bash
# Sets up a fresh Debian machine and runs every test of the project.
set -euo pipefail
cd "$(dirname "$0")/.."
deploy/bootstrap.sh --web
deploy/build.sh
ctest --test-dir build --output-on-failure --timeout 600
# The web viewer: npm ci, build, unit tests, browser tests against build/bin/pslam-server.
web/test.sh
