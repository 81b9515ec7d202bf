#!/usr/bin/env bash
# Starts or stops throwaway PostgreSQL and Redis servers for a fleet on this machine: Debian's
# binaries, data in a temporary directory, listening on 127.0.0.1 only, no persistence beyond the
# directory. For tests, benchmarks and trying a fleet out; not for production (trust auth).
#
# Usage: deploy/cluster/services.sh start STATE_DIR [--postgres] [--redis]   (both by default)
#        deploy/cluster/services.sh stop STATE_DIR
# start writes STATE_DIR/postgres.url (postgresql://pslam@127.0.0.1:PORT/postgres) and
# STATE_DIR/redis.url (redis://127.0.0.1:PORT), and prints them.
set -euo pipefail

usage() {
  sed -n '/^# Usage:/,/^#        /p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
}
die() {
  echo "services: $*" >&2
  exit 1
}
free_port() {
  python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}
# PostgreSQL refuses to run as root; the Debian package's system user runs it then.
as_db_user() {
  if [[ $(id -u) -eq 0 ]]; then runuser -u postgres -- "$@"; else "$@"; fi
}

[[ $# -ge 2 ]] || usage
command=$1 state=$2
shift 2
mkdir -p "$state"
state=$(cd "$state" && pwd)

start_postgres() {
  local bin port dir
  bin=$(ls -d /usr/lib/postgresql/*/bin 2>/dev/null | sort -V | tail -1)
  [[ -x "$bin/initdb" ]] || die "no PostgreSQL server (apt-get install postgresql, or run deploy/bootstrap.sh)"
  dir=$(mktemp -d /tmp/pslam-postgres.XXXXXX)  # readable by the database user, wherever STATE_DIR is
  chmod 700 "$dir"
  [[ $(id -u) -ne 0 ]] || chown postgres: "$dir"
  echo "$dir" >"$state/postgres.dir"
  as_db_user "$bin/initdb" -D "$dir/data" -U pslam --auth=trust --no-sync -E UTF8 >"$state/postgres-init.log" 2>&1 ||
    die "initdb failed, see $state/postgres-init.log"
  port=$(free_port)
  as_db_user "$bin/pg_ctl" -D "$dir/data" -l "$dir/postgres.log" -w -t 60 \
    -o "-c listen_addresses=127.0.0.1 -p $port -c unix_socket_directories=$dir -c max_connections=200" start \
    >/dev/null || die "PostgreSQL did not start, see $dir/postgres.log"
  echo "postgresql://pslam@127.0.0.1:$port/postgres" | tee "$state/postgres.url"
}

start_redis() {
  local port
  command -v redis-server >/dev/null || die "no redis-server (apt-get install redis-server, or run deploy/bootstrap.sh)"
  port=$(free_port)
  redis-server --bind 127.0.0.1 --port "$port" --save "" --appendonly no --daemonize yes \
    --dir "$state" --pidfile "$state/redis.pid" --logfile "$state/redis.log" >/dev/null
  for _ in $(seq 100); do
    redis-cli -p "$port" ping 2>/dev/null | grep -q PONG && break
    sleep 0.05
  done
  redis-cli -p "$port" ping 2>/dev/null | grep -q PONG || die "Redis did not start, see $state/redis.log"
  echo "redis://127.0.0.1:$port" | tee "$state/redis.url"
}

stop_all() {
  if [[ -f "$state/postgres.dir" ]]; then
    local dir bin
    dir=$(cat "$state/postgres.dir")
    bin=$(ls -d /usr/lib/postgresql/*/bin 2>/dev/null | sort -V | tail -1)
    [[ -f "$dir/data/postmaster.pid" ]] && as_db_user "$bin/pg_ctl" -D "$dir/data" -m immediate -w stop >/dev/null || true
    rm -rf "$dir" "$state/postgres.dir" "$state/postgres.url"
  fi
  if [[ -f "$state/redis.pid" ]]; then
    kill "$(cat "$state/redis.pid")" 2>/dev/null || true
    rm -f "$state/redis.pid" "$state/redis.url"
  fi
}

case "$command" in
  start)
    want_pg=0 want_redis=0
    for a in "$@"; do
      case "$a" in
        --postgres) want_pg=1 ;;
        --redis) want_redis=1 ;;
        *) usage ;;
      esac
    done
    (( want_pg + want_redis > 0 )) || want_pg=1 want_redis=1
    (( want_pg == 0 )) || start_postgres
    (( want_redis == 0 )) || start_redis
    ;;
  stop) stop_all ;;
  *) usage ;;
esac
