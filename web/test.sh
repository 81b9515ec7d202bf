#!/usr/bin/env bash
# Builds and tests the web viewer: npm ci, type check + build (web/dist), unit tests, then the
# browser tests in tests/web/ (layer stories always; the tests against the real pslam-server and
# pslam-agent when build/bin has them) and the tile/frame benchmark.
# Usage: web/test.sh [--no-browser]    Env: PSLAM_BIN_DIR (default build/bin), CHROMIUM.
set -euo pipefail
cd "$(dirname "$0")"
npm ci --no-audit --no-fund
npm run build
npm test
if [[ "${1:-}" == "--no-browser" ]]; then exit 0; fi
if [[ ! -x "${CHROMIUM:-/usr/bin/chromium}" ]]; then
  echo "web/test.sh: no chromium at ${CHROMIUM:-/usr/bin/chromium}; browser tests skipped" >&2
  exit 0
fi
bin_dir="${PSLAM_BIN_DIR:-../build/bin}"
if [[ ! -x "$bin_dir/pslam-server" || ! -x "$bin_dir/pslam-agent" ]]; then
  echo "web/test.sh: $bin_dir/pslam-server or pslam-agent missing; the tests against the server are skipped" >&2
fi
npm run test:browser
npm run bench
