#!/usr/bin/env python3
"""A fleet under failure: N pslam-server nodes on one PostgreSQL and one Redis (throwaway servers
on loopback, deploy/cluster/services.sh), R simulated robots that know every node, and one node
killed with SIGKILL every --kill-every seconds (restarted --restart-after seconds later under the
same id) for --minutes. Then every robot is stopped (it closes its session) and the run is checked:

  - lost: inputs a robot had acknowledged that are not stored (robot's last acked seq > stored);
  - doubled: sessions whose filter processed more scans than are stored, or not all of them;
  - back: per killed node, seconds from the kill until each of its sessions had a live owner again
    (minus the lease: the time a takeover took once the lease had expired);
  - coordination: bytes each node exchanged with PostgreSQL and Redis, per scan stored.

Usage: tests/bench/fleet_soak.py [--nodes 3] [--robots 12] [--minutes 5] [--kill-every 30]
"""
import argparse
import collections
import json
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
import urllib.request

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
BIN = os.path.join(ROOT, "build", "bin")


def free_port():
    import socket
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


def get(port, path):
    with urllib.request.urlopen(f"http://127.0.0.1:{port}{path}", timeout=5) as r:
        return json.load(r)


def psql(url, sql):
    out = subprocess.run(["psql", "-At", "-F", "\t", url, "-c", sql], capture_output=True, text=True, check=True).stdout
    return [line.split("\t") for line in out.splitlines() if line]


def socket_bytes(pid, port):
    """Bytes sent and received by process 'pid' on its TCP connections to 127.0.0.1:'port'."""
    out = subprocess.run(["ss", "-tinpH", "dst", f"127.0.0.1:{port}"], capture_output=True, text=True).stdout
    sent = received = 0
    blocks = out.split("\n")
    for i, line in enumerate(blocks):
        if f"pid={pid}," not in line:
            continue
        info = blocks[i + 1] if i + 1 < len(blocks) else ""
        m = re.search(r"bytes_sent:(\d+)", info)
        sent += int(m.group(1)) if m else 0
        m = re.search(r"bytes_received:(\d+)", info)
        received += int(m.group(1)) if m else 0
    return sent, received


def cpu_seconds(pid):
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


class Node:
    def __init__(self, name, port, state, args):
        self.name, self.port, self.state, self.args = name, port, state, args
        self.proc = None
        self.start()

    def start(self):
        log = open(os.path.join(self.state, f"{self.name}.log"), "a")
        self.proc = subprocess.Popen([os.path.join(BIN, "pslam-server"), "--listen", f"127.0.0.1:{self.port}",
                                      "--data", os.path.join(self.state, self.name), "--node-id", self.name] + self.args,
                                     stdout=subprocess.DEVNULL, stderr=log)
        for _ in range(200):
            try:
                get(self.port, "/api/health")
                return
            except OSError:
                time.sleep(0.05)
        raise RuntimeError(f"{self.name} did not start")

    def alive(self):
        return self.proc is not None and self.proc.poll() is None


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--nodes", type=int, default=3)
    ap.add_argument("--robots", type=int, default=12)
    ap.add_argument("--minutes", type=float, default=5)
    ap.add_argument("--kill-every", type=float, default=30)
    ap.add_argument("--restart-after", type=float, default=10)
    ap.add_argument("--lease", type=int, default=5)
    ap.add_argument("--particles", type=int, default=10)
    args = ap.parse_args()

    state = tempfile.mkdtemp(prefix="pslam-fleet-soak-")
    services = os.path.join(ROOT, "deploy", "cluster", "services.sh")
    subprocess.run([services, "start", state], check=True, stdout=subprocess.DEVNULL)
    postgres = open(os.path.join(state, "postgres.url")).read().strip()
    redis = open(os.path.join(state, "redis.url")).read().strip()
    pg_port = int(re.search(r":(\d+)/", postgres).group(1))
    redis_port = int(redis.rsplit(":", 1)[1])
    node_args = ["--postgres", postgres, "--redis", redis, "--lease-seconds", str(args.lease),
                 "--particles", str(args.particles), "--max-sessions", str(args.robots)]
    nodes, robots = [], []
    coordination = {"pg_bytes": 0, "redis_bytes": 0, "cpu_s": 0.0}
    try:
        for i in range(args.nodes):
            nodes.append(Node(f"node-{i + 1}", free_port(), state, node_args))
        servers = ",".join(f"127.0.0.1:{n.port}" for n in nodes)
        for i in range(args.robots):
            log = open(os.path.join(state, f"robot-{i + 1}.log"), "w")
            robots.append(subprocess.Popen([os.path.join(BIN, "pslam-agent"), "--server", servers, "--source", "sim",
                                            "--robot-id", f"robot-{i + 1}", "--spool", os.path.join(state, f"spool-{i + 1}"),
                                            "--status-period", "2"], stdout=log, stderr=subprocess.STDOUT))
        time.sleep(10)
        print(f"{args.nodes} nodes, {args.robots} robots; killing one node every {args.kill_every:.0f} s "
              f"for {args.minutes:.1f} min (lease {args.lease} s)", flush=True)

        def live_port():
            return next(n.port for n in nodes if n.alive())

        def leases():
            return {l["session_id"]: l for l in get(live_port(), "/api/cluster")["leases"]}

        backs, start, victim = [], time.monotonic(), 0
        while time.monotonic() - start < args.minutes * 60:
            time.sleep(args.kill_every - args.restart_after)
            node = nodes[victim % len(nodes)]
            victim += 1
            if not node.alive():
                continue
            moved = [sid for sid, l in leases().items() if l["node_id"] == node.name]
            coordination["pg_bytes"] += sum(socket_bytes(node.proc.pid, pg_port))
            coordination["redis_bytes"] += sum(socket_bytes(node.proc.pid, redis_port))
            coordination["cpu_s"] += cpu_seconds(node.proc.pid)
            node.proc.send_signal(signal.SIGKILL)
            node.proc.wait()
            killed = time.monotonic()
            pending = set(moved)
            while pending and time.monotonic() - killed < 60:
                now = leases()
                for sid in list(pending):
                    l = now.get(sid)
                    if l and l["node_id"] != node.name and l["expires_in_seconds"] > 0:
                        backs.append(time.monotonic() - killed)
                        pending.discard(sid)
                time.sleep(0.1)
            print(f"t={killed - start:5.0f} s: killed {node.name} running {len(moved)} session(s); "
                  f"back after {', '.join(f'{b:.1f}' for b in backs[-len(moved):]) if moved else '-'} s"
                  f"{'; NOT BACK: ' + ', '.join(pending) if pending else ''}", flush=True)
            time.sleep(max(0.0, args.restart_after - (time.monotonic() - killed)))
            node.start()

        for n in nodes:
            if n.alive():
                coordination["pg_bytes"] += sum(socket_bytes(n.proc.pid, pg_port))
                coordination["redis_bytes"] += sum(socket_bytes(n.proc.pid, redis_port))
                coordination["cpu_s"] += cpu_seconds(n.proc.pid)
        # Where the sessions run at the end, and once rebalancing has had 30 s more.
        for wait in (0, 30):
            time.sleep(wait)
            counts = collections.Counter(l["node_id"] for l in leases().values() if l["expires_in_seconds"] > 0)
            print(f"sessions per node{f' {wait} s later' if wait else ' at the end'}: "
                  + ", ".join(f"{n.name} {counts.get(n.name, 0)}" for n in nodes), flush=True)
        # Robots stop: each waits for its acks and closes its session.
        for r in robots:
            r.send_signal(signal.SIGINT)
        for r in robots:
            try:
                r.wait(timeout=120)
            except subprocess.TimeoutExpired:
                r.kill()

        # Every session's filter catches up with what is stored, on the node that runs it.
        ports = {n.name: n.port for n in nodes if n.alive()}
        filters = {}
        deadline = time.monotonic() + 180
        while time.monotonic() < deadline:
            filters = {}
            owners = {sid: l["node_id"] for sid, l in leases().items()}
            for (sid,) in psql(postgres, "SELECT id FROM sessions"):
                # A running session's live figures on its node; a closed one's final checkpoint on any.
                st = get(ports.get(owners.get(sid), live_port()), f"/api/sessions/{sid}/stats")
                filters[sid] = (st["filter"].get("processed_seq", 0), st["ingest"]["received_seq"], st["filter"].get("scans", 0))
            if filters and all(p == r for p, r, _ in filters.values()):
                break
            time.sleep(2)

        acked = {}
        for i in range(args.robots):
            text = open(os.path.join(state, f"robot-{i + 1}.log")).read()
            sessions = set(re.findall(r"in session (s-[0-9a-f]+)", text))
            last = re.findall(r"acked (\d+)", text)
            acked[f"robot-{i + 1}"] = (sessions, int(last[-1]) if last else 0)
        stored = {row[0]: row for row in psql(postgres, "SELECT s.id, s.status, "
                                                         "(SELECT coalesce(max(seq), 0) FROM inputs i WHERE i.session_id = s.id), "
                                                         "(SELECT count(*) FROM inputs i WHERE i.session_id = s.id AND kind = 2) "
                                                         "FROM sessions s")}
        lost = doubled = unchecked = 0
        for robot, (sessions, last_acked) in acked.items():
            if len(sessions) != 1:
                print(f"{robot}: {len(sessions)} sessions: {sorted(sessions)}")
            for sid in sessions:
                row = stored.get(sid)
                if not row:
                    print(f"{robot}: session {sid} not stored")
                elif len(sessions) == 1 and last_acked > int(row[2]):
                    lost += last_acked - int(row[2])
                    print(f"{robot}: acked {last_acked}, stored up to {row[2]}")
        for sid, row in stored.items():
            f = filters.get(sid)
            if not f or f[0] != f[1] or f[1] != int(row[2]):
                unchecked += 1
                print(f"session {sid}: filter not caught up with storage: {f}, stored up to {row[2]}")
            elif f[2] != int(row[3]):
                doubled += 1
                print(f"session {sid}: filter scans {f[2]}, stored scans {row[3]}")
        lapsed = sum(open(os.path.join(state, f"{n.name}.log")).read().count("lost the lease") for n in nodes)
        backlog = [int(m) for i in range(args.robots)
                   for m in re.findall(r"spool (\d+) unacked", open(os.path.join(state, f"robot-{i + 1}.log")).read())[-1:]]
        scans = sum(int(row[3]) for row in stored.values())
        print()
        print("| nodes | robots | minutes | kills | sessions | scans stored | acked inputs lost | sessions with scans "
              "filtered twice or skipped (not checked) | back after kill (s): median / max | leases lapsed on live nodes | "
              "robots' backlog at the end (max) | lease |")
        print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
        backs.sort()
        print(f"| {args.nodes} | {args.robots} | {args.minutes:g} | {victim} | {len(stored)} | {scans} | {lost} | {doubled} ({unchecked}) | "
              f"{backs[len(backs) // 2] if backs else float('nan'):.1f} / {backs[-1] if backs else float('nan'):.1f} | {lapsed} | "
              f"{max(backlog) if backlog else 0} | {args.lease} s |")
        if scans:
            print(f"\ncoordination and storage per scan stored (all nodes): PostgreSQL {coordination['pg_bytes'] / scans:.0f} B, "
                  f"Redis {coordination['redis_bytes'] / scans:.0f} B; node CPU {1000 * coordination['cpu_s'] / scans:.1f} ms "
                  f"(filter included)")
    finally:
        for r in robots:
            if r.poll() is None:
                r.kill()
        for n in nodes:
            if n.alive():
                n.proc.send_signal(signal.SIGTERM)
                n.proc.wait()
        subprocess.run([services, "stop", state], stdout=subprocess.DEVNULL)
        print(f"logs in {state}")


if __name__ == "__main__":
    sys.exit(main())
