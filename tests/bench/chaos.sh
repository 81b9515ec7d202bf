#!/usr/bin/env bash
# Crash chaos: pslam-agent streams to pslam-server (127.0.0.1, a temporary data dir) while one or
# the other, at random, is killed with SIGKILL and restarted, N times. Once the server has caught
# up, both are stopped and tests/bench/chaos_count.py compares the agent's spool with the server's
# SQLite file: every message the agent produced must be stored once or still wait in the spool;
# none lost, none stored twice.
# Usage: tests/bench/chaos.sh [--kills N] [--source SOURCE] [--rate R] [--seed S]
#   --kills N      number of kills (100)
#   --source S     the agent's source (sim); e.g. log:../shared/data/intel/intel.clf
#   --rate R       the agent's --rate (1: real time)
#   --seed S       seed of the random victims and pauses (from $RANDOM)
# PSLAM_BIN names another directory holding the two binaries (default build/bin).
# Exits non-zero if anything was lost or duplicated, or if a process did not come back.
set -euo pipefail
cd "$(dirname "$0")/../.."
kills=100 source=sim rate=1 seed=$RANDOM
while (( $# )); do
  case "$1" in
    --kills) kills=$2 ;;
    --source) source=$2 ;;
    --rate) rate=$2 ;;
    --seed) seed=$2 ;;
    *) sed -n 2,13p "$0"; exit 2 ;;
  esac
  shift 2
done
bin=${PSLAM_BIN:-build/bin}
[[ -x $bin/pslam-server && -x $bin/pslam-agent ]] || deploy/build.sh pslam-server pslam-agent
RANDOM=$seed

work=$(mktemp -d)
server_pid='' agent_pid=''
stop() {  # PID SIGNAL: signal a process of ours and reap it
  [[ -n "$1" ]] && kill "-$2" "$1" 2>/dev/null && wait "$1" 2>/dev/null || true
}
cleanup() {
  stop "$agent_pid" KILL
  stop "$server_pid" KILL
  rm -rf "$work"
}
trap cleanup EXIT
fail() {
  echo "chaos: $*" >&2
  echo "--- server log (tail)" >&2; tail -n 20 "$work/server.log" >&2 || true
  echo "--- agent log (tail)" >&2; tail -n 20 "$work/agent.log" >&2 || true
  exit 1
}

port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
start_server() {
  "$bin/pslam-server" --listen "127.0.0.1:$port" --data "$work/data" >>"$work/server.log" 2>&1 &
  server_pid=$!
  for _ in $(seq 600); do
    curl -sf -o /dev/null "http://127.0.0.1:$port/api/health" && return 0
    kill -0 "$server_pid" 2>/dev/null || fail "pslam-server exited on start"
    sleep 0.1
  done
  fail "pslam-server not healthy within 60 s"
}
# --keep-session: a restarted agent resumes its session, as a robot's does (a simulator agent would
# otherwise start a new session at each run).
start_agent() {
  "$bin/pslam-agent" --server "127.0.0.1:$port" --source "$source" --rate "$rate" --spool "$work/spool" \
    --keep-session --status-period 0.5 >>"$work/agent.log" 2>&1 &
  agent_pid=$!
}
# Highest acknowledgement the agent has reported ("acked N" in its status lines).
max_acked() { grep -o 'acked [0-9]*' "$work/agent.log" | awk '$2 > m { m = $2 } END { print m + 0 }'; }

start_server
start_agent
started=$SECONDS
server_kills=0 agent_kills=0
for (( i = 1; i <= kills; i++ )); do
  sleep "$(( RANDOM % 4 )).$(( RANDOM % 10 ))"  # 0.0 to 3.9 s of streaming between kills
  kill -0 "$agent_pid" 2>/dev/null || fail "pslam-agent exited by itself"
  kill -0 "$server_pid" 2>/dev/null || fail "pslam-server exited by itself"
  if (( RANDOM % 2 )); then
    stop "$server_pid" KILL
    server_kills=$(( server_kills + 1 ))
    start_server
  else
    stop "$agent_pid" KILL
    agent_kills=$(( agent_kills + 1 ))
    start_agent
  fi
done
# Let the server catch up (at most 120 s). The agent never stops producing, so caught up means a
# backlog under 50 messages (2.5 s of input); what is left is counted as pending.
for _ in $(seq 240); do
  sleep 0.5
  unacked=$(grep -o 'spool [0-9]* unacked' "$work/agent.log" | tail -n 1 | awk '{ print $2 }')
  (( ${unacked:-0} < 50 )) && break
done
stop "$agent_pid" TERM
agent_pid=''
acked=$(max_acked)
stop "$server_pid" TERM
server_pid=''

echo "chaos: $server_kills server kills, $agent_kills agent kills in $(( SECONDS - started )) s (source $source, rate $rate, seed $seed)"
python3 tests/bench/chaos_count.py "$work/spool" "$work/data/pslam.sqlite" "$acked" || fail "inputs lost or duplicated"
