#!/usr/bin/env bash
# The main job on a fresh Debian machine: installs what is needed, builds the C++ binaries and the
# web viewer, starts pslam-server with a data directory, and starts pslam-agent driving a simulated
# Pioneer 3-DX through the office world with predictions on. Open the printed URL to watch.
# Ctrl-C stops both cleanly; the session stays stored in the data directory.
#
# Environment: PSLAM_PORT (8080), PSLAM_DATA (data/), PSLAM_WORLD (office: maze, irregular, or a
# map_server YAML), PSLAM_SIM_RATE (2: simulated seconds per real second).
set -euo pipefail
cd "$(dirname "$0")/.."
port="${PSLAM_PORT:-8080}"
data="${PSLAM_DATA:-data}"
world="${PSLAM_WORLD:-office}"
rate="${PSLAM_SIM_RATE:-2}"

deploy/bootstrap.sh --web
deploy/build.sh pslam-server pslam-agent pslam
(cd web && { [[ -d node_modules ]] || npm ci --no-audit --no-fund; } && npm run build --silent)

mkdir -p "$data"
server_pid="" agent_pid=""
stop() {
  trap - INT TERM
  echo; echo "stopping: agent first (the robot stops), then the server (it checkpoints and closes)"
  [[ -n "$agent_pid" ]] && kill -INT "$agent_pid" 2>/dev/null || true
  [[ -n "$agent_pid" ]] && wait "$agent_pid" 2>/dev/null || true
  [[ -n "$server_pid" ]] && kill -TERM "$server_pid" 2>/dev/null || true
  [[ -n "$server_pid" ]] && wait "$server_pid" 2>/dev/null || true
  echo "stopped; sessions are stored in $data/ (restart this script, or query them: see README, 'REST queries')"
  exit 0
}
trap stop INT TERM

build/bin/pslam-server --listen "127.0.0.1:$port" --data "$data" --web web/dist &
server_pid=$!
for _ in $(seq 1 100); do
  curl -fsS "http://127.0.0.1:$port/api/health" >/dev/null 2>&1 && break
  kill -0 "$server_pid" 2>/dev/null || { echo "pslam-server failed to start (is port $port free? set PSLAM_PORT)" >&2; exit 1; }
  sleep 0.1
done
# The simulated LMS-200 reaches 8 m, so in a long corridor it sees neither end: the degeneracy
# guard keeps scan matching from sliding along it (README, Experiments).
build/bin/pslam-agent --server "127.0.0.1:$port" --source "sim:$world" --rate "$rate" \
  --spool "$data/agent-spool" --session-name "simulated $world" --settings '{"degenerate_ratio": 0.15}' &
agent_pid=$!

echo
echo "  P-SLAM is mapping the simulated $world world. Open http://127.0.0.1:$port/ in a browser."
echo "  Ctrl-C stops the robot and the server; the session stays in $data/."
echo
wait "$agent_pid" || true
echo "the agent ended (exploration done, or see its messages above); the server keeps serving. Ctrl-C to stop."
wait "$server_pid"
