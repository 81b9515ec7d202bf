#!/usr/bin/env bash
# The main job on a fresh Debian machine: installs what is needed, builds the C++ binaries and the
# web viewer, starts pslam-server with a data directory, and starts pslam-agent driving a simulated
# Pioneer 3-DX through the office world with predictions on. Open the printed URL to watch.
# Ctrl-C stops the agent first (it closes its session, which stays stored in the data directory),
# then the server; the next run starts a new session, since the simulated robot starts afresh.
# The server replays CARMEN logs from PSLAM_REPLAY_DIR (README, "Replays").
#
# Environment: PSLAM_PORT (8080), PSLAM_DATA (data/), PSLAM_WORLD (office: maze, irregular, or a
# map_server YAML), PSLAM_SIM_RATE (2: simulated seconds per real second), PSLAM_REPLAY_DIR
# (../shared/data when it exists, else data/replays/).
set -euo pipefail
cd "$(dirname "$0")/.."
port="${PSLAM_PORT:-8080}"
data="${PSLAM_DATA:-data}"
world="${PSLAM_WORLD:-office}"
rate="${PSLAM_SIM_RATE:-2}"
default_replays="$data/replays"
[[ -d ../shared/data ]] && default_replays=../shared/data
replays="${PSLAM_REPLAY_DIR:-$default_replays}"

deploy/bootstrap.sh --web
deploy/build.sh pslam-server pslam-agent pslam
(cd web && { [[ -d node_modules ]] || npm ci --no-audit --no-fund; } && npm run build --silent)

mkdir -p "$data" "$replays"
# Job control: the server and the agent get process groups of their own, so a Ctrl-C reaches this
# script alone, which stops the agent first and the server after it (stopped together, the agent
# would see its link drop and try to reconnect).
set -m
server_pid="" agent_pid=""
stop() {
  trap - INT TERM
  echo; echo "stopping: agent first (the robot stops, its session is closed), then the server"
  [[ -n "$agent_pid" ]] && kill -INT "$agent_pid" 2>/dev/null || true
  [[ -n "$agent_pid" ]] && wait "$agent_pid" 2>/dev/null || true
  [[ -n "$server_pid" ]] && kill -TERM "$server_pid" 2>/dev/null || true
  [[ -n "$server_pid" ]] && wait "$server_pid" 2>/dev/null || true
  echo "stopped; sessions are stored in $data/ (restart this script, or query them: see README, 'REST queries')"
  exit 0
}
trap stop INT TERM

build/bin/pslam-server --listen "127.0.0.1:$port" --data "$data" --web web/dist --replay-dir "$replays" &
server_pid=$!
for _ in $(seq 1 100); do
  curl -fsS "http://127.0.0.1:$port/api/health" >/dev/null 2>&1 && break
  kill -0 "$server_pid" 2>/dev/null || { echo "pslam-server failed to start (is port $port free? set PSLAM_PORT)" >&2; exit 1; }
  sleep 0.1
done
# The simulated LMS-200 reaches 8 m, so in a long corridor it sees neither end: the degeneracy
# guard keeps scan matching from sliding along it (README, Experiments). The simulated wheels err
# by about 1 % of distance, so scan matching may lean on them where the scan says little.
build/bin/pslam-agent --server "127.0.0.1:$port" --source "sim:$world" --rate "$rate" \
  --spool "$data/agent-spool" --session-name "simulated $world" --settings '{"odometry_prior": 30, "hit_offsets": false}' &
agent_pid=$!

echo
echo "  P-SLAM is mapping the simulated $world world. Open http://127.0.0.1:$port/ in a browser."
echo "  Replays read logs from $replays/ (GET /api/replays/files lists them)."
echo "  Ctrl-C stops the robot and the server; the session stays in $data/."
echo
wait "$agent_pid" || true
echo "the agent ended (exploration done, or see its messages above); the server keeps serving. Ctrl-C to stop."
wait "$server_pid"
