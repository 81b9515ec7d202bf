#!/usr/bin/env bash
# A fleet on this machine, to try it out or measure it: throwaway PostgreSQL and Redis on loopback
# (services.sh), N pslam-server nodes sharing them, and optionally R simulated robots that know
# every node. Ctrl-C stops the robots, the nodes and the services, and removes the data.
#
# Usage: deploy/cluster/local.sh [--nodes N] [--robots R] [--port BASE] [--lease S]
#   Nodes listen on 127.0.0.1:BASE, BASE+1, ... (8080 by default); any of them serves the viewer,
#   REST (GET /api/cluster lists the nodes and their sessions) and agents, which are redirected to
#   the node that runs their session. Kill one (kill -9 PID, printed) to watch its sessions move.
set -euo pipefail
cd "$(dirname "$0")/../.."
nodes=3 robots=0 base=8080 lease=5
while [[ $# -gt 0 ]]; do
  case "$1" in
    --nodes) nodes=$2; shift 2 ;;
    --robots) robots=$2; shift 2 ;;
    --port) base=$2; shift 2 ;;
    --lease) lease=$2; shift 2 ;;
    *) sed -n '/^# Usage:/,/^set /p' "$0" | sed '$d; s/^# \{0,1\}//' >&2; exit 2 ;;
  esac
done

deploy/bootstrap.sh --web
deploy/build.sh pslam-server pslam-agent
(cd web && { [[ -d node_modules ]] || npm ci --no-audit --no-fund; } && npm run build --silent)

state=$(mktemp -d /tmp/pslam-fleet.XXXXXX)
pids=()
stop() {
  trap - INT TERM EXIT
  echo "stopping the fleet"
  for pid in "${pids[@]}"; do kill -TERM "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do wait "$pid" 2>/dev/null || true; done
  deploy/cluster/services.sh stop "$state" || true
  rm -rf "$state"
}
trap stop INT TERM EXIT

deploy/cluster/services.sh start "$state" >/dev/null
postgres=$(cat "$state/postgres.url")
redis=$(cat "$state/redis.url")
servers=""
for i in $(seq 1 "$nodes"); do
  port=$((base + i - 1))
  build/bin/pslam-server --listen "127.0.0.1:$port" --data "$state/node-$i" --postgres "$postgres" \
    --redis "$redis" --node-id "node-$i" --lease-seconds "$lease" >"$state/node-$i.log" 2>&1 &
  pids+=($!)
  echo "node-$i: http://127.0.0.1:$port (pid $!, log $state/node-$i.log)"
  servers+="${servers:+,}127.0.0.1:$port"
done
for i in $(seq 1 "$robots"); do
  build/bin/pslam-agent --server "$servers" --source sim --robot-id "robot-$i" --spool "$state/spool-$i" \
    >"$state/robot-$i.log" 2>&1 &
  pids+=($!)
done
[[ $robots -gt 0 ]] && echo "$robots simulated robot(s) streaming to $servers"
echo "PostgreSQL $postgres, Redis $redis; Ctrl-C stops everything"
wait
